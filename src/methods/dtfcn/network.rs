//! The dilated temporal fully-convolutional network (Cheema et al. 2019, §2 and Fig. 1), in burn.
//!
//! * Layer 1: a convolution whose kernel is as tall as the motion image (every joint, every
//!   channel) and `w` frames wide, so it convolves in time only. A 2-D convolution with kernel
//!   height = image height over 3 colour channels is exactly a 1-D convolution over
//!   `3 × joints` input channels; that is how it is written here (same weights, same count).
//! * Layers 2–5: 1-D temporal acausal convolutions of the same width `w`, stride 1, dilation
//!   `d = w^(l−1)` (l = 1…5: 1, 3, 9, 27, 81 for w = 3), padded so every layer keeps the
//!   take's length (fully convolutional: any length).
//! * ReLU after every layer; [`norm_relu`] normalises the last one's output, and a 1×1
//!   convolution gives each frame its class scores, turned into probabilities by the softmax.
//! * Filters double from 64 to 512 ([`DtFcnConfig::filters`]).
//!
//! Receptive field: `1 + (w − 1) · Σ d = 1 + (w − 1)(w⁵ − 1)/(w − 1) = w⁵` frames (243 for w = 3).

use burn::module::{Module, ModuleMapper, Param, ParamId};
use burn::nn::conv::Conv1dConfig;
use burn::tensor::activation::{relu, softmax};
use burn::tensor::ops::PadMode;
use burn::tensor::{Device, Tensor};
use serde::{Deserialize, Serialize};

use super::normrelu::norm_relu;
use crate::stats::Rng;

/// The shape of a network: what a model file must agree with before its weights are read.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct DtFcnConfig {
    /// Input channels: 3 × the joints of the motion image.
    pub channels: usize,
    /// Output classes.
    pub classes: usize,
    /// Kernel width `w` of every layer.
    pub width: usize,
    /// Filters of layers 1…L (the paper: 64 doubling to 512).
    pub filters: Vec<usize>,
    /// What each layer reads beyond the take's ends (older model files: zeros).
    #[serde(default)]
    pub padding: Padding,
    /// The paper's input: the motion image resized (linearly, along its rows) to this many rows
    /// before layer 1 — 224 gives the paper's 663,562 parameters. None: the image as it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image_rows: Option<usize>,
}

/// What a temporal convolution reads before the first and after the last frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Padding {
    /// Zeros (Keras' `same`, the paper's): a wide receptive field can tell where the take starts
    /// and learn "start of take → the first exercise".
    #[default]
    Zero,
    /// The first and last frame repeated: the take's ends look like a held pose.
    Edge,
}

impl Padding {
    pub fn parse(text: &str) -> Result<Padding, String> {
        match text {
            "zero" => Ok(Padding::Zero),
            "edge" => Ok(Padding::Edge),
            other => Err(format!("padding `{other}`: expected zero or edge")),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Padding::Zero => "zero",
            Padding::Edge => "edge",
        }
    }
}

/// Filters of an `layers`-layer network in the paper's pattern: doubling from 64 to 512, the first
/// repeated (5 layers: 64, 64, 128, 256, 512).
pub fn paper_filters(layers: usize) -> Vec<usize> {
    let tail = [64, 128, 256, 512];
    let n = layers.max(1);
    let mut f: Vec<usize> = tail[tail.len().saturating_sub(n)..].to_vec();
    while f.len() < n {
        f.insert(0, 64);
    }
    f
}

impl DtFcnConfig {
    /// The network's shape in one line: kernel width, layers, receptive field in frames and seconds at
    /// `fps`, padding, what layer 1 reads, and its parameters beside the paper's (663,562: five layers
    /// reading 224 rows, ten classes).
    pub fn describe(&self, fps: f64) -> String {
        let ten = DtFcnConfig { classes: 10, ..self.clone() }.parameter_count();
        format!(
            "network: w = {}, {} layers ({}), receptive field {} frames = {:.2} s at {fps} Hz, {} padding, layer 1 reads {} values per frame{}; {} parameters ({ten} with the paper's 10 classes; the paper's network: 663562, reading 224 rows)",
            self.width,
            self.filters.len(),
            self.filters.iter().map(|f| f.to_string()).collect::<Vec<_>>().join(","),
            self.receptive_field(),
            self.receptive_field_s(fps),
            self.padding.name(),
            self.first_layer_inputs(),
            self.image_rows.map(|r| format!(" (the image resized to {r} rows)")).unwrap_or_default(),
            self.parameter_count(),
        )
    }

