//! A training's form as a supervised method declares it: the label CSV, the takes added and the validation take,
//! the advice before training, the options (basic, and under "More options") and each input's refusal.

use crate::app::loader::MAX_FILE_BYTES;
use crate::app::method_panel::fields::field;
use crate::app::models::picked::{picked_files, read_bytes, read_text, MAX_LABELS_BYTES};
use crate::app::models::supervised::{Supervised, TrainState};
use crate::app::models::training_advice;
use crate::app::player::motion_image::stem;
use crate::app::state::AppState;
use crate::app::state::MethodSlot;
use crate::method::ParamSpec;
use leptos::prelude::*;
use std::sync::Arc;
use web_sys::File;

/// Forgets the refusal shown at training input `input`.
pub(crate) fn clear_error(s: &'static Supervised, input: &str) {
    s.errors.update(|e| e.retain(|(i, _)| i != input));
}

/// The refusal of training input `input`, shown at it (`#<method>-train-error-<input>`).
pub(crate) fn train_error(method: &str, s: &'static Supervised, input: &'static str) -> impl IntoView {
    let id = format!("{method}-train-error-{input}");
    let text = move || s.errors.with(|e| e.iter().find(|(i, _)| i == input).map(|(_, m)| m.clone()));
    view! {
        <span id=id class="ms-field-error" role="alert" hidden=move || text().is_none()>
            {move || text().unwrap_or_default()}
        </span>
    }
}

/// The takes a training would see: the one on screen, then the ones added.
pub(crate) fn take_names(state: AppState, s: &'static Supervised) -> Vec<String> {
    let mut names: Vec<String> =
        state.motion.with(|m| m.as_ref().map(|m| m.summary.name.clone())).into_iter().collect();
    s.extra.with(|e| names.extend(e.iter().map(|(n, _)| n.clone())));
    names
}

/// The label CSV a training reads: its file input, its name, its refusal.
pub(crate) fn labels_choice(slot: &'static MethodSlot, s: &'static Supervised) -> impl IntoView {
    let method = slot.info.name.clone();
    let on_labels = move |ev: leptos::ev::Event| {
        let Some(file) = picked_files(&ev).into_iter().next() else { return };
        clear_error(s, "labels");
        let method = slot.info.name.clone();
        wasm_bindgen_futures::spawn_local(async move {
            match read_text(&file, MAX_LABELS_BYTES).await {
                Ok(text) => {
                    if !s.named.get_untracked() {
                        s.name.set(format!("{}-{method}", stem(&file.name())));
                    }
                    if !s.state.with_untracked(TrainState::busy) {
                        s.status.set(format!("{}: ready to train on the take on screen.", file.name()));
                    }
                    s.labels.set(Some((file.name(), text)));
                }
                Err(message) => {
                    s.labels.set(None);
                    s.refuse("labels", message);
                }
            }
        });
    };
    let labels_id = format!("{method}-train-labels");
    let labels_accept = ".csv,text/csv";
    view! {
        <div class="ms-method-params">
            <label class="ms-button ms-button--quiet" for=labels_id.clone()>"Label CSV…"</label>
            <input id=labels_id class="ms-visually-hidden" type="file" accept=labels_accept on:change=on_labels/>
            <span id=format!("{method}-train-labels-name") class="ms-lma-file">
                {move || s.labels.with(|l| l.as_ref().map_or("no file chosen".to_string(), |(n, _)| n.clone()))}
            </span>
            {train_error(&method, s, "labels")}
        </div>
    }
}

/// The takes a training adds to the one on screen (`More takes…`, capped in total before any is read), and the
/// validation take among them.
#[component]
pub(crate) fn MoreTakes(state: AppState, s: &'static Supervised, method: String) -> impl IntoView {
    let on_takes = move |ev: leptos::ev::Event| {
        let files = picked_files(&ev);
        if files.is_empty() {
            return;
        }
        clear_error(s, "takes");
        // the takes a training adds are capped in total (the worker refuses more too): checked
        // from the files' sizes, before any is read
        let names: Vec<String> = files.iter().map(File::name).collect();
        let kept: Vec<u64> = s.extra.with_untracked(|list| {
            list.iter().filter(|(n, _)| !names.contains(n)).map(|(_, b)| b.len() as u64).collect()
        });
        let total = crate::protocol::extra_takes_total(kept.into_iter().chain(files.iter().map(|f| f.size() as u64)));
        if let Err(message) = total {
            s.refuse("takes", message);
            return;
        }
        wasm_bindgen_futures::spawn_local(async move {
            let mut read = Vec::new();
            for file in files {
                match read_bytes(&file, MAX_FILE_BYTES).await {
                    Ok(bytes) => read.push((file.name(), Arc::new(bytes))),
                    Err(message) => {
                        s.refuse("takes", message);
                        return;
                    }
                }
            }
            s.extra.update(|list| {
                for (n, b) in read {
                    list.retain(|(m, _)| *m != n);
                    list.push((n, b));
                }
            });
        });
    };
    let on_clear_takes = move |_| {
        s.extra.set(Vec::new());
        s.validation.set(String::new());
        clear_error(s, "takes");
        clear_error(s, "validation");
    };
    let takes_text = move || {
        s.extra.with(|list| {
            if list.is_empty() {
                "only the take on screen".to_string()
            } else {
                format!(
                    "the take on screen and {}",
                    list.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(", ")
                )
            }
        })
    };
    let more_takes = s.decl.more_takes.then(|| {
        let id = format!("{method}-train-takes");
        view! {
            <div class="ms-method-params">
                <label class="ms-button ms-button--quiet" for=id.clone()>"More takes…"</label>
                <input id=id class="ms-visually-hidden" type="file" multiple=true accept=".bvh" on:change=on_takes/>
                <span id=format!("{method}-train-takes-names") class="ms-lma-file">{takes_text}</span>
                <button
                    id=format!("{method}-train-takes-clear")
                    class="ms-button ms-button--quiet"
                    type="button"
                    hidden=move || s.extra.with(Vec::is_empty)
                    on:click=on_clear_takes
                >
                    "Only the take on screen"
                </button>
                {train_error(&method, s, "takes")}
            </div>
        }
    });
    let validation_choice = (s.decl.validation_take && s.decl.more_takes).then(|| {
        let id = format!("{method}-train-validation");
        view! {
            <div class="ms-method-params" hidden=move || s.extra.with(Vec::is_empty)>
                <label title="One of the takes kept out of the training: its validation loss chooses the epoch (early stopping, patience under More options) and its labels the model's decoding and unknown threshold (choose_decoding).">
                    "validation take "
                    <select id=id on:change=move |ev| s.validation.set(event_target_value(&ev))>
                        <option value="" selected=move || s.validation.with(String::is_empty)>"none"</option>
                        {move || {
                            take_names(state, s)
                                .into_iter()
                                .map(|n| {
                                    let (chosen, value) = (n.clone(), n.clone());
                                    view! { <option value=value selected=move || s.validation.with(|v| *v == chosen)>{n}</option> }
                                })
                                .collect_view()
                        }}
                    </select>
                </label>
                {train_error(&method, s, "validation")}
            </div>
        }
    });
    view! {
        {more_takes}
        {validation_choice}
    }
}

