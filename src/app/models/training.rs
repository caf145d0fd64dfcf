//! What a supervised method adds to its panel, built from what it declares
//! ([`crate::method::Supervision`]) — nothing here knows any method:
//!
//! * [`ModelFile`] — `#<method>-model-file` ("Load model file…") reads a model file of the method
//!   (`.<ext>` as it declares); the worker reads it with the method's own reader and stores it;
//!   the page adds it to the method's `model` choice (`#<method>-model`), chooses it and runs the
//!   method again. `#<method>-model-status` says which models the method has, what was loaded,
//!   or — for a bad file — the method's message (the model in use stays).
//!   `document.body.dataset.<method>Model` (`data-<method>-model`): `idle`, `loading`, `done` or
//!   `error`. `#<method>-my-models` lists the user's models (kept in this browser), each with a
//!   Forget button (`button.ms-forget[data-model=NAME]`, [`ModelJobs::forget_model`]): the model
//!   leaves the browser, the page and the model choice — the method back on its shipped model and
//!   run again when it was in use — and the status line says what was forgotten.
//! * [`TrainingPanel`] — `#<method>-training`: the label CSV (`#<method>-train-labels`, its
//!   header as the method declares it), more takes besides the one on screen when the method
//!   can use them (`#<method>-train-takes`), the model's name (`#<method>-train-name`), every
//!   training option of the method's table as a field `#<method>-train-<option>` (the basic ones
//!   shown, the others under "More options"), Train (`#<method>-train-start`) and Stop
//!   (`#<method>-train-stop`: after the step under way the best model so far is kept; before the
//!   first step the worker is replaced), `#<method>-train-progress`, `#<method>-train-status`,
//!   the method's report table `#<method>-train-report`, a plot of the values each step reports
//!   `#<method>-train-plot`, and `#<method>-train-download` (the model file, `NAME.<ext>`).
//!   A refusal shows at the input that is wrong: `#<method>-train-error-<input>` (`labels`,
//!   `takes`, `name` or an option). `document.body.dataset.<method>Training`
//!   (`data-<method>-training`): `idle`, `training`, `stopping`, `done`, `cancelled` or `error`.
//!
//! * [`TakeSwitch`] — `#take-switch` (role `alertdialog`, text `#take-switch-text`): opening another
//!   take while a training runs first asks whether to stop it (`#take-switch-stop`) or keep it
//!   running bound to its own take (`#take-switch-keep`, focused); either opens the take, and the
//!   take opens by itself if the training ends before an answer; Esc withdraws it (nothing opens,
//!   the training goes on; `#take-switch-esc` says so). Nothing in it names a method:
//!   the question says the method's short name and the model's, as the jobs reports them.
//!
//! The page holds every model it was given or trained ([`UserModel`], its file's bytes) and the
//! models' jobs send them to each worker the loader starts, so a worker replaced after a cancel or a crash still
//! knows them — the models kept in this browser still being restored, and a model kept from a
//! training that ended on another take, included. The "my labels" row trains the method that declares `trains_on_my_labels` through
//! [`Supervised::request`] ([`TrainRequest`], [`crate::app::models::supervised`]).

use crate::app::models::model_jobs::ModelJobs;
use crate::app::models::picked::{picked_files, read_bytes};
use crate::app::models::row_model::ModelCardView;
use crate::app::models::supervised::{LoadStatus, Supervised, TrainAsk, TrainRequest, TrainState, Unloadable};
use crate::app::models::train_form::{
    clear_error, labels_choice, take_names, training_options, MoreTakes, TrainAdvice,
};
use crate::app::models::train_outcome::{DownloadTrained, PendingTrained, TrainProgress, TrainReport};
use crate::app::state::AppState;
use crate::method::form;
use crate::method::supervised::StepReport;
use leptos::html::Canvas;
use leptos::prelude::*;
use std::sync::Arc;
use wasm_bindgen::{JsCast, JsValue};
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement};

