//! What the user sees when the page's own wasm panics (a bug): `#mocapseg-stopped`, a banner
//! saying "mocapseg stopped: reload the page (your labels are kept)" with a reload link
//! (`#mocapseg-stopped-reload`) and what went wrong; `<body data-stopped="1">`. After a panic the
//! wasm is in no state to run leptos again, so the banner is made with plain DOM calls from the
//! panic hook, styled through the CSSOM (the page's Content-Security-Policy allows no inline
//! style attribute), and needs no script to reload (a link to the page itself). My labels are
//! kept because every finished edit is in the browser's storage already ([`crate::app::my_labels::row`]).

use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// The banner's words.
pub const MESSAGE: &str = "mocapseg stopped: reload the page (your labels are kept)";

/// Id of the banner.
const ID: &str = "mocapseg-stopped";

/// Installs the page's panic hook: the panic is logged to the console as before
/// (`console_error_panic_hook`), then the banner shows.
pub fn install() {
    std::panic::set_hook(Box::new(|info| {
        console_error_panic_hook::hook(info);
        show(&info.to_string());
    }));
    install_test_hook();
}

/// Shows the banner (once), at the top of the page and over it.
fn show(detail: &str) {
    let Some(document) = web_sys::window().and_then(|w| w.document()) else { return };
    let Some(body) = document.body() else { return };
    if document.get_element_by_id(ID).is_some() {
        return;
    }
    let Ok(banner) = document.create_element("div") else { return };
    banner.set_id(ID);
    banner.set_class_name("ms-error-banner ms-stopped");
    let _ = banner.set_attribute("role", "alert");
    if let Ok(title) = document.create_element("strong") {
        title.set_text_content(Some(MESSAGE));
        let _ = banner.append_child(&title);
    }
    if let Ok(link) = document.create_element("a") {
        link.set_id("mocapseg-stopped-reload");
        link.set_class_name("ms-button");
        set_style(&link, &[("marginLeft", "0.75em")]);
        let href = web_sys::window()
            .and_then(|w| js_sys::Reflect::get(&w, &"location".into()).ok())
            .and_then(|l| js_sys::Reflect::get(&l, &"href".into()).ok())
            .and_then(|h| h.as_string())
            .unwrap_or_else(|| "./".into());
        let _ = link.set_attribute("href", &href);
        link.set_text_content(Some("Reload"));
        let _ = banner.append_child(&link);
    }
    if let Ok(what) = document.create_element("div") {
        what.set_class_name("ms-error-message");
        what.set_text_content(Some(&format!("What went wrong (a bug in mocapseg; please report it): {detail}")));
        let _ = banner.append_child(&what);
    }
    set_style(
        &banner,
        &[
            ("position", "fixed"),
            ("top", "0"),
            ("left", "0"),
            ("right", "0"),
            ("zIndex", "2147483647"),
            ("margin", "0"),
        ],
    );
    let _ = body.prepend_with_node_1(&banner);
    let _ = body.set_attribute("data-stopped", "1");
}

/// Sets `style.<name> = value` for each pair (the CSSOM, which the page's CSP allows).
fn set_style(element: &web_sys::Element, pairs: &[(&str, &str)]) {
    let Ok(style) = js_sys::Reflect::get(element, &"style".into()) else { return };
    for (name, value) in pairs {
        let _ = js_sys::Reflect::set(&style, &(*name).into(), &(*value).into());
    }
}

/// `window.__mocapsegPanic()`: panics in the page's wasm, on its main thread. It exists for the
/// end-to-end test of this banner (tests/e2e/reliability.test.mjs) — no input the page reads
/// should make it panic, so a test has no other way to reach the hook — and it is installed only
/// in a browser driven by automation (`navigator.webdriver`), never for a user.
fn install_test_hook() {
    let Some(window) = web_sys::window() else { return };
    let driven = js_sys::Reflect::get(&window, &"navigator".into())
        .and_then(|n| js_sys::Reflect::get(&n, &"webdriver".into()))
        .is_ok_and(|d| d.as_bool() == Some(true));
    if !driven {
        return;
    }
    let panic = Closure::<dyn Fn()>::new(|| panic!("window.__mocapsegPanic(): a panic asked by a test"));
    let _ = js_sys::Reflect::set(&window, &"__mocapsegPanic".into(), panic.as_ref().unchecked_ref());
    panic.forget();
}
