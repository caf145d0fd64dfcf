//! The motion image (DT-FCN paper: one column per frame, one row per joint, RGB = the joint's
//! root-relative XYZ scaled to 0–255 per axis over the take), as built by the worker:
//! `#motion-image` draws its RGBA pixels stretched to the timeline's width, and
//! `#download-png` saves the worker's PNG encoding as `<name>_motion_image.png`.

use super::AppState;
use crate::protocol::ImageData as Pixels;
use gloo::events::EventListener;
use js_sys::{Array, Uint8Array};
use leptos::html::Canvas;
use leptos::prelude::*;
use wasm_bindgen::{Clamped, JsCast, JsValue};
use web_sys::{Blob, BlobPropertyBag, CanvasRenderingContext2d, HtmlAnchorElement, HtmlCanvasElement, Url};

/// Columns copied per step: keeps the scratch canvas well under browsers' size limits however
/// long the take is.
const CHUNK_COLUMNS: usize = 4096;

/// Height of one joint row on screen, in CSS pixels.
const ROW_HEIGHT_PX: usize = 3;

#[component]
pub fn MotionImageCanvas(state: AppState) -> impl IntoView {
    let canvas_ref = NodeRef::<Canvas>::new();
    let resized = RwSignal::new(0u32);
    let rows = move || state.motion.with(|m| m.as_ref().map_or(0, |m| m.image.height));

    Effect::new(move |_| {
        resized.track();
        let Some(canvas) = canvas_ref.get() else { return };
        state.motion.with(|m| {
            if let Some(m) = m {
                if let Err(e) = draw(&canvas, &m.image) {
                    web_sys::console::error_2(&"motion image: could not draw".into(), &e);
                }
            }
        });
    });
    canvas_ref.on_load(move |_| {
        EventListener::new(&gloo::utils::window(), "resize", move |_| resized.update(|n| *n += 1)).forget();
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
pub(super) fn stem(name: &str) -> &str {
    match name.rsplit_once('.') {
        Some((stem, _)) if !stem.is_empty() => stem,
        _ => name,
    }
}

/// Stretches `image` over the whole canvas: columns to its width, rows to its height.
fn draw(canvas: &HtmlCanvasElement, image: &Pixels) -> Result<(), JsValue> {
    let dpr = gloo::utils::window().device_pixel_ratio().max(1.0);
    let (w, h) = (((canvas.client_width() as f64) * dpr).max(1.0), ((canvas.client_height() as f64) * dpr).max(1.0));
    canvas.set_width(w as u32);
    canvas.set_height(h as u32);
    let ctx = context(canvas)?;
    ctx.clear_rect(0.0, 0.0, w, h);
    if image.width == 0 || image.height == 0 {
        return Ok(());
    }
    let pixels = web_sys::ImageData::new_with_u8_clamped_array_and_sh(
        Clamped(&image.rgba),
        image.width as u32,
        image.height as u32,
    )?;
    // Crisp columns when stretched, averaged when squeezed.
    ctx.set_image_smoothing_enabled(image.width as f64 > w);
    let scratch: HtmlCanvasElement = gloo::utils::document().create_element("canvas")?.unchecked_into();
    let scratch_ctx = context(&scratch)?;
    for start in (0..image.width).step_by(CHUNK_COLUMNS) {
        let columns = CHUNK_COLUMNS.min(image.width - start);
        scratch.set_width(columns as u32);
        scratch.set_height(image.height as u32);
        scratch_ctx.put_image_data_with_dirty_x_and_dirty_y_and_dirty_width_and_dirty_height(
            &pixels,
            -(start as f64),
            0.0,
            start as f64,
            0.0,
            columns as f64,
            image.height as f64,
        )?;
        let (x, dw) = (start as f64 / image.width as f64 * w, columns as f64 / image.width as f64 * w);
        ctx.draw_image_with_html_canvas_element_and_sw_and_sh_and_dx_and_dy_and_dw_and_dh(
            &scratch,
            0.0,
            0.0,
            columns as f64,
            image.height as f64,
            x,
            0.0,
            dw,
            h,
        )?;
    }
    Ok(())
}

fn context(canvas: &HtmlCanvasElement) -> Result<CanvasRenderingContext2d, JsValue> {
    canvas.get_context("2d")?.ok_or("no 2d context")?.dyn_into().map_err(JsValue::from)
}

/// Saves `bytes` as a file called `name` through a temporary object URL.
pub(super) fn download(bytes: &[u8], mime: &str, name: &str) -> Result<(), JsValue> {
    let options = BlobPropertyBag::new();
    options.set_type(mime);
    let blob = Blob::new_with_u8_array_sequence_and_options(&Array::of1(&Uint8Array::from(bytes)), &options)?;
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
