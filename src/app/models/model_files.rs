//! The shipped model files the page fetches from beside itself (`models/`, the root element's
//! `data-models-url`) instead of carrying them in its wasm ([`crate::method::shipped`]).
//!
//! A method that needs a file its worker does not hold answers `needs_model`; the page fetches
//! the file once (its progress shown on whatever waits for it), keeps it for the page's life,
//! hands it to the worker (`provide_model`, checked there against this build's SHA-256) and asks
//! again. A worker started later (after a cancel or a crash) is handed every file the page holds
//! before anything else. Offline, the service worker answers from its cache (every file of the
//! build is precached), so nothing here knows whether the network is there.

use std::cell::RefCell;
use std::rc::Rc;

use js_sys::{Function, Promise, Reflect, Uint8Array};
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_futures::JsFuture;
use web_sys::Response as FetchResponse;

use crate::app::dom::js_message;

use crate::protocol::RunId;

/// The files fetched, and what waits for files still on their way.
pub struct ModelFiles {
    /// Where the files are, ending in `/` (`./models/`).
    base: String,
    /// Fetched: name and bytes.
    held: RefCell<Vec<(String, Rc<Vec<u8>>)>>,
    /// Runs waiting for a file on its way, and the file.
    waiting: RefCell<Vec<(RunId, String)>>,
}

impl ModelFiles {
    pub fn new(base: &str) -> ModelFiles {
        let base = if base.ends_with('/') { base.to_string() } else { format!("{base}/") };
        ModelFiles { base, held: RefCell::new(Vec::new()), waiting: RefCell::new(Vec::new()) }
    }

    /// The URL of `file`.
    pub fn url(&self, file: &str) -> String {
        format!("{}{file}", self.base)
    }

    /// The bytes of `file` if it was fetched.
    pub fn held(&self, file: &str) -> Option<Rc<Vec<u8>>> {
        self.held.borrow().iter().find(|(f, _)| f == file).map(|(_, b)| b.clone())
    }

    /// Every file fetched (for a new worker).
    pub fn all(&self) -> Vec<(String, Rc<Vec<u8>>)> {
        self.held.borrow().clone()
    }

    /// `run` waits for `file`; true when nothing asked for it before, so it is to be fetched now.
    pub fn wait(&self, run: RunId, file: &str) -> bool {
        let mut waiting = self.waiting.borrow_mut();
        let first = !waiting.iter().any(|(_, f)| f == file);
        if !waiting.iter().any(|(r, f)| *r == run && f == file) {
            waiting.push((run, file.to_string()));
        }
        first
    }

    /// The runs waiting for `file`.
    pub fn waiting_for(&self, file: &str) -> Vec<RunId> {
        self.waiting.borrow().iter().filter(|(_, f)| f == file).map(|(r, _)| *r).collect()
    }

    /// `file` arrived: it is kept, and the runs that waited for it are returned.
    pub fn arrived(&self, file: &str, bytes: Rc<Vec<u8>>) -> Vec<RunId> {
        self.held.borrow_mut().push((file.to_string(), bytes));
        self.take_waiting(file)
    }

    /// `file` could not be fetched: the runs that waited for it.
    pub fn take_waiting(&self, file: &str) -> Vec<RunId> {
        let runs = self.waiting_for(file);
        self.waiting.borrow_mut().retain(|(_, f)| f != file);
        runs
    }
}

/// What a run that waits for `file` shows while it comes (`fraction` of its `size` bytes).
pub fn fetching_stage(file: &str, size: u64) -> String {
    format!("fetching the model {file} ({:.1} MB)", size as f64 / 1e6)
}

/// The bytes at `url`, reporting the fraction of `size` bytes read so far (the body is read as a
/// stream where the browser offers one).
pub async fn fetch(url: &str, size: u64, progress: impl Fn(f64)) -> Result<Vec<u8>, String> {
    let window = web_sys::window().ok_or("no window")?;
    let response: FetchResponse =
        JsFuture::from(window.fetch_with_str(url)).await.map_err(|e| js_message(&e))?.unchecked_into();
    if !response.ok() {
        return Err(format!("HTTP {} {}", response.status(), response.status_text()));
    }
    let body = Reflect::get(&response, &"body".into()).unwrap_or(JsValue::NULL);
    if body.is_null() || body.is_undefined() {
        let whole =
            JsFuture::from(response.array_buffer().map_err(|e| js_message(&e))?).await.map_err(|e| js_message(&e))?;
        return Ok(Uint8Array::new(&whole).to_vec());
    }
    let method = |object: &JsValue, name: &str| -> Result<Function, String> {
        Reflect::get(object, &name.into())
            .ok()
            .and_then(|f| f.dyn_into::<Function>().ok())
            .ok_or_else(|| format!("the response body has no {name}()"))
    };
    let reader = method(&body, "getReader")?.call0(&body).map_err(|e| js_message(&e))?;
    let read = method(&reader, "read")?;
    let mut out: Vec<u8> = Vec::with_capacity(size as usize);
    loop {
        let promise: Promise =
            read.call0(&reader).map_err(|e| js_message(&e))?.dyn_into().map_err(|_| "read() gave no promise")?;
        let chunk = JsFuture::from(promise).await.map_err(|e| js_message(&e))?;
        if Reflect::get(&chunk, &"done".into()).ok().and_then(|d| d.as_bool()) == Some(true) {
            break;
        }
        let value: Uint8Array = Reflect::get(&chunk, &"value".into())
            .ok()
            .and_then(|v| v.dyn_into().ok())
            .ok_or("the response body gave something other than bytes")?;
        let start = out.len();
        out.resize(start + value.length() as usize, 0);
        value.copy_to(&mut out[start..]);
        if size > 0 {
            progress((out.len() as f64 / size as f64).min(1.0));
        }
    }
    Ok(out)
}
