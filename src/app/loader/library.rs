//! The library's jobs in the workers (issue 26): the takes of the library segmented as many at a
//! time as the pool has workers (issue 46; `library_take`: a worker reads the take, segments it and
//! lets its frames go; the take on screen stays the one it holds — each take is a run of the pool,
//! [`crate::worker::pool`], placed beside the rows' runs), cancelled by replacing the workers that
//! run them, and the clips of
//! several takes cut into one zip (`library_clips`: each take's file read again from its `File`).
//! Once no take is left to segment, the segmented takes (their features and segmentations, never
//! their frames) are matched into clusters shared across takes (`library_cluster`), again when
//! takes are added. The take on screen's labels are carried to the others on request
//! (`library_transfer`: [`Loader::carry_labels`]), or — the k-NN and DT-FCN routes — that method is trained on
//! them (its panel's training, `train`) and every other take labelled with it (`library_take`, the model in its
//! params), one after another; [`Loader::cancel_carry`] stops any.
//! The queue's state is [`crate::app::library::takes::Queue`]; what the page shows is
//! [`crate::app::library::panel`].

use crate::app::dom::js_message;
use crate::app::library::carry::{Carried, Route};
use crate::app::library::state::{ModelCarry, Source};
use crate::app::library::takes::{group_files, Shared};
use crate::app::loader::{next_id, pool, post_buffers, post_request, replace_slot, replace_worker, Inner, Loader};
use crate::app::models::supervised::TrainAsk;
use crate::app::player::motion_image::download;
use crate::app::take::fetch::blob_bytes;
use crate::library::TakeFeatures;
use crate::protocol::RunId;
use crate::protocol::{ClipTake, FailureKind, Request, Response};
use crate::worker::pool::{Placed, Slot, Stop};
use leptos::prelude::*;
use std::rc::Rc;
use std::sync::Arc;
use web_sys::{Blob, File};

impl Loader {
    /// Opens files dropped or picked together: one take as ever ([`Loader::load_files`]); two
    /// or more (a folder's) go to the library, queued for the worker, and the first of them opens.
    pub fn open_dropped(&self, files: Vec<File>) {
        let names: Vec<String> = files.iter().map(file_path).collect();
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let (takes, mut refused) = group_files(&refs);
        let sizes: Vec<f64> = files.iter().map(|f| f.size()).collect();
        let (takes, too_large) = crate::app::library::takes::within_cap(takes, &refs, &sizes);
        refused.extend(too_large);
        if takes.len() < 2 {
            let library = self.0.state.library;
            if takes.len() == 1 && files.len() >= 2 {
                // a folder or a selection holding one take (and other files, e.g. a BVH with its README): that take
                let t = takes[0];
                let mut one = vec![files[t.motion].clone()];
                one.extend(t.skeleton.map(|s| files[s].clone()));
                library.open.set(None);
                return self.load_files(one);
            }
            library.open.set(None);
            return self.load_files(files);
        }
        let library = self.0.state.library;
        let sources: Vec<Source> = takes
            .iter()
            .map(|t| Source { motion: files[t.motion].clone(), skeleton: t.skeleton.map(|s| files[s].clone()) })
            .collect();
        let added = library.add(sources);
        if !refused.is_empty() {
            library.status.set(Some((true, refused.join("; "))));
        }
        self.0.state.panel.set(crate::app::library::state::TAB.to_string());
        self.open_library_take(added.start);
        pump(&self.0);
    }

    /// Opens take `i` of the library on screen, as a dropped file opens (its file read again).
    pub fn open_library_take(&self, i: usize) {
        let Some(source) = self.0.state.library.source(i) else { return };
        self.0.state.library.open.set(Some(i));
        let mut files = vec![source.motion];
        files.extend(source.skeleton);
        self.load_files(files);
    }

