//! The page ↔ worker protocol and the worker's entry points (issue 2, "The page": parsing a
//! large file must not freeze the tab, and shows progress).
//!
//! `www/worker.js` runs this module in a dedicated module worker and calls [`worker_load`],
//! which dispatches to the core — [`crate::bvh::parse_with_progress`] →
//! [`Motion::from_bvh`] (forward kinematics, units, up axis) → [`MotionImage::from_motion`] —
//! and packs the result into one message. The page (`crate::app`) decodes the messages with
//! [`WorkerEvent::from_js`]; this file is the only place that knows their shape.
//!
//! Messages (plain JS objects; bulk data as typed arrays whose buffers are transferred):
//! * page → worker: `{id, name, bytes: ArrayBuffer}` ([`load_request`]);
//! * worker → page: `{type: "progress", id, stage, fraction}` (fraction 0..1, or `null` when a
//!   stage cannot measure its progress);
//! * worker → page: `{type: "done", id, summary, skeleton, bounds, positions: Float32Array,
//!   image: {width, height, rows, rgba: Uint8Array, png: Uint8Array}}`;
//! * worker → page: `{type: "error", id, message, fatal}` — `message` is the parser's error with
//!   the file name in front ("02_bad.bvh: line 12, column 5: expected …"); `fatal` asks the page
//!   to start a fresh worker (the wasm module trapped).
//!
//! The SSSM segmentation (Krüger et al. 2017, issue 3) runs on the take the worker loaded last
//! (kept in the worker after [`worker_load`]) with [`worker_sssm`]:
//! * page → worker: `{id, kind: "sssm", params: "<SssmParams JSON, fields optional>"}`
//!   ([`sssm_request`]);
//! * worker → page: `{type: "sssm-progress", id, stage, fraction}`;
//! * worker → page: `{type: "sssm-done", id, report: "<SssmReport JSON>", image: {size, block,
//!   rgba: Uint8Array}}` — the segmentation at the file's frame rate plus the SSSM image
//!   rendered by [`crate::sssm::image`];
//! * worker → page: `{type: "sssm-error", id, message, fatal}` (a bad parameter names it).

use crate::bvh::{parse_with_progress, ParseLimits};
use crate::image::MotionImage;
use crate::motion::{Motion, Units, UpAxis};
use crate::segment::Segmentation;
use crate::sssm::{segment_with_progress, SssmParams};
use crate::sssm::image::{self as sssm_image, SssmImage};
use glam::Vec3;
use js_sys::{Array, ArrayBuffer, Float32Array, Function, Object, Reflect, Uint8Array};
use serde::{Deserialize, Serialize};
use std::cell::RefCell;
use wasm_bindgen::prelude::*;

/// What the summary line shows about a loaded take.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// File name as given by the page.
    pub name: String,
    /// Joints that are not End Sites.
    pub joints: usize,
    pub end_sites: usize,
    pub frames: usize,
    /// Frames per second at full precision (1 / Frame Time).
    pub fps: f64,
    pub duration_s: f64,
    /// Detected length units.
    pub units: Units,
    pub up_axis: UpAxis,
    /// The parser's warnings and the unit / up-axis detection notes, as sentences.
    pub warnings: Vec<String>,
}

/// The skeleton as the player draws it: one entry per node (End Sites included), file order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Skeleton {
    pub names: Vec<String>,
    pub parents: Vec<Option<usize>>,
    pub is_end_site: Vec<bool>,
}

/// The box every joint stays inside over the whole take (file units and axes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Bounds {
    pub min: [f32; 3],
    pub max: [f32; 3],
}

impl Bounds {
    /// The bounds of a set of points (a unit box around the origin if there are none).
    pub fn of(points: &[Vec3]) -> Bounds {
        let finite = points.iter().filter(|p| p.is_finite());
        let (min, max) = finite
            .fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        if min.cmple(max).all() {
            Bounds { min: min.to_array(), max: max.to_array() }
        } else {
            Bounds { min: [-0.5; 3], max: [0.5; 3] }
        }
    }

    pub fn min(&self) -> Vec3 {
        Vec3::from_array(self.min)
    }

