//! The user's models kept in this browser (IndexedDB), so that a model trained or loaded on the
//! page is listed in its method's model choice again after a reload — without a download.
//!
//! One database `mocapseg`, one object store `models`, one record per method and model name
//! (key `<method>/<name>`): `{method, name, file, bytes: Uint8Array, saved: ms since 1970}`.
//! The page's database ([`crate::app::idb`]) holds the store. A browser without IndexedDB
//! (some private windows) gives a message; the page works as before, models last for the tab.

use js_sys::{Array, Object, Reflect, Uint8Array};
use wasm_bindgen::{JsCast, JsValue};
use web_sys::{IdbDatabase, IdbObjectStore, IdbTransaction, IdbTransactionMode};

use crate::app::dom::js_message;
use crate::app::idb::{self, committed, finished, open};

const STORE: &str = "models";

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

fn store(db: &IdbDatabase, mode: IdbTransactionMode) -> Result<(IdbTransaction, IdbObjectStore), String> {
    idb::store(db, STORE, mode)
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