    /// Cancels the library's queue: the take running (the worker is replaced: a wasm worker cannot
    /// be interrupted) and every take still queued.
    pub fn cancel_library(&self) {
        let library = self.0.state.library;
        library.queue.update(|q| {
            q.cancel();
        });
        // the takes under way: dropped where they wait, their run workers replaced, the main
        // worker replaced below if one runs there
        let runs = library.running.get_value();
        library.running.set_value(Vec::new());
        let stops: Vec<Stop> = runs.iter().map(|&(run, _)| self.0.pool.borrow_mut().stop(run)).collect();
        let mut running = false;
        for stop in stops {
            match stop {
                Stop::Replace(0) => running = true,
                Stop::Replace(slot) => pool::replace(&self.0, slot),
                Stop::Dequeued | Stop::Unknown => {}
            }
        }
        // the matching under way goes too
        let matching = library.cluster_run.with_value(|r| r.is_some());
        if matching {
            library.cluster_run.set_value(None);
            library.matching.set(Some((true, "matching cancelled".into())));
        }
        // and the carrying of labels
        let carrying = stop_carrying(&self.0);
        if running || matching || carrying {
            replace_worker(&self.0);
        }
    }

    /// Cancels the carrying of labels under way (either route): the worker is replaced when it
    /// works on it; a method still training stops as its panel's Stop does.
    pub fn cancel_carry(&self) {
        if stop_carrying(&self.0) {
            replace_worker(&self.0);
        }
    }

    /// Queues the library's cancelled and failed takes again.
    pub fn rerun_library(&self) {
        self.0.state.library.queue.update(|q| q.requeue());
        pump(&self.0);
    }

    /// Carries the take on screen's labels (my labels, else its ground truth) to every take of the
    /// library that can be matched, by the route chosen (`library_transfer`). Takes added later get
    /// labels when this is asked again.
    pub fn carry_labels(&self) {
        let state = self.0.state;
        let library = state.library;
        let (source, frame_labels, _) = match untrack(|| crate::app::library::on_screen::source_labels(state)) {
            Ok(found) => found,
            Err(why) => return library.carrying.set(Some((true, why))),
        };
        let chosen = library.route.get_untracked();
        let Some(route) = chosen.transfer() else {
            return self.carry_by_model(chosen, source, frame_labels);
        };
        let (takes, indices) = library.matchable();
        let Some(labelled) = indices.iter().position(|&i| i == source) else {
            let why = "the take on screen has no features to match (not segmented yet, or it lacks hands, feet, head or hips)";
            return library.carrying.set(Some((true, why.into())));
        };
        if indices.len() < 2 {
            return library
                .carrying
                .set(Some((true, "the library has no other take to carry the labels to yet".into())));
        }
        let run = next_id(&self.0);
        library.transfer_run.set_value(Some((run, source, indices)));
        library.carrying.set(Some((false, "carrying the labels…".into())));
        library.carry_busy.set(true);
        let request = Request::LibraryTransfer { take: 0, run, takes, labelled, frame_labels, route };
        if let Err(e) = post_request(&self.0, request) {
            library.transfer_run.set_value(None);
            library.carry_busy.set(false);
            library.carrying.set(Some((true, e)));
        }
    }

