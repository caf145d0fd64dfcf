//! From a label CSV and takes to what a labeller is trained on, the same for both labellers and for the command line
//! and the browser: matching label rows to takes, the class list, each take's per-frame labels, and the header a new
//! model file starts from.

use super::fit::TravelProfile;
use super::method::Kind;
use super::model::{ModelHeader, Provenance};
use crate::labels::{same_file, LabelRow};
use crate::motion::Motion;

/// The class names and, per take, the class of every file frame (`None` = unlabelled).
pub type ClassLabels = (Vec<String>, Vec<Vec<Option<usize>>>);

/// The files `rows` name that are not among `takes` (their rows are left out of training).
pub fn rows_without_takes(rows: &[LabelRow], takes: &[&Motion]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for r in rows {
        if !takes.iter().any(|m| same_file(&m.name, &r.file)) && !out.contains(&r.file) {
            out.push(r.file.clone());
        }
    }
    out
}

/// The classes of `rows` in order of first appearance, and each take's per-file-frame labels
/// (`None` where no row covers a frame). Rows naming no given take are left out
/// ([`rows_without_takes`] names them); rows past a take's end are refused.
pub fn class_labels(rows: &[LabelRow], takes: &[&Motion]) -> Result<ClassLabels, String> {
    let mut classes: Vec<String> = Vec::new();
    let mut labels: Vec<Vec<Option<usize>>> = takes.iter().map(|m| vec![None; m.frames()]).collect();
    for (i, r) in rows.iter().enumerate() {
        let Some(t) = takes.iter().position(|m| same_file(&m.name, &r.file)) else {
            continue; // a row of a take not given (see `rows_without_takes`)
        };
        let n = takes[t].frames();
        if r.end_frame >= n {
            return Err(format!(
                "label row {} ({} frames {}–{}) goes past the take's last frame {} (frames are 0-based)",
                i + 2,
                r.file,
                r.start_frame,
                r.end_frame,
                n.saturating_sub(1)
            ));
        }
        let c = classes.iter().position(|c| *c == r.label).unwrap_or_else(|| {
            classes.push(r.label.clone());
            classes.len() - 1
        });
        labels[t][r.start_frame..=r.end_frame].iter_mut().for_each(|l| *l = Some(c));
    }
    if classes.len() < 2 {
        return Err(format!("the labels name {} class(es); a labeller needs at least 2", classes.len()));
    }
    // what a model file may hold (`model::check_header`): refused here, before training, not after it
    let max = super::model::MAX_CLASSES;
    if classes.len() > max {
        return Err(format!("the labels name {} classes; a labeller holds at most {max}", classes.len()));
    }
    if let Some(c) = classes.iter().find(|c| c.chars().count() > super::model::MAX_NAME_CHARS) {
        let shown: String = c.chars().take(40).collect();
        return Err(format!(
            "the label `{shown}…` has {} characters; a labeller's class names have at most {}",
            c.chars().count(),
            super::model::MAX_NAME_CHARS
        ));
    }
    if let Some(c) = classes.iter().find(|c| c.trim().is_empty() || c.chars().any(char::is_control)) {
        let shown: String = c.chars().map(|ch| if ch.is_control() { '·' } else { ch }).collect();
        return Err(format!("the label `{shown}` is blank or has a control character: a class needs a name"));
    }
    Ok((classes, labels))
}

/// Frame rates a label file may have been written at by mistake (its frames counted at a video's or a
/// down-sampled take's rate instead of the file's).
const LABEL_RATES: [f64; 7] = [24.0, 25.0, 30.0, 50.0, 60.0, 100.0, 120.0];

/// A warning for each take whose labels look written at another frame rate: they end well before the take does,
/// and counted at one of [`LABEL_RATES`] below the file's they would end within 5 % of its end — the mocap6 truth
/// converted at 30 Hz for a 120 Hz take labels only its first quarter, silently, and a model taught on that quarter
/// says every faster take does not fit it. Labels that stop early for any other reason (a take labelled in part)
/// raise nothing.
pub fn labels_at_another_rate(takes: &[&Motion], labels: &[Vec<Option<usize>>]) -> Vec<String> {
    takes
        .iter()
        .zip(labels)
        .filter_map(|(m, l)| {
            let n = m.frames();
            let last = l.iter().rposition(Option::is_some)? + 1;
            if n < 2 || last as f64 > 0.8 * n as f64 {
                return None;
            }
            let rate = LABEL_RATES.iter().copied().find(|&r| {
                r < m.fps - 0.5 && ((last as f64 * m.fps / r) - n as f64).abs() <= 0.05 * n as f64
            })?;
            Some(format!(
                "the labels of {} end at frame {last} of {n} ({:.0} %), where frames counted at {rate:.0} Hz would span \
                 the take ({:.0} Hz): is the label file at {rate:.0} Hz?",
                m.name,
                100.0 * last as f64 / n as f64,
                m.fps
            ))
        })
        .collect()
}

/// A colour per class ([`crate::segment::palette::class_colour`]).
pub fn class_colours(classes: usize) -> Vec<String> {
    (0..classes).map(crate::segment::palette::class_colour).collect()
}

/// What to call a model and how it was made.
pub struct ModelMeta {
    pub name: String,
    pub command: String,
    pub data_hash: String,
    /// The decoding a run with `decoding = "model"` uses (none: raw per-frame labels).
    pub decoding: Option<super::decode::Decoding>,
    /// The unknown threshold its runs use unless they ask for another (the header's).
    pub unknown_threshold: f64,
    /// How fast the training takes' labelled frames travelled ([`travel_of`]; for the take fit).
    pub travel: Option<TravelProfile>,
}

