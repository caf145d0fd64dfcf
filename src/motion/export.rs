//! World positions as CSV, one row per frame: `frame,time_s,<joint>_x,<joint>_y,<joint>_z,…`
//! (file units and axes; `time_s` = frame / fps). Joint names are quoted as CSV requires
//! (`"Left, Arm_x"`), so any CSV reader gets the columns back.

use std::fmt::Write as _;

use super::Motion;

/// Writes the world position of every joint (and every End Site if `end_sites`) in every frame
/// of `motion` as CSV to `w`. Joints come in skeleton order.
pub fn write_positions_csv<W: std::io::Write>(motion: &Motion, end_sites: bool, w: W) -> Result<(), csv::Error> {
    let cols: Vec<usize> = (0..motion.joints()).filter(|&j| end_sites || !motion.skeleton.is_end_site[j]).collect();
    let mut out = csv::Writer::from_writer(w);
    out.write_field("frame")?;
    out.write_field("time_s")?;
    for &j in &cols {
        let name = &motion.skeleton.names[j];
        for axis in ["x", "y", "z"] {
            out.write_field(format!("{name}_{axis}"))?;
        }
    }
    out.write_record(None::<&[u8]>)?;
    let mut buf = String::new();
    let mut field = |out: &mut csv::Writer<W>, v: &dyn std::fmt::Display| {
        buf.clear();
        let _ = write!(buf, "{v}");
        out.write_field(&buf)
    };
    for f in 0..motion.frames() {
        field(&mut out, &f)?;
        field(&mut out, &(f as f64 / motion.fps))?;
        let frame = motion.frame(f);
        for &j in &cols {
            let p = frame[j];
            field(&mut out, &p.x)?;
            field(&mut out, &p.y)?;
            field(&mut out, &p.z)?;
        }
        out.write_record(None::<&[u8]>)?;
    }
    out.flush()?;
    Ok(())
}
