//! A BVH file packed for the download: the same bytes back, in about half the gzipped size.
//!
//! The page's bundled sample (`www/sample.bvh`, CMU 13_30: 2,465 frames of 96 values with 2
//! decimals) weighs 0.41 MB gzipped, 0.14 MB packed. Gzip sees a BVH's MOTION section
//! row by row, where neighbouring numbers belong to different channels; a channel's values from
//! one frame to the next change smoothly. [`pack`] therefore writes each channel's column as
//! integers (the value times 10^decimals) in second differences (`v[0]`, `v[1] − v[0]`, then
//! `v[k] − 2·v[k−1] + v[k−2]`: mostly small numbers that repeat) and gzips that; [`unpack`]
//! turns it back into the very same bytes. The page fetches `www/sample.bvh.pack` and unpacks it
//! before the take goes to the worker (`src/app/loader`); `www/sample.bvh` stays beside it for the
//! tests, the embed example and anyone who wants the file.
//!
//! Only a file that comes back byte for byte is packed: every frame value written the one way
//! [`pack`] writes it back (at most `decimals` decimals, trailing zeros dropped, `0` for zero —
//! what `scripts/round-bvh.py` writes), one space between values, `\n` line ends. [`pack`]
//! refuses anything else ([`PackError`]); it checks its own result by unpacking it.
//!
//! The packed bytes, gzipped: the line `mocapseg-bvh-pack 2 DECIMALS COLUMNS FRAMES HEAD_BYTES
//! FINAL_NEWLINE`, the file's first HEAD_BYTES bytes verbatim (through the `Frame Time:` line),
//! then column after column FRAMES integers, each zigzag-mapped (0, −1, 1, −2, … → 0, 1, 2, 3, …)
//! and written in LEB128 (seven bits a byte, the high bit saying another byte follows): one byte
//! for most second differences, where version 1 wrote them as text separated by spaces (gzip then
//! spent 21 % more on the sample; version 1 packs are still read).
//!
//! Regenerate the shipped pack after changing the sample: `cargo run --example pack_bvh --
//! www/sample.bvh` (a unit test fails while they differ).

use std::io::{Read, Write};

/// The first word of a packed file.
const MAGIC: &str = "mocapseg-bvh-pack";
/// The format's version (1: the integers as text; still read).
const VERSION: u32 = 2;
/// At most this many decimals (10^9 still fits every value of a real take in an `i64`).
const MAX_DECIMALS: u32 = 9;
/// How a packed file's name ends: `sample.bvh.pack` holds `sample.bvh`.
pub const PACK_EXTENSION: &str = ".pack";

/// The name of the file a pack named `name` holds (`sample.bvh.pack` → `sample.bvh`), or `None`
/// when `name` is not a pack's.
pub fn unpacked_name(name: &str) -> Option<&str> {
    name.strip_suffix(PACK_EXTENSION).filter(|n| !n.is_empty())
}

/// The largest unpacked file (the page's cap on a take, 512 MiB).
pub const MAX_UNPACKED_BYTES: u64 = 512 << 20;

/// Why a file cannot be packed, or a pack cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PackError {
    /// The BVH text would not come back byte for byte from its numbers.
    #[error("this BVH cannot be packed exactly: {0}")]
    NotPackable(String),
    /// The packed bytes are damaged or are not a pack.
    #[error("not a packed BVH file: {0}")]
    Damaged(String),
}

