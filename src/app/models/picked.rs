//! The files a user picks for a supervised method (a model file, a label CSV, more takes): read with a cap on their
//! size, the input emptied so that picking the same file again reads it again.

use js_sys::Uint8Array;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{File, HtmlInputElement};

/// The largest label CSV the page reads.
pub(crate) const MAX_LABELS_BYTES: f64 = 16.0 * 1024.0 * 1024.0;

/// The bytes of `file`, or why it cannot be read.
pub async fn read_bytes(file: &File, limit: f64) -> Result<Vec<u8>, String> {
    let name = file.name();
    if file.size() > limit {
        let mib = file.size() / 1024.0 / 1024.0;
        return Err(format!("{name}: {mib:.0} MiB is more than the page reads ({:.0} MiB)", limit / 1024.0 / 1024.0));
    }
    let buffer =
        JsFuture::from(file.array_buffer()).await.map_err(|e| format!("{name}: could not read the file: {e:?}"))?;
    Ok(Uint8Array::new(&buffer).to_vec())
}

/// The text of `file`, or why it cannot be read.
pub(crate) async fn read_text(file: &File, limit: f64) -> Result<String, String> {
    let name = file.name();
    if file.size() > limit {
        let mib = file.size() / 1024.0 / 1024.0;
        return Err(format!("{name}: {mib:.0} MiB is more than the page reads ({:.0} MiB)", limit / 1024.0 / 1024.0));
    }
    let text = JsFuture::from(file.text()).await.map_err(|e| format!("{name}: could not read the file: {e:?}"))?;
    text.as_string().ok_or_else(|| format!("{name}: the file is not text"))
}

/// The files an `<input type=file>` change picked (and the input emptied, so that picking the
/// same file again reads it again).
pub fn picked_files(ev: &leptos::ev::Event) -> Vec<File> {
    let Some(input) = ev.target().and_then(|t| t.dyn_into::<HtmlInputElement>().ok()) else { return Vec::new() };
    let files = input.files().map(|list| (0..list.length()).filter_map(|i| list.get(i)).collect()).unwrap_or_default();
    input.set_value("");
    files
}