    pub fn max(&self) -> Vec3 {
        Vec3::from_array(self.max)
    }
}

/// The motion image as the page draws it (see [`MotionImage`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ImageData {
    /// One column per frame.
    pub width: usize,
    /// One row per joint.
    pub height: usize,
    /// Name of the joint each row shows.
    pub rows: Vec<String>,
    /// `width × height` RGBA pixels, row-major.
    pub rgba: Vec<u8>,
    /// The same image encoded as PNG, for download.
    pub png: Vec<u8>,
}

/// A loaded take, as received by the page.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedMotion {
    pub summary: Summary,
    pub skeleton: Skeleton,
    pub bounds: Bounds,
    /// World positions, `frames × nodes × 3` floats (End Sites included), file units.
    pub positions: Vec<f32>,
    pub image: ImageData,
}

impl LoadedMotion {
    /// Number of nodes per frame (End Sites included).
    pub fn nodes(&self) -> usize {
        self.skeleton.names.len()
    }

    /// The positions of every node in frame `i` (clamped to the last frame).
    pub fn frame(&self, i: usize) -> impl Iterator<Item = Vec3> + '_ {
        let n = self.nodes();
        let i = i.min(self.summary.frames.saturating_sub(1));
        self.positions[i * n * 3..(i + 1) * n * 3].chunks_exact(3).map(Vec3::from_slice)
    }
}

/// What the page shows of an SSSM run besides the image.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SssmReport {
    /// Actions, transitions and primitives at the file's frame rate.
    pub segmentation: Segmentation,
    /// For each primitive cluster, the cluster that holds its mirror images (§V), if any.
    pub mirror_of: Vec<Option<usize>>,
    /// Working frame rate and frames (the SSSM image's axes).
    pub working_fps: f64,
    pub working_frames: usize,
}

/// A finished SSSM run, as received by the page.
#[derive(Debug, Clone, PartialEq)]
pub struct SssmView {
    pub report: SssmReport,
    /// The SSSM image (see [`crate::sssm::image`]).
    pub image: SssmImage,
}

/// A message from the worker, decoded on the page.
#[derive(Debug, Clone, PartialEq)]
pub enum WorkerEvent {
    Progress { id: u32, stage: String, fraction: Option<f64> },
    Done { id: u32, motion: Box<LoadedMotion> },
    Error { id: u32, message: String, fatal: bool },
    SssmProgress { id: u32, stage: String, fraction: Option<f64> },
    SssmDone { id: u32, view: Box<SssmView> },
    SssmError { id: u32, message: String, fatal: bool },
}

impl WorkerEvent {
    /// Decodes a `MessageEvent.data` posted by `www/worker.js`.
    pub fn from_js(data: &JsValue) -> Result<WorkerEvent, String> {
        let id = field(data, "id")?.as_f64().ok_or("worker message without an id")? as u32;
        match field(data, "type")?.as_string().as_deref() {
            Some("progress") => {
                let (stage, fraction) = progress_fields(data)?;
                Ok(WorkerEvent::Progress { id, stage, fraction })
            }
            Some("done") => Ok(WorkerEvent::Done { id, motion: Box::new(decode_motion(data)?) }),
            Some("error") => {
                let (message, fatal) = error_fields(data)?;
                Ok(WorkerEvent::Error { id, message, fatal })
            }
            Some("sssm-progress") => {
                let (stage, fraction) = progress_fields(data)?;
                Ok(WorkerEvent::SssmProgress { id, stage, fraction })
            }
            Some("sssm-done") => Ok(WorkerEvent::SssmDone { id, view: Box::new(decode_sssm(data)?) }),
            Some("sssm-error") => {
                let (message, fatal) = error_fields(data)?;
                Ok(WorkerEvent::SssmError { id, message, fatal })
            }
            other => Err(format!("unknown worker message type {other:?}")),
        }
    }
}