/// `text` packed (gzipped at the best level).
pub fn pack(text: &str) -> Result<Vec<u8>, PackError> {
    let not = |why: String| PackError::NotPackable(why);
    let (head, motion) = split_head(text).ok_or_else(|| not("no `Frame Time:` line after MOTION".into()))?;
    let final_newline = motion.ends_with('\n');
    let body = motion.strip_suffix('\n').unwrap_or(motion);
    if body.is_empty() {
        return Err(not("no frames".into()));
    }
    let rows: Vec<Vec<&str>> = body.split('\n').map(|line| line.split(' ').collect()).collect();
    let columns = rows[0].len();
    if let Some((i, row)) = rows.iter().enumerate().find(|(_, r)| r.len() != columns) {
        return Err(not(format!("frame {} has {} values where the first has {columns}", i + 1, row.len())));
    }
    let decimals =
        rows.iter().flatten().map(|t| t.split_once('.').map_or(0, |(_, f)| f.len())).max().unwrap_or(0) as u32;
    if decimals > MAX_DECIMALS {
        return Err(not(format!("values with {decimals} decimals (at most {MAX_DECIMALS})")));
    }
    let mut values = vec![Vec::with_capacity(rows.len()); columns];
    for (i, row) in rows.iter().enumerate() {
        for (c, token) in row.iter().enumerate() {
            let v = parse_fixed(token, decimals).filter(|&v| format_fixed(v, decimals) == *token).ok_or_else(|| {
                not(format!(
                    "frame {}, value {}: {token:?} is not written the one way a pack writes it back",
                    i + 1,
                    c + 1
                ))
            })?;
            values[c].push(v);
        }
    }
    let mut out = format!(
        "{MAGIC} {VERSION} {decimals} {columns} {} {} {}\n{head}",
        rows.len(),
        head.len(),
        u8::from(final_newline)
    )
    .into_bytes();
    for column in &values {
        for (k, &v) in column.iter().enumerate() {
            let d = match k {
                0 => Some(v),
                1 => v.checked_sub(column[0]),
                _ => v
                    .checked_sub(column[k - 1])
                    .zip(column[k - 1].checked_sub(column[k - 2]))
                    .and_then(|(a, b)| a.checked_sub(b)),
            }
            .ok_or_else(|| not("values too large".into()))?;
            write_varint(&mut out, d);
        }
    }
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    gz.write_all(&out).map_err(|e| not(e.to_string()))?;
    let packed = gz.finish().map_err(|e| not(e.to_string()))?;
    match unpack(&packed) {
        Ok(back) if back == text.as_bytes() => Ok(packed),
        Ok(_) => Err(not("it does not unpack to the same bytes".into())),
        Err(e) => Err(not(format!("its pack does not unpack: {e}"))),
    }
}

/// The BVH file `packed` holds, byte for byte (a version 2 pack, or a version 1 one).
pub fn unpack(packed: &[u8]) -> Result<Vec<u8>, PackError> {
    let bad = |why: &str| PackError::Damaged(why.to_string());
    let mut bytes = Vec::new();
    flate2::read::GzDecoder::new(packed)
        .take(MAX_UNPACKED_BYTES)
        .read_to_end(&mut bytes)
        .map_err(|e| PackError::Damaged(format!("gzip: {e}")))?;
    let line_end = bytes.iter().position(|&b| b == b'\n').ok_or_else(|| bad("no header line"))?;
    let first = std::str::from_utf8(&bytes[..line_end]).map_err(|_| bad("its first line is not a pack's header"))?;
    let rest = &bytes[line_end + 1..];
    let fields: Vec<&str> = first.split(' ').collect();
    if fields.len() != 7 || fields[0] != MAGIC {
        return Err(bad("its first line is not a pack's header"));
    }
    let version = fields[1];
    if version != "1" && version != VERSION.to_string() {
        return Err(PackError::Damaged(format!("format version {version} (this build reads 1 and {VERSION})")));
    }
    let num = |i: usize| {
        fields[i].parse::<usize>().map_err(|_| PackError::Damaged(format!("header field {i} is {:?}", fields[i])))
    };
    let (decimals, columns, frames, head_bytes, final_newline) = (num(2)?, num(3)?, num(4)?, num(5)?, num(6)?);
    if decimals > MAX_DECIMALS as usize || columns == 0 || frames == 0 || final_newline > 1 {
        return Err(bad("header values out of range"));
    }
    // every packed value takes at least one byte
    if columns.checked_mul(frames).is_none_or(|n| n > rest.len()) {
        return Err(bad("fewer values than the header says"));
    }
    let head = rest.get(..head_bytes).ok_or_else(|| bad("the BVH head is cut short"))?;
    let head = std::str::from_utf8(head).map_err(|_| bad("the BVH head is not UTF-8"))?;
    let body = &rest[head_bytes..];
    let differences =
        if version == "1" { text_columns(body, columns, frames)? } else { varint_columns(body, columns, frames)? };
    let mut values = vec![0i64; columns * frames];
    for (c, column) in differences.chunks(frames).enumerate() {
        let (mut prev, mut step) = (0i64, 0i64);
        for (k, &d) in column.iter().enumerate() {
            let v = match k {
                0 => Some(d),
                1 => prev.checked_add(d),
                _ => step.checked_add(d).and_then(|s| prev.checked_add(s)),
            }
            .ok_or_else(|| bad("values out of range"))?;
            step = if k == 0 { 0 } else { v.checked_sub(prev).ok_or_else(|| bad("values out of range"))? };
            prev = v;
            values[k * columns + c] = v;
        }
    }
    let mut out = String::with_capacity(head.len() + values.len() * 8);
    out.push_str(head);
    for (k, row) in values.chunks(columns).enumerate() {
        if k > 0 {
            out.push('\n');
        }
        for (c, &v) in row.iter().enumerate() {
            if c > 0 {
                out.push(' ');
            }
            out.push_str(&format_fixed(v, decimals as u32));
        }
        if out.len() as u64 > MAX_UNPACKED_BYTES {
            return Err(bad("it unpacks to more than 512 MiB"));
        }
    }
    if final_newline == 1 {
        out.push('\n');
    }
    Ok(out.into_bytes())
}

