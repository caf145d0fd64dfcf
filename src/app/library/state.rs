//! The library's state (signals; cheap to copy): its takes and their files, the worker's queue over them, the
//! shared clusters and their names, the labels carried across it, and the library's jobs in the workers.

use crate::app::library::carry::{Carried, Route};
use crate::app::library::names::ClusterNames;
use crate::app::library::queue::Queue;
use crate::app::library::takes::{Playlist, Shared, Spot};
use crate::library::{LibraryTake, TakeFeatures};
use crate::protocol::RunId;
use leptos::prelude::*;
use std::sync::Arc;
use web_sys::File;

/// The library tab's id.
pub const TAB: &str = "library";

/// A take of the library as the page keeps it: its file (a handle, not its bytes) and, for an AMC
/// motion, its ASF skeleton's.
#[derive(Clone)]
pub struct Source {
    pub motion: File,
    pub skeleton: Option<File>,
}

/// A clip export of the library under way (issue 49: "clips encoded and zipped one take at a time"): the worker cuts
/// and zips one take's clips per request; each zip's entries join the archive as a part of the Blob the page saves
/// ([`crate::clips::ZipJoin`]), so neither the page nor the worker ever holds more than one take's files and clips.
pub struct ClipExport {
    /// The zip's name.
    pub file: String,
    pub to_origin: bool,
    /// The takes still to cut: library index, its segments to cut, the name its clips are named from (unique among
    /// the export's takes, its extension kept).
    pub todo: std::collections::VecDeque<(usize, crate::segment::Segmentation, String)>,
    /// Takes in the export.
    pub takes: usize,
    pub join: crate::clips::ZipJoin,
    /// The archive's parts so far (`Uint8Array`s).
    pub parts: js_sys::Array,
    pub clips: usize,
}

/// The library's state (signals; cheap to copy).
#[derive(Clone, Copy)]
pub struct LibraryState {
    /// The takes and the worker's queue over them.
    pub queue: RwSignal<Queue>,
    /// Each take's files, in the queue's order.
    pub(super) files: StoredValue<Vec<Source>, LocalStorage>,
    /// The method (registry name) the library's takes are segmented with.
    pub method: RwSignal<String>,
    /// The library's runs in the pool's workers: their run ids and takes.
    pub running: StoredValue<Vec<(RunId, usize)>>,
    /// The library's clip export in the worker: the take being cut.
    pub clip_run: StoredValue<Option<RunId>>,
    /// The clip export under way, one take at a time.
    pub clip_export: StoredValue<Option<ClipExport>, LocalStorage>,
    /// The take of the library on screen (`None`: the take on screen is not one of the library's).
    pub open: RwSignal<Option<usize>>,
    /// The names the user gave the shared clusters.
    pub names: RwSignal<ClusterNames>,
    /// The cluster whose occurrences are playing.
    pub playlist: RwSignal<Option<Playlist>>,
    /// What the last export (or a refused file) did: (failed, message).
    pub status: RwSignal<Option<(bool, String)>>,
    /// Each take's features for the shared clusters (or why it has none), in the queue's order.
    pub(super) features: StoredValue<Vec<Option<Result<TakeFeatures, String>>>>,
    /// The shared clusters of the takes matched last.
    pub shared: RwSignal<Option<Arc<Shared>>>,
    /// The matching in the worker: its run and the takes sent.
    pub cluster_run: StoredValue<Option<(RunId, Vec<usize>)>>,
    /// Where the matching stands: (failed, message).
    pub matching: RwSignal<Option<(bool, String)>>,
    /// The occurrence waiting for its take to open before it plays, and the take on screen when it
    /// was asked (its address: the take opened for it is another).
    pub(super) pending: StoredValue<Option<(Spot, usize)>>,
    /// An occurrence is playing (it ends where the playlist's current one ends).
    pub(super) playing: StoredValue<bool>,
    /// How labels are carried across the library.
    pub route: RwSignal<Route>,
    /// The carrying by a supervised method (k-NN or DT-FCN) trained on the source's labels, under way.
    pub by_model: StoredValue<Option<ModelCarry>>,
    /// A carrying (either route) is under way (`#library-carry-cancel` shown).
    pub carry_busy: RwSignal<bool>,
    /// The labels carried last.
    pub carried: RwSignal<Option<Arc<Carried>>>,
    /// The carrying in the worker: its run, the source take and the takes sent (library indices).
    pub transfer_run: StoredValue<Option<(RunId, usize, Vec<usize>)>>,
    /// Where the carrying stands: (failed, message).
    pub carrying: RwSignal<Option<(bool, String)>>,
    /// Asks my labels to copy the take on screen's carried labels (counts the asks).
    pub copy_asked: RwSignal<u32>,
}

