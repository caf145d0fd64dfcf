//! The library's takes in the workers: each take is a run of the pool (`library_take`: a worker reads the take,
//! segments it and lets its frames go; the take on screen stays the one it holds), placed beside the rows' runs,
//! as many at once as the pool has workers; cancelled by replacing the workers that run them. Once no take is left
//! to segment, the segmented takes (their features and segmentations, never their frames) are matched into clusters
//! shared across takes (`library_cluster`), again when takes are added. The clips of several takes are cut into one
//! zip (`library_clips`: each take's file read again from its `File`).

use crate::app::library::library_jobs::{read_files, take_request, LibraryJobs};
use crate::app::library::state::Source;
use crate::app::library::takes::{group_files, Shared};
use crate::app::take::fetch::blob_bytes;
use crate::library::TakeFeatures;
use crate::protocol::{ClipTake, Request, RunId};
use crate::worker::pool::{Placed, Slot, Stop};
use leptos::prelude::*;
use web_sys::{Blob, File};

/// What the worker made of a take of the library: its frames, seconds, segmentation and features
/// (or why it has none).
pub(super) type Took = (usize, f64, crate::segment::Segmentation, Result<Box<TakeFeatures>, String>);

impl LibraryJobs {
    /// Opens files dropped or picked together: one take as ever ([`crate::app::loader::Loader::load_files`]); two
    /// or more (a folder's) go to the library, queued for the workers, and the first of them opens.
    pub fn open_dropped(&self, files: Vec<File>) {
        let names: Vec<String> = files.iter().map(file_path).collect();
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let (takes, mut refused) = group_files(&refs);
        let sizes: Vec<f64> = files.iter().map(|f| f.size()).collect();
        let held = self.0.state.library.held_bytes();
        let (takes, too_large) = crate::app::library::takes::within_cap(takes, &refs, &sizes, held);
        refused.extend(too_large);
        let library = self.0.state.library;
        if takes.len() < 2 {
            library.open.set(None);
            if takes.len() == 1 && files.len() >= 2 {
                // a folder or a selection holding one take (and other files, e.g. a BVH with its README): that take
                let t = takes[0];
                let mut one = vec![files[t.motion].clone()];
                one.extend(t.skeleton.map(|s| files[s].clone()));
                return self.0.loader.load_files(one);
            }
            return self.0.loader.load_files(files);
        }
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
        self.pump();
    }

    /// Which of `sources` (a kept library's, a project's) the library admits: the same caps as files dropped (a take's,
    /// the library's total, counting what it holds); those left out are said in the library's status.
    pub fn admit(&self, sources: &[Source]) -> Vec<bool> {
        let library = self.0.state.library;
        let mut files = Vec::new();
        let mut whole = Vec::new();
        for s in sources {
            whole.push(crate::app::library::takes::TakeFiles {
                motion: files.len(),
                skeleton: s.skeleton.as_ref().map(|_| files.len() + 1),
            });
            files.push(s.motion.clone());
            files.extend(s.skeleton.clone());
        }
        let names: Vec<String> = files.iter().map(File::name).collect();
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let sizes: Vec<f64> = files.iter().map(|f| f.size()).collect();
        let (admitted, refused) =
            crate::app::library::takes::within_cap(whole.clone(), &refs, &sizes, library.held_bytes());
        if !refused.is_empty() {
            library.status.set(Some((true, refused.join("; "))));
        }
        whole.iter().map(|t| admitted.contains(t)).collect()
    }

    /// Sets the library again as it was kept (its takes' files, the method they are segmented with, the names given
    /// to its clusters): the takes are queued and segmented again, and the names follow their clusters once matched.
    pub fn restore(&self, sources: Vec<Source>, method: String, names: crate::app::library::names::ClusterNames) {
        let library = self.0.state.library;
        if sources.is_empty() {
            return;
        }
        library.method.set(method);
        library.names.set(names);
        library.add(sources);
        self.pump();
    }

    /// Opens take `i` of the library on screen, as a dropped file opens (its file read again).
    pub fn open_library_take(&self, i: usize) {
        let Some(source) = self.0.state.library.source(i) else { return };
        self.0.state.library.open.set(Some(i));
        let mut files = vec![source.motion];
        files.extend(source.skeleton);
        self.0.loader.load_files(files);
    }

