//! What the page's URL asks for (docs/page.md, "Embedding"): `?src=URL&methods=…&t=…&autoplay=1&embed=1`,
//! read once from `location.search` and checked by [`crate::app::embed::url_params`].
//!
//! [`start`] loads the `src=` file (else the bundled sample), makes the loader run only the
//! `methods=` listed, and once that take is on screen seeks to `t=` and plays if `autoplay=1`.
//! `#url-notice` lists every parameter that could not be used and why (a load's failure goes to
//! the error banner, naming the URL). In embed mode (`embed=1`: `.ms-embed` on the root,
//! `data-embed` on `<body>`) the page is the player and the timeline only, under
//! `#embed-bar`: the take's name and `#open-full`, a link to the full page with the same
//! parameters.

use crate::app::dom::js_message;
use crate::app::embed::fetch_rules;
use crate::app::embed::url_params::{self, UrlParams};
use crate::app::loader::{Loader, Urls};
use crate::app::method_panel::runs::MethodRuns;
use crate::app::session::keeper::Keeper;
use crate::app::state::AppState;
use crate::app::take::fetch::{blob_bytes, read_capped, ReadError, MAX_FILE_BYTES};
use leptos::prelude::*;
use wasm_bindgen::JsCast;
use wasm_bindgen_futures::JsFuture;
use web_sys::{Blob, Response as FetchResponse};

/// The page's URL parameters, read once.
#[derive(Debug, Clone, PartialEq)]
pub struct Launch {
    pub params: UrlParams,
    /// What could not be used, one message per parameter.
    pub messages: Vec<String>,
    /// The full page for the same take: this page (on its own origin, whatever its path) with
    /// the query without `embed` ([`url_params::full_page_href`]).
    pub full_page: String,
}

impl Launch {
    /// Reads `location.search`.
    pub fn from_location() -> Launch {
        let search = location_part("search");
        let names: Vec<String> = crate::methods::registry().iter().map(|m| m.info().name).collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let parsed = url_params::parse(&search, &names);
        let full_page = url_params::full_page_href(&location_part("origin"), &location_part("pathname"), &search);
        Launch { params: parsed.params, messages: parsed.messages, full_page }
    }

    /// Marks the root (`.ms-embed`) and `<body>` (`data-embed`) for the compact layout.
    pub fn mark(&self, root: &web_sys::HtmlElement) {
        if !self.params.embed {
            return;
        }
        let class = root.class_name();
        root.set_class_name(&format!("{class} ms-embed"));
        if let Some(body) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.body()) {
            let _ = body.set_attribute("data-embed", "1");
        }
    }
}

/// `location.<part>` as text (empty when there is none).
fn location_part(part: &str) -> String {
    web_sys::window()
        .and_then(|w| js_sys::Reflect::get(&w, &"location".into()).ok())
        .and_then(|l| js_sys::Reflect::get(&l, &part.into()).ok())
        .and_then(|v| v.as_string())
        .unwrap_or_default()
}

/// Loads what the URL names (else the workspace kept in this browser, [`Keeper::restore`], else the sample; an
/// embedded page keeps nothing), sets the methods to run, and seeks / plays once
/// the take is on screen; the messages that can only be known then go to `notice`.
pub fn start(
    state: AppState,
    loader: &Loader,
    runs: &MethodRuns,
    keeper: &Keeper,
    urls: &Urls,
    launch: &Launch,
    notice: RwSignal<Vec<String>>,
) {
    let params = &launch.params;
    if let Some(methods) = &params.methods {
        runs.set_auto_run(methods.clone());
    }
    let expected = match &params.src {
        Some(src) => {
            let name = url_params::file_name(src);
            let (url, asf) = (src.clone(), params.asf.clone());
            let fetch = async move {
                // an AMC's skeleton first: its failure is the one to report
                let skeleton = match asf {
                    Some(asf) => {
                        let blob = fetch_src("asf", asf.clone()).await?;
                        let bytes =
                            blob_bytes(&blob).await.map_err(|e| fetch_rules::fetch_failed("asf", &asf, None, &e))?;
                        Some((url_params::file_name(&asf), js_sys::Uint8Array::new(&bytes).to_vec()))
                    }
                    None => None,
                };
                Ok((fetch_src("src", url).await?, skeleton))
            };
            loader.load_src(src.clone(), name.clone(), fetch);
            // (an embedded page keeps nothing: it must not overwrite the workspace of the page it is part of)
            if !params.embed {
                keeper.skip();
            }
            name
        }
        // a page that names nothing to show opens the workspace kept in this browser (else the sample)
        None if !params.says_what_to_show => {
            let loader = loader.clone();
            keeper.restore(move || loader.load_sample());
            return;
        }
        None => {
            if !params.embed {
                keeper.skip();
            }
            loader.load_sample();
            urls.sample_name()
        }
    };
    let (t, autoplay) = (params.t, params.autoplay);
    if t.is_none() && !autoplay {
        return;
    }
    // the first take on screen, if it is the one the URL named
    let done = StoredValue::new(false);
    Effect::new(move |_| {
        let Some((name, fps, frames)) =
            state.motion.with(|m| m.as_ref().map(|m| (m.summary.name.clone(), m.summary.fps, m.summary.frames)))
        else {
            return;
        };
        if done.get_value() {
            return;
        }
        done.set_value(true);
        if name != expected {
            return;
        }
        if let Some(t) = t {
            let (frame, message) = url_params::start_frame(t, fps, frames, &name);
            state.frame.set(frame);
            if let Some(message) = message {
                notice.update(|n| n.push(message));
            }
        }
        if autoplay {
            state.playing.set(true);
        }
    });
}

