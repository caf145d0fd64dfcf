//! A method's parameter fields, built from its parameter table: a checkbox, a choice, or a number with its unit,
//! each named in words ([`ParamSpec::words`]) with the parameter's help shown under it (issue 48: "every
//! parameter's help visible beside its field"), the control described by it (`aria-describedby`).

use crate::app::models::row_model::choice_options;
use crate::app::state::MethodSlot;
use crate::method::{ParamKind, ParamSpec};
use leptos::prelude::*;
use wasm_bindgen::JsCast;

/// A field's help, shown under it (`#<id>-help`, which describes the control).
fn help_view(id: &str, help: String) -> impl IntoView {
    view! { <span id=format!("{id}-help") class="ms-field-help">{help}</span> }
}

/// The label of a parameter's field: its name in words, with its unit ("horizon (s)").
fn field_label(spec: &ParamSpec) -> String {
    let words = spec.words();
    match &spec.unit {
        Some(unit) => format!("{words} ({unit})"),
        None => words,
    }
}

/// A field's unit after its control (`None`: no unit).
fn unit_view(spec: &ParamSpec) -> Option<AnyView> {
    spec.unit.clone().map(|u| view! { <span class="ms-field-unit">{u}</span> }.into_any())
}

/// One form field for `spec`, bound to `value` (a choice offers `choices`); its id is
/// `<prefix>-<param>` (`<prefix>-<param>-<option>` for each box of a set of flags). The label is
/// two cells, the name (`.ms-field-name`) and the control with its unit (`.ms-field-control`),
/// laid out as a grid by `www/style.css` so that no name runs into the control before it; the
/// name with its unit is the control's accessible name.
pub(crate) fn field(
    method: &str,
    spec: &ParamSpec,
    value: RwSignal<String>,
    choices: RwSignal<Vec<String>>,
) -> AnyView {
    let id = format!("{method}-{}", spec.name);
    let help = spec.help.clone();
    let described = format!("{id}-help");
    let label = field_label(spec);
    let words = spec.words();
    let unit = unit_view(spec);
    match &spec.kind {
        ParamKind::Bool => {
            let checked = move || value.get() == "true";
            let on_change = move |ev: leptos::ev::Event| {
                let on = ev
                    .target()
                    .and_then(|t| t.dyn_into::<web_sys::HtmlInputElement>().ok())
                    .is_some_and(|i| i.checked());
                value.set(on.to_string());
            };
            view! {
                <label>
                    <span class="ms-field-name">{words}</span>
                    <span class="ms-field-control">
                        <input id=id.clone() type="checkbox" aria-label=label aria-describedby=described prop:checked=checked on:change=on_change/>
                    </span>
                    {help_view(&id, help)}
                </label>
            }
            .into_any()
        }
        ParamKind::Choice { .. } => {
            // the options may grow (a model the user loads or trains); each option says whether
            // it is the one chosen, so a value set before its option exists still shows
            let options = move || choice_options(choices, value);
            view! {
                <label>
                    <span class="ms-field-name">{words}</span>
                    <span class="ms-field-control">
                        <select id=id.clone() aria-label=label aria-describedby=described bind:value=value>
                            {options}
                        </select>
                        {unit}
                    </span>
                    {help_view(&id, help)}
                </label>
            }
            .into_any()
        }
        ParamKind::Number { min, max } => {
            number_input(id, (label, words, unit), help, (min.to_string(), max.to_string(), "any"), value)
        }
        ParamKind::Integer { min, max } => {
            number_input(id, (label, words, unit), help, (min.to_string(), max.to_string(), "1"), value)
        }
        ParamKind::IntegerList { .. } => view! {
            <label>
                <span class="ms-field-name">{words}</span>
                <span class="ms-field-control">
                    <input id=id.clone() type="text" size="16" aria-label=label aria-describedby=described bind:value=value/>
                    {unit}
                </span>
                {help_view(&id, help)}
            </label>
        }
        .into_any(),
        ParamKind::Flags { options } => {
            // one box per option; the value is the chosen options, comma-separated
            let boxes = options
                .iter()
                .map(|option| {
                    let on = {
                        let option = option.clone();
                        move || value.with(|v| v.split(',').any(|o| o.trim() == option))
                    };
                    let toggled = option.clone();
                    let on_change = move |ev: leptos::ev::Event| {
                        let checked = ev
                            .target()
                            .and_then(|t| t.dyn_into::<web_sys::HtmlInputElement>().ok())
                            .is_some_and(|i| i.checked());
                        value.update(|v| {
                            let mut chosen: Vec<String> = v
                                .split(',')
                                .map(|o| o.trim().to_string())
                                .filter(|o| !o.is_empty() && *o != toggled)
                                .collect();
                            if checked {
                                chosen.push(toggled.clone());
                            }
                            *v = chosen.join(",");
                        });
                    };
                    view! {
                        <label>
                            <input id=format!("{id}-{option}") type="checkbox" prop:checked=on on:change=on_change/>
                            " "
                            {option.clone()}
                        </label>
                    }
                })
                .collect_view();
            view! {
                <span class="ms-flags" role="group" aria-label=label aria-describedby=described>
                    <span class="ms-field-name">{words}</span>
                    <span class="ms-field-control">{boxes}</span>
                    {help_view(&id, help)}
                </span>
            }
            .into_any()
        }
    }
}

/// A parameter's field with the place for its refusal: `#<method>-<param>-error` under it holds
/// the message of the last run refused for this parameter (an alert; the field is outlined red).
pub(crate) fn checked_field(
    slot: &'static MethodSlot,
    spec: &ParamSpec,
    value: RwSignal<String>,
    choices: RwSignal<Vec<String>>,
) -> AnyView {
    let param = spec.name.clone();
    let mine = move || slot.field_error.with(|e| e.as_ref().filter(|(p, _)| *p == param).map(|(_, m)| m.clone()));
    let invalid = mine.clone();
    let shown = mine.clone();
    let error_id = format!("{}-{}-error", slot.info.name, spec.name);
    view! {
        <div class="ms-field" class:ms-field--invalid=move || invalid().is_some()>
            {field(&slot.info.name, spec, value, choices)}
            <span id=error_id class="ms-field-error" role="alert" hidden=move || shown().is_none()>
                {move || mine().unwrap_or_default()}
            </span>
        </div>
    }
    .into_any()
}

/// A number field with its bounds and step (`any` or `1`) as hints; the method checks the value.
/// `label`: its accessible name, its name in words and its unit.
fn number_input(
    id: String,
    (label, words, unit): (String, String, Option<AnyView>),
    help: String,
    (min, max, step): (String, String, &'static str),
    value: RwSignal<String>,
) -> AnyView {
    view! {
        <label>
            <span class="ms-field-name">{words}</span>
            <span class="ms-field-control">
                <input id=id.clone() type="number" step=step min=min max=max size="6" aria-label=label
                    aria-describedby=format!("{id}-help") bind:value=value/>
                {unit}
            </span>
            {help_view(&id, help)}
        </label>
    }
    .into_any()
}