/// `v` zigzag-mapped and written in LEB128 (see the module's docs).
fn write_varint(out: &mut Vec<u8>, v: i64) {
    let mut z = ((v << 1) ^ (v >> 63)) as u64;
    while z >= 0x80 {
        out.push((z as u8 & 0x7f) | 0x80);
        z >>= 7;
    }
    out.push(z as u8);
}

/// Version 2's body: `columns` × `frames` varints, column after column, and nothing after them.
fn varint_columns(body: &[u8], columns: usize, frames: usize) -> Result<Vec<i64>, PackError> {
    let mut out = Vec::with_capacity(columns * frames);
    let mut at = 0;
    while out.len() < columns * frames {
        let (mut z, mut shift) = (0u64, 0u32);
        loop {
            let &b = body
                .get(at)
                .ok_or_else(|| PackError::Damaged(format!("column {} is cut short", out.len() / frames + 1)))?;
            at += 1;
            if shift > 63 || (shift == 63 && b > 1) {
                return Err(PackError::Damaged(format!("column {}: a number past 64 bits", out.len() / frames + 1)));
            }
            z |= u64::from(b & 0x7f) << shift;
            if b < 0x80 {
                break;
            }
            shift += 7;
        }
        out.push((z >> 1) as i64 ^ -((z & 1) as i64));
    }
    if at != body.len() {
        return Err(PackError::Damaged(format!("{} bytes after the last column", body.len() - at)));
    }
    Ok(out)
}

/// Version 1's body: one line per column of `frames` integers separated by spaces.
fn text_columns(body: &[u8], columns: usize, frames: usize) -> Result<Vec<i64>, PackError> {
    let body = std::str::from_utf8(body).map_err(|_| PackError::Damaged("the columns are not text".into()))?;
    let lines: Vec<&str> = body.strip_suffix('\n').unwrap_or(body).split('\n').collect();
    if lines.len() != columns {
        return Err(PackError::Damaged(format!("{} columns where the header says {columns}", lines.len())));
    }
    let mut out = Vec::with_capacity(columns * frames);
    for (c, line) in lines.iter().enumerate() {
        let before = out.len();
        for token in line.split(' ') {
            if out.len() - before == frames {
                return Err(PackError::Damaged(format!("column {} has more than {frames} values", c + 1)));
            }
            out.push(
                token
                    .parse()
                    .map_err(|_| PackError::Damaged(format!("column {}: {token:?} is not an integer", c + 1)))?,
            );
        }
        if out.len() - before != frames {
            return Err(PackError::Damaged(format!(
                "column {} has {} values where the header says {frames}",
                c + 1,
                out.len() - before
            )));
        }
    }
    Ok(out)
}