    /// A supervised route (`route`: the k-NN or DT-FCN): trains that method on take `source`'s `labels` (the take on
    /// screen) with its panel's training options, then labels every other take of the library with the model
    /// ([`model_trained`], [`model_next`]).
    fn carry_by_model(&self, route: Route, source: usize, labels: Vec<Option<String>>) {
        let inner = &self.0;
        let library = inner.state.library;
        let fail = |why: String| library.carrying.set(Some((true, why)));
        let Some(method) = route.method() else { return };
        let Some((index, slot)) = inner.state.methods.iter().enumerate().find(|(_, s)| s.info.name == method) else {
            return fail(format!("this page has no {method}"));
        };
        let title = slot.info.short.clone();
        let Some(s) = slot.supervised.as_ref() else { return fail(format!("the {title} cannot be trained here")) };
        if inner.train_job.borrow().is_some() {
            return fail("a training is under way: carry the labels once it has ended".into());
        }
        let todo: Vec<usize> =
            library.queue.with_untracked(|q| (0..q.entries.len()).filter(|&i| i != source).collect());
        if todo.is_empty() {
            return fail("the library has no other take to carry the labels to yet".into());
        }
        let Some(file) = inner.shown.borrow().as_ref().map(|t| t.name.clone()) else {
            return fail("open a take of the library (its name in the list) to carry its labels".into());
        };
        let texts: Vec<String> = s.fields.iter().map(|f| f.get_untracked()).collect();
        let options = match crate::method::form::params_from_form(&slot.info.short, &s.decl.training, &texts) {
            Ok(options) => options,
            Err(e) => return fail(format!("the {title} panel's training options: {e}")),
        };
        let rows = crate::app::library::carry::label_rows(&file, &labels);
        let fps = inner.state.motion.with_untracked(|m| m.as_ref().map_or(0.0, |m| m.summary.fps));
        let count = todo.len();
        library.by_model.set_value(Some(ModelCarry {
            route,
            source,
            file: file.clone(),
            fps,
            labels,
            model: None,
            todo,
            running: None,
            count,
            done: Vec::new(),
            failed: Vec::new(),
            misfits: Vec::new(),
        }));
        library.carry_busy.set(true);
        library.carrying.set(Some((false, format!("training the {title} on the labels of {file}…"))));
        let stem = crate::app::player::motion_image::stem(&file).to_string();
        self.train(
            index,
            TrainAsk {
                name: format!("{stem}-library-{method}"),
                labels_name: format!("labels of {file}"),
                labels: crate::labels::to_csv(&rows),
                extra: Vec::new(),
                options,
                continue_from: None,
                validation: None,
            },
        );
    }

    /// Cuts the occurrences `takes` (library index, its segments to cut, each labelled with its
    /// cluster's name) as BVH clips into one zip `file`, each take's file read again.
    pub fn export_library_clips(
        &self,
        file: String,
        takes: Vec<(usize, crate::segment::Segmentation)>,
        to_origin: bool,
    ) {
        let inner = self.0.clone();
        let library = inner.state.library;
        library.status.set(Some((false, "cutting the clips…".into())));
        wasm_bindgen_futures::spawn_local(async move {
            let buffers = js_sys::Array::new();
            let mut asked = Vec::new();
            for (i, segmentation) in takes {
                let Some(source) = library.source(i) else { continue };
                for blob in std::iter::once(&source.motion).chain(source.skeleton.as_ref()) {
                    match blob_bytes(&Blob::from(blob.clone())).await {
                        Ok(bytes) => {
                            buffers.push(&bytes);
                        }
                        Err(e) => {
                            let message = format!("{}: could not read the file again: {e}", blob.name());
                            return library.status.set(Some((true, message)));
                        }
                    }
                }
                let name = source.motion.name();
                asked.push(ClipTake { name, skeleton: source.skeleton.as_ref().map(File::name), segmentation });
            }
            let run = next_id(&inner);
            let request = Request::LibraryClips { take: 0, run, file, takes: asked, to_origin, bytes: Vec::new() };
            match post_buffers(&inner, &request, buffers) {
                Ok(()) => library.clip_run.set_value(Some(run)),
                Err(e) => library.status.set(Some((true, e))),
            }
        });
    }
}

