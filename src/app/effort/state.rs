//! The Effort bars' state, shared by the toggle, every lane and the loader: what was asked of the worker
//! for which row, and its answers.

use crate::method::Annotations;
use crate::segment::Effort;
use leptos::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;

/// One row's annotation: for which take, parameters and segments, and the answer.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Entry {
    pub(super) take: u32,
    pub(super) params: serde_json::Value,
    pub(super) spans: Arc<Vec<(usize, usize)>>,
    pub(super) result: Result<Arc<Annotations>, String>,
}

/// What a key asked: take, parameters and segments.
pub(super) type Asked = (u32, serde_json::Value, Arc<Vec<(usize, usize)>>);

/// The bars' state, shared by the toggle, every lane and the loader.
#[derive(Debug, Clone, Copy)]
pub struct EffortBars {
    /// The bars are shown.
    pub on: RwSignal<bool>,
    /// Counts the takes shown (part of every key: another take asks again).
    pub(super) take: RwSignal<u32>,
    /// The annotations by key ([`super::layout::cache_key`]).
    pub(super) entries: RwSignal<HashMap<u64, Entry>>,
    /// The keys asked of the worker and not answered yet, with what each asked: take, parameters
    /// and segments (kept with its answer).
    pub(super) asked: RwSignal<HashMap<u64, Asked>>,
    /// What the worker is doing for the bars (a stage), or the last failure: (failed, text).
    pub(super) status: RwSignal<Option<(bool, String)>>,
}

impl EffortBars {
    pub fn new() -> EffortBars {
        EffortBars {
            on: RwSignal::new(false),
            take: RwSignal::new(0),
            entries: RwSignal::new(HashMap::new()),
            asked: RwSignal::new(HashMap::new()),
            status: RwSignal::new(None),
        }
    }

    /// A new take is on screen: what was computed for the last one is let go.
    pub(super) fn new_take(&self) {
        self.take.update(|t| *t = t.wrapping_add(1));
        self.entries.update(HashMap::clear);
        self.asked.update(HashMap::clear);
        self.status.set(None);
    }

    /// Whether `key` is being computed (the loader asks only once).
    pub fn is_asked(&self, key: u64) -> bool {
        self.asked.with_untracked(|a| a.contains_key(&key))
    }

    /// `key` is sent to the worker: it asked for `spans` of take `take` with `params`.
    pub(super) fn asking(&self, key: u64, asked: Asked) {
        self.asked.update(|a| {
            a.insert(key, asked);
        });
    }

    /// The worker answered `key` (a failure's message is kept too, so that it is not asked again
    /// in a loop; the status says it). An answer nobody waits for any more (another take) is dropped.
    pub fn answered(&self, key: u64, result: Result<Annotations, String>) {
        let mut asked = None;
        self.asked.update(|a| asked = a.remove(&key));
        let Some((take, params, spans)) = asked else { return };
        if let Err(message) = &result {
            self.status.set(Some((true, format!("Effort: {message}"))));
        } else if self.asked.with_untracked(HashMap::is_empty) {
            self.status.set(None);
        }
        let entry = Entry { take, params, spans, result: result.map(Arc::new) };
        self.entries.update(|e| {
            e.insert(key, entry);
        });
    }

    /// The annotation `key` was lost with its worker (`message` says how): not kept as the row's answer, so that the
    /// row asks again when the bars are next turned on.
    pub fn lost(&self, key: u64, message: String) {
        self.asked.update(|a| {
            a.remove(&key);
        });
        self.status.set(Some((true, format!("Effort: {message} (turn the bars off and on to ask again)"))));
    }

    /// The worker is at `stage` of a row's annotation.
    pub fn stage(&self, stage: &str, fraction: Option<f64>) {
        let percent = fraction.map(|f| format!(" {:.0} %", f * 100.0)).unwrap_or_default();
        self.status.set(Some((false, format!("Effort: {stage}{percent}…"))));
    }

    /// The Effort computed for the take on screen with the parameters `params`, by segment.
    pub(super) fn known(&self, params: &serde_json::Value) -> HashMap<(usize, usize), Effort> {
        let take = self.take.get_untracked();
        let mut known = HashMap::new();
        self.entries.with_untracked(|entries| {
            for e in entries.values().filter(|e| e.take == take && e.params == *params) {
                let Ok(a) = &e.result else { continue };
                for (span, annotated) in e.spans.iter().zip(&a.segments) {
                    if let Some(effort) = annotated.effort {
                        known.insert(*span, effort);
                    }
                }
            }
        });
        known
    }
}

impl Default for EffortBars {
    fn default() -> Self {
        Self::new()
    }
}
