//! The class probabilities of every working frame of a take: what a labeller gives (the network's softmax, the
//! k-NN's vote shares) and what the decoding ([`super::decode`]), the unknown threshold and the class-probability
//! picture read.

/// Class probabilities of every working frame, frame-major (`frames × classes`).
#[derive(Debug, Clone, PartialEq)]
pub struct Probabilities {
    pub frames: usize,
    pub classes: usize,
    pub values: Vec<f32>,
}

impl Probabilities {
    /// Probability of class `c` at frame `f`.
    pub fn prob(&self, f: usize, c: usize) -> f32 {
        self.values[f * self.classes + c]
    }

    /// The mean of several labellings of the same frames (an ensemble's), or `None` when there are none or
    /// their shapes differ.
    pub fn mean(all: &[&Probabilities]) -> Option<Probabilities> {
        let first = all.first()?;
        if all
            .iter()
            .any(|p| (p.frames, p.classes, p.values.len()) != (first.frames, first.classes, first.values.len()))
        {
            return None;
        }
        let k = all.len() as f32;
        let values = (0..first.values.len()).map(|i| all.iter().map(|p| p.values[i]).sum::<f32>() / k).collect();
        Some(Probabilities { frames: first.frames, classes: first.classes, values })
    }

    /// The most probable class of frame `f` and its probability.
    pub fn best(&self, f: usize) -> (usize, f32) {
        let row = &self.values[f * self.classes..(f + 1) * self.classes];
        row.iter().enumerate().fold((0, f32::NEG_INFINITY), |b, (c, &p)| if p > b.1 { (c, p) } else { b })
    }
}