/// Ends the carrying under way (either route) as cancelled; whether the worker works on it.
fn stop_carrying(inner: &Rc<Inner>) -> bool {
    let library = inner.state.library;
    let transfer = library.transfer_run.with_value(|r| r.is_some());
    library.transfer_run.set_value(None);
    let by_model =
        library.by_model.with_value(|k| k.as_ref().map(|k| (k.model.is_none(), k.running.is_some(), k.route)));
    library.by_model.set_value(None);
    if let Some((true, _, route)) = by_model {
        if let Some(index) = model_slot(inner, route) {
            // still training: stopped as the panel's Stop does (it replaces the worker itself if need be)
            Loader(inner.clone()).stop_training(index);
        }
    }
    if transfer || by_model.is_some() {
        library.carry_busy.set(false);
        library.carrying.set(Some((true, "carrying cancelled".into())));
    }
    transfer || by_model.is_some_and(|(_, running, _)| running)
}

/// The slot of the method a supervised route trains.
fn model_slot(inner: &Inner, route: Route) -> Option<usize> {
    let method = route.method()?;
    inner.state.methods.iter().position(|s| s.info.name == method)
}

/// The training of method `index` ended (`Ok`: the model's name, stored in the worker): when it
/// was a supervised route's, the other takes are labelled with it, or the carrying fails with why.
pub(super) fn model_trained(inner: &Rc<Inner>, index: usize, model: Result<String, String>) {
    let library = inner.state.library;
    let Some(route) = library.by_model.with_value(|k| k.as_ref().filter(|k| k.model.is_none()).map(|k| k.route)) else {
        return;
    };
    if model_slot(inner, route) != Some(index) {
        return;
    }
    let title = inner.state.methods[index].info.short.clone();
    match model {
        Ok(name) => {
            library.by_model.update_value(|k| {
                if let Some(k) = k {
                    k.model = Some(name);
                }
            });
            model_next(inner);
        }
        Err(message) => {
            library.by_model.set_value(None);
            library.carry_busy.set(false);
            library.carrying.set(Some((true, format!("the {title} was not trained: {message}"))));
        }
    }
}

/// Labels the next take of a supervised route with its model; once none is left, the labels are
/// carried ([`Carried::by_model`]).
fn model_next(inner: &Rc<Inner>) {
    let library = inner.state.library;
    let Some(mut k) = library.by_model.get_value() else { return };
    let Some(model) = k.model.clone() else { return };
    let Some(index) = model_slot(inner, k.route) else { return };
    let Some(i) = (!k.todo.is_empty()).then(|| k.todo.remove(0)) else {
        library.by_model.set_value(None);
        library.carry_busy.set(false);
        let name =
            library.queue.with_untracked(|q| q.entries.get(k.source).map(|e| e.name.clone())).unwrap_or_default();
        let carried = Carried::by_model(k.route, k.source, &k.file, k.fps, k.labels, k.done);
        let short = inner.state.methods[index].info.short.clone();
        let summary = carried.model_summary(&name, &short, &k.misfits, &k.failed);
        library.carrying.set(Some((!k.failed.is_empty() && carried.takes.len() < 2, summary)));
        library.carried.set(Some(Arc::new(carried)));
        return;
    };
    let Some(source) = library.source(i) else {
        library.by_model.set_value(Some(k));
        return model_next(inner);
    };
    let run = next_id(inner);
    k.running = Some((run, i));
    let at = k.count - k.todo.len();
    let count = k.count;
    library.by_model.set_value(Some(k));
    let name = source.motion.name();
    let slot = &inner.state.methods[index];
    let (method, title) = (slot.info.name.clone(), slot.info.short.clone());
    library.carrying.set(Some((false, format!("labelling take {at} of {count} ({name}) with the {title}…"))));
    let params = match slot.params() {
        Ok(mut params) => {
            params["model"] = serde_json::Value::String(model);
            params
        }
        Err(_) => serde_json::json!({ "model": model }),
    };
    let inner = inner.clone();
    wasm_bindgen_futures::spawn_local(async move {
        let read = read_files(&source).await;
        // cancelled (or replaced) while the file was read
        let library = inner.state.library;
        if library.by_model.with_value(|k| k.as_ref().and_then(|k| k.running).map(|(r, _)| r)) != Some(run) {
            return;
        }
        let sent = read.and_then(|buffers| post_buffers(&inner, &take_request(run, &source, method, params), buffers));
        if let Err(e) = sent {
            model_took(&inner, run, Err(e));
        }
    });
}