/// The carrying by a supervised method (`route`: the k-NN or DT-FCN) trained on the take on screen's labels: first
/// the training (the method panel's, its model kept as the panel keeps it), then every other take labelled with
/// the model, one after another (`library_take` with that method).
#[derive(Debug, Clone)]
pub struct ModelCarry {
    /// The route, and so the method trained.
    pub route: Route,
    /// The source take (library index), its file name, fps and every frame's label.
    pub source: usize,
    pub file: String,
    pub fps: f64,
    pub labels: Vec<Option<String>>,
    /// The model's name, once trained (`None`: training).
    pub model: Option<String>,
    /// The takes still to label, the one being labelled (its run) and how many in all.
    pub todo: Vec<usize>,
    pub running: Option<(RunId, usize)>,
    pub count: usize,
    /// The takes labelled (library index, the method's segmentation) and those that failed.
    pub done: Vec<(usize, crate::segment::Segmentation)>,
    pub failed: Vec<String>,
    /// The takes the model does not fit ("name: why"): labelled unknown by the method's fit check.
    pub misfits: Vec<String>,
}

impl std::fmt::Debug for LibraryState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LibraryState({} takes)", self.queue.with_untracked(|q| q.entries.len()))
    }
}

impl LibraryState {
    pub fn new() -> LibraryState {
        LibraryState {
            queue: RwSignal::new(Queue::default()),
            files: StoredValue::new_local(Vec::new()),
            method: RwSignal::new("sssm".into()),
            running: StoredValue::new(Vec::new()),
            clip_run: StoredValue::new(None),
            clip_export: StoredValue::new_local(None),
            open: RwSignal::new(None),
            names: RwSignal::new(ClusterNames::default()),
            playlist: RwSignal::new(None),
            status: RwSignal::new(None),
            features: StoredValue::new(Vec::new()),
            shared: RwSignal::new(None),
            cluster_run: StoredValue::new(None),
            matching: RwSignal::new(None),
            pending: StoredValue::new(None),
            playing: StoredValue::new(false),
            route: RwSignal::new(Route::Nearest),
            by_model: StoredValue::new(None),
            carry_busy: RwSignal::new(false),
            carried: RwSignal::new(None),
            transfer_run: StoredValue::new(None),
            carrying: RwSignal::new(None),
            copy_asked: RwSignal::new(0),
        }
    }

    /// Empties the library (its takes, clusters, names and carried labels): the page starts afresh. Its jobs in the
    /// workers are cancelled first ([`crate::app::library::library_jobs::LibraryJobs::clear`]).
    pub(super) fn clear(&self) {
        self.queue.set(Queue::default());
        self.files.set_value(Vec::new());
        self.features.set_value(Vec::new());
        self.open.set(None);
        self.names.set(ClusterNames::default());
        self.playlist.set(None);
        self.status.set(None);
        self.shared.set(None);
        self.matching.set(None);
        self.pending.set_value(None);
        self.playing.set_value(false);
        self.carried.set(None);
        self.carrying.set(None);
    }

    /// Keeps take `i`'s features (or why it has none).
    pub fn set_features(&self, i: usize, features: Result<TakeFeatures, String>) {
        self.features.update_value(|f| {
            if f.len() <= i {
                f.resize(i + 1, None);
            }
            f[i] = Some(features);
        });
    }

