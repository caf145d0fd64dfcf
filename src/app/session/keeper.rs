//! Keeps the workspace in this browser as the user works, and sets it again when the page opens
//! ([`Keeper::restore`]): the take on screen (its file kept beside the record, within the record's size limit; the
//! bundled sample as a mark), its ground truth (file and choices), and each row's form — its model choice set again
//! once that model is in the choice (the user's models come back from this browser after the page starts). A take not
//! kept, or a storage that is full, is said in `#workspace-status`; `#workspace-forget` starts afresh. The library
//! is kept too: its takes' files (each within the take's limit, all within the library's), the method they are
//! segmented with and the names given to its clusters; when the page opens its takes are segmented and matched again,
//! and each name follows the cluster that holds its motion.

use crate::app::library::library_jobs::LibraryJobs;
use crate::app::library::names::ClusterNames;
use crate::app::library::state::Source;
use crate::app::loader::Loader;
use crate::app::session::record::{
    library_kept, not_kept, restored_text, take_kept, KeptLibrary, KeptLibraryTake, KeptTake, KeptTruth, Record,
};
use crate::app::session::store::{self, KeptFile};
use crate::app::state::{AppState, MethodSlot};
use gloo::timers::callback::Timeout;
use leptos::prelude::*;
use std::cell::{Cell, RefCell};
use std::collections::BTreeMap;
use std::rc::Rc;
use std::sync::Arc;

/// How long the forms and the truth must stay unchanged before the record is written again.
const SETTLE_MS: u32 = 300;

/// The workspace keeper; cheap to clone (one per page).
#[derive(Clone)]
pub struct Keeper(Rc<Inner>);

struct Inner {
    state: AppState,
    loader: Loader,
    library: LibraryJobs,
    /// What `#workspace-status` says: (a problem, the message).
    status: RwSignal<Option<(bool, String)>>,
    /// Whether the workspace kept was read (and set again): nothing is written before, so that the page's defaults
    /// never overwrite it.
    ready: Cell<bool>,
    /// The take as the record has it, and a count of its changes (the record's watcher tracks it).
    take: RefCell<Option<KeptTake>>,
    take_changes: RwSignal<u32>,
    /// The take restored, until it is on screen (it is not written again).
    restored: RefCell<Option<String>>,
    /// The ground truth to set again once its take is on screen.
    truth: RefCell<Option<(String, KeptTruth)>>,
    /// The next write of the record.
    timer: RefCell<Option<Timeout>>,
    /// The page's reactive owner (the model choices' watchers are made after an await).
    owner: Option<Owner>,
    /// Whether each of the library's takes has its files kept (in the library's order), and a count of its changes.
    library_kept: RefCell<Vec<bool>>,
    library_changes: RwSignal<u32>,
    /// The library's takes by name.
    library_takes: Memo<Vec<String>>,
}

impl Keeper {
    /// Keeps the workspace of `state` from now on (once [`Keeper::restore`] has read the one kept, or was skipped).
    pub fn new(state: AppState, loader: Loader, library: LibraryJobs) -> Keeper {
        // the library's takes by name (a take's progress changes its queue, not this)
        let library_takes = Memo::new(move |_| {
            state.library.queue.with(|q| q.entries.iter().map(|e| e.name.clone()).collect::<Vec<_>>())
        });
        let keeper = Keeper(Rc::new(Inner {
            state,
            loader,
            library,
            status: RwSignal::new(None),
            ready: Cell::new(false),
            take: RefCell::new(None),
            take_changes: RwSignal::new(0),
            restored: RefCell::new(None),
            truth: RefCell::new(None),
            timer: RefCell::new(None),
            owner: Owner::current(),
            library_kept: RefCell::new(Vec::new()),
            library_changes: RwSignal::new(0),
            library_takes,
        }));
        let shown = keeper.clone();
        Effect::new(move |_| {
            state.motion.track();
            shown.take_shown();
        });
        let takes = keeper.0.library_takes;
        let added = keeper.clone();
        Effect::new(move |_| {
            let count = takes.with(Vec::len);
            if added.0.ready.get() {
                added.keep_library_takes(count);
            }
        });
        let written = keeper.clone();
        Effect::new(move |_| {
            // every part of the record, tracked
            let record = written.record();
            if written.0.ready.get() {
                written.write_soon(record);
            }
        });
        keeper
    }