    /// The paper's network (w = 3, five layers) for `channels` inputs and `classes` classes.
    pub fn paper(channels: usize, classes: usize) -> DtFcnConfig {
        DtFcnConfig { channels, classes, width: 3, filters: paper_filters(5), padding: Padding::Zero, image_rows: None }
    }

    /// Seconds of input one output frame depends on, at `fps`.
    pub fn receptive_field_s(&self, fps: f64) -> f64 {
        self.receptive_field() as f64 / fps
    }

    /// Dilation of layer `l` (0-based): `w^l`.
    pub fn dilation(&self, l: usize) -> usize {
        self.width.pow(l as u32)
    }

    /// Frames of input one output frame depends on.
    pub fn receptive_field(&self) -> usize {
        1 + (self.width - 1) * (0..self.filters.len()).map(|l| self.dilation(l)).sum::<usize>()
    }

    /// Weights and biases of the whole network.
    pub fn parameter_count(&self) -> usize {
        let mut n = 0;
        let mut inputs = self.first_layer_inputs();
        for &f in &self.filters {
            n += inputs * self.width * f + f;
            inputs = f;
        }
        n + inputs * self.classes + self.classes
    }

    /// Values per frame layer 1 reads: the channels, or 3 × the resized image's rows.
    pub fn first_layer_inputs(&self) -> usize {
        self.image_rows.map_or(self.channels, |r| 3 * r)
    }

    /// Refuses shapes the network cannot have (and absurd sizes, before anything is allocated).
    pub fn check(&self) -> Result<(), String> {
        if self.classes < 2 || self.classes > 1000 {
            return Err(format!("{} classes: a labelling network needs 2 to 1000", self.classes));
        }
        if !(2..=7).contains(&self.width) {
            return Err(format!("kernel width {}: expected 2 to 7", self.width));
        }
        if self.filters.is_empty() || self.filters.len() > 6 {
            return Err(format!("{} layers: expected 1 to 6", self.filters.len()));
        }
        if self.filters.iter().any(|&f| f == 0 || f > 2048) {
            return Err(format!("filters {:?}: each layer needs 1 to 2048", self.filters));
        }
        if self.channels == 0 || self.channels > 3 * 128 || self.channels % 3 != 0 {
            return Err(format!("{} input channels: expected 3 × 1 to 128 joints", self.channels));
        }
        if let Some(r) = self.image_rows {
            if !(2..=512).contains(&r) {
                return Err(format!("image rows {r}: expected 2 to 512"));
            }
        }
        Ok(())
    }

    /// A network with fresh (random) weights on `device`.
    pub fn init(&self, device: &Device) -> DtFcn {
        let mut layers = Vec::with_capacity(self.filters.len());
        let mut inputs = self.first_layer_inputs();
        for (l, &f) in self.filters.iter().enumerate() {
            layers.push(TemporalConv::new(inputs, f, self.width, self.dilation(l), device).padded(self.padding));
            inputs = f;
        }
        let classifier = TemporalConv::new(inputs, self.classes, 1, 1, device);
        DtFcn { layers, classifier, rows_in: self.channels / 3, rows_out: self.image_rows.unwrap_or(0) }
    }

    /// [`DtFcnConfig::init`] with every weight and bias drawn from `seed` (uniform in
    /// ±1/√fan-in, PyTorch's and burn's default for convolutions) and parameter ids numbered in
    /// order: the same seed gives the same network, byte for byte, whatever else runs.
    pub fn init_seeded(&self, device: &Device, seed: u64) -> DtFcn {
        self.init(device).map(&mut SeededInit { rng: Rng::new(seed), fan_in: 1, next_id: 1 })
    }
}