/// The file's text through its `Frame Time:` line, and the frame lines after it.
fn split_head(text: &str) -> Option<(&str, &str)> {
    let motion = text.find("MOTION")?;
    let at = motion + text[motion..].find("Frame Time:")?;
    let end = at + text[at..].find('\n')? + 1;
    Some((&text[..end], &text[end..]))
}

/// `token` (at most `decimals` decimals) times 10^decimals, exactly.
fn parse_fixed(token: &str, decimals: u32) -> Option<i64> {
    let (negative, digits) = match token.strip_prefix('-') {
        Some(rest) => (true, rest),
        None => (false, token),
    };
    let (whole, frac) = digits.split_once('.').unwrap_or((digits, ""));
    if whole.is_empty() || !whole.bytes().all(|b| b.is_ascii_digit()) || !frac.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let scale = 10i64.checked_pow(decimals)?;
    let frac_scaled: i64 = if frac.is_empty() {
        0
    } else {
        frac.parse::<i64>().ok()?.checked_mul(10i64.pow(decimals - frac.len() as u32))?
    };
    let v = whole.parse::<i64>().ok()?.checked_mul(scale)?.checked_add(frac_scaled)?;
    Some(if negative { -v } else { v })
}

/// `v / 10^decimals` with trailing zeros dropped, `0` for zero.
fn format_fixed(v: i64, decimals: u32) -> String {
    let scale = 10u64.pow(decimals);
    let a = v.unsigned_abs();
    let (whole, frac) = (a / scale, a % scale);
    let sign = if v < 0 { "-" } else { "" };
    if frac == 0 {
        return format!("{sign}{whole}");
    }
    let frac = format!("{frac:0width$}", width = decimals as usize);
    format!("{sign}{whole}.{}", frac.trim_end_matches('0'))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 3 Xposition Yposition Zposition\n\tEnd Site\n\t{\n\t\tOFFSET 0 1 0\n\t}\n}\nMOTION\nFrames: 4\nFrame Time: 0.0083333\n0 1.5 -2.25\n0.001 1.5 -2.3\n-0.5 12 0\n3 -0.125 7.007\n";

    #[test]
    fn a_pack_is_named_after_the_file_it_holds() {
        assert_eq!(unpacked_name("sample.bvh.pack"), Some("sample.bvh"));
        assert_eq!(unpacked_name("sample.bvh"), None);
        assert_eq!(unpacked_name(".pack"), None);
    }

    #[test]
    fn a_small_file_comes_back_byte_for_byte() {
        let packed = pack(SMALL).unwrap();
        assert_eq!(String::from_utf8(unpack(&packed).unwrap()).unwrap(), SMALL);
        // without the final newline too
        let cut = SMALL.trim_end_matches('\n');
        assert_eq!(unpack(&pack(cut).unwrap()).unwrap(), cut.as_bytes());
    }

    #[test]
    fn the_shipped_sample_pack_is_the_sample_and_about_half_its_gzipped_size() {
        let sample = include_str!("../../www/sample.bvh");
        let shipped = include_bytes!("../../www/sample.bvh.pack");
        assert!(
            unpack(shipped).unwrap() == sample.as_bytes(),
            "www/sample.bvh.pack is not www/sample.bvh: run `cargo run --example pack_bvh -- www/sample.bvh`"
        );
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
        gz.write_all(sample.as_bytes()).unwrap();
        let gzipped = gz.finish().unwrap().len();
        assert!(shipped.len() * 10 < gzipped * 6, "pack {} bytes, gzip -9 {gzipped}", shipped.len());
    }

    #[test]
    fn values_not_written_back_the_same_way_are_refused() {
        for (from, to) in [
            ("1.5 -2.25\n0.001", "1.50 -2.25\n0.001"),
            ("-0.5 12", "-0.5  12"),
            ("3 -0.125", "+3 -0.125"),
            ("-0.5 12 0", "-0.5 12 -0"),
        ] {
            let text = SMALL.replace(from, to);
            assert_ne!(text, SMALL);
            assert!(matches!(pack(&text), Err(PackError::NotPackable(_))), "{to:?}");
        }
        assert!(matches!(pack(&SMALL.replace('\n', "\r\n")), Err(PackError::NotPackable(_))));
        assert!(matches!(pack(&SMALL.replace("0 1.5 -2.25\n", "0 1.5\n")), Err(PackError::NotPackable(_))));
        assert!(matches!(pack("HIERARCHY\n"), Err(PackError::NotPackable(_))));
    }

    fn regz(bytes: &[u8]) -> Vec<u8> {
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(bytes).unwrap();
        gz.finish().unwrap()
    }

    #[test]
    fn damaged_packs_are_refused_with_a_message_never_a_panic() {
        let packed = pack(SMALL).unwrap();
        assert!(matches!(unpack(b"HIERARCHY"), Err(PackError::Damaged(_))));
        assert!(matches!(unpack(&packed[..packed.len() / 2]), Err(PackError::Damaged(_))));
        let raw = gunzip(&packed);
        let line_end = raw.iter().position(|&b| b == b'\n').unwrap();
        let header = String::from_utf8(raw[..line_end].to_vec()).unwrap();
        assert_eq!(header, format!("mocapseg-bvh-pack 2 3 3 4 {} 1", split_head(SMALL).unwrap().0.len()));
        let rest = &raw[line_end..];
        let with_header = |h: String| [h.as_bytes(), rest].concat();
        let body_at = raw.len() - 12; // 3 columns × 4 frames, one byte each here
        let mut damaged: Vec<Vec<u8>> = vec![
            with_header(header.replacen(" 2 ", " 3 ", 1)),
            with_header(header.replacen(" 4 ", " 5 ", 1)),
            with_header(header.replacen(" 3 4 ", " 2 4 ", 1)),
            with_header("mocapseg-bvh-pack 2 3 3 99999999999 1 1".to_string()),
            raw[..raw.len() - 1].to_vec(),
            [&raw[..], &[0u8][..]].concat(),
        ];
        // a number past 64 bits, and one that overflows when the differences are summed
        let mut long = raw[..body_at].to_vec();
        long.extend([0xff; 10]);
        long.extend(&raw[body_at + 1..]);
        damaged.push(long);
        let mut huge = raw[..body_at].to_vec();
        for _ in 0..2 {
            huge.extend([0xfe, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x01]);
        }
        huge.extend(&raw[body_at + 2..]);
        damaged.push(huge);
        for d in damaged {
            assert!(matches!(unpack(&regz(&d)), Err(PackError::Damaged(_))), "{:?}", String::from_utf8_lossy(&d));
        }
    }

    /// A version 1 pack (the integers as text) still unpacks, and refuses a word among its integers.
    #[test]
    fn a_version_1_pack_is_still_read() {
        let head = split_head(SMALL).unwrap().0;
        // SMALL's columns in second differences, at 3 decimals
        let columns = "0 1 -502 4001\n1500 0 10500 -22625\n-2250 -50 2350 4707\n";
        let v1 = format!("mocapseg-bvh-pack 1 3 3 4 {} 1\n{head}{columns}", head.len());
        assert_eq!(unpack(&regz(v1.as_bytes())).unwrap(), SMALL.as_bytes());
        let word = v1.replacen("\n0 1 ", "\n0 x ", 1);
        assert!(matches!(unpack(&regz(word.as_bytes())), Err(PackError::Damaged(_))));
    }

    fn gunzip(bytes: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        flate2::read::GzDecoder::new(bytes).read_to_end(&mut out).unwrap();
        out
    }
}
