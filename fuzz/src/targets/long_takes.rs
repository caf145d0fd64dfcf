//! The methods on long *working* takes — the region `load_pipeline` skips: a take of a few
//! fixture frames whose Frame Time the fuzzer picks (`Frame Time: 100` makes 200 frames 5.5
//! hours long; 1e-9 makes them a microsecond), run by every registered method with its default
//! parameters under small [`WorkLimits`] (16 MiB), then every annotator (LMA's Effort layer) on one segment over
//! the whole take and every supervised method's training on the take labelled in two halves (its file as the
//! training's take) under the same limits — the other doors of the budget gate (issue 49). A method must refuse
//! before it allocates past them (the work check, `src/method/work.rs`) or finish within them: a panic, a hang
//! (libFuzzer's `-timeout`) or the live heap passing the fuzz budget is a finding. What comes out must fit the
//! schema and cover the take; a refusal must say why.

use arbitrary::Arbitrary;
use mocapseg::load::{load_bytes_with_budget, MemoryBudget};
use mocapseg::method::{MethodError, NoProgress, RunOptions, WorkLimits};

/// The loader's budget here (the page's is 1 GiB).
const BUDGET: MemoryBudget = MemoryBudget { max_bytes: 4 << 20 };
/// What a run may take here: 16 MiB is about 1500 LMA frames, 1800 DT-FCN frames, 10 000 velocity
/// frames — milliseconds to a second or two each (DT-FCN's 12 MiB of fixed work must fit); 2·10⁹ multiply-adds
/// where a model sets them (the page's 2·10¹¹ would let one input run for minutes).
const LIMITS: WorkLimits = WorkLimits { min_file_fps: 1.0, max_seconds: 7200.0, max_bytes: 16 << 20, max_ops: 2e9 };
/// What a training may hold here: its fixed part (DT-FCN's 16 MiB of networks and batch, LMA's 16 MiB) and a few
/// thousand working frames.
const TRAIN_LIMITS: WorkLimits = WorkLimits { max_bytes: 48 << 20, ..LIMITS };

#[derive(Debug, Arbitrary)]
struct Input {
    /// Which fixture (of the few whose skeleton every method reads).
    fixture: u8,
    /// How many of its frames (at least one).
    frames: u16,
    /// The Frame Time written into the file, as its bits: any f64 (NaN, infinities, 0, 100, 1e-300).
    frame_time: f64,
}

const FIXTURES: [&str; 3] = ["12_01.bvh", "assimp_Boxing_Toes_100fps.bvh", "131_03.bvh"];

pub fn seeds() -> Vec<(String, Vec<u8>)> {
    // the file and its siblings: 200 frames at Frame Time 100, 10, 1, 1/30 and 1e-6
    let mut out = Vec::new();
    for (k, frame_time) in [100.0f64, 10.0, 1.0, 1.0 / 30.0, 1e-6].into_iter().enumerate() {
        let mut bytes = vec![k as u8 % 3];
        bytes.extend_from_slice(&200u16.to_le_bytes());
        bytes.extend_from_slice(&frame_time.to_le_bytes());
        out.push((format!("frame-time-{frame_time}"), bytes));
    }
    out
}