/// The largest model file the page reads (the core refuses weights over 256 MiB).
const MAX_MODEL_BYTES: f64 = 300.0 * 1024.0 * 1024.0;

/// Sets `data-<name>` on `<body>` to what `value` says, whenever it changes.
fn body_data(name: String, value: impl Fn() -> &'static str + 'static) {
    Effect::new(move |_| {
        crate::app::dom::set_body_data(&[(&name, value())]);
    });
}

/// The Forget button of the user's model `name` (`button.ms-forget[data-model=NAME]`).
fn forget_button(name: &str, title: &'static str, forget: impl Fn() + 'static) -> AnyView {
    view! {
        <button
            class="ms-button ms-button--quiet ms-forget"
            type="button"
            data-model=name.to_string()
            aria-label=format!("Forget {name}")
            title=title
            on:click=move |_| forget()
        >
            "Forget"
        </button>
    }
    .into_any()
}

/// The model file's status line (tracked): the last load's outcome, else the models the method has.
fn model_status(s: &'static Supervised, short: &str) -> String {
    let text = s.file_status.get();
    if !text.is_empty() {
        return text;
    }
    let mine: Vec<String> = s.models.with(|l| l.iter().map(|m| m.info.name.clone()).collect());
    let shipped = s.decl.shipped.join(", ");
    let broken = match s.unloadable.with(Vec::len) {
        0 => String::new(),
        1 => " One kept model does not load here (below).".to_string(),
        n => format!(" {n} kept models do not load here (below)."),
    };
    if mine.is_empty() {
        format!("Shipped {short} models: {shipped}. Load a model file to add your own.{broken}")
    } else {
        format!("Shipped {short} models: {shipped}; yours (kept in this browser): {}.{broken}", mine.join(", "))
    }
}

/// A kept model that does not load here: why, Export (the file as kept) and Forget — never dropped unasked.
fn unloadable_item(
    m: Arc<Unloadable>,
    index: usize,
    forget_jobs: StoredValue<ModelJobs, LocalStorage>,
) -> impl IntoView {
    let name = m.name.clone();
    let forget = name.clone();
    let export = m.clone();
    view! {
        <li data-model=name.clone() class="ms-my-model--unloadable">
            <span class="ms-my-model-name">{name.clone()}</span>
            <span class="ms-my-model-why">{format!("does not load here: {}", m.why)}</span>
            <button
                class="ms-button ms-button--quiet ms-export-model"
                type="button"
                data-model=name.clone()
                aria-label=format!("Export {name}")
                title="Download the model file as it is kept in this browser"
                on:click=move |_| {
                    let _ = crate::app::player::motion_image::download(&export.bytes, "application/octet-stream", &export.file);
                }
            >
                "Export"
            </button>
            {forget_button(&name, "Remove it from this browser", move || {
                forget_jobs.with_value(|l| l.forget_model(index, &forget))
            })}
        </li>
    }
}