    /// Cancels the library's queue: the takes running (their workers are replaced: a wasm worker cannot
    /// be interrupted), every take still queued, the matching and the carrying of labels.
    pub fn cancel_library(&self) {
        let library = self.0.state.library;
        library.queue.update(|q| {
            q.cancel();
        });
        // the takes under way: dropped where they wait, their run workers replaced, the main
        // worker replaced below if one runs there
        let runs = library.running.get_value();
        library.running.set_value(Vec::new());
        for &(run, _) in &runs {
            self.0.loader.forget(run);
        }
        let stops: Vec<Stop> = runs.iter().map(|&(run, _)| self.0.loader.stop(run)).collect();
        let mut running = false;
        for stop in stops {
            match stop {
                Stop::Replace(0) => running = true,
                Stop::Replace(slot) => self.0.loader.replace_slot(slot),
                Stop::Dequeued | Stop::Unknown => {}
            }
        }
        // the matching under way goes too
        let matching = library.cluster_run.get_value();
        if let Some((run, _)) = matching {
            self.0.loader.forget(run);
            library.cluster_run.set_value(None);
            library.matching.set(Some((true, "matching cancelled".into())));
        }
        // and the clips being cut
        self.stop_clip_export();
        // and the carrying of labels
        let carrying = self.stop_carrying();
        if running || matching.is_some() || carrying {
            self.0.loader.replace_worker();
        }
    }

    /// Empties the library, its jobs in the workers cancelled (the page starts afresh).
    pub fn clear(&self) {
        self.cancel_library();
        self.0.state.library.clear();
        if self.0.state.panel.get_untracked() == crate::app::library::state::TAB {
            self.0.state.panel.set(crate::app::state::TRUTH_TAB.to_string());
        }
    }

    /// Queues the library's cancelled and failed takes again.
    pub fn rerun_library(&self) {
        self.0.state.library.queue.update(|q| q.requeue());
        self.pump();
    }

    /// Cuts the occurrences `takes` (library index, its segments to cut, each labelled with its cluster's name) as BVH
    /// clips into one zip `file`, one take at a time: each take's file read again and sent alone, its clips zipped in
    /// the worker and joined to the archive ([`crate::app::library::state::ClipExport`]).
    pub fn export_library_clips(
        &self,
        file: String,
        takes: Vec<(usize, crate::segment::Segmentation)>,
        to_origin: bool,
    ) {
        let library = self.0.state.library;
        // an export under way gives way (its take in the worker forgotten: its zip must not join this one)
        self.stop_clip_export();
        // the clips are named from their take's name: takes of one name (from two folders) get distinct ones
        let names: Vec<String> = takes.iter().map(|(i, _)| library.take_name(*i)).collect();
        let mut stems: Vec<String> = names.iter().map(|n| crate::clips::stem_of(n).to_string()).collect();
        crate::app::library::takes::make_unique(&mut stems);
        let todo = takes
            .into_iter()
            .zip(names.iter().zip(&stems))
            .map(|((i, s), (name, stem))| {
                let ext = name.rsplit_once('.').map_or(String::new(), |(_, e)| format!(".{e}"));
                (i, s, format!("{stem}{ext}"))
            })
            .collect::<std::collections::VecDeque<_>>();
        let count = todo.len();
        library.clip_export.set_value(Some(crate::app::library::state::ClipExport {
            file,
            to_origin,
            todo,
            takes: count,
            join: crate::clips::ZipJoin::new(),
            parts: js_sys::Array::new(),
            clips: 0,
        }));
        self.next_clip_take();
    }

