//! The take on screen's labels carried to the library's other takes on request: by a transfer in the worker
//! (`library_transfer`, the routes that match features), or — the k-NN and DT-FCN routes — by training that method on
//! them (its panel's training, [`crate::app::models::training_jobs`]) and labelling every other take with the model
//! (`library_take`, the model in its params), one after another. [`LibraryJobs::cancel_carry`] stops either.

use crate::app::library::carry::{Carried, Route};
use crate::app::library::library_jobs::{read_files, take_request, LibraryJobs};
use crate::app::library::state::ModelCarry;
use crate::app::models::supervised::TrainAsk;
use crate::protocol::{Request, RunId};
use leptos::prelude::*;
use std::sync::Arc;

impl LibraryJobs {
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
        let run = self.0.loader.new_run();
        library.transfer_run.set_value(Some((run, source, indices)));
        library.carrying.set(Some((false, "carrying the labels…".into())));
        library.carry_busy.set(true);
        let request = Request::LibraryTransfer { take: 0, run, takes, labelled, frame_labels, route };
        if let Err(e) = self.0.loader.send_own(self.jobs(), request) {
            library.transfer_run.set_value(None);
            library.carry_busy.set(false);
            library.carrying.set(Some((true, e)));
        }
    }

    /// A supervised route (`route`: the k-NN or DT-FCN): trains that method on take `source`'s `labels` (the take on
    /// screen) with its panel's training options, then labels every other take of the library with the model
    /// ([`LibraryJobs::model_trained`], [`LibraryJobs::model_next`]).
    fn carry_by_model(&self, route: Route, source: usize, labels: Vec<Option<String>>) {
        let state = self.0.state;
        let library = state.library;
        let fail = |why: String| library.carrying.set(Some((true, why)));
        let Some(method) = route.method() else { return };
        let Some((index, slot)) = state.methods.iter().enumerate().find(|(_, s)| s.info.name == method) else {
            return fail(format!("this page has no {method}"));
        };
        let title = slot.info.short.clone();
        let Some(s) = slot.supervised.as_ref() else { return fail(format!("the {title} cannot be trained here")) };
        if self.0.models.training() {
            return fail("a training is under way: carry the labels once it has ended".into());
        }
        let todo: Vec<usize> =
            library.queue.with_untracked(|q| (0..q.entries.len()).filter(|&i| i != source).collect());
        if todo.is_empty() {
            return fail("the library has no other take to carry the labels to yet".into());
        }
        let Some((file, _)) = self.0.loader.shown_file() else {
            return fail("open a take of the library (its name in the list) to carry its labels".into());
        };
        let texts: Vec<String> = s.fields.iter().map(|f| f.get_untracked()).collect();
        let options = match crate::method::form::params_from_form(&slot.info.short, &s.decl.training, &texts) {
            Ok(options) => options,
            Err(e) => return fail(format!("the {title} panel's training options: {e}")),
        };
        let rows = crate::app::library::carry::label_rows(&file, &labels);
        let fps = state.motion.with_untracked(|m| m.as_ref().map_or(0.0, |m| m.summary.fps));
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
        self.0.models.train(
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

    /// Cancels the carrying of labels under way (either route): the worker is replaced when it
    /// works on it; a method still training stops as its panel's Stop does.
    pub fn cancel_carry(&self) {
        if self.stop_carrying() {
            self.0.loader.replace_worker();
        }
    }

    /// Ends the carrying under way (either route) as cancelled; whether the worker works on it.
    pub(super) fn stop_carrying(&self) -> bool {
        let library = self.0.state.library;
        let transfer = library.transfer_run.with_value(|r| r.as_ref().map(|(run, _, _)| *run));
        library.transfer_run.set_value(None);
        let by_model = library
            .by_model
            .with_value(|k| k.as_ref().map(|k| (k.model.is_none(), k.running.map(|(run, _)| run), k.route)));
        library.by_model.set_value(None);
        for run in transfer.into_iter().chain(by_model.and_then(|(_, running, _)| running)) {
            self.0.loader.forget(run);
        }
        if let Some((true, _, route)) = by_model {
            if let Some(index) = self.model_slot(route) {
                // still training: stopped as the panel's Stop does (it replaces the worker itself if need be)
                self.0.models.stop_training(index);
            }
        }
        if transfer.is_some() || by_model.is_some() {
            library.carry_busy.set(false);
            library.carrying.set(Some((true, "carrying cancelled".into())));
        }
        transfer.is_some() || by_model.is_some_and(|(_, running, _)| running.is_some())
    }

    /// The slot of the method a supervised route trains.
    pub(super) fn model_slot(&self, route: Route) -> Option<usize> {
        let method = route.method()?;
        self.0.state.methods.iter().position(|s| s.info.name == method)
    }

    /// The training of method `index` ended (`Ok`: the model's name, stored in the worker): when it
    /// was a supervised route's, the other takes are labelled with it, or the carrying fails with why.
    pub(super) fn model_trained(&self, index: usize, model: Result<String, String>) {
        let library = self.0.state.library;
        let route = library.by_model.with_value(|k| k.as_ref().filter(|k| k.model.is_none()).map(|k| k.route));
        let Some(route) = route else { return };
        if self.model_slot(route) != Some(index) {
            return;
        }
        let title = self.0.state.methods[index].info.short.clone();
        match model {
            Ok(name) => {
                library.by_model.update_value(|k| {
                    if let Some(k) = k {
                        k.model = Some(name);
                    }
                });
                self.model_next();
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
    pub(super) fn model_next(&self) {
        let state = self.0.state;
        let library = state.library;
        let Some(mut k) = library.by_model.get_value() else { return };
        let Some(model) = k.model.clone() else { return };
        let Some(index) = self.model_slot(k.route) else { return };
        let Some(i) = (!k.todo.is_empty()).then(|| k.todo.remove(0)) else {
            library.by_model.set_value(None);
            library.carry_busy.set(false);
            let name = self.take_name(k.source);
            let carried = Carried::by_model(k.route, k.source, &k.file, k.fps, k.labels, k.done);
            let short = state.methods[index].info.short.clone();
            let summary = carried.model_summary(&name, &short, &k.misfits, &k.failed);
            library.carrying.set(Some((!k.failed.is_empty() && carried.takes.len() < 2, summary)));
            library.carried.set(Some(Arc::new(carried)));
            return;
        };
        let Some(source) = library.source(i) else {
            library.by_model.set_value(Some(k));
            return self.model_next();
        };
        let run = self.0.loader.new_run();
        k.running = Some((run, i));
        let at = k.count - k.todo.len();
        let count = k.count;
        library.by_model.set_value(Some(k));
        let name = source.motion.name();
        let slot = &state.methods[index];
        let (method, title) = (slot.info.name.clone(), slot.info.short.clone());
        library.carrying.set(Some((false, format!("labelling take {at} of {count} ({name}) with the {title}…"))));
        let params = match slot.params() {
            Ok(mut params) => {
                params["model"] = serde_json::Value::String(model);
                params
            }
            Err(_) => serde_json::json!({ "model": model }),
        };
        let this = self.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let read = read_files(&source).await;
            // cancelled (or replaced) while the file was read
            if this.model_run() != Some(run) {
                return;
            }
            let sent = read.and_then(|buffers| {
                this.0.loader.send_buffers(this.jobs(), &take_request(run, &source, method, params), buffers)
            });
            if let Err(e) = sent {
                this.model_took(run, Err(e));
            }
        });
    }

    /// The run labelling a take with a supervised route's model, if one is under way.
    pub(super) fn model_run(&self) -> Option<RunId> {
        self.0.state.library.by_model.with_value(|k| k.as_ref().and_then(|k| k.running).map(|(r, _)| r))
    }

    /// A supervised route's run `run` labelled its take (with why the model does not fit it, if so) or failed: kept,
    /// and the next take is sent.
    pub(super) fn model_took(
        &self,
        run: RunId,
        outcome: Result<(crate::segment::Segmentation, Option<String>), String>,
    ) {
        let library = self.0.state.library;
        let Some(mut k) = library.by_model.get_value().filter(|k| k.running.is_some_and(|(r, _)| r == run)) else {
            return;
        };
        self.0.loader.forget(run);
        let Some((_, i)) = k.running.take() else { return };
        match outcome {
            Ok((segmentation, misfit)) => {
                if let Some(why) = misfit {
                    k.misfits.push(format!("{}: {why}", self.take_name(i)));
                }
                k.done.push((i, segmentation))
            }
            Err(message) => k.failed.push(format!("{}: {message}", self.take_name(i))),
        }
        library.by_model.set_value(Some(k));
        self.model_next();
    }

    /// A supervised route labelling a take when the main worker was replaced: its model was kept by the page (given
    /// to the new worker), so the take is sent again; a transfer under way is asked again by the user.
    pub(super) fn resend_carrying(&self) {
        let library = self.0.state.library;
        if let Some((run, _, _)) = library.transfer_run.get_value() {
            self.0.loader.forget(run);
            library.transfer_run.set_value(None);
            library.carry_busy.set(false);
            library.carrying.set(Some((true, "the worker was restarted: carry the labels again".into())));
        }
        let relabel = library.by_model.with_value(|k| k.as_ref().and_then(|k| k.running));
        if let Some((run, i)) = relabel {
            self.0.loader.forget(run);
            library.by_model.update_value(|k| {
                if let Some(k) = k {
                    k.running = None;
                    k.todo.insert(0, i);
                }
            });
            self.model_next();
        }
    }

    /// The transfer `run` answered: the labels carried, or why not.
    pub(super) fn transferred(&self, run: RunId, outcome: Result<crate::library::Transfer, String>) {
        let library = self.0.state.library;
        self.0.loader.forget(run);
        let Some((_, source, takes)) = library.transfer_run.get_value() else { return };
        library.transfer_run.set_value(None);
        library.carry_busy.set(false);
        match outcome {
            Ok(transfer) => {
                let carried = Carried { route: transfer.route.into(), source, takes, transferred: transfer.takes };
                library.carrying.set(Some((false, carried.summary(&self.take_name(source)))));
                library.carried.set(Some(Arc::new(carried)));
            }
            Err(message) => library.carrying.set(Some((true, message))),
        }
    }

    /// The transfer under way, if any.
    pub(super) fn transfer_run(&self) -> Option<RunId> {
        self.0.state.library.transfer_run.with_value(|r| r.as_ref().map(|(run, _, _)| *run))
    }
}