/// Take `source`'s files read again (the motion, then its skeleton) as a request's buffers.
async fn read_files(source: &Source) -> Result<js_sys::Array, String> {
    let buffers = js_sys::Array::new();
    for blob in std::iter::once(&source.motion).chain(source.skeleton.as_ref()) {
        let bytes = blob_bytes(&Blob::from(blob.clone()))
            .await
            .map_err(|e| format!("{}: could not read the file: {e}", blob.name()))?;
        buffers.push(&bytes);
    }
    Ok(buffers)
}

/// The `library_take` request segmenting take `source` with `method` and `params` as run `run`
/// (its files' bytes go as buffers).
fn take_request(run: u32, source: &Source, method: String, params: serde_json::Value) -> Request {
    Request::LibraryTake {
        take: 0,
        run,
        name: source.motion.name(),
        bytes: Vec::new(),
        skeleton: source.skeleton.as_ref().map(File::name),
        skeleton_bytes: Vec::new(),
        method,
        params,
    }
}

/// A supervised route's run `run` labelled its take (with why the model does not fit it, if so) or failed: kept,
/// and the next take is sent.
fn model_took(inner: &Rc<Inner>, run: u32, outcome: Result<(crate::segment::Segmentation, Option<String>), String>) {
    let library = inner.state.library;
    let Some(mut k) = library.by_model.get_value().filter(|k| k.running.is_some_and(|(r, _)| r == run)) else {
        return;
    };
    let Some((_, i)) = k.running.take() else { return };
    match outcome {
        Ok((segmentation, misfit)) => {
            if let Some(why) = misfit {
                let name =
                    library.queue.with_untracked(|q| q.entries.get(i).map(|e| e.name.clone())).unwrap_or_default();
                k.misfits.push(format!("{name}: {why}"));
            }
            k.done.push((i, segmentation))
        }
        Err(message) => {
            let name = library.queue.with_untracked(|q| q.entries.get(i).map(|e| e.name.clone())).unwrap_or_default();
            k.failed.push(format!("{name}: {message}"));
        }
    }
    library.by_model.set_value(Some(k));
    model_next(inner);
}

/// A dropped or picked file's path within the folder picked (`webkitRelativePath`), else its name.
fn file_path(file: &File) -> String {
    js_sys::Reflect::get(file, &"webkitRelativePath".into())
        .ok()
        .and_then(|p| p.as_string())
        .filter(|p| !p.is_empty())
        .unwrap_or_else(|| file.name())
}

/// Sends the library's queued takes to the pool, as many at once as it has workers (each waits
/// there for a free worker, beside the rows' runs).
pub(super) fn pump(inner: &Rc<Inner>) {
    let library = inner.state.library;
    let workers = inner.pool.borrow().workers();
    loop {
        let mut next = None;
        library.queue.update(|q| next = q.start_next(workers));
        let Some(i) = next else { return };
        let run = next_id(inner);
        library.running.update_value(|r| r.push((run, i)));
        let placed = inner.pool.borrow_mut().place(run);
        match placed {
            Placed::Now(slot) => send(inner, run, i, slot),
            Placed::Queued => library.queue.update(|q| q.progress(i, "waiting for a worker", 0.0)),
        }
    }
}

/// The take of the library that run `run` segments, if the library still wants it.
fn take_of(inner: &Inner, run: RunId) -> Option<usize> {
    inner.state.library.running.with_value(|r| r.iter().find(|(r, _)| *r == run).map(|&(_, i)| i))
}

/// Whether `run` is one of the library's takes under way (a run of the pool that is not a row's).
pub(super) fn owns(inner: &Inner, run: RunId) -> bool {
    take_of(inner, run).is_some()
}