/// Re-draws every parameter from a seeded generator (see [`DtFcnConfig::init_seeded`]).
struct SeededInit {
    rng: Rng,
    /// Fan-in of the last weight seen (a bias follows its weight).
    fan_in: usize,
    next_id: u64,
}

impl ModuleMapper for SeededInit {
    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        let (_, tensor, mapper) = param.consume();
        let shape = tensor.dims();
        if D == 3 {
            self.fan_in = shape[1] * shape[2];
        }
        let bound = 1.0 / (self.fan_in.max(1) as f32).sqrt();
        let n: usize = shape.iter().product();
        let values: Vec<f32> = (0..n).map(|_| (2.0 * self.rng.next_f32() - 1.0) * bound).collect();
        let fresh = Tensor::<1>::from_floats(values.as_slice(), &tensor.device())
            .reshape(shape)
            .set_require_grad(tensor.is_require_grad());
        let id = ParamId::from(self.next_id);
        self.next_id += 1;
        Param::from_mapped_value(id, fresh, mapper)
    }
}

/// One temporal convolution: `out × in × kernel` weights, dilation `d`, padding that keeps the
/// length (`d·(kernel − 1)` frames, ⌊half⌋ before and ⌈half⌉ after: acausal) — zeros, or with
/// `edge` the first and last frame repeated.
///
/// Computed as one matrix product (im2col): the `kernel` shifted copies of the input stacked as
/// `kernel × in` rows, times the weights as an `out × (kernel · in)` matrix. burn's ndarray
/// `conv1d` was measured at 50 s per training epoch of the exercises set on this machine (a
/// direct multiply-add loop, one core); the same layer as a product runs on the backend's GEMM.
#[derive(Module, Debug)]
pub struct TemporalConv {
    /// `[out, in, kernel]`, as burn's `Conv1d` holds it.
    pub weight: Param<Tensor<3>>,
    /// `[out]`.
    pub bias: Param<Tensor<1>>,
    pub kernel_size: usize,
    pub dilation: usize,
    /// Pads by repeating the end frames instead of zeros (from the network's shape, not stored
    /// with the weights).
    pub edge: bool,
}

impl TemporalConv {
    fn new(inputs: usize, outputs: usize, kernel: usize, dilation: usize, device: &Device) -> TemporalConv {
        // burn's Conv1d initialisation (uniform ±1/√fan-in for weights and bias)
        let conv = Conv1dConfig::new(inputs, outputs, kernel).init(device);
        let bias = conv.bias.unwrap_or_else(|| Param::from_tensor(Tensor::zeros([outputs], device)));
        TemporalConv { weight: conv.weight, bias, kernel_size: kernel, dilation, edge: false }
    }

    fn padded(self, padding: Padding) -> TemporalConv {
        TemporalConv { edge: padding == Padding::Edge, ..self }
    }

    /// `[batch, in, frames]` → `[batch, out, frames]`.
    pub fn forward(&self, x: Tensor<3>) -> Tensor<3> {
        let [_, c, t] = x.dims();
        let [out, _, k] = self.weight.dims();
        let cols = if k == 1 {
            x
        } else {
            let pad = self.dilation * (k - 1);
            let (left, right) = (pad / 2, pad - pad / 2);
            let mode = if self.edge { PadMode::Edge } else { PadMode::Constant(0.0) };
            let padded = x.pad([(left, right)], mode);
            let shifted: Vec<Tensor<3>> = (0..k).map(|i| padded.clone().narrow(2, i * self.dilation, t)).collect();
            Tensor::cat(shifted, 1) // [b, k·c, t], row i·c + channel
        };
        let w = self.weight.val().swap_dims(1, 2).reshape([1, out, k * c]);
        w.matmul(cols).add(self.bias.val().reshape([1, out, 1]))
    }
}

/// The network (see the module docs).
#[derive(Module, Debug)]
pub struct DtFcn {
    /// Layer 1 (the full-height kernel) and the dilated layers.
    pub layers: Vec<TemporalConv>,
    /// The 1×1 convolution from the last layer's features to class scores.
    pub classifier: TemporalConv,
    /// Rows of the motion image given.
    pub rows_in: usize,
    /// Rows it is resized to before layer 1 (0: not resized).
    pub rows_out: usize,
}

