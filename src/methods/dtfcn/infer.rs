//! Labelling a take with a trained network: the motion image standardised, the network run over
//! it in blocks (each with the receptive field's half of real frames on either side, so the
//! result is the whole take's result while memory stays bounded on long takes), and each frame's
//! most probable class with its softmax probability as the confidence. A model of several networks (an
//! ensemble, [`super::training::TrainOptions::members`]) gives the mean of their probabilities.

use burn::tensor::Tensor;

use super::network::DtFcn;
use crate::labeller::input::{NetworkInput, Standardise, CHANNELS};
use crate::labeller::probabilities::Probabilities;

/// Output frames computed per block (plus context on either side).
pub const BLOCK_FRAMES: usize = 2048;

/// Class probabilities of every frame of `input` (see the module docs). `classes` is the
/// network's class count.
pub fn predict_input(net: &DtFcn, standardise: &Standardise, input: &NetworkInput, classes: usize) -> Probabilities {
    run_blocks(net, standardise, input, classes, BLOCK_FRAMES, None, &mut |_| true)
        .unwrap_or_else(|| unreachable(input))
}

/// What a run that never stops cannot give back.
fn unreachable(input: &NetworkInput) -> Probabilities {
    Probabilities { frames: input.frames, classes: 0, values: Vec::new() }
}

/// The mean of the class probabilities of the networks `nets` (an ensemble of the same shape; one network: its
/// own), each run over blocks of `block` frames, reporting the share done after each block of each network; `None`
/// as soon as `done` answers false (the run is cancelled: no block after it is computed).
pub fn predict_members(
    nets: &[DtFcn],
    standardise: &Standardise,
    input: &NetworkInput,
    classes: usize,
    block: usize,
    done: &mut dyn FnMut(f64) -> bool,
) -> Option<Probabilities> {
    let k = nets.len().max(1) as f64;
    let each = nets
        .iter()
        .enumerate()
        .map(|(m, net)| run_blocks(net, standardise, input, classes, block, None, &mut |f| done((m as f64 + f) / k)))
        .collect::<Option<Vec<Probabilities>>>()?;
    Some(Probabilities::mean(&each.iter().collect::<Vec<_>>()).unwrap_or_else(|| Probabilities {
        frames: input.frames,
        classes,
        values: vec![0.0; input.frames * classes],
    }))
}

/// [`predict_input`] and the features of every frame ([`DtFcn::features`], frame-major: `frames ×
/// features`), as [`super::novelty`] reads them.
pub fn predict_with_features(
    net: &DtFcn,
    standardise: &Standardise,
    input: &NetworkInput,
    classes: usize,
) -> (Probabilities, Vec<f32>) {
    let mut features = Vec::new();
    let p = run_blocks(net, standardise, input, classes, BLOCK_FRAMES, Some(&mut features), &mut |_| true)
        .unwrap_or_else(|| unreachable(input));
    (p, features)
}

fn run_blocks(
    net: &DtFcn,
    standardise: &Standardise,
    input: &NetworkInput,
    classes: usize,
    block: usize,
    mut features: Option<&mut Vec<f32>>,
    done: &mut dyn FnMut(f64) -> bool,
) -> Option<Probabilities> {
    let n = input.frames;
    let z = standardise.apply(input);
    let device = super::device();
    let margin = receptive_half(net);
    let mut values = vec![0f32; n * classes];
    let block = block.max(1);
    let mut start = 0;
    while start < n {
        let end = (start + block).min(n);
        let (lo, hi) = (start.saturating_sub(margin), (end + margin).min(n));
        let m = hi - lo;
        let mut x = Vec::with_capacity(CHANNELS * m);
        for c in 0..CHANNELS {
            x.extend_from_slice(&z[c * n + lo..c * n + hi]);
        }
        let x = Tensor::<1>::from_floats(x.as_slice(), &device).reshape([1, CHANNELS, m]);
        let f = net.features(x);
        if let Some(out) = features.as_deref_mut() {
            let [_, width, _] = f.dims();
            let values: Vec<f32> = f.clone().into_data().try_to_vec::<f32>().unwrap_or_default();
            // values is [1, width, m]: frame-major rows for the frames of this block
            for t in start..end {
                out.extend((0..width).map(|k| values.get(k * m + (t - lo)).copied().unwrap_or(0.0)));
            }
        }
        let p: Vec<f32> =
            burn::tensor::activation::softmax(net.logits_of(f), 1).into_data().try_to_vec::<f32>().unwrap_or_default();
        // p is [1, classes, m]
        for f in start..end {
            for c in 0..classes {
                values[f * classes + c] = p.get(c * m + (f - lo)).copied().unwrap_or(0.0);
            }
        }
        if !done(end as f64 / n as f64) {
            return None;
        }
        start = end;
    }
    Some(Probabilities { frames: n, classes, values })
}

/// Bytes one block of inference holds at its peak, whatever the take's length: the block's frames and their
/// context on either side ([`receptive_half`]) times the widest layer's columns (`kernel × inputs`, the shifted copies
/// a dilated convolution concatenates), its input and its output, as f32 — twice over (the counting allocator of
/// `tests/limits.rs` measures about once over on the shipped networks and on a wide network with a 2.4 k-frame
/// receptive field, whose block it fills).
pub fn block_bytes(net: &DtFcn) -> usize {
    let frames = BLOCK_FRAMES + 2 * receptive_half(net);
    let widest = net
        .layers
        .iter()
        .chain(std::iter::once(&net.classifier))
        .map(|l| {
            let [outputs, inputs, kernel] = l.weight.dims();
            kernel * inputs + inputs + outputs
        })
        .max()
        .unwrap_or(0);
    2 * 4 * frames * widest
}

/// Half the receptive field of `net`: frames of context one output frame needs on each side.
pub fn receptive_half(net: &DtFcn) -> usize {
    net.layers.iter().map(|l| l.dilation * (l.kernel_size - 1)).sum::<usize>().div_ceil(2)
}