/// The pool gave run `run` a worker: its take is sent there (false: not a library run).
pub(super) fn post_run(inner: &Rc<Inner>, run: RunId) -> bool {
    let Some(i) = take_of(inner, run) else { return false };
    let slot = inner.pool.borrow().slot_of(run);
    if let Some(slot) = slot {
        inner.state.library.queue.update(|q| q.progress(i, "starting", 0.0));
        send(inner, run, i, slot);
    }
    true
}

/// Sends take `i` of the library as run `run` to worker `slot` (its file read from its `File`).
fn send(inner: &Rc<Inner>, run: u32, i: usize, slot: Slot) {
    let library = inner.state.library;
    let Some(source) = library.source(i) else { return };
    let slot_of = inner.state.methods.iter().find(|s| s.info.name == library.method.get_untracked());
    let (method, params) = match slot_of.map(|s| (s.info.name.clone(), s.params())) {
        Some((name, Ok(params))) => (name, params),
        Some((_, Err(e))) => return finish(inner, run, Err(e.to_string())),
        None => return finish(inner, run, Err("no method chosen for the library".into())),
    };
    let inner = inner.clone();
    wasm_bindgen_futures::spawn_local(async move {
        let buffers = match read_files(&source).await {
            Ok(buffers) => buffers,
            Err(e) => return finish(&inner, run, Err(e)),
        };
        // cancelled, or its worker replaced, while the file was read
        if !owns(&inner, run) || inner.pool.borrow().slot_of(run) != Some(slot) {
            return;
        }
        if let Err(e) = pool::post_buffers_to(&inner, slot, &take_request(run, &source, method, params), buffers) {
            finish(&inner, run, Err(e));
        }
    });
}

/// What the worker made of a take of the library: its frames, seconds, segmentation and features
/// (or why it has none).
type Took = (usize, f64, crate::segment::Segmentation, Result<Box<TakeFeatures>, String>);

/// Ends run `run` of the library (its take done or failed): its worker is free for the next run,
/// and the next takes are sent; once none is left, the takes are matched across the library.
fn finish(inner: &Rc<Inner>, run: u32, outcome: Result<Took, String>) {
    let library = inner.state.library;
    // the worker is free (also for an answer the library no longer wants: a cancelled take's)
    pool::release_run(inner, run);
    let Some(i) = take_of(inner, run) else { return };
    library.running.update_value(|r| r.retain(|(r, _)| *r != run));
    match outcome {
        Ok((frames, duration_s, segmentation, features)) => {
            library.set_features(i, features.map(|f| *f));
            library.queue.update(|q| q.done(i, frames, duration_s, segmentation));
        }
        Err(message) => library.queue.update(|q| q.failed(i, message)),
    }
    pump(inner);
    if !library.queue.with_untracked(|q| q.busy()) {
        match_takes(inner);
    }
}

/// Run `run` of the library trapped in its worker: the take fails (it would trap again) and the
/// worker is replaced.
fn trapped(inner: &Rc<Inner>, run: RunId, message: String) {
    let slot = inner.pool.borrow().slot_of(run);
    finish(inner, run, Err(message));
    if let Some(slot) = slot {
        replace_slot(inner, slot);
    }
}

/// A run worker died under run `run` of the library (out of memory, say): the take fails, naming
/// why (the worker itself is replaced by the pool).
pub(super) fn died(inner: &Rc<Inner>, run: RunId) {
    if let Some(i) = take_of(inner, run) {
        inner.state.library.running.update_value(|r| r.retain(|(r, _)| *r != run));
        let message = "the worker segmenting it stopped (out of memory?)".to_string();
        inner.state.library.queue.update(|q| q.failed(i, message));
        pump(inner);
        if !inner.state.library.queue.with_untracked(|q| q.busy()) {
            match_takes(inner);
        }
    }
}