/// The `out × in` matrix that resizes a column of `rows_in` values to `rows_out` by linear
/// interpolation (pixel centres aligned, as an image resize does: output row `i` samples input
/// position `(i + ½)·in/out − ½`, clamped to the ends).
pub fn resize_matrix(rows_in: usize, rows_out: usize) -> Vec<f32> {
    let mut m = vec![0f32; rows_out * rows_in];
    for i in 0..rows_out {
        let x = ((i as f64 + 0.5) * rows_in as f64 / rows_out as f64 - 0.5).clamp(0.0, (rows_in - 1) as f64);
        let lo = x.floor() as usize;
        let hi = (lo + 1).min(rows_in - 1);
        let f = (x - lo as f64) as f32;
        m[i * rows_in + lo] += 1.0 - f;
        m[i * rows_in + hi] += f;
    }
    m
}

impl DtFcn {
    /// Class scores before the softmax: `[batch, channels, frames]` → `[batch, classes, frames]`.
    pub fn logits(&self, input: Tensor<3>) -> Tensor<3> {
        self.logits_of(self.features(input))
    }

    /// The last layer's activations after its ReLU, before NormReLU (what
    /// [`super::novelty`] measures): `[batch, channels, frames]` → `[batch, filters, frames]`.
    pub fn features(&self, input: Tensor<3>) -> Tensor<3> {
        let mut x = self.resized(input);
        for layer in &self.layers {
            x = relu(layer.forward(x));
        }
        x
    }

    /// Class scores from [`DtFcn::features`].
    pub fn logits_of(&self, features: Tensor<3>) -> Tensor<3> {
        self.classifier.forward(norm_relu(features))
    }

    /// The motion image resized to [`DtFcnConfig::image_rows`] rows (each of X, Y, Z on its own):
    /// `[batch, 3·rows_in, frames]` → `[batch, 3·rows_out, frames]`.
    fn resized(&self, input: Tensor<3>) -> Tensor<3> {
        if self.rows_out == 0 {
            return input;
        }
        let (n, m) = (self.rows_in, self.rows_out);
        let block = resize_matrix(n, m);
        let mut full = vec![0f32; 3 * m * 3 * n];
        for axis in 0..3 {
            for i in 0..m {
                for j in 0..n {
                    full[(axis * m + i) * 3 * n + axis * n + j] = block[i * n + j];
                }
            }
        }
        let device = input.device();
        let r = Tensor::<1>::from_floats(full.as_slice(), &device).reshape([1, 3 * m, 3 * n]);
        r.matmul(input)
    }