/// The message asking the worker to load `bytes` (an `ArrayBuffer` to be transferred).
pub fn load_request(id: u32, name: &str, bytes: &ArrayBuffer) -> Result<JsValue, JsValue> {
    let message = Object::new();
    Reflect::set(&message, &"id".into(), &id.into())?;
    Reflect::set(&message, &"name".into(), &name.into())?;
    Reflect::set(&message, &"bytes".into(), bytes)?;
    Ok(message.into())
}

/// The message asking the worker to run the SSSM on the loaded take with `params_json`.
pub fn sssm_request(id: u32, params_json: &str) -> Result<JsValue, JsValue> {
    let message = Object::new();
    Reflect::set(&message, &"id".into(), &id.into())?;
    Reflect::set(&message, &"kind".into(), &"sssm".into())?;
    Reflect::set(&message, &"params".into(), &params_json.into())?;
    Ok(message.into())
}

thread_local! {
    /// The take loaded last (the SSSM runs on it).
    static LOADED: RefCell<Option<Motion>> = const { RefCell::new(None) };
}

/// Worker entry point: run the SSSM segmentation (Krüger et al. 2017) on the take loaded last.
///
/// `params_json` is an [`SssmParams`] object whose fields are all optional (the defaults fill
/// in the rest); `progress(stage, fraction)` reports the method's stages. Returns `{report,
/// image: {size, block, rgba}}` (see the module documentation); throws a string naming the bad
/// parameter or what else went wrong.
#[wasm_bindgen]
pub fn worker_sssm(params_json: &str, progress: &Function) -> Result<JsValue, JsValue> {
    console_error_panic_hook::set_once();
    let params: SssmParams =
        serde_json::from_str(params_json).map_err(|e| JsValue::from_str(&format!("SSSM parameters: {e}")))?;
    let mut report = |stage: &str, fraction: f64| {
        let _ = progress.call2(&JsValue::NULL, &stage.into(), &fraction.into());
        Ok(())
    };
    LOADED.with_borrow(|loaded| {
        let motion = loaded.as_ref().ok_or_else(|| JsValue::from_str("SSSM: no take is loaded"))?;
        let result = segment_with_progress(motion, &params, &mut report)
            .map_err(|e| JsValue::from_str(&format!("SSSM on {}: {e}", motion.name)))?;
        let _ = report("image", 1.0);
        let image = sssm_image::render(&result.outcome);
        let summary = SssmReport {
            mirror_of: result.outcome.clusters.iter().map(|c| c.mirror_of).collect(),
            working_fps: result.outcome.fps,
            working_frames: result.outcome.frames,
            segmentation: result.segmentation,
        };
        encode_sssm(&summary, &image)
    })
}

fn encode_sssm(report: &SssmReport, image: &SssmImage) -> Result<JsValue, JsValue> {
    let text = serde_json::to_string(report).map_err(|e| JsValue::from_str(&format!("SSSM report: {e}")))?;
    let result = Object::new();
    set(&result, "report", text.into())?;
    let img = Object::new();
    set(&img, "size", image.size.into())?;
    set(&img, "block", image.block.into())?;
    set(&img, "rgba", Uint8Array::from(&image.rgba[..]).into())?;
    set(&result, "image", img.into())?;
    Ok(result.into())
}

fn decode_sssm(data: &JsValue) -> Result<SssmView, String> {
    let text = field(data, "report")?.as_string().ok_or("worker message `report` is not text")?;
    let report: SssmReport = serde_json::from_str(&text).map_err(|e| format!("worker message `report`: {e}"))?;
    report.segmentation.validate().map_err(|e| format!("worker message `report`: {e}"))?;
    let image = field(data, "image")?;
    let image = SssmImage {
        size: decode(&image, "size")?,
        block: decode(&image, "block")?,
        rgba: decode_bytes(&image, "rgba")?,
    };
    if image.rgba.len() != image.size * image.size * 4 {
        return Err("worker message: the SSSM image's size does not match its pixels".into());
    }
    Ok(SssmView { report, image })
}

