//! The user's models kept in this browser (IndexedDB), so that a model trained or loaded on the
//! page is listed in its method's model choice again after a reload — without a download.
//!
//! One database `mocapseg`, one object store `models`, one record per method and model name
//! (key `<method>/<name>`): `{method, name, file, bytes: Uint8Array, saved: ms since 1970}`.
//! web-sys's IndexedDB bindings directly (a request's events turned into a promise): the wrapper
//! crates (rexie, indexed_db_futures) pin their own wasm-bindgen releases, and this crate pins
//! one (`=0.2.130`) that the worker's glue is generated with. A browser without IndexedDB
//! (some private windows) gives a message; the page works as before, models last for the tab.

use js_sys::{Array, Object, Promise, Reflect, Uint8Array};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{IdbDatabase, IdbObjectStore, IdbOpenDbRequest, IdbRequest, IdbTransaction, IdbTransactionMode};

use crate::app::dom::js_message;

const DATABASE: &str = "mocapseg";
const STORE: &str = "models";
const VERSION: u32 = 1;

/// A model kept in this browser.
#[derive(Debug, Clone)]
pub struct Kept {
    pub method: String,
    pub name: String,
    pub file: String,
    pub bytes: Vec<u8>,
}

fn key(method: &str, name: &str) -> String {
    format!("{method}/{name}")
}

/// The result of `request` once it succeeds, or its error's message.
async fn finished(request: &IdbRequest) -> Result<JsValue, String> {
    let promise = Promise::new(&mut |resolve, reject| {
        let ok_request = request.clone();
        let on_ok = Closure::once_into_js(move |_: web_sys::Event| {
            let _ = resolve.call1(&JsValue::NULL, &ok_request.result().unwrap_or(JsValue::UNDEFINED));
        });
        let failed_request = request.clone();
        let on_error = Closure::once_into_js(move |_: web_sys::Event| {
            let message = failed_request
                .error()
                .ok()
                .flatten()
                .map(|e| format!("{}: {}", e.name(), e.message()))
                .unwrap_or_else(|| "the request failed".into());
            let _ = reject.call1(&JsValue::NULL, &JsValue::from_str(&message));
        });
        request.set_onsuccess(Some(on_ok.unchecked_ref()));
        request.set_onerror(Some(on_error.unchecked_ref()));
    });
    JsFuture::from(promise).await.map_err(|e| js_message(&e))
}

/// Resolves when `tx` is committed.
async fn committed(tx: &IdbTransaction) -> Result<(), String> {
    let promise = Promise::new(&mut |resolve, reject| {
        let on_ok = Closure::once_into_js(move |_: web_sys::Event| {
            let _ = resolve.call0(&JsValue::NULL);
        });
        let failed = tx.clone();
        let on_error = Closure::once_into_js(move |_: web_sys::Event| {
            let message = failed
                .error()
                .map(|e| format!("{}: {}", e.name(), e.message()))
                .unwrap_or_else(|| "the transaction was aborted".into());
            let _ = reject.call1(&JsValue::NULL, &JsValue::from_str(&message));
        });
        tx.set_oncomplete(Some(on_ok.unchecked_ref()));
        tx.set_onerror(Some(on_error.clone().unchecked_ref()));
        tx.set_onabort(Some(on_error.unchecked_ref()));
    });
    JsFuture::from(promise).await.map(|_| ()).map_err(|e| js_message(&e))
}

/// The database, its store made on first use.
async fn open() -> Result<IdbDatabase, String> {
    let factory = web_sys::window()
        .ok_or("no window")?
        .indexed_db()
        .map_err(|e| js_message(&e))?
        .ok_or("this browser offers no IndexedDB here")?;
    let request: IdbOpenDbRequest = factory.open_with_u32(DATABASE, VERSION).map_err(|e| js_message(&e))?;
    let upgrading = request.clone();
    let on_upgrade = Closure::once_into_js(move |_: web_sys::Event| {
        if let Ok(db) = upgrading.result().and_then(|r| r.dyn_into::<IdbDatabase>().map_err(JsValue::from)) {
            if let Err(e) = db.create_object_store(STORE) {
                web_sys::console::warn_1(&e);
            }
        }
    });
    request.set_onupgradeneeded(Some(on_upgrade.unchecked_ref()));
    let db = finished(&request).await?;
    db.dyn_into::<IdbDatabase>().map_err(|_| "IndexedDB gave no database".to_string())
}

fn store(db: &IdbDatabase, mode: IdbTransactionMode) -> Result<(IdbTransaction, IdbObjectStore), String> {
    let tx = db.transaction_with_str_and_mode(STORE, mode).map_err(|e| js_message(&e))?;
    let store = tx.object_store(STORE).map_err(|e| js_message(&e))?;
    Ok((tx, store))
}

/// Keeps the model `name` of `method` (its file's name and bytes), replacing one of that name.
pub async fn save(method: &str, name: &str, file: &str, bytes: &[u8]) -> Result<(), String> {
    let db = open().await?;
    let (tx, store) = store(&db, IdbTransactionMode::Readwrite)?;
    let record = Object::new();
    let set = |k: &str, v: &JsValue| Reflect::set(&record, &k.into(), v).map(|_| ()).map_err(|e| js_message(&e));
    set("method", &method.into())?;
    set("name", &name.into())?;
    set("file", &file.into())?;
    set("bytes", &Uint8Array::from(bytes).into())?;
    set("saved", &js_sys::Date::now().into())?;
    store.put_with_key(&record, &key(method, name).into()).map_err(|e| js_message(&e))?;
    committed(&tx).await?;
    db.close();
    Ok(())
}

/// Forgets the model `name` of `method`.
pub async fn remove(method: &str, name: &str) -> Result<(), String> {
    let db = open().await?;
    let (tx, store) = store(&db, IdbTransactionMode::Readwrite)?;
    store.delete(&key(method, name).into()).map_err(|e| js_message(&e))?;
    committed(&tx).await?;
    db.close();
    Ok(())
}

/// Every model kept, oldest first (records that are not what [`save`] writes are skipped).
pub async fn load_all() -> Result<Vec<Kept>, String> {
    let db = open().await?;
    let (_, store) = store(&db, IdbTransactionMode::Readonly)?;
    let all = finished(&store.get_all().map_err(|e| js_message(&e))?).await?;
    db.close();
    let text = |o: &JsValue, k: &str| Reflect::get(o, &k.into()).ok().and_then(|v| v.as_string());
    let mut kept: Vec<(f64, Kept)> = Array::from(&all)
        .iter()
        .filter_map(|o| {
            let bytes = Reflect::get(&o, &"bytes".into()).ok()?.dyn_into::<Uint8Array>().ok()?.to_vec();
            let saved = Reflect::get(&o, &"saved".into()).ok().and_then(|v| v.as_f64()).unwrap_or(0.0);
            Some((saved, Kept { method: text(&o, "method")?, name: text(&o, "name")?, file: text(&o, "file")?, bytes }))
        })
        .collect();
    kept.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(kept.into_iter().map(|(_, k)| k).collect())
}
