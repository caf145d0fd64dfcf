//! The page's IndexedDB database, made async: one database `mocapseg` whose object stores are the features' (the
//! user's models, [`crate::app::models::browser_models`]; the workspace kept across reloads,
//! [`crate::app::session::store`]), a request's result and a transaction's commit as futures. web-sys's IndexedDB
//! bindings directly (a request's events turned into a promise): the wrapper crates (rexie, indexed_db_futures) pin
//! their own wasm-bindgen releases, and this crate pins one (`=0.2.130`) that the worker's glue is generated with.

use js_sys::Promise;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{IdbDatabase, IdbObjectStore, IdbOpenDbRequest, IdbRequest, IdbTransaction, IdbTransactionMode};

use crate::app::dom::js_message;

const DATABASE: &str = "mocapseg";
/// 1: the models; 2: the workspace too.
const VERSION: u32 = 2;
/// Every object store of the database (made when missing, on first use of a new version).
const STORES: [&str; 2] = ["models", "workspace"];

/// The result of `request` once it succeeds, or its error's message.
pub async fn finished(request: &IdbRequest) -> Result<JsValue, String> {
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

/// Resolves when `tx` is committed (its error's message, `QuotaExceededError: …` when the browser's storage is full).
pub async fn committed(tx: &IdbTransaction) -> Result<(), String> {
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

/// The database, its missing stores made on first use.
pub async fn open() -> Result<IdbDatabase, String> {
    let factory = web_sys::window()
        .ok_or("no window")?
        .indexed_db()
        .map_err(|e| js_message(&e))?
        .ok_or("this browser offers no IndexedDB here")?;
    let request: IdbOpenDbRequest = factory.open_with_u32(DATABASE, VERSION).map_err(|e| js_message(&e))?;
    let upgrading = request.clone();
    let on_upgrade = Closure::once_into_js(move |_: web_sys::Event| {
        if let Ok(db) = upgrading.result().and_then(|r| r.dyn_into::<IdbDatabase>().map_err(JsValue::from)) {
            for name in STORES {
                if !db.object_store_names().contains(name) {
                    if let Err(e) = db.create_object_store(name) {
                        web_sys::console::warn_1(&e);
                    }
                }
            }
        }
    });
    request.set_onupgradeneeded(Some(on_upgrade.unchecked_ref()));
    let db = finished(&request).await?;
    db.dyn_into::<IdbDatabase>().map_err(|_| "IndexedDB gave no database".to_string())
}

/// A transaction on store `name` of `db` in `mode`, and the store.
pub fn store(
    db: &IdbDatabase,
    name: &str,
    mode: IdbTransactionMode,
) -> Result<(IdbTransaction, IdbObjectStore), String> {
    let tx = db.transaction_with_str_and_mode(name, mode).map_err(|e| js_message(&e))?;
    let store = tx.object_store(name).map_err(|e| js_message(&e))?;
    Ok((tx, store))
}