/// Worker entry point: parse `bytes` as BVH, run forward kinematics and build the motion image.
///
/// `progress(stage, fraction)` is called while working (`fraction` is `null` for stages that
/// cannot measure progress). Returns `{summary, skeleton, bounds, positions, image}`, whose
/// typed arrays the glue transfers to the page; throws a string naming the file on failure.
#[wasm_bindgen]
pub fn worker_load(bytes: &[u8], name: String, progress: &Function) -> Result<JsValue, JsValue> {
    console_error_panic_hook::set_once();
    let report = |stage: &str, fraction: Option<f64>| {
        let fraction = fraction.map_or(JsValue::NULL, JsValue::from);
        // A failing progress callback must not abort the load.
        let _ = progress.call2(&JsValue::NULL, &stage.into(), &fraction);
    };
    let fail = |message: String| JsValue::from_str(&format!("{name}: {message}"));

    let text = String::from_utf8_lossy(bytes);
    report("parsing", Some(0.0));
    let bvh = parse_with_progress(&text, &ParseLimits::default(), &mut |f| report("parsing", Some(f)))
        .map_err(|e| fail(e.to_string()))?;
    drop(text);
    report("forward kinematics", None);
    let motion = Motion::from_bvh(&name, &bvh).map_err(|e| fail(e.to_string()))?;
    drop(bvh);
    report("motion image", None);
    let image = MotionImage::from_motion(&motion);
    let png = image.try_to_png().map_err(|e| fail(format!("motion image: {e}")))?;
    let result = encode_result(&motion, &image, &png)?;
    LOADED.set(Some(motion));
    Ok(result)
}

fn encode_result(motion: &Motion, image: &MotionImage, png: &[u8]) -> Result<JsValue, JsValue> {
    let result = Object::new();
    set(&result, "summary", to_js(&summary_of(motion))?)?;
    set(&result, "skeleton", to_js(&skeleton_of(motion))?)?;
    set(&result, "bounds", to_js(&Bounds::of(&motion.positions))?)?;
    set(&result, "positions", flat_positions(&motion.positions).into())?;
    let img = Object::new();
    set(&img, "width", image.width.into())?;
    set(&img, "height", image.height.into())?;
    set(&img, "rows", to_js(&image.rows)?)?;
    set(&img, "rgba", Uint8Array::from(&image.rgba[..]).into())?;
    set(&img, "png", Uint8Array::from(png).into())?;
    set(&result, "image", img.into())?;
    Ok(result.into())
}

fn to_js<T: Serialize + ?Sized>(value: &T) -> Result<JsValue, JsValue> {
    serde_wasm_bindgen::to_value(value).map_err(JsValue::from)
}

fn summary_of(motion: &Motion) -> Summary {
    let end_sites = motion.skeleton.is_end_site.iter().filter(|e| **e).count();
    Summary {
        name: motion.name.clone(),
        joints: motion.joints() - end_sites,
        end_sites,
        frames: motion.frames(),
        fps: motion.fps,
        duration_s: motion.duration_s(),
        units: motion.units,
        up_axis: motion.up_axis,
        warnings: motion.warnings.clone(),
    }
}

fn skeleton_of(motion: &Motion) -> Skeleton {
    Skeleton {
        names: motion.skeleton.names.clone(),
        parents: motion.skeleton.parents.clone(),
        is_end_site: motion.skeleton.is_end_site.clone(),
    }
}

/// Positions as one `Float32Array` of `frames × nodes × 3` floats.
fn flat_positions(positions: &[Vec3]) -> Float32Array {
    let flat: Vec<f32> = positions.iter().flat_map(|p| p.to_array()).collect();
    Float32Array::from(&flat[..])
}

fn set(target: &Object, key: &str, value: JsValue) -> Result<(), JsValue> {
    Reflect::set(target, &key.into(), &value).map(|_| ())
}

/// `stage` and `fraction` of a progress message (a load's or an SSSM run's).
fn progress_fields(data: &JsValue) -> Result<(String, Option<f64>), String> {
    Ok((field(data, "stage")?.as_string().unwrap_or_default(), field(data, "fraction")?.as_f64()))
}

/// `message` and `fatal` of an error message (a load's or an SSSM run's).
fn error_fields(data: &JsValue) -> Result<(String, bool), String> {
    let message = field(data, "message")?.as_string().unwrap_or_else(|| "unknown error".into());
    Ok((message, field(data, "fatal")?.is_truthy()))
}

