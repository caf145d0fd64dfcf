//! NormReLU (Cheema et al. 2019, §2, after Lea et al. 2017's ED-TCN):
//! `NormReLU(x) = ReLU(x) / (max ReLU(x) + ε)`, ε = 1e-5, so the values the classifier turns
//! into softmax scores stay in `[0, 1]` however large the features grow.
//!
//! The maximum is taken per frame over the channels, as in ED-TCN's code where NormReLU comes
//! from (`x / (max over channels + 1e-5)`): a maximum over the whole take would make every
//! frame's label depend on every other frame, break the receptive field and make a take's
//! labels change when it is cut.

use burn::tensor::activation::relu;
use burn::tensor::Tensor;

/// ε of the paper.
pub const EPSILON: f32 = 1e-5;

/// `[batch, channels, frames]` → the same shape, each frame's channels divided by their
/// maximum after the ReLU (plus [`EPSILON`]).
pub fn norm_relu(x: Tensor<3>) -> Tensor<3> {
    let r = relu(x);
    let max = r.clone().max_dim(1).add_scalar(EPSILON);
    r.div(max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_frame_is_divided_by_its_largest_positive_channel() {
        let device = crate::methods::dtfcn::device();
        // one take, 3 channels, 2 frames: frame 0 = (2, −1, 4), frame 1 = (−3, −1, 0)
        let x = Tensor::<1>::from_floats([2.0, -3.0, -1.0, -1.0, 4.0, 0.0], &device).reshape([1, 3, 2]);
        let y: Vec<f32> = norm_relu(x).into_data().try_to_vec::<f32>().unwrap();
        let e = EPSILON;
        let expected = [2.0 / (4.0 + e), 0.0, 0.0, 0.0, 4.0 / (4.0 + e), 0.0];
        for (a, b) in y.iter().zip(expected) {
            assert!((a - b).abs() < 1e-6, "{y:?}");
        }
        // a frame with nothing positive stays zero instead of dividing by zero
        assert!(y.iter().all(|v| v.is_finite()));
    }
}