    /// Sends the next take of the clip export under way to the worker, or, none left, saves the archive.
    pub(super) fn next_clip_take(&self) {
        let library = self.0.state.library;
        let next = library.clip_export.with_value(|e| {
            e.as_ref().map(|e| (e.todo.front().cloned(), e.takes - e.todo.len(), e.takes, e.to_origin))
        });
        let Some((next, done, count, to_origin)) = next else { return };
        let Some((i, segmentation, name)) = next else { return self.save_clip_export() };
        library.status.set(Some((false, format!("cutting the clips: take {} of {count}…", done + 1))));
        let this = self.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let fail = |message: String| {
                library.clip_export.set_value(None);
                library.status.set(Some((true, message)));
            };
            let Some(source) = library.source(i) else {
                return fail("the library changed while its clips were cut".into());
            };
            let buffers = js_sys::Array::new();
            for blob in std::iter::once(&source.motion).chain(source.skeleton.as_ref()) {
                match blob_bytes(&Blob::from(blob.clone())).await {
                    Ok(bytes) => {
                        buffers.push(&bytes);
                    }
                    Err(e) => return fail(format!("{}: could not read the file again: {e}", blob.name())),
                }
            }
            if library.clip_export.with_value(Option::is_none) {
                return; // cancelled while the file was read
            }
            library.clip_export.update_value(|e| {
                if let Some(e) = e {
                    e.todo.pop_front();
                }
            });
            let take = ClipTake { name, skeleton: source.skeleton.as_ref().map(File::name), segmentation };
            let run = this.0.loader.new_run();
            let file = library.clip_export.with_value(|e| e.as_ref().map(|e| e.file.clone())).unwrap_or_default();
            let request = Request::LibraryClips { take: 0, run, file, takes: vec![take], to_origin, bytes: Vec::new() };
            match this.0.loader.send_buffers(this.jobs(), &request, buffers) {
                Ok(()) => library.clip_run.set_value(Some(run)),
                Err(e) => fail(e),
            }
        });
    }

    /// One take's clips, zipped by the worker: joined to the archive, then the next take.
    pub(super) fn clip_part(&self, clips: usize, zipped: &[u8]) {
        let library = self.0.state.library;
        let joined = library.clip_export.try_update_value(|e| {
            let e = e.as_mut()?;
            Some(e.join.add(zipped).map(|local| {
                e.parts.push(&js_sys::Uint8Array::from(local));
                e.clips += clips;
            }))
        });
        match joined.flatten() {
            Some(Ok(())) => self.next_clip_take(),
            Some(Err(e)) => {
                library.clip_export.set_value(None);
                library.status.set(Some((true, e.to_string())));
            }
            None => {}
        }
    }

    /// Every take cut: the archive's end joined, and the archive saved.
    fn save_clip_export(&self) {
        let library = self.0.state.library;
        let Some(export) = library.clip_export.try_update_value(Option::take).flatten() else { return };
        let crate::app::library::state::ClipExport { file, join, parts, clips, .. } = export;
        let said = join.finish().map_err(|e| e.to_string()).and_then(|end| {
            parts.push(&js_sys::Uint8Array::from(&end[..]));
            crate::app::player::motion_image::download_parts(&parts, "application/zip", &file)
                .map_err(|e| format!("could not save {file}: {}", crate::app::dom::js_message(&e)))
        });
        library.status.set(Some(match said {
            Ok(()) => (false, format!("saved {file} ({})", crate::method::counted(clips, "clip"))),
            Err(message) => (true, message),
        }));
    }

    /// Stops the clip export under way (its take in the worker is forgotten); whether one was.
    pub(super) fn stop_clip_export(&self) -> bool {
        let library = self.0.state.library;
        let was = library.clip_export.try_update_value(Option::take).flatten().is_some();
        if let Some(run) = library.clip_run.get_value() {
            self.0.loader.forget(run);
            library.clip_run.set_value(None);
        }
        if was {
            library.status.set(Some((false, "cutting the clips cancelled".into())));
        }
        was
    }

    /// Sends the library's queued takes to the pool, as many at once as it has workers (each waits
    /// there for a free worker, beside the rows' runs).
    pub(super) fn pump(&self) {
        let library = self.0.state.library;
        let workers = self.0.loader.workers();
        loop {
            let mut next = None;
            library.queue.update(|q| next = q.start_next(workers));
            let Some(i) = next else { return };
            let run = self.0.loader.new_run();
            library.running.update_value(|r| r.push((run, i)));
            match self.0.loader.place(self.jobs(), run) {
                Placed::Now(slot) => self.send(run, i, slot),
                Placed::Queued => library.queue.update(|q| q.progress(i, "waiting for a worker", 0.0)),
            }
        }
    }

    /// The pool gave run `run` worker `slot`: its take is sent there.
    pub(super) fn post_take(&self, run: RunId, slot: Slot) {
        let Some(i) = self.take_of(run) else { return };
        self.0.state.library.queue.update(|q| q.progress(i, "starting", 0.0));
        self.send(run, i, slot);
    }

    /// Sends take `i` of the library as run `run` to worker `slot` (its file read from its `File`).
    fn send(&self, run: u32, i: usize, slot: Slot) {
        let library = self.0.state.library;
        let Some(source) = library.source(i) else { return };
        let slot_of = self.0.state.methods.iter().find(|s| s.info.name == library.method.get_untracked());
        let (method, params) = match slot_of.map(|s| (s.info.name.clone(), s.params())) {
            Some((name, Ok(params))) => (name, params),
            Some((_, Err(e))) => return self.finish(run, Err(e.to_string())),
            None => return self.finish(run, Err("no method chosen for the library".into())),
        };
        let this = self.clone();
        wasm_bindgen_futures::spawn_local(async move {
            let buffers = match read_files(&source).await {
                Ok(buffers) => buffers,
                Err(e) => return this.finish(run, Err(e)),
            };
            // cancelled, or its worker replaced, while the file was read
            if this.take_of(run).is_none() || this.0.loader.worker_of(run) != Some(slot) {
                return;
            }
            let request = take_request(run, &source, method, params);
            if let Err(e) = this.0.loader.post_buffers_to(slot, &request, buffers) {
                this.finish(run, Err(e));
            }
        });
    }

    /// Ends run `run` of the library (its take done or failed): its worker is free for the next run,
    /// and the next takes are sent; once none is left, the takes are matched across the library.
    pub(super) fn finish(&self, run: u32, outcome: Result<Took, String>) {
        let library = self.0.state.library;
        let Some(i) = self.take_of(run) else { return };
        library.running.update_value(|r| r.retain(|(r, _)| *r != run));
        self.0.loader.forget(run);
        // the worker is free
        self.0.loader.release(run);
        match outcome {
            Ok((frames, duration_s, segmentation, features)) => {
                library.set_features(i, features.map(|f| *f));
                library.queue.update(|q| q.done(i, frames, duration_s, segmentation));
            }
            Err(message) => library.queue.update(|q| q.failed(i, message)),
        }
        self.pump();
        if !library.queue.with_untracked(|q| q.busy()) {
            self.match_takes();
        }
    }

    /// Matches the library's segmented takes into shared clusters in the worker, unless that set of
    /// takes was matched already or a matching is under way (its answer asks again).
    pub(super) fn match_takes(&self) {
        let library = self.0.state.library;
        if library.cluster_run.with_value(|r| r.is_some()) {
            return;
        }
        let (takes, indices) = library.matchable();
        let done_already = library.shared.with_untracked(|s| s.as_ref().is_some_and(|s| s.takes == indices));
        if indices.len() < 2 || done_already {
            return;
        }
        let run = self.0.loader.new_run();
        library.cluster_run.set_value(Some((run, indices)));
        library.matching.set(Some((false, "matching the takes…".into())));
        let request = Request::LibraryCluster { take: 0, run, takes };
        if let Err(e) = self.0.loader.send_own(self.jobs(), request) {
            library.cluster_run.set_value(None);
            library.matching.set(Some((true, e)));
        }
    }

    /// The takes matched into clusters (`run`'s answer).
    pub(super) fn matched(&self, run: RunId, clusters: crate::library::SharedClusters) {
        let library = self.0.state.library;
        self.0.loader.forget(run);
        let takes = library.cluster_run.with_value(|r| r.as_ref().map(|(_, t)| t.clone())).unwrap_or_default();
        library.cluster_run.set_value(None);
        let shared = Shared { clusters, takes };
        library.matching.set(Some((false, shared.summary())));
        library.show_matching(shared);
        // takes segmented meanwhile are matched too
        if !library.queue.with_untracked(|q| q.busy()) {
            self.match_takes();
        }
    }

    /// A new main worker: the matching under way asked again (a take of the library it was
    /// segmenting is the pool's to send again).
    pub(super) fn resend_matching(&self) {
        let library = self.0.state.library;
        if let Some((run, _)) = library.cluster_run.get_value() {
            self.0.loader.forget(run);
            library.cluster_run.set_value(None);
            self.match_takes();
        }
    }

    /// The main worker failed outside a request: the library's takes it was segmenting fail with
    /// `message` — those the pool no longer places (neither waiting nor on a run worker); the run
    /// workers' go on.
    pub(super) fn fail_takes(&self, message: &str) {
        let runs = self.0.state.library.running.get_value();
        for (run, _) in runs {
            if !self.0.loader.away_from_main(run) {
                self.finish(run, Err(message.to_string()));
            }
        }
    }
}

/// A dropped or picked file's path within the folder picked (`webkitRelativePath`), else its name.
fn file_path(file: &File) -> String {
    js_sys::Reflect::get(file, &"webkitRelativePath".into())
        .ok()
        .and_then(|p| p.as_string())
        .filter(|p| !p.is_empty())
        .unwrap_or_else(|| file.name())
}