/// `#<method>-model-file` and its status line.
#[component]
pub fn ModelFile(state: AppState, jobs: ModelJobs, index: usize) -> impl IntoView {
    let slot = &state.methods[index];
    let Some(s) = slot.supervised.as_ref() else { return ().into_any() };
    let method = slot.info.name.clone();
    let short = slot.info.short.clone();
    let slot_short = short.clone();
    body_data(format!("data-{method}-model"), move || s.file_state.get().body_state());
    // (kept aside: the list below is reactive, and a handle cannot go to another thread)
    let forget_jobs = StoredValue::new_local(jobs.clone());

    let on_file = move |ev: leptos::ev::Event| {
        let Some(file) = picked_files(&ev).into_iter().next() else { return };
        let jobs = jobs.clone();
        s.file_state.set(LoadStatus::Loading);
        s.file_status.set(format!("Reading {}…", file.name()));
        wasm_bindgen_futures::spawn_local(async move {
            match read_bytes(&file, MAX_MODEL_BYTES).await {
                Ok(bytes) => jobs.use_model(index, file.name(), bytes),
                Err(message) => {
                    s.file_status.set(message);
                    s.file_state.set(LoadStatus::Failed);
                }
            }
        });
    };
    // the status line: the last load's outcome, else the models the method has
    let status = move || model_status(s, &slot_short);
    let id = format!("{method}-model-file");
    let accept = format!(".{},application/octet-stream,application/json", s.decl.model_extension);
    // the user's models, each with its Forget button
    let mine = move || {
        s.models.with(|list| {
            list.iter()
                .map(|m| {
                    let name = m.info.name.clone();
                    let forget = name.clone();
                    view! {
                        <li data-model=name.clone()>
                            <span class="ms-my-model-name">{name.clone()}</span>
                            {forget_button(&name, "Remove it from this browser and from the model choice", move || {
                                forget_jobs.with_value(|l| l.forget_model(index, &forget))
                            })}
                        </li>
                    }
                })
                .collect_view()
        })
    };
    // the user's models that do not load here: why, Export (the file as kept) and Forget — never dropped unasked
    let unloadable = move || {
        s.unloadable.with(|list| list.iter().map(|m| unloadable_item(m.clone(), index, forget_jobs)).collect_view())
    };
    view! {
        <div class="ms-method-params ms-model-file">
            <label class="ms-button ms-button--quiet" for=id.clone()>"Load model file…"</label>
            <input
                id=id
                class="ms-visually-hidden"
                type="file"
                accept=accept
                disabled=move || s.file_state.get() == LoadStatus::Loading
                on:change=on_file
            />
            <span
                id=format!("{method}-model-status")
                class="ms-model-status"
                class:ms-field-error=move || s.file_state.get() == LoadStatus::Failed
                role="status"
                aria-live="polite"
            >
                {status}
            </span>
            <ul
                id=format!("{method}-my-models")
                class="ms-my-models"
                aria-label=format!("Your {short} models kept in this browser")
                hidden=move || s.models.with(Vec::is_empty) && s.unloadable.with(Vec::is_empty)
            >
                {mine}
                {unloadable}
            </ul>
        </div>
        <ModelCardView state=state index=index id=format!("{method}-model-card")/>
    }
    .into_any()
}

