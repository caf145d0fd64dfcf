//! The web worker's entry point and the `postMessage` glue of the protocol (feature `web`).
//!
//! `www/worker.js` runs this module in a dedicated module worker and hands every message to
//! [`worker_handle`]; the page (`crate::app`) builds requests with [`request_message`] and reads
//! the worker's messages with [`response_from_js`]. Messages are [`Packet`]s of
//! [`crate::protocol`]: `{json: "<Request or Response>", buffers: [ArrayBuffer | Uint8Array, …]}`,
//! whose buffers are transferred, never copied, across `postMessage`. All decisions (which take
//! is held, what a request may do) are made by [`WorkerState`] ([`super::state`]).

use super::WorkerState;
use crate::protocol::{FailureKind, Packet, Request, Response};
use js_sys::{Array, ArrayBuffer, Function, Object, Reflect, Uint8Array};
use std::cell::RefCell;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

thread_local! {
    /// The worker's take and everything it knows.
    static STATE: RefCell<WorkerState> = RefCell::new(WorkerState::default());
}

/// Worker entry point: answers one message `{json, buffers}` from the page, posting progress
/// and the final response with `post(message, transfer)`. A request that cannot be read is
/// answered with a `failed` response; only a trap (a bug) escapes, and the glue reports it.
#[wasm_bindgen]
pub fn worker_handle(message: JsValue, post: &Function) {
    console_error_panic_hook::set_once();
    let mut send = |response: Response| {
        let (message, transfer) = packet_to_js(response.into_packet());
        // a page that went away cannot be told anything
        let _ = post.call2(&JsValue::NULL, &message, &transfer);
    };
    let request = packet_from_js(&message).and_then(Request::from_packet);
    match request {
        Ok(request) => STATE.with_borrow_mut(|state| state.handle(request, &mut send)),
        Err(message) => {
            let take = take_of(&message);
            send(Response::Failed { take, run: None, message, kind: FailureKind::Input, param: None })
        }
    }
}

/// What the worker should send itself next, as a message for [`worker_handle`] (`undefined`
/// when nothing): `www/worker.js` asks after every message and schedules the answer with
/// `setTimeout(0)`, so that the page's messages (a `stop_training`) are read in between — this is
/// how a DT-FCN training runs one epoch per message.
#[wasm_bindgen]
pub fn worker_next() -> JsValue {
    match STATE.with_borrow(|state| state.next_step()) {
        Some(request) => packet_to_js(request.into_packet()).0,
        None => JsValue::UNDEFINED,
    }
}

/// The take named in a request that could not be decoded (0 if none can be read).
fn take_of(json: &str) -> u32 {
    serde_json::from_str::<serde_json::Value>(json)
        .ok()
        .and_then(|v| v["take"].as_u64())
        .and_then(|t| u32::try_from(t).ok())
        .unwrap_or(0)
}

/// The page's message for `request` and its transfer list: the request's own buffers (a
/// family's JSON text, a model file, training takes), or for a load whose file is `bytes`, that
/// `ArrayBuffer` (transferred; `Request::Load`'s own `bytes` are left empty), followed by an AMC's
/// ASF skeleton (`skeleton_bytes`, copied: it is small).
pub fn request_message(request: &Request, bytes: Option<&ArrayBuffer>) -> (JsValue, Array) {
    match bytes {
        Some(b) => {
            let json = serde_json::to_string(request).unwrap_or_default();
            let buffers = Array::of1(b);
            if let Request::Load { skeleton: Some(_), skeleton_bytes, .. } = request {
                buffers.push(&Uint8Array::from(&skeleton_bytes[..]).buffer());
            }
            (message(&json, &buffers), buffers)
        }
        None => packet_to_js(request.clone().into_packet()),
    }
}

/// The page's message for `request` whose buffers the page already holds as JS values
/// (`ArrayBuffer`s, transferred): a training's takes, read from their files or made from the bytes
/// the page keeps, never copied into a `Request` first (the request's own `bytes` are left empty).
pub fn request_with_buffers(request: &Request, buffers: Array) -> (JsValue, Array) {
    let json = serde_json::to_string(request).unwrap_or_default();
    (message(&json, &buffers), buffers)
}

fn message(json: &str, buffers: &Array) -> JsValue {
    let object = Object::new();
    let _ = Reflect::set(&object, &"json".into(), &json.into());
    let _ = Reflect::set(&object, &"buffers".into(), buffers);
    object.into()
}

/// A packet as a JS message and the transfer list of its buffers.
pub fn packet_to_js(packet: Packet) -> (JsValue, Array) {
    let buffers = Array::new();
    let transfer = Array::new();
    for b in &packet.buffers {
        let array = Uint8Array::from(&b[..]);
        transfer.push(&array.buffer());
        buffers.push(&array);
    }
    (message(&packet.json, &buffers), transfer)
}

/// A JS message `{json, buffers}` as a packet (buffers may be `ArrayBuffer`s or `Uint8Array`s).
pub fn packet_from_js(data: &JsValue) -> Result<Packet, String> {
    let json = Reflect::get(data, &"json".into())
        .ok()
        .and_then(|j| j.as_string())
        .ok_or("worker message without `json` text")?;
    let list = Reflect::get(data, &"buffers".into()).map_err(|_| "worker message without `buffers`")?;
    let list: Array = list.dyn_into().map_err(|_| "worker message `buffers` is not an array")?;
    let mut buffers = Vec::with_capacity(list.length() as usize);
    for item in list.iter() {
        let bytes = if let Some(a) = item.dyn_ref::<Uint8Array>() {
            a.to_vec()
        } else if let Some(b) = item.dyn_ref::<ArrayBuffer>() {
            Uint8Array::new(b).to_vec()
        } else {
            return Err("worker message: a buffer is neither an ArrayBuffer nor bytes".into());
        };
        buffers.push(bytes);
    }
    Ok(Packet { json, buffers })
}

/// Decodes a `MessageEvent.data` posted by the worker.
pub fn response_from_js(data: &JsValue) -> Result<Response, String> {
    packet_from_js(data).and_then(Response::from_packet)
}