    /// What `#workspace-status` says.
    pub fn status(&self) -> RwSignal<Option<(bool, String)>> {
        self.0.status
    }

    /// The page starts without the workspace kept (its URL names what to show).
    pub fn skip(&self) {
        self.0.ready.set(true);
    }

    /// Sets the take as the record has it.
    fn set_take(&self, take: Option<KeptTake>) {
        *self.0.take.borrow_mut() = take;
        self.0.take_changes.update(|n| *n = n.wrapping_add(1));
    }

    /// Reads the workspace kept and sets it again: the rows' forms at once, then its take (or `fallback`, which loads
    /// the bundled sample, when none was kept) and, once that take is on screen, its ground truth.
    pub fn restore(&self, fallback: impl FnOnce() + 'static) {
        let this = self.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let record = match store::get_record().await {
                Ok(Some(record)) => record,
                Ok(None) => return this.start(fallback),
                Err(why) => {
                    this.0.status.set(Some((true, why)));
                    return this.start(fallback);
                }
            };
            let library = match &record.library {
                Some(kept) => kept_library_files(kept).await,
                None => Vec::new(),
            };
            let in_library = record.take.as_ref().and_then(|t| library.get(t.library?)?.as_ref());
            let take = match &record.take {
                Some(take) if take.kept && in_library.is_none() => match store::get_take().await {
                    Ok(Some(file)) if file.name == take.name => Some(Opened::Kept(file)),
                    Ok(_) => None,
                    Err(why) => {
                        web_sys::console::warn_1(&format!("{}: the file kept does not read: {why}", take.name).into());
                        None
                    }
                },
                _ => None,
            };
            this.apply(record, take, library, Apply { kept: true, from: "this browser".into(), missing: Vec::new() });
            this.start(fallback);
        });
    }

    /// Opens a project: the workspace it holds, with the take files found among those opened with it (`take`: the
    /// take on screen's; `library`: each library take's, in the project's order; `missing`: what was not found),
    /// replacing the workspace on screen; its files are then kept in this browser as if dropped.
    pub fn open_project(
        &self,
        from: &str,
        record: Record,
        take: Option<Vec<web_sys::File>>,
        library: Vec<Option<Source>>,
        missing: Vec<String>,
    ) {
        self.0.state.truth.file.set(None);
        self.0.library.clear();
        self.0.library_kept.borrow_mut().clear();
        self.0.restored.borrow_mut().take();
        self.apply(record, take.map(Opened::Files), library, Apply { kept: false, from: from.into(), missing });
    }

    /// Sets `record` on the page: each row's form, the library (`library`: its takes' files, in the record's order;
    /// `None` where not found), the side panel's tab, the take on screen (a library take opened as such, else `take`,
    /// else the sample when the record's was) and, once that take is on screen, its ground truth; says what came back.
    fn apply(&self, record: Record, take: Option<Opened>, library: Vec<Option<Source>>, how: Apply) {
        match &self.0.owner {
            Some(owner) => owner.with(|| self.set_forms(&record)),
            None => self.set_forms(&record),
        }
        let mut missing = how.missing;
        let library_at = match &record.library {
            Some(kept) => self.set_library(kept, library, how.kept, &mut missing),
            None => Vec::new(),
        };
        self.set_panel(&record.panel);
        let in_library = record.take.as_ref().and_then(|t| Some((t.name.clone(), (*library_at.get(t.library?)?)?)));
        let shown = match (take, in_library) {
            (_, Some((name, i))) => {
                self.0.library.open_library_take(i);
                Some(name)
            }
            (Some(Opened::Kept(KeptFile { name, file, skeleton })), None) => {
                self.0.loader.load_blob(&name, file, skeleton);
                Some(name)
            }
            (Some(Opened::Files(files)), None) => {
                let name = files[0].name();
                self.0.loader.load_files(files);
                Some(name)
            }
            (None, None) => None,
        };
        if how.kept {
            *self.0.restored.borrow_mut() = shown.clone();
        }
        let sample = record.take.as_ref().is_some_and(|t| t.sample);
        if shown.is_none() {
            if let Some(take) = record.take.as_ref().filter(|t| !t.sample) {
                note_missing(&mut missing, &take.name);
            } else if sample && !how.kept {
                self.0.loader.load_sample();
            }
        }
        let library_count = library_at.iter().flatten().count();
        let said = restored_text(shown.as_deref(), record.truth.is_some(), library_count, &how.from, &missing);
        if said.is_some() || !how.kept {
            self.0.status.set(said);
        }
        let on_screen = shown.or_else(|| sample.then(|| self.0.loader.sample_name()));
        if let (Some(name), Some(truth)) = (on_screen, record.truth) {
            *self.0.truth.borrow_mut() = Some((name, truth));
        }
        if how.kept {
            self.set_take(record.take);
        }
    }

    /// Shows the side panel's tab `tab` when the page has it.
    fn set_panel(&self, tab: &str) {
        let state = self.0.state;
        let offered = tab == crate::app::state::TRUTH_TAB
            || state.methods.iter().any(|s| s.info.name == tab)
            || (tab == crate::app::library::state::TAB && state.library.shown_untracked());
        if offered {
            state.panel.set(tab.to_string());
        }
    }

    /// Forgets the workspace kept and opens the bundled sample.
    pub fn forget(&self) {
        let this = self.clone();
        self.0.status.set(None);
        self.0.state.truth.file.set(None);
        self.0.library.clear();
        self.0.library_kept.borrow_mut().clear();
        wasm_bindgen_futures::spawn_local(async move {
            let cleared = async { store::clear_all().await.and(store::put_record(&Record::new()).await) }.await;
            if let Err(why) = cleared {
                this.0.status.set(Some((true, format!("the workspace kept could not be forgotten: {why}"))));
            }
            this.0.loader.load_sample();
        });
    }

    /// Writing begins; the take restored (if any) is loading, else `fallback` loads the sample.
    fn start(&self, fallback: impl FnOnce()) {
        if self.0.restored.borrow().is_none() {
            fallback();
        }
        self.0.ready.set(true);
    }

    /// Sets every row's form from `record`.
    fn set_forms(&self, record: &Record) {
        for slot in self.0.state.methods {
            set_form(slot, record);
        }
    }

    /// The take now on screen is kept (its file within the limit; the sample as a mark), and its ground truth set
    /// again when it is the workspace's.
    fn take_shown(&self) {
        let Some((name, file, skeleton, sample)) = self.0.loader.shown_take_files() else { return };
        let truth = {
            let mut truth = self.0.truth.borrow_mut();
            truth.take_if(|(n, _)| *n == name).map(|(_, t)| t)
        };
        if let Some(truth) = truth {
            let t = self.0.state.truth;
            // after the truth panel's own reaction to the new take (it forgets the trial chosen for the last one)
            Timeout::new(0, move || {
                t.base.set(truth.base);
                t.fps.set(truth.fps);
                t.trial.set(truth.trial);
                t.file.set(Some((truth.name, Arc::new(truth.text))));
            })
            .forget();
        }
        if let Some(i) = self.0.state.library.open.get_untracked() {
            // a take of the library: its files are kept with the library's
            self.0.restored.borrow_mut().take();
            return self.set_take(Some(KeptTake { name, sample: false, kept: false, library: Some(i) }));
        }
        if self.0.restored.borrow_mut().take_if(|r| *r == name).is_some() {
            return; // the file kept is this one
        }
        if sample {
            self.set_take(Some(KeptTake { name, sample: true, kept: false, library: None }));
            return wasm_bindgen_futures::spawn_local(async move {
                let _ = store::clear_take().await;
            });
        }
        if let Err(why) = take_kept(&name, file.size()) {
            self.0.status.set(Some((true, why)));
            return self.set_take(Some(KeptTake { name, sample: false, kept: false, library: None }));
        }
        let this = self.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let kept = store::put_take(&KeptFile { name: name.clone(), file, skeleton }).await;
            let status = this.0.status;
            if let Err(why) = &kept {
                status.set(Some((true, not_kept(&name, why))));
            } else if status.with_untracked(|s| s.as_ref().is_some_and(|(problem, _)| *problem)) {
                status.set(None);
            }
            this.set_take(Some(KeptTake { name, sample: false, kept: kept.is_ok(), library: None }));
        });
    }

    /// Keeps the files of the library's takes added since (takes `known..count`), each within the take's limit and
    /// all within the library's; a take not kept is said.
    fn keep_library_takes(&self, count: usize) {
        let known = self.0.library_kept.borrow().len();
        if count <= known {
            return;
        }
        let library = self.0.state.library;
        let sources: Vec<Source> = (0..count).filter_map(|i| library.source(i)).collect();
        if sources.len() != count {
            return;
        }
        let size = |s: &Source| s.motion.size() + s.skeleton.as_ref().map_or(0.0, |f| f.size());
        let names: Vec<String> = sources.iter().map(|s| s.motion.name()).collect();
        let sizes: Vec<f64> = sources.iter().map(size).collect();
        // the takes kept already count against the library's limit as they are
        let (mut kept, why) = library_kept(&names, &sizes);
        let before = self.0.library_kept.borrow().clone();
        kept[..known].copy_from_slice(&before);
        *self.0.library_kept.borrow_mut() = kept.clone();
        if let Some(why) = why.into_iter().find(|w| names[known..].iter().any(|n| w.starts_with(n.as_str()))) {
            self.0.status.set(Some((true, why)));
        }
        let this = self.clone();
        wasm_bindgen_futures::spawn_local(async move {
            for i in known..count {
                if !kept[i] {
                    continue;
                }
                let s = &sources[i];
                if let Err(why) = store::put_library_take(i, &s.motion, s.skeleton.as_ref()).await {
                    this.0.status.set(Some((true, not_kept(&names[i], &why))));
                    if let Some(k) = this.0.library_kept.borrow_mut().get_mut(i) {
                        *k = false;
                    }
                }
            }
            this.0.library_changes.update(|n| *n = n.wrapping_add(1));
        });
    }

    /// Sets the library again (`files`: its takes' files in `kept`'s order, `None` for those not found — named in
    /// `missing`); returns the library index each take now has. `kept_already`: the files are kept in this browser
    /// (else they are kept as if dropped).
    fn set_library(
        &self,
        kept: &KeptLibrary,
        files: Vec<Option<Source>>,
        kept_already: bool,
        missing: &mut Vec<String>,
    ) -> Vec<Option<usize>> {
        let mut sources = Vec::new();
        let mut at = Vec::new();
        // the library's caps, as for files dropped: a take past them is left out (the library's status says why)
        let found: Vec<Source> = files.iter().flatten().cloned().collect();
        let mut admitted = self.0.library.admit(&found).into_iter();
        let files: Vec<Option<Source>> =
            files.into_iter().map(|f| f.filter(|_| admitted.next().unwrap_or(false))).collect();
        for (i, take) in kept.takes.iter().enumerate() {
            match files.get(i).cloned().flatten() {
                Some(source) => {
                    at.push(Some(sources.len()));
                    sources.push(source);
                }
                None => {
                    at.push(None);
                    note_missing(missing, &take.name);
                }
            }
        }
        let count = sources.len();
        if kept_already {
            if count < kept.takes.len() {
                // the takes restored move up into the places of those not kept: their files are kept there
                let (sources, status) = (sources.clone(), self.0.status);
                wasm_bindgen_futures::spawn_local(async move {
                    for (j, s) in sources.iter().enumerate() {
                        if let Err(why) = store::put_library_take(j, &s.motion, s.skeleton.as_ref()).await {
                            status.set(Some((true, not_kept(&s.motion.name(), &why))));
                        }
                    }
                });
            }
            *self.0.library_kept.borrow_mut() = vec![true; count];
        }
        self.0.library.restore(sources, kept.method.clone(), ClusterNames::from_kept(kept.names.clone()));
        at
    }

    /// The record of the workspace now, untracked (a project file's).
    pub fn record_now(&self) -> Record {
        untrack(|| self.record())
    }

    /// The record of the workspace now (tracked: a change of any part writes it again).
    fn record(&self) -> Record {
        let truth = self.0.state.truth;
        let kept_truth = truth.file.with(|f| {
            f.as_ref().map(|(name, text)| KeptTruth {
                name: name.clone(),
                text: text.to_string(),
                base: truth.base.get(),
                fps: truth.fps.get(),
                trial: truth.trial.get(),
            })
        });
        let rows = self
            .0
            .state
            .methods
            .iter()
            .map(|slot| {
                let fields: BTreeMap<String, String> =
                    slot.specs.iter().zip(&slot.fields).map(|(spec, field)| (spec.name.clone(), field.get())).collect();
                (slot.info.name.clone(), fields)
            })
            .collect();
        self.0.take_changes.track();
        self.0.library_changes.track();
        let library = self.0.state.library;
        let kept = self.0.library_kept.borrow();
        let takes: Vec<KeptLibraryTake> = self.0.library_takes.with(|names| {
            names
                .iter()
                .enumerate()
                .map(|(i, name)| KeptLibraryTake { name: name.clone(), kept: kept.get(i).copied().unwrap_or(false) })
                .collect()
        });
        let library = (!takes.is_empty()).then(|| KeptLibrary {
            method: library.method.get(),
            takes,
            names: library.names.with(|n| n.kept().to_vec()),
        });
        let panel = self.0.state.panel.get();
        Record { take: self.0.take.borrow().clone(), truth: kept_truth, rows, library, panel, ..Record::new() }
    }

    /// Writes `record` once the workspace has stayed unchanged for [`SETTLE_MS`].
    fn write_soon(&self, record: Record) {
        let status = self.0.status;
        let timer = Timeout::new(SETTLE_MS, move || {
            wasm_bindgen_futures::spawn_local(async move {
                if let Err(why) = store::put_record(&record).await {
                    status.set(Some((true, not_kept("the workspace", &why))));
                }
            });
        });
        // a new timer replaces (and so cancels) the one before
        *self.0.timer.borrow_mut() = Some(timer);
    }
}

