//! The AMC motion file (Acclaim Motion Capture): a header (`:FULLY-SPECIFIED`, `:DEGREES` or
//! `:RADIANS`, `#` comments), then per frame a line with its number and one line per bone,
//! `name v1 v2 …`, the values in the order of the bone's ASF `dof` (the root's in `:root order`).

use super::asf::Asf;
use super::{lines, number, tokens};
use crate::bvh::{BvhError, FrameBudget, ParseLimits, Warning};

/// A parsed AMC file.
#[derive(Debug, Clone, PartialEq)]
pub struct Amc {
    /// `Some(true)` for `:DEGREES`, `Some(false)` for `:RADIANS`, `None` when the header says
    /// neither (the ASF's `:units angle` then applies).
    pub degrees: Option<bool>,
    /// Values per frame: the root's (`:root order`), then each bone's dofs in ASF bone order.
    pub values_per_frame: usize,
    /// Frame-major values, `frames × values_per_frame`.
    pub values: Vec<f64>,
    /// The number the file gives its first frame (CMU: 1).
    pub first_frame: usize,
    pub warnings: Vec<Warning>,
}

impl Amc {
    pub fn frames(&self) -> usize {
        self.values.len().checked_div(self.values_per_frame).unwrap_or(0)
    }

    pub fn frame(&self, i: usize) -> &[f64] {
        &self.values[i * self.values_per_frame..(i + 1) * self.values_per_frame]
    }
}

/// Where each bone's values start in a frame (`None`: a bone without dofs).
pub(crate) fn layout(asf: &Asf) -> (Vec<Option<usize>>, usize) {
    let mut at = asf.root.order.len();
    let starts = asf
        .bones
        .iter()
        .map(|b| {
            (!b.dofs.is_empty()).then(|| {
                at += b.dofs.len();
                at - b.dofs.len()
            })
        })
        .collect();
    (starts, at)
}

/// A frame being read: its number's line and which groups (root, bones) it has.
struct Open {
    line: usize,
    number: usize,
    filled: Vec<bool>,
}

/// Parses AMC text against its skeleton. `extra_per_frame` bytes per frame and `nodes` nodes
/// (what the frame costs once converted and loaded) count against `limits.max_bytes`.
pub fn parse_amc(
    text: &str,
    asf: &Asf,
    limits: &ParseLimits,
    extra_per_frame: usize,
    nodes: usize,
    frame_time: f64,
) -> Result<Amc, BvhError> {
    let (starts, per_frame) = layout(asf);
    let budget = FrameBudget::new(text.len(), per_frame + extra_per_frame / 8, nodes, frame_time, limits);
    let mut amc =
        Amc { degrees: None, values_per_frame: per_frame, values: Vec::new(), first_frame: 1, warnings: Vec::new() };
    let mut open: Option<Open> = None;
    let mut frames = 0usize;
    let mut last_line = 1;
    let mut jump_warned = false;
    for (n, line) in lines(text) {
        last_line = n;
        let toks = tokens(line);
        let Some(&(col, first)) = toks.first() else { continue };
        if let Some(keyword) = first.strip_prefix(':') {
            if open.is_some() {
                return Err(BvhError::new(n, col, format!("expected a bone line or a frame number, found `{first}`")));
            }
            match keyword.to_ascii_uppercase().as_str() {
                "DEGREES" => amc.degrees = Some(true),
                "RADIANS" => amc.degrees = Some(false),
                _ => {}
            }
            continue;
        }
        if toks.len() == 1 && first.bytes().all(|b| b.is_ascii_digit()) {
            let number: usize =
                first.parse().map_err(|_| BvhError::new(n, col, format!("frame number `{first}` is too large")))?;
            if let Some(f) = open.take() {
                close(&f, asf, &starts)?;
                if number != f.number + 1 && !jump_warned {
                    jump_warned = true;
                    amc.warnings.push(Warning {
                        line: n,
                        message: format!(
                            "frame numbers jump from {} to {number}; frames are taken in file order",
                            f.number
                        ),
                    });
                }
            } else {
                amc.first_frame = number;
            }
            if frames >= limits.max_values / per_frame.max(1) || frames >= budget.max_frames {
                return Err(BvhError::new(n, col, budget.message()));
            }
            frames += 1;
            amc.values.resize(frames * per_frame, 0.0);
            open = Some(Open { line: n, number, filled: vec![false; asf.bones.len() + 1] });
            continue;
        }
        let Some(frame) = open.as_mut() else {
            return Err(BvhError::new(
                n,
                col,
                format!("expected a frame number before the first bone line, found `{first}`"),
            ));
        };
        let (group, count, start, name) = if first.eq_ignore_ascii_case("root") {
            (0, asf.root.order.len(), 0, "root")
        } else {
            let b = asf.bone(first).ok_or_else(|| {
                BvhError::new(
                    n,
                    col,
                    format!("no bone `{first}` in the skeleton (ASF); expected a bone name or `root`"),
                )
            })?;
            (b + 1, asf.bones[b].dofs.len(), starts[b].unwrap_or(0), asf.bones[b].name.as_str())
        };
        if frame.filled[group] {
            return Err(BvhError::new(n, col, format!("`{name}` appears twice in frame {}", frame.number)));
        }
        frame.filled[group] = true;
        let given = toks.len() - 1;
        if given != count {
            let c =
                toks.get(count + 1).map_or_else(|| toks.last().map_or(col, |(c, t)| c + t.chars().count()), |t| t.0);
            return Err(BvhError::new(
                n,
                c,
                format!("`{name}` has {count} values in the skeleton (its `dof`), found {given}"),
            ));
        }
        let row = (frames - 1) * per_frame + start;
        for (i, &(c, t)) in toks[1..].iter().enumerate() {
            amc.values[row + i] = number(t)
                .ok_or_else(|| BvhError::new(n, c, format!("expected a finite number for `{name}`, found `{t}`")))?;
        }
    }
    match open {
        Some(f) => close(&f, asf, &starts)?,
        None => {
            return Err(BvhError::new(
                last_line,
                1,
                "the file has no frames (no frame number line such as `1`): is it an AMC motion?",
            ))
        }
    }
    Ok(amc)
}

/// Checks that a frame gave the root and every bone with dofs.
fn close(frame: &Open, asf: &Asf, starts: &[Option<usize>]) -> Result<(), BvhError> {
    if !frame.filled[0] {
        return Err(BvhError::new(frame.line, 1, format!("frame {} has no `root` line", frame.number)));
    }
    if let Some(b) = (0..asf.bones.len()).find(|&b| starts[b].is_some() && !frame.filled[b + 1]) {
        return Err(BvhError::new(
            frame.line,
            1,
            format!("frame {} has no line for bone `{}`", frame.number, asf.bones[b].name),
        ));
    }
    Ok(())
}
