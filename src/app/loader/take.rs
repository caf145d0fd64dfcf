//! The take's loads: reading a dropped or picked file (or fetching the bundled sample, or the page's `src=` file),
//! handing its bytes to the main worker (transferred, not copied), the worker's answers about the load, and the
//! take on screen sent again to a worker that lost it.
//!
//! Every load gets a new take id; only the newest load counts. The page keeps the take on screen
//! as a `Blob` — the dropped `File` itself (a handle on the file, not its bytes), or what a
//! download read — never a second copy of its bytes: they are read from it each time they go to
//! a worker, and the worker holds the only copy.

use crate::app::dom::js_message;
use crate::app::loader::pool;
use crate::app::loader::transport::{features, next_id, post, Inner, Open, Take};
use crate::app::state::LoadState;
use crate::app::take::fetch::{blob_bytes, read_capped, ReadError, MAX_FILE_BYTES};
use crate::load::Opening;
use crate::protocol::{Request, Response, TakeId};
use leptos::prelude::*;
use std::rc::Rc;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{Blob, File, Response as FetchResponse};

/// Opens `open` at once.
pub(super) fn open_now(inner: &Rc<Inner>, open: Open) {
    match open {
        Open::Sample => open_sample(inner),
        Open::Files(files) => open_files(inner, files),
    }
}

/// Loads the bundled sample.
fn open_sample(inner: &Rc<Inner>) {
    let inner = inner.clone();
    let (url, name, packed) = (inner.urls.sample.clone(), inner.urls.sample_name(), inner.urls.sample_is_packed());
    let id = begin(&inner, &name);
    wasm_bindgen_futures::spawn_local(async move {
        let file = match fetch_blob(&url).await {
            Ok(file) if packed => unpack_blob(&file).await,
            fetched => fetched,
        };
        match file {
            Ok(file) => send_load(&inner, id, &name, (file, None), true),
            Err(message) => fail_load(&inner, id, format!("{name}: could not load the sample: {message}")),
        }
    });
}

/// Loads the file at `url` (the URL parameter `src`) as `name` ([`crate::app::loader::Loader::load_src`]).
pub(super) fn open_src(
    inner: &Rc<Inner>,
    url: String,
    name: String,
    fetch: impl std::future::Future<Output = Result<(Blob, Option<(String, Vec<u8>)>), String>> + 'static,
) {
    let inner = inner.clone();
    let id = begin(&inner, &name);
    *inner.src_take.borrow_mut() = Some((id, url));
    wasm_bindgen_futures::spawn_local(async move {
        match fetch.await {
            Ok((file, skeleton)) => send_load(&inner, id, &name, (file, skeleton), false),
            Err(message) => {
                inner.src_take.borrow_mut().take();
                fail_load(&inner, id, message)
            }
        }
    });
}

/// Loads `file` (with an AMC motion's ASF `skeleton`) as `name` ([`crate::app::loader::Loader::load_blob`]).
pub(super) fn open_blob(inner: &Rc<Inner>, name: &str, file: Blob, skeleton: Option<(String, Vec<u8>)>) {
    let id = begin(inner, name);
    send_load(inner, id, name, (file, skeleton), false);
}

/// Loads the files `files` (see [`crate::app::loader::Loader::load_files`]).
fn open_files(inner: &Rc<Inner>, files: Vec<File>) {
    let inner = inner.clone();
    let names: Vec<String> = files.iter().map(File::name).collect();
    let refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let opening = crate::load::opening(&refs);
    let (motion, skeleton) = match opening {
        Ok(Opening::One(i)) => (files[i].clone(), None),
        Ok(Opening::AsfAmc { asf, amc }) => (files[amc].clone(), Some(files[asf].clone())),
        Err(message) => {
            let id = begin(&inner, names.first().map_or("", String::as_str));
            return fail_load(&inner, id, message);
        }
    };
    let name = motion.name();
    let id = begin(&inner, &name);
    if let Some(big) = files.iter().find(|f| f.size() > MAX_FILE_BYTES as f64) {
        let mib = big.size() / 1024.0 / 1024.0;
        return fail_load(
            &inner,
            id,
            format!("{}: {mib:.0} MiB is more than the page reads (512 MiB); cut the take", big.name()),
        );
    }
    wasm_bindgen_futures::spawn_local(async move {
        let skeleton = match skeleton {
            None => None,
            Some(asf) => match JsFuture::from(asf.array_buffer()).await {
                Ok(b) => Some((asf.name(), js_sys::Uint8Array::new(&b).to_vec())),
                Err(e) => {
                    let message = format!("{}: could not read the file: {}", asf.name(), js_message(&e));
                    return fail_load(&inner, id, message);
                }
            },
        };
        // the File itself: its bytes are read when it is sent, and not kept
        send_load(&inner, id, &name, (Blob::from(motion), skeleton), false);
    });
}

/// Starts a new load: it becomes the current one.
fn begin(inner: &Inner, name: &str) -> TakeId {
    let id = next_id(inner);
    inner.current.set(id);
    inner.state.load.set(LoadState::Loading { name: name.to_string(), stage: "reading".into(), fraction: None });
    id
}