/// Fetches the file of parameter `param` (`src`, `asf`): refused before asking when the page's
/// Content-Security-Policy does not allow its origin, and past [`MAX_FILE_BYTES`] as a dropped
/// file is (from its `Content-Length`, else as it arrives); every failure says what happened,
/// naming the parameter and its URL.
async fn fetch_src(param: &'static str, src: String) -> Result<Blob, String> {
    let href = location_part("href");
    let page_origin = location_part("origin");
    let url = web_sys::Url::new_with_base(&src, &href)
        .map_err(|e| format!("{param}={src}: not a URL ({})", js_message(&e)))?;
    let origin = url.origin();
    let cross = origin != page_origin;
    if cross && !fetch_rules::connect_src_allows(&page_csp(), &page_origin, &origin) {
        return Err(fetch_rules::csp_refused(param, &src, &origin, &page_origin));
    }
    let cross_origin = cross.then_some((origin.as_str(), page_origin.as_str()));
    let window = web_sys::window().ok_or("no window")?;
    let response: FetchResponse = JsFuture::from(window.fetch_with_str(&url.href()))
        .await
        .map_err(|e| fetch_rules::fetch_failed(param, &src, cross_origin, &js_message(&e)))?
        .unchecked_into();
    if !response.ok() {
        return Err(fetch_rules::http_failed(param, &src, response.status(), &response.status_text()));
    }
    read_capped(&response, MAX_FILE_BYTES).await.map_err(|e| match e {
        ReadError::TooLarge { size, declared } => fetch_rules::too_large(param, &src, size, declared, MAX_FILE_BYTES),
        ReadError::Failed(e) => fetch_rules::fetch_failed(param, &src, cross_origin, &e),
    })
}

/// The content of the page's Content-Security-Policy `<meta>` (empty when it has none).
fn page_csp() -> String {
    web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.query_selector("meta[http-equiv='Content-Security-Policy' i]").ok().flatten())
        .and_then(|m| m.get_attribute("content"))
        .unwrap_or_default()
}

/// `#url-notice`: the URL parameters that could not be used, each with why; dismissable.
#[component]
pub fn UrlNotice(messages: RwSignal<Vec<String>>) -> impl IntoView {
    view! {
        <div id="url-notice" class="ms-url-notice" role="status" hidden=move || messages.with(Vec::is_empty)>
            <strong class="ms-url-notice-title">"About this page's address:"</strong>
            <ul id="url-notice-list">
                {move || messages.get().into_iter().map(|m| view! { <li>{m}</li> }).collect_view()}
            </ul>
            <button
                id="url-notice-dismiss"
                class="ms-error-dismiss"
                type="button"
                aria-label="Dismiss"
                title="Dismiss"
                on:click=move |_| messages.set(Vec::new())
            >
                "×"
            </button>
        </div>
    }
}

/// `#embed-bar`: the take on screen and `#open-full`, the full page with the same parameters.
#[component]
pub fn EmbedBar(state: AppState, full_page: String) -> impl IntoView {
    let title = move || {
        state.motion.with(|m| {
            m.as_ref().map_or_else(String::new, |m| {
                let s = &m.summary;
                format!("{} · {:.2} s · {} fps", s.name, s.duration_s, crate::app::take::summary::format_fps(s.fps))
            })
        })
    };
    view! {
        <div id="embed-bar" class="ms-embed-bar">
            <span id="embed-title" class="ms-embed-title">{title}</span>
            <a id="open-full" class="ms-embed-open" href=full_page target="_blank" rel="noopener">
                "Open in mocapseg ↗"
            </a>
        </div>
    }
}