fn field(data: &JsValue, key: &str) -> Result<JsValue, String> {
    Reflect::get(data, &key.into()).map_err(|_| format!("worker message: cannot read `{key}`"))
}

fn decode<T: serde::de::DeserializeOwned>(data: &JsValue, key: &str) -> Result<T, String> {
    serde_wasm_bindgen::from_value(field(data, key)?).map_err(|e| format!("worker message `{key}`: {e}"))
}

fn decode_bytes(data: &JsValue, key: &str) -> Result<Vec<u8>, String> {
    let value = field(data, key)?;
    value.dyn_ref::<Uint8Array>().map(Uint8Array::to_vec).ok_or_else(|| format!("worker message `{key}` is not bytes"))
}

fn decode_motion(data: &JsValue) -> Result<LoadedMotion, String> {
    let summary: Summary = decode(data, "summary")?;
    let skeleton: Skeleton = decode(data, "skeleton")?;
    let bounds: Bounds = decode(data, "bounds")?;
    let positions = field(data, "positions")?
        .dyn_ref::<Float32Array>()
        .map(Float32Array::to_vec)
        .ok_or("worker message `positions` is not a Float32Array")?;
    let image = field(data, "image")?;
    let image = ImageData {
        width: decode(&image, "width")?,
        height: decode(&image, "height")?,
        rows: decode(&image, "rows")?,
        rgba: decode_bytes(&image, "rgba")?,
        png: decode_bytes(&image, "png")?,
    };
    let motion = LoadedMotion { summary, skeleton, bounds, positions, image };
    check_shapes(&motion)?;
    Ok(motion)
}

/// Refuses a message whose arrays do not match its own counts (so views can index freely).
fn check_shapes(m: &LoadedMotion) -> Result<(), String> {
    let nodes = m.nodes();
    let consistent = m.skeleton.parents.len() == nodes
        && m.skeleton.is_end_site.len() == nodes
        && m.skeleton.parents.iter().enumerate().all(|(i, p)| p.is_none_or(|p| p < i))
        && m.positions.len() == m.summary.frames * nodes * 3
        && m.summary.frames > 0
        && m.image.rgba.len() == m.image.width * m.image.height * 4;
    if consistent {
        Ok(())
    } else {
        Err("worker message: array sizes do not match the summary".into())
    }
}

/// The transfer list for [`load_request`]: the bytes' buffer moves to the worker.
pub fn transfer_list(bytes: &ArrayBuffer) -> Array {
    Array::of1(bytes)
}

#[cfg(all(test, target_arch = "wasm32"))]
mod tests {
    use super::*;
    use std::cell::RefCell;
    use std::rc::Rc;
    use wasm_bindgen_test::wasm_bindgen_test;

    /// Two nodes and an End Site, two frames at 23.976 fps; frame 1 moves the root by +1 in X
    /// and turns the chest 90° about Y (which leaves a point straight above it in place).
    const BVH: &str = "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n  JOINT Chest\n  {\n    OFFSET 0 10 0\n    CHANNELS 3 Zrotation Yrotation Xrotation\n    End Site\n    {\n      OFFSET 0 5 0\n    }\n  }\n}\nMOTION\nFrames: 2\nFrame Time: 0.0417083750417\n0 0 0 0 0 0 0 0 0\n1 0 0 0 0 0 0 90 0\n";

    fn load(text: &str, name: &str) -> (Result<JsValue, JsValue>, Vec<(String, Option<f64>)>) {
        let seen = Rc::new(RefCell::new(Vec::new()));
        let sink = seen.clone();
        let progress = Closure::<dyn FnMut(String, JsValue)>::new(move |stage: String, f: JsValue| {
            sink.borrow_mut().push((stage, f.as_f64()));
        });
        let result = worker_load(text.as_bytes(), name.to_string(), progress.as_ref().unchecked_ref());
        let seen = seen.borrow().clone();
        (result, seen)
    }

