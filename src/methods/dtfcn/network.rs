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
}

impl DtFcnConfig {
    /// The paper's network (w = 3, five layers) for `channels` inputs and `classes` classes.
    pub fn paper(channels: usize, classes: usize) -> DtFcnConfig {
        DtFcnConfig { channels, classes, width: 3, filters: vec![64, 64, 128, 256, 512] }
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
        let mut inputs = self.channels;
        for &f in &self.filters {
            n += inputs * self.width * f + f;
            inputs = f;
        }
        n + inputs * self.classes + self.classes
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
        if self.channels == 0 || self.channels > 3 * 128 {
            return Err(format!("{} input channels: expected 3 × 1 to 128 joints", self.channels));
        }
        Ok(())
    }

    /// A network with fresh (random) weights on `device`.
    pub fn init(&self, device: &Device) -> DtFcn {
        let mut layers = Vec::with_capacity(self.filters.len());
        let mut inputs = self.channels;
        for (l, &f) in self.filters.iter().enumerate() {
            layers.push(TemporalConv::new(inputs, f, self.width, self.dilation(l), device));
            inputs = f;
        }
        let classifier = TemporalConv::new(inputs, self.classes, 1, 1, device);
        DtFcn { layers, classifier }
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

/// One temporal convolution: `out × in × kernel` weights, dilation `d`, zero padding that keeps
/// the length (`d·(kernel − 1)` frames, half before and half after: acausal).
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
}

impl TemporalConv {
    fn new(inputs: usize, outputs: usize, kernel: usize, dilation: usize, device: &Device) -> TemporalConv {
        // burn's Conv1d initialisation (uniform ±1/√fan-in for weights and bias)
        let conv = Conv1dConfig::new(inputs, outputs, kernel).init(device);
        let bias = conv.bias.unwrap_or_else(|| Param::from_tensor(Tensor::zeros([outputs], device)));
        TemporalConv { weight: conv.weight, bias, kernel_size: kernel, dilation }
    }

    /// `[batch, in, frames]` → `[batch, out, frames]`.
    pub fn forward(&self, x: Tensor<3>) -> Tensor<3> {
        let [b, c, t] = x.dims();
        let [out, _, k] = self.weight.dims();
        let cols = if k == 1 {
            x
        } else {
            let pad = self.dilation * (k - 1);
            let (left, right) = (pad / 2, pad - pad / 2);
            let device = x.device();
            let padded =
                Tensor::cat(vec![Tensor::zeros([b, c, left], &device), x, Tensor::zeros([b, c, right], &device)], 2);
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
}

impl DtFcn {
    /// Class scores before the softmax: `[batch, channels, frames]` → `[batch, classes, frames]`.
    pub fn logits(&self, input: Tensor<3>) -> Tensor<3> {
        let mut x = input;
        for layer in &self.layers {
            x = relu(layer.forward(x));
        }
        self.classifier.forward(norm_relu(x))
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

    #[test]
    fn any_length_in_the_same_length_out_and_probabilities_sum_to_one() {
        let device = crate::methods::dtfcn::device();
        let c = DtFcnConfig { channels: 6, classes: 3, width: 3, filters: vec![4, 8, 8] };
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
        let ours =
            TemporalConv { weight: conv.weight.clone(), bias: conv.bias.clone().unwrap(), kernel_size: 3, dilation: 4 };
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

    /// Every layer of every shipped DT-FCN model (kernel 2, dilations 1–16, its trained weights)
    /// computes what burn's own `Conv1d` computes with the same padding.
    #[test]
    fn the_shipped_models_layers_equal_burns_conv1d() {
        use crate::methods::dtfcn::model::{Labeller, ModelKind};
        for name in crate::methods::dtfcn::shipped::NAMES {
            let model = crate::methods::dtfcn::shipped::model(ModelKind::Dtfcn, name).unwrap();
            let Labeller::Network(net) = &model.labeller else { panic!("{name}: not a network") };
            assert!(net.layers.iter().any(|l| l.kernel_size == 2), "{name}: the shipped models use kernel 2");
            for (i, layer) in net.layers.iter().chain([&net.classifier]).enumerate() {
                assert_same_output(
                    layer,
                    48,
                    &format!("{name} layer {i} (kernel {}, dilation {})", layer.kernel_size, layer.dilation),
                );
            }
        }
    }

    #[test]
    fn an_impulse_changes_exactly_the_receptive_field() {
        let device = crate::methods::dtfcn::device();
        // positive weights: nothing is cut by a ReLU, so every frame the impulse reaches changes
        let c = DtFcnConfig { channels: 2, classes: 2, width: 3, filters: vec![3, 3, 3] };
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
