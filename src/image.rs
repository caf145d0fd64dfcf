//! The motion image of DT-FCN (Cheema et al. 2019, section 2 "Our Approach", after Laraba et
//! al. 2017): "each column of the image represents a frame in the motion sequence. The rows
//! represent the joints and the RGB values are the scaled XYZ Euclidean coordinates of each
//! corresponding joint".
//!
//! Here: one column per frame, one row per joint (every node that is not an End Site, in file
//! order), R, G, B = the joint's X, Y, Z relative to the root (first node) of the same frame,
//! in file axes. Each axis is scaled linearly from its minimum over the whole take (all rows,
//! all frames) to 0 and its maximum to 255, rounding to nearest; an axis that is constant over
//! the take is 128. Alpha is 255. Pixels are row-major RGBA, ready for a canvas `ImageData`;
//! [`MotionImage::try_to_png`] encodes them with the `png` crate.

use crate::motion::Motion;

/// Value of an axis that does not vary over the take.
pub const CONSTANT_AXIS_VALUE: u8 = 128;

/// Why an image could not be encoded.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("image has no pixels ({width} × {height})")]
    Empty { width: usize, height: usize },
    #[error("image is {width} × {height} but has {len} RGBA bytes (expected {expected})")]
    SizeMismatch { width: usize, height: usize, len: usize, expected: usize },
    #[error("image too large for PNG: {width} × {height}")]
    TooLarge { width: usize, height: usize },
    #[error("PNG encoding failed: {0}")]
    Png(#[from] png::EncodingError),
}

/// An RGBA motion image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MotionImage {
    /// Number of columns = number of frames.
    pub width: usize,
    /// Number of rows = number of joints (End Sites excluded).
    pub height: usize,
    /// Row-major RGBA, `width × height × 4` bytes.
    pub rgba: Vec<u8>,
    /// Joint name of each row.
    pub rows: Vec<String>,
}

/// Per-axis (min, max) of a set of points.
fn axis_ranges(points: impl Iterator<Item = [f32; 3]>) -> [(f32, f32); 3] {
    let mut r = [(f32::INFINITY, f32::NEG_INFINITY); 3];
    for p in points {
        for a in 0..3 {
            r[a].0 = r[a].0.min(p[a]);
            r[a].1 = r[a].1.max(p[a]);
        }
    }
    r
}

/// `v` mapped linearly from `lo..=hi` to `0..=255` (128 for a constant axis).
pub fn scale_to_byte(v: f32, lo: f32, hi: f32) -> u8 {
    let span = hi as f64 - lo as f64;
    if span.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return CONSTANT_AXIS_VALUE;
    }
    let t = ((v as f64 - lo as f64) / span).clamp(0.0, 1.0);
    (t * 255.0).round() as u8
}

impl MotionImage {
    /// The motion image of a take (see the module documentation).
    pub fn from_motion(motion: &Motion) -> MotionImage {
        let rows_idx = motion.skeleton.joint_indices();
        let root = motion.root();
        let frames = motion.frames();
        let rel = |f: usize, j: usize| (motion.position(f, j) - motion.position(f, root)).to_array();
        let ranges = axis_ranges((0..frames).flat_map(|f| rows_idx.iter().map(move |&j| rel(f, j))));
        let (width, height) = (frames, rows_idx.len());
        let mut rgba = vec![0u8; width * height * 4];
        for (row, &j) in rows_idx.iter().enumerate() {
            for f in 0..frames {
                let p = rel(f, j);
                let px = &mut rgba[(row * width + f) * 4..(row * width + f + 1) * 4];
                for a in 0..3 {
                    px[a] = scale_to_byte(p[a], ranges[a].0, ranges[a].1);
                }
                px[3] = 255;
            }
        }
        let rows = rows_idx.iter().map(|&j| motion.skeleton.names[j].clone()).collect();
        MotionImage { width, height, rgba, rows }
    }

    /// The RGBA bytes of the pixel at column `x` (frame), row `y` (joint).
    pub fn pixel(&self, x: usize, y: usize) -> [u8; 4] {
        let i = (y * self.width + x) * 4;
        [self.rgba[i], self.rgba[i + 1], self.rgba[i + 2], self.rgba[i + 3]]
    }

    /// PNG encoding (8-bit RGBA), or why it cannot be encoded: no pixels, more columns or rows
    /// than PNG allows (2^31 − 1), RGBA bytes that do not match the size, or an encoder error.
    pub fn try_to_png(&self) -> Result<Vec<u8>, ImageError> {
        rgba_png(self.width, self.height, &self.rgba)
    }
}

/// PNG encoding (8-bit RGBA) of `width × height` pixels, row-major, or why they cannot be
/// encoded: no pixels, more columns or rows than PNG allows (2^31 − 1), bytes that do not match
/// the size, or an encoder error. The motion image and every method's pictures use it.
pub fn rgba_png(width: usize, height: usize, rgba: &[u8]) -> Result<Vec<u8>, ImageError> {
    if width == 0 || height == 0 {
        return Err(ImageError::Empty { width, height });
    }
    let (w, h) = match (u32::try_from(width), u32::try_from(height)) {
        (Ok(w), Ok(h)) if w <= i32::MAX as u32 && h <= i32::MAX as u32 => (w, h),
        _ => return Err(ImageError::TooLarge { width, height }),
    };
    let expected = width.checked_mul(height).and_then(|n| n.checked_mul(4));
    if expected != Some(rgba.len()) {
        let Some(expected) = expected else { return Err(ImageError::TooLarge { width, height }) };
        return Err(ImageError::SizeMismatch { width, height, len: rgba.len(), expected });
    }
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, w, h);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header()?;
    writer.write_image_data(rgba)?;
    writer.finish()?;
    Ok(out)
}
