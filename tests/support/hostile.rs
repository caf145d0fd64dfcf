//! Model files a user could be sent (issue 49): valid, checksummed, and asking for much more work than the shipped
//! ones — what the budget gate must either run within what it declares or refuse before it starts.

use mocapseg::labeller::model::{Json, Model};
use mocapseg::methods::knn::{Knn, KnnInput, KnnParams, DIMS};
use mocapseg::motion::joints::Canonical;

/// The widest window a k-NN file may ask for: ±300 frames, every frame (601 offsets × 51 values = 30,651 values a
/// window, 46× the shipped ±30 every 5).
pub const WIDE: KnnParams = KnnParams { fps: 30.0, half_window: 300, stride: 1, k: 5, input: KnnInput::Joints };

/// The k-NN file `name`: the shipped `exercises` k-NN's header (its classes, travel, decoding) with the window `WIDE`
/// and a payload of `points` training windows — made up (axes, mean and points from a fixed sequence, labels
/// cycling through the classes) but as valid as a fitted one's, its hash written anew.
pub fn wide_knn_model(name: &str, points: usize) -> Model {
    let bytes = mocapseg::method::ModelStore::default().shipped_bytes("knn-exercises.model").unwrap();
    let mut model = Model::from_bytes(&bytes, "knn-exercises.model", &mocapseg::methods::LABELLERS).unwrap();
    let classes = model.header.classes.len();
    let d = (2 * WIDE.half_window / WIDE.stride + 1) as usize * 3 * Canonical::ALL.len();
    let mut words: Vec<u8> = Vec::new();
    words.extend_from_slice(&(points as u32).to_le_bytes());
    words.extend_from_slice(&(d as u32).to_le_bytes());
    // a fixed sequence in [-1, 1): the mean, the axes (DIMS × d), the points (points × DIMS)
    let mut state = 0x9e37_79b9_u32;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        (state as f32 / u32::MAX as f32) * 2.0 - 1.0
    };
    for _ in 0..d + DIMS * d + points * DIMS {
        words.extend_from_slice(&(next() * 10.0).to_le_bytes());
    }
    for i in 0..points {
        words.extend_from_slice(&((i % classes) as u32).to_le_bytes());
    }
    let knn = Knn::from_bytes(&words, WIDE, classes).unwrap();
    model.header.name = name.to_string();
    model.header.knn = Some(Json::of(&WIDE).unwrap());
    model.labeller = Box::new(knn);
    model
}

/// [`wide_knn_model`] as its file's bytes.
pub fn wide_knn_file(name: &str, points: usize) -> Vec<u8> {
    wide_knn_model(name, points).to_bytes().unwrap()
}