    /// What `www/worker.js` posts: `{type, id, ...result}`.
    fn as_message(kind: &str, id: u32, result: &JsValue) -> JsValue {
        let message = Object::assign(&Object::new(), result.unchecked_ref());
        Reflect::set(&message, &"type".into(), &kind.into()).unwrap();
        Reflect::set(&message, &"id".into(), &id.into()).unwrap();
        message.into()
    }

    #[wasm_bindgen_test]
    fn a_load_reaches_the_page_intact() {
        let (result, progress) = load(BVH, "tiny.bvh");
        let result = result.expect("tiny file loads");
        assert!(progress.iter().any(|(stage, f)| stage == "parsing" && *f == Some(1.0)), "{progress:?}");
        assert!(progress.iter().any(|(stage, f)| stage == "forward kinematics" && f.is_none()));

        let WorkerEvent::Done { id, motion } = WorkerEvent::from_js(&as_message("done", 7, &result)).unwrap() else {
            panic!("not a done message");
        };
        assert_eq!(id, 7);
        let s = &motion.summary;
        assert_eq!((s.name.as_str(), s.joints, s.end_sites, s.frames), ("tiny.bvh", 2, 1, 2));
        assert!((s.fps - 1.0 / 0.0417083750417).abs() < 1e-9);
        assert_eq!(motion.skeleton.parents, vec![None, Some(0), Some(1)]);
        assert_eq!(motion.skeleton.is_end_site, vec![false, false, true]);
        let frame1: Vec<Vec3> = motion.frame(1).collect();
        assert!((frame1[0] - Vec3::new(1.0, 0.0, 0.0)).length() < 1e-5, "{frame1:?}");
        assert!((frame1[2] - Vec3::new(1.0, 15.0, 0.0)).length() < 1e-4, "{frame1:?}");
        assert_eq!(motion.bounds.min, [0.0, 0.0, 0.0]);
        assert!((motion.bounds.max()[1] - 15.0).abs() < 1e-4);
        let image = &motion.image;
        assert_eq!((image.width, image.height, image.rows.len()), (2, 2, 2));
        assert_eq!(image.rgba.len(), 2 * 2 * 4);
        assert_eq!(&image.png[..8], b"\x89PNG\r\n\x1a\n");
    }

    #[wasm_bindgen_test]
    fn a_parse_error_names_the_file_line_and_column() {
        let bad = BVH.replace("OFFSET 0 10 0", "OFFSET 0 ten 0");
        let (result, _) = load(&bad, "bad.bvh");
        let message = result.expect_err("bad file fails").as_string().unwrap();
        assert!(message.starts_with("bad.bvh: line 8, column "), "{message}");
    }

    #[wasm_bindgen_test]
    fn progress_and_error_messages_decode() {
        let progress = Object::new();
        for (k, v) in [
            ("type", JsValue::from("progress")),
            ("id", 3.into()),
            ("stage", "parsing".into()),
            ("fraction", 0.5.into()),
        ] {
            Reflect::set(&progress, &k.into(), &v).unwrap();
        }
        assert_eq!(
            WorkerEvent::from_js(&progress).unwrap(),
            WorkerEvent::Progress { id: 3, stage: "parsing".into(), fraction: Some(0.5) }
        );
        let error = Object::new();
        for (k, v) in [
            ("type", JsValue::from("error")),
            ("id", 4.into()),
            ("message", "x.bvh: boom".into()),
            ("fatal", true.into()),
        ] {
            Reflect::set(&error, &k.into(), &v).unwrap();
        }
        assert_eq!(
            WorkerEvent::from_js(&error).unwrap(),
            WorkerEvent::Error { id: 4, message: "x.bvh: boom".into(), fatal: true }
        );
        assert!(WorkerEvent::from_js(&Object::new().into()).is_err());
    }

    fn sssm(params: &str) -> (Result<JsValue, JsValue>, Vec<(String, Option<f64>)>) {
        let seen = Rc::new(RefCell::new(Vec::new()));
        let sink = seen.clone();
        let progress = Closure::<dyn FnMut(String, JsValue)>::new(move |stage: String, f: JsValue| {
            sink.borrow_mut().push((stage, f.as_f64()));
        });
        let result = worker_sssm(params, progress.as_ref().unchecked_ref());
        let seen = seen.borrow().clone();
        (result, seen)
    }