/// Advice before training: classes with too few labelled segments or seconds in the takes trained on.
#[component]
pub(crate) fn TrainAdvice(state: AppState, s: &'static Supervised, method: String) -> impl IntoView {
    let advice = move || {
        let Some((name, text)) = s.labels.get() else { return Vec::new() };
        let Ok(rows) = crate::labels::read_csv(&text, &name) else { return Vec::new() };
        let Some((take, fps)) = state.motion.with(|m| m.as_ref().map(|m| (m.summary.name.clone(), m.summary.fps)))
        else {
            return Vec::new();
        };
        // the other takes' rates are not read before training: their rows are counted at this take's
        let takes: Vec<(String, f64)> = std::iter::once((take, fps))
            .chain(s.extra.with(|e| e.iter().map(|(n, _)| (n.clone(), fps)).collect::<Vec<_>>()))
            .collect();
        training_advice::advice(&training_advice::class_counts(&rows, &takes))
    };
    view! {
    <ul id=format!("{method}-train-advice") class="ms-train-advice" role="note"
        aria-label="Advice before training" hidden=move || advice().is_empty()>
        {move || advice().into_iter().map(|line| view! { <li>{line}</li> }).collect_view()}
    </ul>
    }
}

/// A training's options as the method declares them — the basic ones and the model's name, the others under "More
/// options" (opened by a refusal of one of them; nothing closes what the user opened).
pub(crate) fn training_options(slot: &'static MethodSlot, s: &'static Supervised) -> impl IntoView {
    let method = slot.info.name.clone();
    let options = || s.decl.training.iter().zip(&s.fields);
    let basic: Vec<AnyView> =
        options().filter(|(spec, _)| spec.basic).map(|(spec, v)| option_field(&slot.info.name, s, spec, *v)).collect();
    let advanced: Vec<AnyView> =
        options().filter(|(spec, _)| !spec.basic).map(|(spec, v)| option_field(&slot.info.name, s, spec, *v)).collect();
    let has_advanced = !advanced.is_empty();
    let details_ref = NodeRef::<leptos::html::Details>::new();
    Effect::new(move |_| {
        let refused =
            s.errors.with(|e| e.iter().any(|(i, _)| s.decl.training.iter().any(|spec| !spec.basic && spec.name == *i)));
        if let Some(details) = details_ref.get().filter(|_| refused) {
            details.set_open(true);
        }
    });
    view! {
        <div class="ms-method-params">
            {basic}
            <label title="The model's name in the model choice, and its file's name.">
                "model name "
                <input
                    id=format!("{method}-train-name")
                    type="text"
                    size="14"
                    bind:value=s.name
                    on:input=move |_| s.named.set(true)
                />
            </label>
            {train_error(&method, s, "name")}
        </div>
        <details class="ms-method-advanced" hidden=!has_advanced node_ref=details_ref>
            <summary>"More options"</summary>
            <div class="ms-method-params">{advanced}</div>
        </details>
    }
}

/// One training option's field with the place for its refusal.
pub(crate) fn option_field(method: &str, s: &'static Supervised, spec: &ParamSpec, value: RwSignal<String>) -> AnyView {
    let input = spec.name.clone();
    let message = move || s.errors.with(|e| e.iter().find(|(i, _)| *i == input).map(|(_, m)| m.clone()));
    let shown = message.clone();
    view! {
        {field(&format!("{method}-train"), spec, value, RwSignal::new(Vec::new()))}
        <span id=format!("{method}-train-error-{}", spec.name) class="ms-field-error" role="alert" hidden=move || shown().is_none()>
            {move || message().unwrap_or_default()}
        </span>
    }
    .into_any()
}