/// One input of the target (what `fuzz_targets/long_takes.rs` hands libFuzzer's bytes to).
pub fn run(data: &[u8]) {
    // as libfuzzer-sys reads a typed input
    let Ok(input) = <Input as arbitrary::Arbitrary>::arbitrary_take_rest(arbitrary::Unstructured::new(data)) else {
        return;
    };
    let fixture = FIXTURES[input.fixture as usize % FIXTURES.len()];
    let mut take = crate::small_take(fixture, (input.frames as usize).clamp(1, 400));
    take.frame_time = input.frame_time;
    let text = mocapseg::bvh::write(&take);
    let loaded = match load_bytes_with_budget("long.bvh", text.as_bytes(), &BUDGET, &mut |_| {}) {
        Ok(l) => l,
        Err(e) => {
            assert!(e.to_string().starts_with("long.bvh: "), "{e}");
            return;
        }
    };
    let motion = &loaded.motion;
    let options = RunOptions { pictures: true, limits: LIMITS };
    for m in mocapseg::methods::registry() {
        let name = m.info().name;
        match m.run_json(motion, &serde_json::Value::Null, &options, &mut NoProgress) {
            Ok(out) => {
                let s = &out.segmentation;
                s.validate().unwrap_or_else(|e| panic!("{name}: the output breaks the schema: {e}"));
                assert_eq!(s.frames, motion.frames(), "{name}");
                for c in &out.details.curves {
                    assert_eq!(c.values.len(), motion.frames(), "{name}: curve {}", c.id);
                }
            }
            Err(MethodError::Failed(message)) => assert!(!message.trim().is_empty(), "{name}: an empty message"),
            Err(e) => panic!("{name}: unexpected error kind: {e}"),
        }
    }
    annotate(motion);
    train(motion, &text);
}

/// Every annotator on one segment over the whole take, under [`LIMITS`]: Effort values for it, or a refusal that
/// says why.
fn annotate(motion: &mocapseg::motion::Motion) {
    let whole = mocapseg::segment::Segment {
        start: 0,
        end: motion.frames() - 1,
        label: "all".into(),
        level: mocapseg::segment::Level::Action,
        cluster: None,
        score: None,
        mirror_of: None,
        effort: None,
    };
    for m in mocapseg::methods::registry() {
        if m.annotator().is_none() {
            continue;
        }
        let name = m.info().name;
        let checked = m.check_json(&serde_json::Value::Null).unwrap_or_else(|e| panic!("{name}: its defaults: {e}"));
        match m.annotate_checked(motion, &checked, std::slice::from_ref(&whole), &LIMITS, &mut NoProgress) {
            Ok(a) => assert!(a.segments.len() <= 1, "{name}: one segment, at most one annotation"),
            Err(MethodError::Failed(message)) => assert!(!message.trim().is_empty(), "{name}: an empty message"),
            Err(e) => panic!("{name}: annotating: unexpected error kind: {e}"),
        }
    }
}

/// Every supervised method's training on the take (its file `text`), labelled in two halves, under [`TRAIN_LIMITS`]
/// and the smallest options: a model, or a refusal that says why.
fn train(motion: &mocapseg::motion::Motion, text: &str) {
    use mocapseg::method::supervised::TrainingAsk;
    let frames = motion.frames();
    if frames < 4 {
        return;
    }
    let half = frames / 2;
    for m in mocapseg::methods::registry() {
        let Some(s) = m.supervised() else { continue };
        let name = m.info().name;
        let lma = name == "lma";
        let options = match name.as_str() {
            "dtfcn" => serde_json::json!({"epochs": 1, "filters": [4, 4], "crop_frames": 16, "batch": 1}),
            "lma" => {
                serde_json::json!({"restarts": 1, "max_epochs": 1, "shift_epochs": 1, "shift_restarts": 1, "saliency_rounds": 1})
            }
            _ => serde_json::json!({}),
        };
        let ask = TrainingAsk {
            name: "fuzzed".into(),
            labels_name: if lma { String::new() } else { "l.csv".into() },
            labels: if lma {
                String::new()
            } else {
                format!(
                    "file,start_frame,end_frame,label\nlong.bvh,0,{},a\nlong.bvh,{half},{},b\n",
                    half - 1,
                    frames - 1
                )
            },
            takes: vec![("long.bvh".into(), text.as_bytes().to_vec())],
            options,
            to_file: true,
            limits: TRAIN_LIMITS,
            ..TrainingAsk::default()
        };
        let trained = s.start_training(ask, &mut NoProgress).and_then(|mut t| {
            while !t.done() {
                t.step(&mut NoProgress)?;
            }
            t.finish()
        });
        if let Err(e) = trained {
            assert!(!e.to_string().trim().is_empty(), "{name}: training: an empty message");
            assert!(!matches!(e, MethodError::Cancelled), "{name}: training: cancelled with nothing cancelling");
        }
    }
}