#[component]
pub fn TrainingPanel(state: AppState, jobs: ModelJobs, index: usize) -> impl IntoView {
    let slot = &state.methods[index];
    let Some(s) = slot.supervised.as_ref() else { return ().into_any() };
    let method = slot.info.name.clone();
    let short = slot.info.short.clone();
    let busy = move || s.state.with(TrainState::busy);
    body_data(format!("data-{method}-training"), move || s.state.with(TrainState::body_state));

    let start_jobs = jobs.clone();
    // a training afresh, or (`from`: a model of the user's) more epochs of that model
    let start_with = move |from: Option<String>| start_training(state, &start_jobs, index, from);
    let start = {
        let start_with = start_with.clone();
        move || start_with(None)
    };
    // "continue training": the chosen model, when it is one of the user's networks (trained in
    // epochs), for the epochs the form asks
    let chosen = move || {
        slot.param("model").map(|(v, _)| v.get()).filter(|m| s.models.with(|l| l.iter().any(|u| u.info.name == *m)))
    };
    let epochs_field = s.decl.training.iter().position(|spec| spec.name == "epochs").map(|i| s.fields[i]);
    let can_continue = move || s.decl.step_name == "epoch" && epochs_field.is_some() && chosen().is_some();
    let continue_text = move || {
        let more = epochs_field.map(|f| f.get()).unwrap_or_default();
        format!("Continue training `{}` for {more} more {}s", chosen().unwrap_or_default(), s.decl.step_name)
    };
    let on_continue = move |_| start_with(chosen());
    let on_start = {
        let start = start.clone();
        move |ev: leptos::ev::SubmitEvent| {
            ev.prevent_default();
            start();
        }
    };
    // the "my labels" row's requests: its rows as the chosen labels, trained at once; or Stop
    let request_jobs = jobs.clone();
    Effect::new(move |_| {
        let Some(request) = s.request.get() else { return };
        s.request.set(None);
        match request {
            TrainRequest::Labels { labels_name, csv, model_name } => {
                clear_error(s, "labels");
                if !s.named.get_untracked() {
                    s.name.set(model_name);
                }
                s.labels.set(Some((labels_name, csv)));
                start();
            }
            TrainRequest::Stop => request_jobs.stop_training(index),
        }
    });
    let stop_jobs = jobs.clone();
    let on_stop = move |_| stop_jobs.stop_training(index);

    let stopping = move || s.state.with(|st| *st == TrainState::Stopping);

    view! {
        <section id=format!("{method}-training") class="ms-dtfcn-training" aria-label=format!("Train a {short} model on your labels")>
            <h3>{format!("Train a {short} model on your labels")}</h3>
            <p class="ms-lma-help">
                "A CSV with the header " <code>{s.decl.labels_header.clone()}</code> ". " {s.decl.labels_help.clone()}
            </p>
            <form id=format!("{method}-train-form") class="ms-dtfcn-train-form" novalidate=true on:submit=on_start>
                {labels_choice(slot, s)}
                <MoreTakes state=state s=s method=method.clone()/>
                <TrainAdvice state=state s=s method=method.clone()/>
                {training_options(slot, s)}
                <div class="ms-method-params">
                    <button
                        id=format!("{method}-train-start")
                        class="ms-button"
                        type="submit"
                        disabled=move || busy() || s.labels.with(Option::is_none) || state.motion.with(Option::is_none)
                    >
                        "Train"
                    </button>
                    <button
                        id=format!("{method}-train-continue")
                        class="ms-button ms-button--quiet"
                        type="button"
                        hidden=move || !can_continue()
                        disabled=move || busy() || s.labels.with(Option::is_none) || state.motion.with(Option::is_none)
                        title="More epochs of the chosen model (its weights, classes and input scaling kept) on the labels chosen"
                        on:click=on_continue
                    >
                        {continue_text}
                    </button>
                    <button
                        id=format!("{method}-train-stop")
                        class="ms-button ms-button--quiet"
                        type="button"
                        hidden=move || !busy()
                        disabled=stopping
                        on:click=on_stop
                    >
                        "Stop"
                    </button>
                    <TrainProgress s=s method=method.clone()/>
                    <DownloadTrained state=state s=s method=method.clone()/>
                </div>
            </form>
            <p
                id=format!("{method}-train-status")
                class="ms-lma-status"
                class:ms-lma-status--error=move || s.state.with(|st| *st == TrainState::Failed)
                role="status"
                aria-live="polite"
                hidden=move || s.status.with(String::is_empty)
            >
                {move || s.status.get()}
            </p>
            <PendingTrained state=state jobs=jobs.clone() index=index s=s method=method.clone()/>
            <TrainReport s=s method=method.clone()/>
            <TrainingPlot method=method.clone() supervised=s/>
        </section>
    }
    .into_any()
}

/// Starts a training of method `index` afresh, or (`from`: a model of the user's) more epochs of that model, with
/// the labels, takes and options the panel holds (unless one is under way; a refused option says why at its field).
fn start_training(state: AppState, jobs: &ModelJobs, index: usize, from: Option<String>) {
    let slot = &state.methods[index];
    let Some(s) = slot.supervised.as_ref() else { return };
    let busy = move || s.state.with(TrainState::busy);
    if busy() {
        return;
    }
    let Some((labels_name, text)) = s.labels.get_untracked() else {
        s.refuse("labels", "choose a label CSV first".into());
        return;
    };
    s.errors.set(Vec::new());
    let texts: Vec<String> = s.fields.iter().map(|f| f.get_untracked()).collect();
    let options = match form::params_from_form(&slot.info.short, &s.decl.training, &texts) {
        Ok(options) => options,
        Err(e) => {
            let input = e.param_name().unwrap_or("labels").to_string();
            s.refuse(&input, e.to_string());
            s.state.set(TrainState::Failed);
            s.status.set("Not trained: an option below cannot be read.".into());
            return;
        }
    };
    jobs.train(
        index,
        TrainAsk {
            name: from.clone().unwrap_or_else(|| s.name.get_untracked().trim().to_string()),
            labels_name,
            labels: text,
            extra: if s.decl.more_takes { s.extra.get_untracked() } else { Vec::new() },
            options,
            continue_from: from,
            // a validation take only among two or more takes (one of them: a take removed since is not sent)
            validation: Some(s.validation.get_untracked())
                .filter(|v| s.decl.validation_take && s.decl.more_takes && !v.is_empty())
                .filter(|v| untrack(|| take_names(state, s)).contains(v)),
        },
    );
}