    /// A real take (CMU 12_01, 120 Hz) through the SSSM entry point and back on the page side.
    #[wasm_bindgen_test]
    fn an_sssm_run_reaches_the_page_intact() {
        let take = include_str!("../tests/fixtures/12_01.bvh");
        let (loaded, _) = load(take, "12_01.bvh");
        let WorkerEvent::Done { motion, .. } = WorkerEvent::from_js(&as_message("done", 1, &loaded.unwrap())).unwrap()
        else {
            panic!("not a done message");
        };
        let (result, progress) = sssm("{}");
        let result = result.expect("the SSSM runs on the loaded take");
        for stage in ["features", "neighbours", "activities", "primitives", "clusters"] {
            assert!(progress.iter().any(|(s, _)| s == stage), "no {stage} progress: {progress:?}");
        }
        let WorkerEvent::SssmDone { id, view } = WorkerEvent::from_js(&as_message("sssm-done", 9, &result)).unwrap()
        else {
            panic!("not an sssm-done message");
        };
        assert_eq!(id, 9);
        let s = &view.report.segmentation;
        assert_eq!((s.file.as_str(), s.frames, s.method.as_str()), ("12_01.bvh", motion.summary.frames, "sssm"));
        assert_eq!(s.params["radius"], 19.0, "the defaults are echoed");
        assert!(!s.segments.is_empty());
        // 120 Hz → 30 Hz working rate: one pixel per working frame
        assert_eq!(view.report.working_fps, 30.0);
        assert_eq!((view.image.size, view.image.block), (view.report.working_frames, 1));
        assert!(view.report.working_frames.abs_diff(motion.summary.frames / 4) <= 1);
        assert_eq!(view.image.rgba.len(), view.image.size * view.image.size * 4);
        // the diagonal (every frame is its own neighbour at distance 0) is drawn dark
        let k = (view.image.size / 2 * (view.image.size + 1)) * 4;
        assert!(view.image.rgba[k] < 128, "diagonal pixel {:?}", &view.image.rgba[k..k + 4]);

        let (radius, _) = sssm(r#"{"radius": 11, "primitive_radius": 8, "offsets": [-5, 0, 5], "mirror": false}"#);
        let WorkerEvent::SssmDone { view: other, .. } =
            WorkerEvent::from_js(&as_message("sssm-done", 10, &radius.unwrap())).unwrap()
        else {
            panic!("not an sssm-done message");
        };
        assert_eq!(other.report.segmentation.params["radius"], 11.0);
        assert_eq!(other.report.segmentation.params["mirror"], false);
    }

    #[wasm_bindgen_test]
    fn bad_sssm_parameters_are_named() {
        let (loaded, _) = load(include_str!("../tests/fixtures/12_01.bvh"), "12_01.bvh");
        loaded.unwrap();
        let message = sssm(r#"{"radius": -1}"#).0.expect_err("negative radius").as_string().unwrap();
        assert!(message.contains("radius = -1"), "{message}");
        let message = sssm(r#"{"radius": 11}"#).0.expect_err("primitive radius > radius").as_string().unwrap();
        assert!(message.contains("primitive_radius"), "{message}");
        let message = sssm(r#"{"offsets": []}"#).0.expect_err("no offsets").as_string().unwrap();
        assert!(message.contains("offsets"), "{message}");
        let message = sssm(r#"{"radus": 3}"#).0.expect_err("unknown field").as_string().unwrap();
        assert!(message.starts_with("SSSM parameters: unknown field `radus`"), "{message}");
    }

    #[wasm_bindgen_test]
    fn bounds_of_points() {
        let b = Bounds::of(&[Vec3::new(1.0, -2.0, 3.0), Vec3::new(-1.0, 5.0, 0.0)]);
        assert_eq!((b.min, b.max), ([-1.0, -2.0, 0.0], [1.0, 5.0, 3.0]));
        assert_eq!(Bounds::of(&[]).min, [-0.5; 3]);
    }
}
