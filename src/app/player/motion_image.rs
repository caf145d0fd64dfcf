//! The motion image (DT-FCN paper: one column per frame, one row per joint, RGB = the joint's
//! root-relative XYZ scaled to 0–255 per axis over the take), as built by the worker:
//! `#motion-image` draws the columns of the timeline's window stretched to its width (the
//! timeline's minimap draws them all), and
//! `#download-png` saves the worker's PNG encoding as `<name>_motion_image.png`.

use crate::app::state::AppState;
use crate::app::timeline::window::Window;
use crate::protocol::ImageData as Pixels;
use js_sys::{Array, Uint8Array};
use leptos::html::Canvas;
use leptos::prelude::*;
use std::cell::RefCell;
use std::rc::Rc;
use wasm_bindgen::{Clamped, JsCast, JsValue};
use web_sys::{Blob, BlobPropertyBag, CanvasRenderingContext2d, HtmlAnchorElement, HtmlCanvasElement, Url};

/// Columns copied per step: keeps the scratch canvas well under browsers' size limits however
/// long the take is.
const CHUNK_COLUMNS: usize = 4096;

/// Height of one joint row on screen, in CSS pixels.
const ROW_HEIGHT_PX: usize = 3;

/// The motion image cut into canvases of at most [`CHUNK_COLUMNS`] columns, made once per take,
/// so that a redraw (every zoom or pan) copies only the visible columns.
#[derive(Clone, Default)]
pub struct Chunks {
    canvases: Rc<RefCell<Vec<(usize, HtmlCanvasElement)>>>,
    /// Columns (frames) and rows (joints) of the image.
    size: Rc<RefCell<(usize, usize)>>,
}

impl Chunks {
    /// Cuts `image` into chunks (replacing any earlier take's).
    pub fn load(&self, image: &Pixels) -> Result<(), JsValue> {
        let mut canvases = self.canvases.borrow_mut();
        canvases.clear();
        *self.size.borrow_mut() = (image.width, image.height);
        if image.width == 0 || image.height == 0 {
            return Ok(());
        }
        let pixels = web_sys::ImageData::new_with_u8_clamped_array_and_sh(
            Clamped(&image.rgba),
            image.width as u32,
            image.height as u32,
        )?;
        for start in (0..image.width).step_by(CHUNK_COLUMNS) {
            let columns = CHUNK_COLUMNS.min(image.width - start);
            let chunk: HtmlCanvasElement = gloo::utils::document().create_element("canvas")?.unchecked_into();
            chunk.set_width(columns as u32);
            chunk.set_height(image.height as u32);
            context(&chunk)?.put_image_data_with_dirty_x_and_dirty_y_and_dirty_width_and_dirty_height(
                &pixels,
                -(start as f64),
                0.0,
                start as f64,
                0.0,
                columns as f64,
                image.height as f64,
            )?;
            canvases.push((start, chunk));
        }
        Ok(())
    }

    /// Draws columns `[window.start, window.end)` stretched over the whole of `canvas` (sized to
    /// its CSS box × device pixels).
    pub fn draw(&self, canvas: &HtmlCanvasElement, window: &Window) -> Result<(), JsValue> {
        let dpr = gloo::utils::window().device_pixel_ratio().max(1.0);
        let (w, h) = (
            ((canvas.client_width() as f64) * dpr).max(1.0).round(),
            ((canvas.client_height() as f64) * dpr).max(1.0).round(),
        );
        if canvas.width() != w as u32 || canvas.height() != h as u32 {
            canvas.set_width(w as u32);
            canvas.set_height(h as u32);
        }
        let ctx = context(canvas)?;
        ctx.clear_rect(0.0, 0.0, w, h);
        let (columns, rows) = *self.size.borrow();
        if columns == 0 || rows == 0 || window.span() <= 0.0 {
            return Ok(());
        }
        // crisp columns when stretched, averaged when squeezed
        ctx.set_image_smoothing_enabled(window.span() > w);
        let scale = w / window.span();
        for (start, chunk) in self.canvases.borrow().iter() {
            let (c0, c1) = (*start as f64, (*start as f64) + chunk.width() as f64);
            let (a, b) = (c0.max(window.start), c1.min(window.end));
            if b <= a {
                continue;
            }
            ctx.draw_image_with_html_canvas_element_and_sw_and_sh_and_dx_and_dy_and_dw_and_dh(
                chunk,
                a - c0,
                0.0,
                b - a,
                rows as f64,
                (a - window.start) * scale,
                0.0,
                (b - a) * scale,
                h,
            )?;
        }
        Ok(())
    }
}