/// `#take-switch`: the question put up when the user opens another take (drop, file picker,
/// sample) while a training runs — stop it (`#take-switch-stop`), or keep it running
/// (`#take-switch-keep`, focused when the question appears), bound to its own take; either opens
/// the take. The question goes when the training ends before an answer: the take opens then.
/// Esc withdraws the take: nothing opens, the training goes on.
#[component]
pub fn TakeSwitch(state: AppState, jobs: ModelJobs) -> impl IntoView {
    let asked = jobs.switch_question();
    // a training that ends (or fails) while the question is up: nothing is left to ask
    let settle = jobs.clone();
    Effect::new(move |_| {
        let Some(index) = asked.with(|a| a.as_ref().map(|a| a.index)) else { return };
        let busy = state.methods[index].supervised.as_ref().is_some_and(|s| s.state.with(TrainState::busy));
        if !busy {
            settle.answer_switch(false);
        }
    });
    let keep_ref = NodeRef::<leptos::html::Button>::new();
    Effect::new(move |_| {
        if asked.with(Option::is_some) {
            // once the bar is shown (its `hidden` goes in the same update)
            request_animation_frame(move || {
                if let Some(button) = keep_ref.get_untracked() {
                    let _ = button.focus();
                }
            });
        }
    });
    let text = move |part: fn(&crate::app::models::kept_models::SwitchQuestion) -> String| {
        move || asked.with(|a| a.as_ref().map(|a| part(&a.question)).unwrap_or_default())
    };
    let (stop_jobs, keep_jobs, esc_jobs) = (jobs.clone(), jobs.clone(), jobs);
    // Esc: the take is not opened after all (the one on screen stays, the training goes on)
    let on_key = move |ev: leptos::ev::KeyboardEvent| {
        if ev.key() == "Escape" {
            ev.prevent_default();
            ev.stop_propagation();
            esc_jobs.cancel_switch();
        }
    };
    view! {
        <div
            id="take-switch"
            class="ms-take-switch"
            role="alertdialog"
            aria-labelledby="take-switch-text"
            aria-describedby="take-switch-esc"
            hidden=move || asked.with(Option::is_none)
            on:keydown=on_key
        >
            <p id="take-switch-text">{text(|q| q.text.clone())}</p>
            <div class="ms-take-switch-answers">
                <button id="take-switch-stop" class="ms-button ms-button--quiet" type="button"
                    on:click=move |_| stop_jobs.answer_switch(true)>{text(|q| q.stop.clone())}</button>
                <button id="take-switch-keep" class="ms-button" type="button" node_ref=keep_ref
                    on:click=move |_| keep_jobs.answer_switch(false)>{text(|q| q.keep.clone())}</button>
                <span id="take-switch-esc" class="ms-take-switch-esc">"Esc: do not open it"</span>
            </div>
        </div>
    }
}

