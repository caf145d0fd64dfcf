//! The ground truth's state: its file, the choices it is read with, and what came of it.

use crate::protocol::MethodView;
use crate::segment::truth_import::Imported;
use leptos::prelude::*;
use std::sync::Arc;

/// Where the ground truth stands.
#[derive(Debug, Clone, PartialEq)]
pub enum TruthState {
    None,
    Loaded(Arc<Imported>),
    /// Why the file could not be read (the file's name first).
    Failed(String),
}

/// The ground truth's file, the choices it is read with, and what came of it.
#[derive(Debug, Clone, Copy)]
pub struct GroundTruth {
    /// The file's name and text.
    pub file: RwSignal<Option<(String, Arc<String>)>>,
    /// The number CSV frames start at (`#truth-base`).
    pub base: RwSignal<String>,
    /// The labels' frame rate as typed (`#truth-fps`; empty: the take's).
    pub fps: RwSignal<String>,
    /// The trial of a shared-data CSV (`#truth-trial`; empty: the take's name or the only one).
    pub trial: RwSignal<String>,
    pub state: RwSignal<TruthState>,
    /// The trials of a shared-data CSV (offered in `#truth-trial`; empty for other files).
    pub trials: RwSignal<Vec<String>>,
    /// The truth as a row's segmentation (each label a cluster, so a colour).
    pub view: RwSignal<Option<Arc<MethodView>>>,
}

impl GroundTruth {
    pub fn new() -> GroundTruth {
        GroundTruth {
            file: RwSignal::new(None),
            base: RwSignal::new("1".into()),
            fps: RwSignal::new(String::new()),
            trial: RwSignal::new(String::new()),
            state: RwSignal::new(TruthState::None),
            trials: RwSignal::new(Vec::new()),
            view: RwSignal::new(None),
        }
    }

    /// The truth, when one is loaded.
    pub fn truth(&self) -> Option<Arc<Imported>> {
        self.state.with(|s| match s {
            TruthState::Loaded(i) => Some(i.clone()),
            _ => None,
        })
    }

    /// `#row-truth`'s id and spans, for the keyboard's previous / next segment (none when empty).
    pub fn row_spans(&self) -> Vec<(String, Vec<(usize, usize)>)> {
        self.view.with_untracked(|v| {
            v.as_ref()
                .map(|v| {
                    vec![("truth".to_string(), v.segmentation.segments.iter().map(|s| (s.start, s.end)).collect())]
                })
                .unwrap_or_default()
        })
    }
}

impl Default for GroundTruth {
    fn default() -> Self {
        GroundTruth::new()
    }
}
