//! The timeline's other rows as my labels see them ([`OtherRow`]): the ground truth's, the methods' and the
//! labels carried across the library, with their segments' colours — the rows my labels copy from, snap to
//! and take their colours from — and the label vocabulary they give ([`vocabulary_of`]).

use crate::app::library::carry::TRANSFERRED;
use crate::app::my_labels::edits::MyLabels as Model;
use crate::app::my_labels::vocabulary::vocabulary;
use crate::app::state::AppState;
use crate::app::timeline::rows::is_labelling;
use crate::app::timeline::rows::labels_classes;
use crate::protocol::MethodView;
use crate::segment::palette::{action_colour, cluster_colour};
use crate::segment::Level;
use leptos::prelude::*;

/// A row of the timeline besides mine: its id, its label and its segments (frames, label, the
/// CSS colour it is drawn in, `None` when hatched).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct OtherRow {
    pub(super) id: String,
    pub(super) name: String,
    pub(super) segments: Vec<(usize, usize, String, Option<String>)>,
    /// Its labels are classes (the ground truth, a labelling method's): my labels' vocabulary.
    pub(super) classes: bool,
}

/// The colour a segment has in its method's row (as `method_panel` draws it; `None`: hatched).
fn segment_colour(state: AppState, v: &MethodView, s: &crate::segment::Segment) -> Option<String> {
    if is_labelling(v) {
        return s.cluster.map(|_| state.label_css(&s.label));
    }
    match (s.level, s.cluster) {
        (Level::Transition, _) => None,
        (Level::Primitive, Some(c)) => Some(cluster_colour(c, s.mirror_of)),
        (_, Some(c)) => {
            let [r, g, b] = action_colour(c);
            Some(format!("rgb({r}, {g}, {b})"))
        }
        (_, None) => Some("#888".to_string()),
    }
}

/// Every method row with segments, in the page's order (tracks the methods' results).
pub(super) fn other_rows(state: AppState) -> Vec<OtherRow> {
    let mut rows = Vec::new();
    // the imported ground truth first: copying it is where a correction usually starts
    state.truth.view.with(|v| {
        let Some(v) = v else { return };
        let mut segments: Vec<_> = v
            .segmentation
            .segments
            .iter()
            .map(|s| (s.start, s.end, s.label.clone(), segment_colour(state, v, s)))
            .collect();
        segments.sort_by_key(|s| s.0);
        if !segments.is_empty() {
            rows.push(OtherRow { id: "truth".into(), name: "Ground truth".into(), segments, classes: true });
        }
    });
    for slot in state.methods {
        slot.view.with(|v| {
            let Some(v) = v else { return };
            for primitive in [false, true] {
                let mut segments: Vec<_> = v
                    .segmentation
                    .segments
                    .iter()
                    .filter(|s| (s.level == Level::Primitive) == primitive)
                    .map(|s| (s.start, s.end, s.label.clone(), segment_colour(state, v, s)))
                    .collect();
                if segments.is_empty() {
                    continue;
                }
                segments.sort_by_key(|s| s.0);
                // the row's name as the timeline gives it (view::rows)
                let kind = crate::app::timeline::rows::row_kind(Some(&**v), primitive);
                rows.push(OtherRow {
                    id: format!("{}-{}", slot.info.name, if primitive { "primitives" } else { "actions" }),
                    name: crate::app::timeline::rows::row_name(&slot.info.short, kind),
                    segments,
                    classes: crate::app::timeline::rows::is_labelling(v) && !primitive,
                });
            }
        });
    }
    // the labels carried across the library to this take
    if let Some(v) = crate::app::library::panel::transferred_view(state) {
        let segments = v
            .segmentation
            .segments
            .iter()
            .map(|s| (s.start, s.end, s.label.clone(), segment_colour(state, &v, s)))
            .collect();
        rows.push(OtherRow { id: TRANSFERRED.into(), name: "Carried labels".into(), segments, classes: true });
    }
    rows
}

/// My labels' vocabulary ([`vocabulary`]): the truth's classes, the labelling methods' model
/// classes (those their rows show, and every class of the models the user loaded or trained),
/// then the labels I gave — never an unsupervised method's cluster names.
pub(super) fn vocabulary_of(state: AppState, others: Memo<Vec<OtherRow>>, model: RwSignal<Model>) -> Vec<String> {
    others.with(|others| {
        let truth: Vec<&str> =
            others.iter().filter(|r| r.id == "truth").flat_map(|r| r.segments.iter().map(|s| s.2.as_str())).collect();
        let mut models: Vec<String> = others
            .iter()
            .filter(|r| r.classes && r.id != "truth")
            .flat_map(|r| r.segments.iter().map(|s| s.2.clone()))
            .collect();
        for slot in state.methods.iter().filter(|m| labels_classes(&m.info.name)) {
            if let Some(sup) = &slot.supervised {
                sup.models.with(|list| models.extend(list.iter().flat_map(|m| m.info.classes.iter().cloned())));
            }
        }
        let excluded: Vec<&str> =
            others.iter().filter(|r| !r.classes).flat_map(|r| r.segments.iter().map(|s| s.2.as_str())).collect();
        let mine = model.with(|m| m.labels_used());
        vocabulary(truth, models.iter().map(String::as_str), mine.iter().map(String::as_str), &excluded)
    })
}