/// Matches the library's segmented takes into shared clusters in the worker, unless that set of
/// takes was matched already or a matching is under way (its answer asks again).
fn match_takes(inner: &Rc<Inner>) {
    let library = inner.state.library;
    if library.cluster_run.with_value(|r| r.is_some()) {
        return;
    }
    let (takes, indices) = library.matchable();
    let done_already = library.shared.with_untracked(|s| s.as_ref().is_some_and(|s| s.takes == indices));
    if indices.len() < 2 || done_already {
        return;
    }
    let run = next_id(inner);
    library.cluster_run.set_value(Some((run, indices)));
    library.matching.set(Some((false, "matching the takes…".into())));
    let request = Request::LibraryCluster { take: 0, run, takes };
    if let Err(e) = post_request(inner, request) {
        library.cluster_run.set_value(None);
        library.matching.set(Some((true, e)));
    }
}

/// A new main worker: the matching under way asked again (a take of the library it was
/// segmenting is the pool's to send again: [`post_run`]).
pub(super) fn resend(inner: &Rc<Inner>) {
    let library = inner.state.library;
    if library.cluster_run.with_value(|r| r.is_some()) {
        library.cluster_run.set_value(None);
        match_takes(inner);
    }
    if library.transfer_run.with_value(|r| r.is_some()) {
        library.transfer_run.set_value(None);
        library.carry_busy.set(false);
        library.carrying.set(Some((true, "the worker was restarted: carry the labels again".into())));
    }
    // a supervised route labelling a take: its model was kept by the page (given to the new worker),
    // so the take is sent again
    let relabel = library.by_model.with_value(|k| k.as_ref().and_then(|k| k.running.map(|(_, i)| i)));
    if let Some(i) = relabel {
        library.by_model.update_value(|k| {
            if let Some(k) = k {
                k.running = None;
                k.todo.insert(0, i);
            }
        });
        model_next(inner);
    }
}