    /// Per-frame class probabilities, `[batch, classes, frames]`.
    pub fn forward(&self, input: Tensor<3>) -> Tensor<3> {
        softmax(self.logits(input), 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_network_sees_243_frames_and_counts_its_parameters() {
        let c = DtFcnConfig::paper(51, 10);
        assert_eq!(c.receptive_field(), 243);
        assert_eq!(DtFcnConfig { width: 5, ..c.clone() }.receptive_field(), 3125);
        // 51·3·64+64 + 64·3·64+64 + 64·3·128+128 + 128·3·256+256 + 256·3·512+512 + 512·10+10
        assert_eq!(c.parameter_count(), 9856 + 12352 + 24704 + 98560 + 393728 + 5130);
        let net = c.init(&crate::methods::dtfcn::device());
        assert_eq!(net.num_params(), c.parameter_count());
    }

    /// The paper's 663,562 parameters: its layout (w = 3, 64–512 filters, 10 classes) reading the
    /// motion image resized to 224 rows — the whole difference from 54 channels is in layer 1.
    #[test]
    fn the_paper_input_of_224_rows_gives_the_papers_663562_parameters() {
        let ours = DtFcnConfig::paper(3 * 17, 10);
        let paper = DtFcnConfig { image_rows: Some(224), ..ours.clone() };
        assert_eq!(paper.parameter_count(), 663_562);
        assert_eq!(paper.parameter_count() - ours.parameter_count(), (672 - 51) * 3 * 64);
        let c = DtFcnConfig { image_rows: Some(224), ..DtFcnConfig::paper(54, 10) };
        assert_eq!(c.parameter_count(), 663_562);
        let device = crate::methods::dtfcn::device();
        let net = c.init(&device);
        assert_eq!(net.num_params(), 663_562);
        let p = net.forward(Tensor::<3>::ones([1, 54, 20], &device));
        assert_eq!(p.dims(), [1, 10, 20]);
    }

    #[test]
    fn resizing_keeps_constant_columns_and_interpolates_between_rows() {
        // every output row's weights sum to 1: a constant column stays constant
        for (n, m) in [(18, 224), (17, 224), (5, 3), (4, 4)] {
            let r = resize_matrix(n, m);
            for i in 0..m {
                let s: f32 = r[i * n..(i + 1) * n].iter().sum();
                assert!((s - 1.0).abs() < 1e-6, "{n}→{m} row {i}: {s}");
            }
        }
        // the same size is the identity; doubling puts rows ¼ and ¾ of the way between
        let same = resize_matrix(4, 4);
        assert!((0..4).all(|i| same[i * 4 + i] == 1.0));
        let up = resize_matrix(2, 4);
        assert_eq!(&up[..], &[1.0, 0.0, 0.75, 0.25, 0.25, 0.75, 0.0, 1.0]);
        // in the network: X, Y and Z resized on their own
        let device = crate::methods::dtfcn::device();
        let c = DtFcnConfig { image_rows: Some(4), ..DtFcnConfig::paper(6, 2) };
        let net = c.init(&device);
        let x = Tensor::<1>::from_floats([1.0, 3.0, 10.0, 30.0, 100.0, 300.0].as_slice(), &device).reshape([1, 6, 1]);
        let got: Vec<f32> = net.resized(x).into_data().try_to_vec::<f32>().unwrap();
        assert_eq!(got, vec![1.0, 1.5, 2.5, 3.0, 10.0, 15.0, 25.0, 30.0, 100.0, 150.0, 250.0, 300.0]);
    }

    #[test]
    fn any_length_in_the_same_length_out_and_probabilities_sum_to_one() {
        let device = crate::methods::dtfcn::device();
        let c = DtFcnConfig { channels: 6, classes: 3, width: 3, filters: vec![4, 8, 8], ..DtFcnConfig::paper(6, 3) };
        let net = c.init(&device);
        for frames in [1, 2, 7, 40] {
            let x = Tensor::<3>::ones([2, 6, frames], &device);
            let p = net.forward(x);
            assert_eq!(p.dims(), [2, 3, frames]);
            let sums: Vec<f32> = p.sum_dim(1).into_data().try_to_vec::<f32>().unwrap();
            assert!(sums.iter().all(|s| (s - 1.0).abs() < 1e-5), "{sums:?}");
        }
    }

    #[test]
    fn the_matrix_product_layer_equals_burns_dilated_conv1d() {
        use burn::nn::PaddingConfig1d;
        let device = crate::methods::dtfcn::device();
        let conv =
            Conv1dConfig::new(5, 7, 3).with_dilation(4).with_padding(PaddingConfig1d::Explicit(4, 4)).init(&device);
        let ours = TemporalConv {
            weight: conv.weight.clone(),
            bias: conv.bias.clone().unwrap(),
            kernel_size: 3,
            dilation: 4,
            edge: false,
        };
        let x = Tensor::<3>::random([2, 5, 30], burn::tensor::Distribution::Normal(0.0, 1.0), &device);
        let a: Vec<f32> = conv.forward(x.clone()).into_data().try_to_vec::<f32>().unwrap();
        let b: Vec<f32> = ours.forward(x).into_data().try_to_vec::<f32>().unwrap();
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-4, "{x} vs {y}");
        }
    }

