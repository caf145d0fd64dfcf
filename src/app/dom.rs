//! What every part of the page asks of the browser: `<body>`'s data attributes (where the page
//! stands, as the end-to-end tests read it), the page's clock and a JS error's message.

use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

pub(crate) fn set_body_data(attributes: &[(&str, &str)]) {
    if let Some(body) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.body()) {
        for (name, value) in attributes {
            let _ = body.set_attribute(name, value);
        }
    }
}

/// Whether the page is embedded (`embed=1`: `<body data-embed>`, set before the page mounts): the player and the
/// rows only — nothing the user makes there is kept, so it offers no editing of my labels.
pub(crate) fn embedded() -> bool {
    web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.body())
        .is_some_and(|b| b.get_attribute("data-embed").as_deref() == Some("1"))
}

/// Milliseconds since the page started.
pub(crate) fn now_ms() -> f64 {
    web_sys::window().and_then(|w| w.performance()).map_or(0.0, |p| p.now())
}

/// The message of a JS error (or the value itself, as text).
pub(crate) fn js_message(value: &JsValue) -> String {
    value
        .dyn_ref::<js_sys::Error>()
        .map(|e| String::from(e.message()))
        .or_else(|| value.as_string())
        .unwrap_or_else(|| format!("{value:?}"))
}

/// Scrolls element `id` into the window the least needed (`scrollIntoView({block: "nearest"})`, every scrolling box
/// around it included): a status the user must read, said below the fold of a scrolled box, is brought to view.
pub(crate) fn reveal(id: &str) {
    let Some(el) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.get_element_by_id(id)) else { return };
    let options = js_sys::Object::new();
    let _ = js_sys::Reflect::set(&options, &"block".into(), &"nearest".into());
    let _ = js_sys::Reflect::set(&options, &"inline".into(), &"nearest".into());
    if let Ok(scroll) =
        js_sys::Reflect::get(&el, &"scrollIntoView".into()).and_then(|f| f.dyn_into::<js_sys::Function>())
    {
        let _ = scroll.call1(&el, &options);
    }
}
