//! What the page's keyboard shortcuts (the timeline's, the "my labels" row's) share: whether a key
//! press belongs to the element it was aimed at.

use wasm_bindgen::JsCast;

/// Whether a key press aimed at `target` is the field's own (typing, a slider, a menu) or a
/// button's own activation (Space, Enter).
pub(crate) fn is_for_the_field(target: Option<web_sys::EventTarget>, key: &str) -> bool {
    let Some(el) = target.and_then(|t| t.dyn_into::<web_sys::HtmlElement>().ok()) else { return false };
    if el.is_content_editable() {
        return true;
    }
    match el.tag_name().to_ascii_lowercase().as_str() {
        "input" | "select" | "textarea" => true,
        "button" | "summary" | "a" => key == " " || key == "Enter",
        _ => false,
    }
}