    /// burn's `Conv1d` with the padding the shipped layers use: `d·(k − 1)` zeros, ⌊half⌋ before and
    /// ⌈half⌉ after — asymmetric for kernel 2 at odd dilations (1 frame after, none before).
    fn burns_layer(layer: &TemporalConv, device: &Device) -> burn::nn::conv::Conv1d {
        use burn::nn::PaddingConfig1d;
        let [out, inputs, k] = layer.weight.dims();
        let pad = layer.dilation * (k - 1);
        let mut conv = Conv1dConfig::new(inputs, out, k)
            .with_dilation(layer.dilation)
            .with_padding(PaddingConfig1d::Explicit(pad / 2, pad - pad / 2))
            .init(device);
        conv.weight = layer.weight.clone();
        conv.bias = Some(layer.bias.clone());
        conv
    }

    fn assert_same_output(layer: &TemporalConv, frames: usize, what: &str) {
        let device = crate::methods::dtfcn::device();
        let conv = burns_layer(layer, &device);
        let [_, inputs, _] = layer.weight.dims();
        let x = Tensor::<3>::random([2, inputs, frames], burn::tensor::Distribution::Normal(0.0, 1.0), &device);
        let a: Vec<f32> = conv.forward(x.clone()).into_data().try_to_vec::<f32>().unwrap();
        let b: Vec<f32> = layer.forward(x).into_data().try_to_vec::<f32>().unwrap();
        assert_eq!(a.len(), b.len(), "{what}: one output per frame");
        let scale = a.iter().fold(1f32, |m, v| m.max(v.abs()));
        for (i, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!((x - y).abs() <= 1e-4 * scale, "{what}: value {i}: burn {x}, ours {y}");
        }
    }

    #[test]
    fn kernel_2_layers_with_their_asymmetric_padding_equal_burns_conv1d() {
        let device = crate::methods::dtfcn::device();
        for (k, d) in [(2, 1), (2, 2), (2, 4), (2, 8), (2, 16), (3, 1), (3, 9)] {
            let layer = TemporalConv::new(5, 7, k, d, &device);
            for frames in [1, 2, 17, 64] {
                assert_same_output(&layer, frames, &format!("kernel {k}, dilation {d}, {frames} frames"));
            }
        }
    }

    /// Every layer of every shipped DT-FCN model (its kernel width, its dilations, its trained
    /// weights) computes what burn's own `Conv1d` computes with the same padding.
    #[test]
    fn the_shipped_models_layers_equal_burns_conv1d() {
        use crate::methods::dtfcn::method::DTFCN;
        use crate::methods::dtfcn::model::networks_of;
        for name in crate::labeller::shipped::NAMES {
            let store = crate::method::ModelStore::default();
            let model = crate::labeller::shipped::model(&DTFCN, name, &store, &[&DTFCN]).unwrap();
            let networks = networks_of(&model).unwrap_or_else(|| panic!("{name}: not a network"));
            let (nets, shape) = (&networks.nets, &networks.config);
            assert!(!nets.is_empty(), "{name}: no network");
            for (m, net) in nets.iter().enumerate() {
                assert!(
                    net.layers.iter().all(|l| l.kernel_size == shape.width),
                    "{name}: every layer has the model's w"
                );
                assert!(
                    !net.layers.iter().any(|l| l.edge),
                    "{name}: burn's Conv1d pads with zeros, as these models do"
                );
                for (i, layer) in net.layers.iter().chain([&net.classifier]).enumerate() {
                    assert_same_output(
                        layer,
                        48,
                        &format!(
                            "{name} network {m} layer {i} (kernel {}, dilation {})",
                            layer.kernel_size, layer.dilation
                        ),
                    );
                }
            }
        }
    }

