//! `#error-banner`: the last error: a load's (the parser's message with file, line and column)
//! or a method's (the parameter it refuses and why).
//! Hidden when there is none; dismissable; the rest of the page — and the take already on
//! screen — stays usable.

use crate::app::state::AppState;
use leptos::prelude::*;

#[component]
pub fn ErrorBanner(state: AppState) -> impl IntoView {
    let message = move || state.error.get().unwrap_or_default();
    view! {
        <div id="error-banner" class="ms-error-banner" role="alert" hidden=move || state.error.with(Option::is_none)>
            <strong class="ms-error-title">
                {move || {
                    if state.error_is_run.get() {
                        "Could not segment the take."
                    } else {
                        "Could not load the file."
                    }
                }}
            </strong>
            <span id="error-message" class="ms-error-message">{message}</span>
            <button
                id="error-dismiss"
                class="ms-error-dismiss"
                type="button"
                aria-label="Dismiss"
                title="Dismiss"
                on:click=move |_| state.error.set(None)
            >
                "×"
            </button>
        </div>
    }
}