/// `#<method>-train-plot`: every value the steps report (each in 0–1) over the steps so far,
/// redrawn after each; a dot marks the step whose model is kept.
#[component]
fn TrainingPlot(method: String, supervised: &'static Supervised) -> impl IntoView {
    let s = supervised;
    let canvas_ref = NodeRef::<Canvas>::new();
    Effect::new(move |_| {
        let Some(canvas) = canvas_ref.get() else { return };
        s.steps.with(|steps| {
            if let Err(e) = draw_plot(&canvas, steps) {
                web_sys::console::error_2(&"could not draw the training plot".into(), &e);
            }
        });
    });
    let empty = move || s.steps.with(|steps| steps.iter().all(|r| r.values.is_empty()));
    let names = move || {
        s.steps.with(|steps| {
            let Some(last) = steps.last() else { return String::new() };
            last.values
                .iter()
                .enumerate()
                .map(|(k, (name, _))| format!("{}: {name}", COLOURS[k % COLOURS.len()].1))
                .collect::<Vec<_>>()
                .join(", ")
        })
    };
    view! {
        <figure class="ms-method-figure" hidden=empty>
            <canvas id=format!("{method}-train-plot") class="ms-train-plot" width="560" height="200" node_ref=canvas_ref
                aria-label="The training's values per step"></canvas>
            <figcaption class="ms-method-legend">
                <strong>"Training. "</strong>
                {move || format!("Steps across, each value from 0 to its largest so far up ({}). A larger dot marks the step whose model is kept.", names())}
            </figcaption>
        </figure>
    }
}

/// The plot's colours and their names.
const COLOURS: [(&str, &str); 4] =
    [("#1d4ed8", "blue"), ("#c2410c", "orange"), ("#15803d", "green"), ("#7e22ce", "purple")];

fn draw_plot(canvas: &HtmlCanvasElement, steps: &[StepReport]) -> Result<(), JsValue> {
    let ctx: CanvasRenderingContext2d = canvas.get_context("2d")?.ok_or("no 2d context")?.dyn_into()?;
    let (w, h) = (canvas.width() as f64, canvas.height() as f64);
    let (left, right, top, bottom) = (44.0, w - 44.0, 12.0, h - 26.0);
    ctx.set_fill_style_str("#ffffff");
    ctx.fill_rect(0.0, 0.0, w, h);
    let Some(last) = steps.last() else { return Ok(()) };
    let n = last.steps.max(steps.len()).max(2);
    let x = |step: usize| left + (step as f64 - 1.0) / (n as f64 - 1.0) * (right - left);
    let y = |share: f64| bottom - share.clamp(0.0, 1.0) * (bottom - top);
    ctx.set_stroke_style_str("#d7dbe2");
    ctx.set_line_width(1.0);
    for k in 0..=4 {
        let yy = y(k as f64 / 4.0);
        ctx.begin_path();
        ctx.move_to(left, yy);
        ctx.line_to(right, yy);
        ctx.stroke();
    }
    ctx.set_font("11px sans-serif");
    ctx.set_fill_style_str("#555b66");
    ctx.set_text_align("center");
    ctx.fill_text("1", x(1), h - 8.0)?;
    ctx.fill_text(&n.to_string(), x(n), h - 8.0)?;
    let kept = steps.iter().rev().find(|r| r.best).map(|r| r.step);
    for (k, (name, _)) in last.values.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()].0;
        let value = |r: &StepReport| r.values.iter().find(|(v, _)| v == name).map(|(_, v)| *v);
        ctx.set_stroke_style_str(colour);
        ctx.set_fill_style_str(colour);
        ctx.set_line_width(2.0);
        ctx.begin_path();
        let mut first = true;
        for r in steps {
            let Some(v) = value(r) else { continue };
            if first {
                ctx.move_to(x(r.step), y(v));
                first = false;
            } else {
                ctx.line_to(x(r.step), y(v));
            }
        }
        ctx.stroke();
        for r in steps {
            let Some(v) = value(r) else { continue };
            ctx.begin_path();
            let radius = if Some(r.step) == kept { 4.0 } else { 2.0 };
            let _ = ctx.arc(x(r.step), y(v), radius, 0.0, std::f64::consts::TAU);
            ctx.fill();
        }
    }
    Ok(())
}