    /// An edge-padded layer on a take equals the zero-padded layer on the take with its first and
    /// last frame repeated by hand, cut back to the take.
    #[test]
    fn edge_padding_repeats_the_end_frames() {
        let device = crate::methods::dtfcn::device();
        for (k, d) in [(2, 1), (2, 8), (3, 9), (3, 27)] {
            let zero = TemporalConv::new(4, 3, k, d, &device);
            let edge = TemporalConv::new(4, 3, k, d, &device).padded(Padding::Edge);
            let edge = TemporalConv { weight: zero.weight.clone(), bias: zero.bias.clone(), ..edge };
            for frames in [1usize, 5, 40] {
                let x = Tensor::<3>::random([1, 4, frames], burn::tensor::Distribution::Normal(0.0, 1.0), &device);
                let values: Vec<f32> = x.clone().into_data().try_to_vec::<f32>().unwrap();
                let pad = d * (k - 1);
                let (left, right) = (pad / 2, pad - pad / 2);
                let long = frames + left + right;
                let mut by_hand = vec![0f32; 4 * long];
                for c in 0..4 {
                    for t in 0..long {
                        let src = t.saturating_sub(left).min(frames - 1);
                        by_hand[c * long + t] = values[c * frames + src];
                    }
                }
                let by_hand = Tensor::<1>::from_floats(by_hand.as_slice(), &device).reshape([1, 4, long]);
                let want: Vec<f32> =
                    zero.forward(by_hand).narrow(2, left, frames).into_data().try_to_vec::<f32>().unwrap();
                let got: Vec<f32> = edge.forward(x.clone()).into_data().try_to_vec::<f32>().unwrap();
                for (i, (a, b)) in want.iter().zip(&got).enumerate() {
                    assert!((a - b).abs() < 1e-4, "kernel {k} dilation {d} {frames} frames, value {i}: {a} vs {b}");
                }
                // and zero padding differs at the ends (the test can fail)
                if frames > 1 {
                    let zeros: Vec<f32> = zero.forward(x).into_data().try_to_vec::<f32>().unwrap();
                    assert!(zeros.iter().zip(&got).any(|(a, b)| (a - b).abs() > 1e-4));
                }
            }
        }
    }

    #[test]
    fn paper_filters_double_from_64_to_512() {
        assert_eq!(paper_filters(5), vec![64, 64, 128, 256, 512]);
        assert_eq!(paper_filters(4), vec![64, 128, 256, 512]);
        assert_eq!(paper_filters(6), vec![64, 64, 64, 128, 256, 512]);
        assert_eq!(paper_filters(2), vec![256, 512]);
    }

    #[test]
    fn an_impulse_changes_exactly_the_receptive_field() {
        let device = crate::methods::dtfcn::device();
        // positive weights: nothing is cut by a ReLU, so every frame the impulse reaches changes
        let c = DtFcnConfig { channels: 2, classes: 2, width: 3, filters: vec![3, 3, 3], ..DtFcnConfig::paper(2, 2) };
        let rfs = c.receptive_field();
        assert_eq!(rfs, 27);
        let net = c.init(&device);
        let net = net.map(&mut PositiveWeights);
        let frames = 80;
        let base = Tensor::<3>::zeros([1, 2, frames], &device);
        let at = 40;
        let mut impulse = vec![0f32; 2 * frames];
        impulse[at] = 1.0;
        let impulse = Tensor::<1>::from_floats(impulse.as_slice(), &device).reshape([1, 2, frames]);
        // logits without the NormReLU's global max (which would spread the change everywhere)
        let features = |x: Tensor<3>| {
            let mut x = x;
            for layer in &net.layers {
                x = relu(layer.forward(x));
            }
            x
        };
        let a: Vec<f32> = features(base).sum_dim(1).into_data().try_to_vec::<f32>().unwrap();
        let b: Vec<f32> = features(impulse).sum_dim(1).into_data().try_to_vec::<f32>().unwrap();
        let changed: Vec<usize> = (0..frames).filter(|&t| (a[t] - b[t]).abs() > 1e-7).collect();
        assert_eq!(changed.len(), rfs, "{changed:?}");
        assert_eq!(changed[0], at - rfs / 2);
        assert_eq!(*changed.last().unwrap(), at + rfs / 2);
    }

    /// Makes every weight positive (|w| + 0.01) and every bias zero.
    struct PositiveWeights;

    impl burn::module::ModuleMapper for PositiveWeights {
        fn map_float<const D: usize>(
            &mut self,
            param: burn::module::Param<Tensor<D>>,
        ) -> burn::module::Param<Tensor<D>> {
            let (id, tensor, mapper) = param.consume();
            let t = if D == 1 { tensor.zeros_like() } else { tensor.abs().add_scalar(0.01) };
            burn::module::Param::from_mapped_value(id, t, mapper)
        }
    }
}