/// The travel profile of the labelled frames of `takes` (per file frame labels), `None` when it
/// cannot be measured (a take without hips and feet: its model cannot label it either).
pub fn travel_of(takes: &[(&Motion, &[Option<usize>])]) -> Option<TravelProfile> {
    let taught: Vec<Vec<bool>> = takes.iter().map(|(_, l)| l.iter().map(Option::is_some).collect()).collect();
    let with: Vec<(&Motion, Option<&[bool]>)> =
        takes.iter().zip(&taught).map(|((m, _), t)| (*m, Some(&t[..]))).collect();
    TravelProfile::fit(&with).ok()
}

/// The header of a new model of `kind` with `classes`, named and made as `meta` and `provenance` say: the labeller's
/// own fields are for it to fill.
pub fn header(kind: &dyn Kind, classes: &[String], meta: &ModelMeta, provenance: Provenance) -> ModelHeader {
    ModelHeader {
        kind: kind.name().into(),
        name: meta.name.clone(),
        classes: classes.to_vec(),
        colours: class_colours(classes.len()),
        joints: kind.joint_names(),
        fps: super::input::NETWORK_FPS,
        unknown_threshold: meta.unknown_threshold as f32,
        decoding: meta.decoding,
        network: None,
        standardise: None,
        knn: None,
        travel: meta.travel,
        open_set: None,
        provenance,
        member_bytes: Vec::new(),
        payload_sha256: String::new(),
        written_by: format!("mocapseg {}", env!("CARGO_PKG_VERSION")),
    }
}

/// The takes of one fold of a nested held-out protocol as a labeller compared on the same folds is fitted on them
/// (labels per file frame, as the protocol gives them: with its label noise and masking): `inner` without the
/// validation take, the validation take whose labels choose the labeller's setting, `train` every take but the
/// held-out one, and the held-out take.
pub struct FoldTakes<'a> {
    pub inner: Vec<(&'a Motion, &'a [Option<usize>])>,
    pub validation: (&'a Motion, &'a [Option<usize>]),
    pub train: Vec<(&'a Motion, &'a [Option<usize>])>,
    pub held: &'a Motion,
}

/// What a labeller compared on a fold gives: the held-out take's labels per file frame (class, confidence), the
/// setting the validation take chose (the k-NN's k), and its model.
pub struct FoldLabels<M> {
    pub labels: Vec<(usize, f32)>,
    pub setting: usize,
    pub model: M,
}

#[cfg(test)]
mod tests {

    /// 30 Hz frames of a 120 Hz take end a quarter of the way: said, with the rate; a take labelled in part, or
    /// labelled to its end, says nothing.
    #[test]
    fn labels_written_at_another_rate_are_told() {
        let motion =
            crate::load::load_bytes("s.bvh", include_bytes!("../../www/sample.bvh"), &mut |_| {}).unwrap().motion;
        let n = motion.frames();
        assert!((motion.fps - 120.0).abs() < 0.01, "{}", motion.fps);
        let upto = |last: usize| -> Vec<Option<usize>> { (0..n).map(|f| (f < last).then_some(f % 2)).collect() };
        let warned = labels_at_another_rate(&[&motion], &[upto(n / 4)]);
        assert_eq!(warned.len(), 1, "{warned:?}");
        assert!(
            warned[0].starts_with(&format!("the labels of s.bvh end at frame {} of {n} (25 %)", n / 4)),
            "{}",
            warned[0]
        );
        assert!(warned[0].ends_with("is the label file at 30 Hz?"), "{}", warned[0]);
        assert!(labels_at_another_rate(&[&motion], &[upto(n / 2)]).iter().any(|w| w.contains("at 60 Hz?")));
        assert!(labels_at_another_rate(&[&motion], &[upto(n / 3)]).is_empty(), "a third is no rate's");
        assert!(labels_at_another_rate(&[&motion], &[upto(n)]).is_empty());
        assert!(labels_at_another_rate(&[&motion], &[vec![None; n]]).is_empty());
    }

    use super::*;

    /// Labels a model file could not hold (`model::check_header`) are refused before training, so that
    /// every model training writes loads again.
    #[test]
    fn labels_past_what_a_model_file_holds_are_refused_before_training() {
        let motion =
            crate::load::load_bytes("s.bvh", include_bytes!("../../www/sample.bvh"), &mut |_| {}).unwrap().motion;
        let row = |f: usize, label: String| LabelRow { file: "s.bvh".into(), start_frame: f, end_frame: f, label };
        let many: Vec<LabelRow> = (0..300).map(|i| row(i, format!("c{i}"))).collect();
        let e = class_labels(&many, &[&motion]).unwrap_err();
        assert!(e.contains("300 classes") && e.contains("at most 256"), "{e}");
        let ok: Vec<LabelRow> = (0..256).map(|i| row(i, format!("c{i}"))).collect();
        assert_eq!(class_labels(&ok, &[&motion]).unwrap().0.len(), 256);
        let long = vec![row(0, "a".into()), row(1, "b".repeat(101))];
        let e = class_labels(&long, &[&motion]).unwrap_err();
        assert!(e.contains("101 characters") && e.contains("at most 100"), "{e}");
        let control = vec![row(0, "a".into()), row(1, "b\tc".into())];
        let e = class_labels(&control, &[&motion]).unwrap_err();
        assert!(e.contains("`b·c`") && e.contains("control character"), "{e}");
    }

    #[test]
    fn colours_are_distinct_css_hex() {
        let c = class_colours(12);
        assert!(c.iter().all(|s| s.len() == 7 && s.starts_with('#')));
        let mut d = c.clone();
        d.sort();
        d.dedup();
        assert_eq!(d.len(), 12);
    }
}