    /// The takes that can be matched (segmented, with features) as the core takes them, and their
    /// indices in the library.
    pub fn matchable(&self) -> (Vec<LibraryTake>, Vec<usize>) {
        let features = self.features.get_value();
        self.queue.with_untracked(|q| {
            q.segmented()
                .into_iter()
                .filter_map(|(i, segmentation)| match features.get(i) {
                    Some(Some(Ok(f))) => Some((
                        LibraryTake {
                            name: q.entries[i].name.clone(),
                            features: f.clone(),
                            segmentation: segmentation.clone(),
                        },
                        i,
                    )),
                    _ => None,
                })
                .unzip()
        })
    }

    /// Adds takes (their files), queued; returns their indices.
    pub fn add(&self, sources: Vec<Source>) -> std::ops::Range<usize> {
        let names: Vec<String> = sources.iter().map(|s| s.motion.name()).collect();
        self.files.update_value(|f| f.extend(sources));
        let mut added = 0..0;
        self.queue.update(|q| added = q.add(names));
        added
    }

    /// The bytes of the library's take files (motion and skeleton), the total [`crate::app::library::takes::within_cap`]
    /// bounds.
    pub fn held_bytes(&self) -> f64 {
        self.files
            .with_value(|f| f.iter().map(|s| s.motion.size() + s.skeleton.as_ref().map_or(0.0, |k| k.size())).sum())
    }

    /// Library take `i`'s name.
    pub fn take_name(&self, i: usize) -> String {
        self.queue.with_untracked(|q| q.entries.get(i).map(|e| e.name.clone()).unwrap_or_default())
    }

    /// Names cluster `id` of the matching shown (kept with what it holds: its names follow it to the next matching).
    pub fn rename(&self, id: usize, name: &str) {
        let spots = self.shared.with_untracked(|s| {
            let s = s.as_ref()?;
            s.named_spots(|i| self.take_name(i)).into_iter().find(|(c, _)| *c == id).map(|(_, spots)| spots)
        });
        self.names.update(|n| n.rename(id, name, spots.unwrap_or_default()));
    }

    /// A new matching shown: the names given follow their clusters.
    pub fn show_matching(&self, shared: Shared) {
        let spots = shared.named_spots(|i| self.take_name(i));
        self.names.update(|n| n.follow(&spots));
        self.shared.set(Some(Arc::new(shared)));
    }

    /// Whether the library has a take (untracked).
    pub fn shown_untracked(&self) -> bool {
        self.queue.with_untracked(|q| !q.entries.is_empty())
    }

    /// Take `i`'s files.
    pub fn source(&self, i: usize) -> Option<Source> {
        self.files.with_value(|f| f.get(i).cloned())
    }

    /// Whether the library has a take (its tab is shown).
    pub fn shown(&self) -> bool {
        self.queue.with(|q| !q.entries.is_empty())
    }

    /// Take `i`'s segmentation — with the shared clusters' ids when it was matched, its clusters'
    /// segments labelled by their names — and whether it is the shared one.
    pub(super) fn labelled(&self, i: usize) -> Option<(crate::segment::Segmentation, bool)> {
        let names = self.names.get();
        let shared = self.shared.with(|s| s.as_ref().and_then(|s| s.segmentation(i).map(|seg| names.label(seg))));
        match shared {
            Some(seg) => Some((seg, true)),
            None => self.queue.with(|q| q.entries.get(i).and_then(|e| e.segmentation.clone()).map(|s| (s, false))),
        }
    }

    /// Every segmented take's segmentation as the CSV exports it: its carried labels where labels
    /// were carried to it, else the shared one named where the take was matched, else its own.
    pub(super) fn all_labelled(&self) -> Vec<crate::segment::Segmentation> {
        let count = self.queue.with_untracked(|q| q.entries.len());
        let segmented = (0..count).filter_map(|i| self.labelled(i).map(|(s, _)| (i, s))).collect();
        crate::app::library::carry::export(segmented, self.carried.get_untracked().as_deref())
    }
}

impl Default for LibraryState {
    fn default() -> Self {
        LibraryState::new()
    }
}