/// Handles `response` when it is about the library's jobs; gives it back otherwise.
pub(super) fn handle(inner: &Rc<Inner>, response: Response) -> Option<Response> {
    let library = inner.state.library;
    let running = |run: RunId| owns(inner, run);
    let clip_run = library.clip_run.get_value();
    let cluster_run = library.cluster_run.with_value(|r| r.as_ref().map(|(run, _)| *run));
    let transfer_run = library.transfer_run.with_value(|r| r.as_ref().map(|(run, _, _)| *run));
    let model_run = library.by_model.with_value(|k| k.as_ref().and_then(|k| k.running.map(|(run, _)| run)));
    match response {
        Response::Progress { run: Some(run), fraction, .. } if model_run == Some(run) => {
            let (at, count, route) = library
                .by_model
                .with_value(|k| k.as_ref().map_or((0, 0, None), |k| (k.count - k.todo.len(), k.count, Some(k.route))));
            let title = route
                .and_then(|r| model_slot(inner, r))
                .map_or_else(String::new, |i| inner.state.methods[i].info.short.clone());
            let percent = fraction.unwrap_or(0.0) * 100.0;
            library
                .carrying
                .set(Some((false, format!("labelling take {at} of {count} with the {title}… {percent:.0} %"))));
        }
        Response::LibraryTake { run, segmentation, misfit, .. } if model_run == Some(run) => {
            model_took(inner, run, Ok((*segmentation, misfit)))
        }
        Response::Refused { run, message, .. } if model_run == Some(run) => model_took(inner, run, Err(message)),
        Response::Failed { run: Some(run), message, kind, .. } if model_run == Some(run) => {
            model_took(inner, run, Err(message));
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        Response::Progress { run: Some(run), stage, fraction, .. } if running(run) => {
            let i = take_of(inner, run).unwrap_or(0);
            library.queue.update(|q| q.progress(i, &stage, fraction.unwrap_or(0.0)));
        }
        Response::Progress { run: Some(run), fraction, .. } if cluster_run == Some(run) => {
            let percent = fraction.unwrap_or(0.0) * 100.0;
            library.matching.set(Some((false, format!("matching the takes… {percent:.0} %"))));
        }
        Response::Progress { run: Some(run), fraction, .. } if transfer_run == Some(run) => {
            let percent = fraction.unwrap_or(0.0) * 100.0;
            library.carrying.set(Some((false, format!("carrying the labels… {percent:.0} %"))));
        }
        Response::LibraryTransferred { run, transfer, .. } if transfer_run == Some(run) => {
            let Some((_, source, takes)) = library.transfer_run.get_value() else { return None };
            library.transfer_run.set_value(None);
            library.carry_busy.set(false);
            let carried = Carried { route: transfer.route.into(), source, takes, transferred: transfer.takes };
            let name =
                library.queue.with_untracked(|q| q.entries.get(source).map(|e| e.name.clone())).unwrap_or_default();
            library.carrying.set(Some((false, carried.summary(&name))));
            library.carried.set(Some(Arc::new(carried)));
        }
        Response::Failed { run: Some(run), message, kind, .. } if transfer_run == Some(run) => {
            library.transfer_run.set_value(None);
            library.carry_busy.set(false);
            library.carrying.set(Some((true, message)));
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        Response::LibraryTake { run, frames, duration_s, segmentation, features, .. } => {
            finish(inner, run, Ok((frames, duration_s, *segmentation, features)))
        }
        Response::LibraryClusters { run, clusters, .. } if cluster_run == Some(run) => {
            let takes = library.cluster_run.with_value(|r| r.as_ref().map(|(_, t)| t.clone())).unwrap_or_default();
            library.cluster_run.set_value(None);
            let shared = Shared { clusters: *clusters, takes };
            library.matching.set(Some((false, shared.summary())));
            library.shared.set(Some(Arc::new(shared)));
            // takes segmented meanwhile are matched too
            if !library.queue.with_untracked(|q| q.busy()) {
                match_takes(inner);
            }
        }
        Response::Failed { run: Some(run), message, kind, .. } if cluster_run == Some(run) => {
            library.cluster_run.set_value(None);
            library.matching.set(Some((true, message)));
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        Response::Refused { run, message, .. } if running(run) => finish(inner, run, Err(message)),
        // the library segments with the unsupervised methods only, which need no model file
        Response::NeedsModel { run, file, .. } if running(run) => finish(
            inner,
            run,
            Err(format!("the library's method asked for a model file ({file}), which it does not fetch")),
        ),
        Response::Failed { run: Some(run), message, kind, .. } if running(run) => {
            if kind == FailureKind::Internal {
                trapped(inner, run, message);
            } else {
                finish(inner, run, Err(message));
            }
        }
        Response::Failed { run: Some(run), message, kind, .. } if clip_run == Some(run) => {
            library.clip_run.set_value(None);
            library.status.set(Some((true, message)));
            if kind == FailureKind::Internal {
                replace_worker(inner);
            }
        }
        Response::Clips { run, file, clips, bytes, .. } if clip_run == Some(run) => {
            library.clip_run.set_value(None);
            library.status.set(Some(match download(&bytes, "application/zip", &file) {
                Ok(()) => (false, format!("saved {file} ({})", crate::method::counted(clips, "clip"))),
                Err(e) => (true, format!("could not save {file}: {}", js_message(&e))),
            }));
        }
        other => return Some(other),
    }
    None
}

/// The main worker failed outside a request: the library's takes it was segmenting fail with
/// `message` — those the pool no longer places (neither waiting nor on a run worker); the run
/// workers' go on.
pub(super) fn fail_all(inner: &Rc<Inner>, message: &str) {
    let runs = inner.state.library.running.get_value();
    for (run, _) in runs {
        let elsewhere = {
            let pool = inner.pool.borrow();
            pool.is_queued(run) || pool.slot_of(run).is_some_and(|slot| slot > 0)
        };
        if !elsewhere {
            finish(inner, run, Err(message.to_string()));
        }
    }
}
