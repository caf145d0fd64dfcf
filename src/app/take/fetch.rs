//! Downloads the page reads as takes (the `src=` file, its `asf=` skeleton, the bundled sample),
//! held to [`MAX_FILE_BYTES`] as dropped files are: the answer's `Content-Length` is read first
//! and a file that says it is larger is refused before its body is read; the body is read as a
//! stream and given up as soon as it passes the cap (a server may send no length, or a wrong
//! one). The bytes become a `Blob`: the page keeps a take as one ([`crate::app::loader`]).

use crate::app::dom::js_message;
use crate::app::embed::fetch_rules::SizeCap;
pub use crate::app::embed::fetch_rules::MAX_FILE_BYTES;
use js_sys::{Array, Promise, Reflect, Uint8Array};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{Blob, Response};

#[wasm_bindgen]
extern "C" {
    /// `Response.headers` (bound here rather than through a web-sys feature the crate does not
    /// turn on).
    type FetchHeaders;
    #[wasm_bindgen(method, catch)]
    fn get(this: &FetchHeaders, name: &str) -> Result<Option<String>, JsValue>;

    /// `Response.body`: a `ReadableStream` of bytes.
    type ByteStream;
    #[wasm_bindgen(method, catch, js_name = getReader)]
    fn get_reader(this: &ByteStream) -> Result<StreamReader, JsValue>;
    #[wasm_bindgen(method, js_name = cancel)]
    fn cancel_stream(this: &ByteStream) -> Promise;

    /// Its reader.
    type StreamReader;
    #[wasm_bindgen(method)]
    fn read(this: &StreamReader) -> Promise;
    #[wasm_bindgen(method)]
    fn cancel(this: &StreamReader) -> Promise;
}

/// Why a download was not read.
#[derive(Debug, Clone, PartialEq)]
pub enum ReadError {
    /// Past the cap: the size its `Content-Length` says (`declared`), or what had arrived when
    /// the page stopped reading.
    TooLarge { size: u64, declared: bool },
    /// The browser's words.
    Failed(String),
}

/// `response`'s body as a `Blob` of at most `cap` bytes (the body is not read, or not read on,
/// past it).
pub async fn read_capped(response: &Response, cap: u64) -> Result<Blob, ReadError> {
    let failed = |e: JsValue| ReadError::Failed(js_message(&e));
    let mut count = SizeCap::new(cap);
    let body = Reflect::get(response, &"body".into()).map_err(failed)?;
    let stream = (!body.is_null() && !body.is_undefined()).then(|| body.unchecked_into::<ByteStream>());
    let headers: FetchHeaders = Reflect::get(response, &"headers".into()).map_err(failed)?.unchecked_into();
    let length = headers.get("content-length").ok().flatten();
    if let Err(size) = count.declared(length.as_deref()) {
        if let Some(stream) = &stream {
            let _ = stream.cancel_stream(); // the browser need not download it
        }
        return Err(ReadError::TooLarge { size, declared: true });
    }
    let chunks = Array::new();
    if let Some(stream) = stream {
        let reader = stream.get_reader().map_err(failed)?;
        loop {
            let step = JsFuture::from(reader.read()).await.map_err(failed)?;
            if Reflect::get(&step, &"done".into()).ok().and_then(|d| d.as_bool()).unwrap_or(true) {
                break;
            }
            let chunk: Uint8Array = Reflect::get(&step, &"value".into()).map_err(failed)?.unchecked_into();
            if let Err(size) = count.add(u64::from(chunk.length())) {
                let _ = reader.cancel();
                return Err(ReadError::TooLarge { size, declared: false });
            }
            chunks.push(&chunk);
        }
    }
    Blob::new_with_u8_array_sequence(&chunks).map_err(failed)
}

/// The bytes of `blob` (a take's file), read again each time they are sent.
pub async fn blob_bytes(blob: &Blob) -> Result<js_sys::ArrayBuffer, String> {
    JsFuture::from(blob.array_buffer()).await.map(JsCast::unchecked_into).map_err(|e| js_message(&e))
}