/// Sets `slot`'s form from `record`: every field it still has, the model choice once that model is offered (the
/// user's models come back from this browser after the page starts).
fn set_form(slot: &'static MethodSlot, record: &Record) {
    let names: Vec<&str> = slot.specs.iter().map(|s| s.name.as_str()).collect();
    for (i, text) in record.fields_of(&slot.info.name, &names) {
        if names[i] != "model" {
            slot.fields[i].set(text);
            continue;
        }
        let (value, choices) = (slot.fields[i], slot.choices[i]);
        let before = value.get_untracked();
        Effect::new(move |done: Option<bool>| {
            if done == Some(true) {
                return true;
            }
            let offered = choices.with(|c| c.contains(&text));
            // (the user chose another model meanwhile: theirs stays)
            if offered && value.get_untracked() == before {
                value.set(text.clone());
            }
            offered
        });
    }
}

/// `#workspace-status`: what the keeper says (the workspace restored, a take not kept, a storage full), and
/// `#workspace-forget`, which starts afresh.
#[component]
pub fn WorkspaceStatus(keeper: Keeper) -> impl IntoView {
    let status = keeper.status();
    let text = move || status.with(|s| s.as_ref().map(|(_, t)| t.clone()).unwrap_or_default());
    view! {
        <p
            id="workspace-status"
            class="ms-workspace-status"
            class:ms-workspace-status--problem=move || status.with(|s| s.as_ref().is_some_and(|(p, _)| *p))
            role="status"
            aria-live="polite"
            hidden=move || status.with(Option::is_none)
        >
            <span id="workspace-status-text">{text}</span>
            " "
            <button id="workspace-forget" class="ms-button ms-button--quiet ms-button--small" type="button"
                title="Forget the take, ground truth and row settings kept in this browser, and open the sample"
                on:click=move |_| keeper.forget()>
                "Start afresh"
            </button>
        </p>
    }
}

