//! Fitting the k-NN on labelled takes into a model file.

use super::{Knn, KnnParams, Labelled};
use crate::labeller::corpus::{header, FoldLabels, FoldTakes, ModelMeta};
use crate::labeller::model::{Json, Model, Provenance};
use crate::motion::Motion;

/// Fits a k-NN model with `params` on `takes` (motions with per-file-frame labels; unlabelled frames left out).
pub fn fit_knn_model(
    takes: &[(&Motion, &[Option<usize>])],
    classes: &[String],
    meta: &ModelMeta,
    params: KnnParams,
) -> Result<Model, String> {
    let knn = fit_knn(takes, params)?;
    let provenance = Provenance {
        command: meta.command.clone(),
        data_hash: meta.data_hash.clone(),
        takes: takes.iter().map(|t| t.0.name.clone()).collect(),
        frames: takes.iter().map(|t| t.1.iter().flatten().count()).sum(),
        options: super::model::recorded_options()?,
        epochs_run: 0,
        best_epoch: 0,
        take_sha256: Vec::new(),
        members: Vec::new(),
    };
    let mut h = header(&super::method::KNN, classes, meta, provenance);
    h.joints = params.input.row_names();
    h.knn = Some(Json::of(&params)?);
    Ok(Model { header: h, labeller: Box::new(knn) })
}

/// The k-NN on the labelled frames of `takes`.
pub fn fit_knn(takes: &[(&Motion, &[Option<usize>])], params: KnnParams) -> Result<Knn, String> {
    // the k-NN takes a label for every frame: unlabelled stretches are cut out as separate takes
    let mut parts: Vec<(Motion, Vec<usize>)> = Vec::new();
    for (m, labels) in takes {
        if labels.iter().all(Option::is_some) {
            parts.push(((*m).clone(), labels.iter().map(|l| l.unwrap_or(0)).collect()));
        } else {
            let mut start = None;
            for f in 0..=labels.len() {
                match (labels.get(f).copied().flatten(), start) {
                    (Some(_), None) => start = Some(f),
                    (None, Some(s)) => {
                        if f - s >= 30 {
                            let sub = m.slice(s, f);
                            parts.push((sub, labels[s..f].iter().map(|l| l.unwrap_or(0)).collect()));
                        }
                        start = None;
                    }
                    _ => {}
                }
            }
        }
    }
    let labelled: Vec<Labelled> = parts.iter().map(|(m, l)| Labelled { motion: m, labels: l }).collect();
    if labelled.is_empty() {
        return Err("no labelled stretch of at least 30 frames to fit the k-NN on".into());
    }
    Knn::fit(&labelled, params)
}

/// The k-NN's votes the nested protocol chooses from on the validation take.
pub const KNN_KS: [usize; 6] = [1, 3, 5, 9, 15, 25];

/// The k-NN beside the network in one fold of the nested held-out protocol (`crate::methods::dtfcn::corpus::
/// predict_held_out`): its k chosen among [`KNN_KS`] on the validation take (fitted without it, scored on its labels),
/// then fitted on every take but the held-out one; the held-out take's votes.
pub fn knn_fold(takes: &FoldTakes) -> Result<FoldLabels<Knn>, String> {
    // the k-NN's k: fitted without the validation take, scored on its (noisy) labels
    let mut knn_k = (KnnParams::default().k, f64::MIN);
    for k in KNN_KS {
        let votes = fit_knn(&takes.inner, KnnParams { k, ..KnnParams::default() })?.predict(takes.validation.0)?;
        let (mut right, mut total) = (0usize, 0usize);
        for (v, l) in votes.iter().zip(takes.validation.1) {
            if let Some(l) = l {
                total += 1;
                right += usize::from(v.0 == *l);
            }
        }
        let accuracy = right as f64 / total.max(1) as f64;
        if accuracy > knn_k.1 + 1e-12 {
            knn_k = (k, accuracy);
        }
    }
    let fitted = fit_knn(&takes.train, KnnParams { k: knn_k.0, ..KnnParams::default() })?;
    let labels = fitted.predict(takes.held)?;
    Ok(FoldLabels { labels, setting: knn_k.0, model: fitted })
}

/// The open-set unknown of a k-NN with `params` made on `takes` ([`crate::labeller::openset`], issue 50): every
/// class in turn is left out — each take holding it labelled by a k-NN fitted on the other takes without the class,
/// decoded as the model will be (`decoding`, `threshold`), its frames scored by their class's training windows
/// ([`Knn::voted_ratios_going`]) — and the ratio with the best open-set frame accuracy over the frames of every such
/// fold is chosen, kept only when its gain over the scored takes is sure ([`choose_confirmed`]). `None` when no class can be left out (one take; no class held by a take while another take has
/// other labels) or once `go` (asked with the share of the folds done) answers false.
pub fn choose_open_set_unknown(
    takes: &[(&Motion, &[Option<usize>])],
    classes: usize,
    params: KnnParams,
    decoding: &crate::labeller::decode::Decoding,
    threshold: f64,
    go: crate::method::Go,
) -> Result<Option<crate::labeller::openset::OpenSetChoice>, String> {
    use crate::labeller::decode::file_labels;
    use crate::labeller::openset::{choose_confirmed, OpenSetFrame};
    let holds = |t: usize, c: usize| takes[t].1.contains(&Some(c));
    let folds: Vec<(usize, usize)> = (0..classes)
        .flat_map(|c| (0..takes.len()).map(move |v| (c, v)))
        .filter(|&(c, v)| {
            holds(v, c) && (0..takes.len()).any(|i| i != v && takes[i].1.iter().any(|l| l.is_some_and(|l| l != c)))
        })
        .collect();
    // each scored take's frames, from every fold that scored it
    let (mut by_take, mut done): (Vec<Vec<OpenSetFrame>>, usize) = (vec![Vec::new(); takes.len()], 0);
    for (n, &(c, v)) in folds.iter().enumerate() {
        if !go(n as f64 / folds.len() as f64) {
            return Ok(None);
        }
        let without: Vec<Vec<Option<usize>>> = (0..takes.len())
            .filter(|&i| i != v)
            .map(|i| takes[i].1.iter().map(|l| l.filter(|&l| l != c)).collect())
            .collect();
        let train: Vec<(&Motion, &[Option<usize>])> =
            (0..takes.len()).filter(|&i| i != v).zip(&without).map(|(i, l)| (takes[i].0, l.as_slice())).collect();
        let knn = match fit_knn(&train, params) {
            Ok(k) => k,
            // the other takes hold no stretch long enough without the class: no fold here
            Err(_) => continue,
        };
        let (motion, truth) = takes[v];
        let (p, source) = knn.probabilities_at(motion, classes)?;
        let decoded = file_labels(&p, &source, params.fps, motion.frames(), decoding, threshold);
        let labels: Vec<Option<usize>> = decoded.iter().map(|d| d.0).collect();
        let Some(ratios) = knn.voted_ratios_going(motion, &labels, &mut |_| true)? else { return Ok(None) };
        done += 1;
        by_take[v].extend(truth.iter().zip(&labels).zip(&ratios).filter_map(|((t, l), r)| {
            let t = (*t)?;
            Some(OpenSetFrame {
                score: if l.is_some() { *r } else { f32::INFINITY },
                unseen: t == c,
                right: *l == Some(t),
            })
        }));
    }
    if done == 0 || by_take.iter().all(Vec::is_empty) {
        return Ok(None);
    }
    Ok(Some(crate::labeller::openset::OpenSetChoice { folds: done, ..choose_confirmed(&by_take) }))
}
