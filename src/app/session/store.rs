//! The workspace's object store in the page's IndexedDB database ([`crate::app::idb`]): the record
//! ([`crate::app::session::record`], key `record`, its JSON) and the take's file (key `take`:
//! `{name, file: Blob, skeleton_name, skeleton: Uint8Array}` — the `Blob` as the browser stores it, never a copy in the
//! page's memory), and the library's take files (keys `library:<index>`: `{motion: File, skeleton: File}`).

use crate::app::dom::js_message;
use crate::app::idb::{committed, finished, open, store};
use crate::app::session::record::Record;
use js_sys::{Object, Reflect, Uint8Array};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use web_sys::{Blob, File, IdbTransactionMode};

const STORE: &str = "workspace";

/// A take's file as kept: its name, its bytes as a `Blob`, and an AMC motion's ASF skeleton (name, bytes).
pub struct KeptFile {
    pub name: String,
    pub file: Blob,
    pub skeleton: Option<(String, Vec<u8>)>,
}

/// Puts `value` under `key`.
async fn put(key: &str, value: &JsValue) -> Result<(), String> {
    let db = open().await?;
    let (tx, store) = store(&db, STORE, IdbTransactionMode::Readwrite)?;
    store.put_with_key(value, &key.into()).map_err(|e| js_message(&e))?;
    let done = committed(&tx).await;
    db.close();
    done
}

/// The value under `key` (`undefined` when none).
async fn get(key: &str) -> Result<JsValue, String> {
    let db = open().await?;
    let (_, store) = store(&db, STORE, IdbTransactionMode::Readonly)?;
    let value = finished(&store.get(&key.into()).map_err(|e| js_message(&e))?).await;
    db.close();
    value
}

/// Keeps `record`.
pub async fn put_record(record: &Record) -> Result<(), String> {
    put("record", &JsValue::from_str(&record.to_json())).await
}

/// The record kept (`Ok(None)`: none yet; `Err`: why it cannot be read).
pub async fn get_record() -> Result<Option<Record>, String> {
    let value = get("record").await?;
    match value.as_string() {
        Some(text) => Record::from_json(&text).map(Some),
        None => Ok(None),
    }
}

/// Keeps the take's file (replacing the one kept).
pub async fn put_take(kept: &KeptFile) -> Result<(), String> {
    let record = Object::new();
    let set = |k: &str, v: &JsValue| Reflect::set(&record, &k.into(), v).map(|_| ()).map_err(|e| js_message(&e));
    set("name", &kept.name.as_str().into())?;
    set("file", &kept.file)?;
    if let Some((name, bytes)) = &kept.skeleton {
        set("skeleton_name", &name.as_str().into())?;
        set("skeleton", &Uint8Array::from(bytes.as_slice()).into())?;
    }
    put("take", &record).await
}

/// Forgets the take's file kept.
pub async fn clear_take() -> Result<(), String> {
    let db = open().await?;
    let (tx, store) = store(&db, STORE, IdbTransactionMode::Readwrite)?;
    store.delete(&"take".into()).map_err(|e| js_message(&e))?;
    let done = committed(&tx).await;
    db.close();
    done
}

/// The take's file kept, if any.
pub async fn get_take() -> Result<Option<KeptFile>, String> {
    let value = get("take").await?;
    if value.is_undefined() || value.is_null() {
        return Ok(None);
    }
    let field = |k: &str| Reflect::get(&value, &k.into()).ok().filter(|v| !v.is_undefined());
    let name = field("name").and_then(|v| v.as_string()).ok_or("the take kept has no name")?;
    let file = field("file").and_then(|v| v.dyn_into::<Blob>().ok()).ok_or("the take kept has no file")?;
    let skeleton = match (field("skeleton_name").and_then(|v| v.as_string()), field("skeleton")) {
        (Some(name), Some(bytes)) => Some((name, Uint8Array::new(&bytes).to_vec())),
        _ => None,
    };
    Ok(Some(KeptFile { name, file, skeleton }))
}

/// The key of library take `i`'s files.
fn library_key(i: usize) -> String {
    format!("library:{i}")
}

/// Keeps library take `i`'s files (its motion, and an AMC motion's ASF skeleton), as the browser stores files.
pub async fn put_library_take(i: usize, motion: &File, skeleton: Option<&File>) -> Result<(), String> {
    let record = Object::new();
    let set = |k: &str, v: &JsValue| Reflect::set(&record, &k.into(), v).map(|_| ()).map_err(|e| js_message(&e));
    set("motion", motion)?;
    if let Some(skeleton) = skeleton {
        set("skeleton", skeleton)?;
    }
    put(&library_key(i), &record).await
}

/// Library take `i`'s files kept (`Ok(None)`: none).
pub async fn get_library_take(i: usize) -> Result<Option<(File, Option<File>)>, String> {
    let value = get(&library_key(i)).await?;
    if value.is_undefined() || value.is_null() {
        return Ok(None);
    }
    let field = |k: &str| Reflect::get(&value, &k.into()).ok().and_then(|v| v.dyn_into::<File>().ok());
    let motion = field("motion").ok_or("a library take kept without its file")?;
    Ok(Some((motion, field("skeleton"))))
}

/// Forgets everything kept of the workspace: the record, the take's file and the library's.
pub async fn clear_all() -> Result<(), String> {
    let db = open().await?;
    let (tx, store) = store(&db, STORE, IdbTransactionMode::Readwrite)?;
    store.clear().map_err(|e| js_message(&e))?;
    let done = committed(&tx).await;
    db.close();
    done
}