/// Names take `name` among those not found, unless it is named already (with its SHA-256, or why).
fn note_missing(missing: &mut Vec<String>, name: &str) {
    if !missing.iter().any(|m| m == name || m.starts_with(&format!("{name} ("))) {
        missing.push(name.to_string());
    }
}

/// A take file to open: kept in this browser, or opened with a project.
enum Opened {
    Kept(KeptFile),
    Files(Vec<web_sys::File>),
}

/// How a record is set on the page: whether its files are kept in this browser already (restored) or not (a project
/// opened), where it comes from (for the status), and what of it was not found.
struct Apply {
    kept: bool,
    from: String,
    missing: Vec<String>,
}

/// The library's take files kept in this browser, in `kept`'s order (`None`: not kept, or unreadable).
async fn kept_library_files(kept: &KeptLibrary) -> Vec<Option<Source>> {
    let mut files = Vec::new();
    for (i, take) in kept.takes.iter().enumerate() {
        let got = if take.kept { store::get_library_take(i).await } else { Ok(None) };
        files.push(match got {
            Ok(found) => found.map(|(motion, skeleton)| Source { motion, skeleton }),
            Err(why) => {
                web_sys::console::warn_1(&format!("{}: the file kept does not read: {why}", take.name).into());
                None
            }
        });
    }
    files
}