/// Sends a load of `files` as take `id`: the file, with its ASF skeleton (name, bytes) for an AMC motion
/// (`None` for any other file); `sample`: the bundled sample's; the page keeps the `Blob`, to send it again if needed. One
/// function for both, so that no path (a worker restart) can send an AMC without its skeleton.
pub(super) fn send_load(
    inner: &Rc<Inner>,
    id: TakeId,
    name: &str,
    files: (Blob, Option<(String, Vec<u8>)>),
    sample: bool,
) {
    let (file, skeleton) = files;
    if inner.current.get() != id {
        return;
    }
    let take = Take { id, name: name.to_string(), file, skeleton, sample };
    *inner.pending.borrow_mut() = Some(take.clone());
    let send = inner.load_sends.get().wrapping_add(1);
    inner.load_sends.set(send);
    let inner = inner.clone();
    wasm_bindgen_futures::spawn_local(async move {
        let bytes = blob_bytes(&take.file).await.map_err(|e| format!("could not read the file: {e}"));
        // a newer load, or a newer send of this one, is the one to post
        let newest = inner.load_sends.get() == send && inner.pending.borrow().as_ref().is_some_and(|t| t.id == take.id);
        if !newest {
            return;
        }
        let sent = bytes.and_then(|bytes| post(&inner, &load_request(&take, false), Some(&bytes)));
        if let Err(e) = sent {
            fail_load(&inner, take.id, format!("{}: {e}", take.name));
        }
    });
}

/// The pending load sent again (to a new main worker), as it was asked: an AMC motion with its ASF skeleton.
pub(super) fn send_pending(inner: &Rc<Inner>) {
    let pending = inner.pending.borrow().clone();
    if let Some(take) = pending {
        send_load(inner, take.id, &take.name, (take.file, take.skeleton), take.sample);
    }
}

/// The load request of `take` (its bytes go as the transferred buffer).
fn load_request(take: &Take, restore: bool) -> Request {
    let (skeleton, skeleton_bytes) = match &take.skeleton {
        Some((name, bytes)) => (Some(name.clone()), bytes.clone()),
        None => (None, Vec::new()),
    };
    Request::Load { take: take.id, name: take.name.clone(), restore, bytes: Vec::new(), skeleton, skeleton_bytes }
}

/// Sends the take on screen to the main worker again (it answers `restored`); its bytes are read from
/// its `Blob` first.
pub(super) async fn restore(inner: &Rc<Inner>) -> Result<(), String> {
    let take = inner.shown.borrow().clone().ok_or("no take is loaded")?;
    let bytes =
        blob_bytes(&take.file).await.map_err(|e| format!("{}: could not read the file again: {e}", take.name))?;
    post(inner, &load_request(&take, true), Some(&bytes))
}

/// The load `id` failed with `message` (naming the page's `src=` URL when it was that file's).
pub(super) fn fail_load(inner: &Inner, id: TakeId, message: String) {
    let message = match inner.src_take.borrow().as_ref() {
        Some((take, url)) if *take == id => crate::app::embed::url_params::load_failed(url, &message),
        _ => message,
    };
    if inner.current.get() == id {
        *inner.pending.borrow_mut() = None;
        inner.state.show_error(message);
        inner.state.load.set(LoadState::Failed);
    }
}

/// The main worker's answers about the newest load (its progress, the take loaded); gives back any other answer.
pub(super) fn on_load_reply(inner: &Rc<Inner>, response: Response) -> Option<Response> {
    let state = inner.state;
    match response {
        Response::Progress { take, run: None, stage, fraction } => {
            if take == inner.current.get() {
                state.load.update(|load| {
                    if let LoadState::Loading { stage: s, fraction: f, .. } = load {
                        *s = stage;
                        *f = fraction;
                    }
                });
            }
        }
        Response::Loaded { take, motion } => {
            if take != inner.current.get() {
                return None; // a load that has been superseded
            }
            *inner.shown.borrow_mut() = inner.pending.borrow_mut().take();
            state.playing.set(false);
            state.play_until.set(None);
            state.frame.set(0);
            for jobs in features(inner) {
                jobs.take_changed();
            }
            state.motion.set(Some(Arc::new(*motion)));
            state.error.set(None);
            state.load.set(LoadState::Ready);
            // every run worker gets the take (the main worker's motion of it) before its first run
            pool::new_take(inner);
            for jobs in features(inner) {
                jobs.take_ready();
            }
        }
        Response::Restored { .. } | Response::Held { .. } => {}
        other => return Some(other),
    }
    None
}

/// The file a packed file holds (`crate::bvh::unpack`: the same bytes as the file packed), as a
/// `Blob` the page keeps as the take.
async fn unpack_blob(packed: &Blob) -> Result<Blob, String> {
    let bytes = js_sys::Uint8Array::new(&blob_bytes(packed).await?.into()).to_vec();
    let file = crate::bvh::unpack(&bytes).map_err(|e| e.to_string())?;
    Blob::new_with_u8_array_sequence(&js_sys::Array::of1(&js_sys::Uint8Array::from(file.as_slice())))
        .map_err(|e| js_message(&e))
}

/// The file at `url` (the bundled sample), held to the cap of every take.
async fn fetch_blob(url: &str) -> Result<Blob, String> {
    let window = web_sys::window().ok_or("no window")?;
    let response: FetchResponse =
        JsFuture::from(window.fetch_with_str(url)).await.map_err(|e| js_message(&e))?.unchecked_into();
    if !response.ok() {
        return Err(format!("HTTP {} {} for {url}", response.status(), response.status_text()));
    }
    read_capped(&response, MAX_FILE_BYTES).await.map_err(|e| match e {
        ReadError::TooLarge { .. } => format!("{url} is larger than the page reads (512 MiB)"),
        ReadError::Failed(e) => e,
    })
}