/// `#motion-image`: the image's columns of the timeline's window, redrawn when the window, the
/// take (`resized` is bumped once its chunks are cut) or the page's size changes.
#[component]
pub fn MotionImageCanvas(state: AppState, chunks: Chunks, resized: RwSignal<u32>) -> impl IntoView {
    let canvas_ref = NodeRef::<Canvas>::new();
    let rows = move || state.motion.with(|m| m.as_ref().map_or(0, |m| m.image.height));
    Effect::new(move |_| {
        resized.track(); // also bumped when the timeline has cut a new take into chunks
        let window = state.window.get();
        let Some(canvas) = canvas_ref.get() else { return };
        if let Err(e) = chunks.draw(&canvas, &window) {
            web_sys::console::error_2(&"motion image: could not draw".into(), &e);
        }
    });
    view! {
        <canvas
            id="motion-image"
            class="ms-motion-image"
            node_ref=canvas_ref
            style:height=move || format!("{}px", (rows() * ROW_HEIGHT_PX).clamp(48, 180))
            aria-label="Motion image: one column per frame, one row per joint, colour = joint position"
        ></canvas>
    }
}

#[component]
pub fn DownloadPng(state: AppState) -> impl IntoView {
    let on_click = move |_| {
        state.motion.with_untracked(|m| {
            if let Some(m) = m {
                let name = format!("{}_motion_image.png", stem(&m.summary.name));
                if let Err(e) = download(&m.image.png, "image/png", &name) {
                    state.show_error(format!("could not save {name}: {e:?}"));
                }
            }
        })
    };
    view! {
        <button
            id="download-png"
            class="ms-button ms-button--quiet"
            type="button"
            disabled=move || state.motion.with(Option::is_none)
            on:click=on_click
        >
            "Download PNG"
        </button>
    }
}

/// The file name without its extension ("02_01.bvh" → "02_01").
pub(crate) fn stem(name: &str) -> &str {
    match name.rsplit_once('.') {
        Some((stem, _)) if !stem.is_empty() => stem,
        _ => name,
    }
}

fn context(canvas: &HtmlCanvasElement) -> Result<CanvasRenderingContext2d, JsValue> {
    canvas.get_context("2d")?.ok_or("no 2d context")?.dyn_into().map_err(JsValue::from)
}

/// Saves `bytes` as a file called `name` through a temporary object URL.
pub(crate) fn download(bytes: &[u8], mime: &str, name: &str) -> Result<(), JsValue> {
    download_parts(&Array::of1(&Uint8Array::from(bytes)), mime, name)
}

/// Saves the file made of `parts` (`Uint8Array`s, in order) as `name`: the browser joins them (a large file never
/// one buffer of the page's).
pub(crate) fn download_parts(parts: &Array, mime: &str, name: &str) -> Result<(), JsValue> {
    let options = BlobPropertyBag::new();
    options.set_type(mime);
    let blob = Blob::new_with_u8_array_sequence_and_options(parts, &options)?;
    let url = Url::create_object_url_with_blob(&blob)?;
    let link: HtmlAnchorElement = gloo::utils::document().create_element("a")?.unchecked_into();
    link.set_href(&url);
    link.set_download(name);
    link.click();
    // Let the download start before the URL goes away.
    gloo::timers::callback::Timeout::new(10_000, move || {
        let _ = Url::revoke_object_url(&url);
    })
    .forget();
    Ok(())
}
