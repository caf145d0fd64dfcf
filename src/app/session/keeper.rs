//! Keeps the workspace in this browser as the user works, and sets it again when the page opens
//! ([`Keeper::restore`]): the take on screen (its file kept beside the record, within the record's size limit; the
//! bundled sample as a mark), its ground truth (file and choices), and each row's form — its model choice set again
//! once that model is in the choice (the user's models come back from this browser after the page starts). A take not
//! kept, or a storage that is full, is said in `#workspace-status`; `#workspace-forget` starts afresh.

use crate::app::loader::Loader;
use crate::app::session::record::{not_kept, take_kept, KeptTake, KeptTruth, Record};
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
}

impl Keeper {
    /// Keeps the workspace of `state` from now on (once [`Keeper::restore`] has read the one kept, or was skipped).
    pub fn new(state: AppState, loader: Loader) -> Keeper {
        let keeper = Keeper(Rc::new(Inner {
            state,
            loader,
            status: RwSignal::new(None),
            ready: Cell::new(false),
            take: RefCell::new(None),
            take_changes: RwSignal::new(0),
            restored: RefCell::new(None),
            truth: RefCell::new(None),
            timer: RefCell::new(None),
            owner: Owner::current(),
        }));
        let shown = keeper.clone();
        Effect::new(move |_| {
            state.motion.track();
            shown.take_shown();
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
            match &this.0.owner {
                Some(owner) => owner.with(|| this.set_forms(&record)),
                None => this.set_forms(&record),
            }
            let kept = match &record.take {
                Some(take) if take.kept => match store::get_take().await {
                    Ok(Some(file)) if file.name == take.name => Some(file),
                    Ok(_) => None,
                    Err(why) => {
                        let why = format!("the take kept in this browser does not read: {why}");
                        this.0.status.set(Some((true, why)));
                        None
                    }
                },
                _ => None,
            };
            let shown = match kept {
                Some(KeptFile { name, file, skeleton }) => {
                    *this.0.restored.borrow_mut() = Some(name.clone());
                    this.0.loader.load_blob(&name, file, skeleton);
                    let what = if record.truth.is_some() {
                        ", its ground truth and the rows' settings"
                    } else {
                        " and the rows' settings"
                    };
                    this.0.status.set(Some((false, format!("Restored {name}{what} from this browser."))));
                    Some(name)
                }
                None => {
                    if let Some(take) = record.take.as_ref().filter(|t| !t.sample) {
                        let why = format!("{} was not kept in this browser: drop it again to go on with it", take.name);
                        this.0.status.set(Some((true, why)));
                    }
                    record.take.as_ref().filter(|t| t.sample).map(|_| this.0.loader.sample_name())
                }
            };
            if let (Some(name), Some(truth)) = (shown, record.truth) {
                *this.0.truth.borrow_mut() = Some((name, truth));
            }
            this.set_take(record.take);
            this.start(fallback);
        });
    }

    /// Forgets the workspace kept and opens the bundled sample.
    pub fn forget(&self) {
        let this = self.clone();
        self.0.status.set(None);
        self.0.state.truth.file.set(None);
        wasm_bindgen_futures::spawn_local(async move {
            let cleared = async { store::clear_take().await.and(store::put_record(&Record::new()).await) }.await;
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
        if self.0.restored.borrow_mut().take_if(|r| *r == name).is_some() {
            return; // the file kept is this one
        }
        if sample {
            self.set_take(Some(KeptTake { name, sample: true, kept: false }));
            return wasm_bindgen_futures::spawn_local(async move {
                let _ = store::clear_take().await;
            });
        }
        if let Err(why) = take_kept(&name, file.size()) {
            self.0.status.set(Some((true, why)));
            return self.set_take(Some(KeptTake { name, sample: false, kept: false }));
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
            this.set_take(Some(KeptTake { name, sample: false, kept: kept.is_ok() }));
        });
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
        Record { take: self.0.take.borrow().clone(), truth: kept_truth, rows, ..Record::new() }
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
            {text}
            " "
            <button id="workspace-forget" class="ms-button ms-button--quiet ms-button--small" type="button"
                title="Forget the take, ground truth and row settings kept in this browser, and open the sample"
                on:click=move |_| keeper.forget()>
                "Start afresh"
            </button>
        </p>
    }
}
