//! `#my-labels-tools`: my labels' buttons, label field and status, under the timeline — start (copy a row, or
//! empty), cut (split, merge, fill, delete), label (the field and the vocabulary), history (undo, redo) and use
//! (train the method my labels train, clear them).

use crate::app::models::supervised::{TrainRequest, TrainState};
use crate::app::my_labels::edits::MyLabels as Model;
use crate::app::my_labels::row::MyRow;
use crate::app::my_labels::vocabulary::HOTKEYS;
use crate::app::timeline::row_exports::RowExports;
use leptos::ev::KeyboardEvent;
use leptos::prelude::*;

/// `#my-labels-tools`: the row's buttons, label field and status, under the timeline.
#[component]
pub fn MyLabelsTools(mine: MyRow) -> impl IntoView {
    let state = mine.state;
    // the method my labels train (DT-FCN declares it); without one its buttons stay hidden
    let trainer = state.my_labels_trainer();
    let short = trainer.map_or("", |(short, _)| short);
    let t = trainer.map(|(_, t)| t);
    let loaded = move || state.frames() > 0;
    let train_text = move || {
        let Some(t) = t.filter(|_| mine.training.get()) else { return String::new() };
        let step = &t.decl.step_name;
        t.state.with(|s| match s {
            TrainState::Training { stage, step: 0, .. } => format!("{short} on my labels: {stage}…"),
            TrainState::Training { step: done, steps, .. } => format!("{short} on my labels: {step} {done} of {steps}"),
            TrainState::Stopping => format!("{short} on my labels: stopping after this {step}…"),
            TrainState::Done | TrainState::Failed | TrainState::Cancelled => t.status.get(),
            TrainState::Idle => String::new(),
        })
    };
    let note_text = move || mine.note.with(|n| n.as_ref().map(|n| n.text.clone()).unwrap_or_default());
    view! {
        <div
            id="my-labels-tools"
            class="ms-my-tools"
            role="toolbar"
            aria-label="Edit my labels"
            hidden=move || !loaded()
        >
            <span class="ms-my-tools-title">"My labels"</span>
            {start_group(mine)}
            {cut_group(mine)}
            {label_group(mine)}
            {history_group(mine)}
            {use_group(mine)}
            <RowExports state=state id="my-labels" what="my labels" row=state.mine.into()/>
            <span id="my-labels-train-status" class="ms-my-status" role="status" aria-live="polite" hidden=move || train_text().is_empty()>
                {train_text}
            </span>
            <span
                id="my-labels-status"
                class="ms-my-status"
                class:ms-my-status--error=move || mine.note.with(|n| n.as_ref().is_some_and(|n| n.error))
                role="status"
                aria-live="polite"
                hidden=move || mine.note.with(Option::is_none)
            >
                {note_text}
            </span>
        </div>
    }
}

/// My labels' "Start" group: copy another row into them, or start empty.
fn start_group(mine: MyRow) -> impl IntoView {
    let loaded = move || mine.state.frames() > 0;
    let rows = move || {
        mine.others.with(|rows| {
            rows.iter()
                .map(|r| {
                    let id = r.id.clone();
                    let chosen = r.id.clone();
                    view! { <option value=id prop:selected=move || mine.source.get() == chosen>{r.name.clone()}</option> }
                })
                .collect_view()
        })
    };
    view! {
    <div class="ms-my-group" role="group" aria-label="Start my labels">
        <select
            id="my-labels-source"
            aria-label="Row to copy into my labels"
            disabled=move || mine.others.with(Vec::is_empty)
            on:change=move |ev| mine.source.set(event_target_value(&ev))
        >
            {rows}
        </select>
        <button id="my-labels-copy" class="ms-button ms-button--quiet" type="button"
            aria-label="Copy the chosen row into my labels (replaces them; undoable)"
            title="Copy the chosen row into my labels (replaces them; undoable)"
            disabled=move || mine.others.with(Vec::is_empty)
            on:click=move |_| mine.copy()>"Copy"</button>
        <button id="my-labels-empty" class="ms-button ms-button--quiet" type="button"
            aria-label="Start empty: one unlabelled segment over the whole take"
            title="Start empty: one unlabelled segment over the whole take (replaces my labels; undoable)"
            disabled=move || !loaded()
            on:click=move |_| { mine.edit(Model::start_empty, None); }>"Start empty"</button>
    </div>
    }
}

/// My labels' "Cut" group: split, merge, fill a gap, delete.
fn cut_group(mine: MyRow) -> impl IntoView {
    let state = mine.state;
    let loaded = move || state.frames() > 0;
    let selected = move || mine.model.with(|m| m.selected().is_some());
    let in_segment = move || {
        let f = state.frame.get();
        mine.model.with(|m| m.index_at(f).map(|i| m.spans()[i].start != f))
    };
    let can_split = move || in_segment() == Some(true);
    let can_fill = move || loaded() && in_segment().is_none();
    let can_merge = move || mine.model.with(|m| m.selected().is_some_and(|i| i + 1 < m.spans().len()));
    view! {
    <div class="ms-my-group" role="group" aria-label="Cut my segments">
        <button id="my-labels-split" class="ms-button ms-button--quiet" type="button"
            aria-label="Split my segment at the playhead (S)" title="Split my segment at the playhead (S)"
            disabled=move || !can_split() on:click=move |_| mine.split()>"Split"</button>
        <button id="my-labels-merge" class="ms-button ms-button--quiet" type="button"
            aria-label="Merge the selected segment with the next one (M)" title="Merge the selected segment with the next one (M)"
            disabled=move || !can_merge() on:click=move |_| mine.merge()>"Merge next"</button>
        <button id="my-labels-fill" class="ms-button ms-button--quiet" type="button"
            aria-label="Fill the gap under the playhead with an unlabelled segment"
            title="Fill the gap under the playhead with an unlabelled segment"
            disabled=move || !can_fill() on:click=move |_| { let f = mine.frame(); mine.edit(|m| m.fill_gap(f), None); }>"Fill gap"</button>
        <button id="my-labels-delete" class="ms-button ms-button--quiet" type="button"
            aria-label="Delete the selected segment (Delete); its frames become a gap"
            title="Delete the selected segment (Delete); its frames become a gap"
            disabled=move || !selected() on:click=move |_| mine.delete()>"Delete"</button>
    </div>
    }
}

/// My labels' "Label" group: the label field, its suggestions and the vocabulary's buttons (keys 1–9).
fn label_group(mine: MyRow) -> impl IntoView {
    let selected = move || mine.model.with(|m| m.selected().is_some());
    let offered = mine.vocabulary;
    let entries = move || {
        offered
            .get()
            .into_iter()
            .enumerate()
            .map(|(n, label)| {
                let key = (n < HOTKEYS).then(|| (n + 1).to_string());
                let tip = match &key {
                    Some(k) => format!("Label the selected segment {label} (key {k})"),
                    None => format!("Label the selected segment {label}"),
                };
                let chosen = label.clone();
                view! {
                    <li>
                        <button class="ms-button ms-button--quiet ms-vocab" type="button" data-label=label.clone()
                            aria-label=tip.clone() title=tip disabled=move || !selected()
                            on:click=move |_| mine.label_with(chosen.clone())>
                            <kbd hidden=key.is_none()>{key.clone().unwrap_or_default()}</kbd>
                            " "
                            {label.clone()}
                        </button>
                    </li>
                }
            })
            .collect_view()
    };
    let on_label_key = move |ev: KeyboardEvent| {
        if ev.key() == "Enter" {
            ev.prevent_default();
            mine.relabel();
        }
    };
    view! {
    <div class="ms-my-group" role="group" aria-label="Label the selected segment">
        <input
            id="my-labels-label"
            type="text"
            size="14"
            list="my-labels-suggestions"
            placeholder="label…"
            aria-label="Label of the selected segment (Enter applies)"
            disabled=move || !selected()
            bind:value=mine.label
            on:keydown=on_label_key
        />
        <datalist id="my-labels-suggestions">
            {move || offered.get().into_iter().map(|l| view! { <option value=l></option> }).collect_view()}
        </datalist>
        <button id="my-labels-apply" class="ms-button ms-button--quiet" type="button"
            aria-label="Give the selected segment this label" title="Give the selected segment this label (Enter)"
            disabled=move || !selected() on:click=move |_| mine.relabel()>"Set label"</button>
        <ol id="my-labels-vocabulary" class="ms-vocabulary" aria-label="Label vocabulary (keys 1–9)"
            hidden=move || offered.with(Vec::is_empty)>
            {entries}
        </ol>
    </div>
    }
}

/// My labels' undo and redo.
fn history_group(mine: MyRow) -> impl IntoView {
    view! {
    <div class="ms-my-group" role="group" aria-label="History">
        <button id="my-labels-undo" class="ms-button ms-button--quiet" type="button"
            aria-label="Undo (Ctrl+Z)" title="Undo (Ctrl+Z)"
            disabled=move || !mine.model.with(Model::can_undo) on:click=move |_| mine.undo()>"↶ Undo"</button>
        <button id="my-labels-redo" class="ms-button ms-button--quiet" type="button"
            aria-label="Redo (Ctrl+Shift+Z)" title="Redo (Ctrl+Shift+Z or Ctrl+Y)"
            disabled=move || !mine.model.with(Model::can_redo) on:click=move |_| mine.redo()>"↷ Redo"</button>
    </div>
    }
}

/// My labels' "Use" group: train the method my labels train (and stop it), clear them.
fn use_group(mine: MyRow) -> impl IntoView {
    let trainer = mine.state.my_labels_trainer();
    let short = trainer.map_or("", |(short, _)| short);
    let t = trainer.map(|(_, t)| t);
    let labelled = move || mine.model.with(|m| m.spans().iter().any(|s| !s.label.is_empty()));
    let busy = move || t.is_some_and(|t| t.state.with(TrainState::busy));
    let stopping = move || t.is_some_and(|t| t.state.with(|s| *s == TrainState::Stopping));
    view! {
    <div class="ms-my-group" role="group" aria-label="Use my labels">
        <button id="my-labels-train" class="ms-button" type="button"
            aria-label=format!("Train a {short} model on my labels (with the {short} panel's options)")
            title=format!("Train a {short} model on my labels, in this tab, with the {short} panel's options")
            hidden=t.is_none()
            disabled=move || busy() || !labelled() on:click=move |_| mine.train()>{format!("Train {short}")}</button>
        <button id="my-labels-train-stop" class="ms-button ms-button--quiet" type="button"
            aria-label=format!("Stop the {short} training after the step under way")
            hidden=move || !(mine.training.get() && busy())
            disabled=stopping
            on:click=move |_| { if let Some(t) = t { t.request.set(Some(TrainRequest::Stop)) } }>"Stop"</button>
        <button id="my-labels-clear" class="ms-button ms-button--quiet" type="button"
            aria-label="Clear my labels and remove them from this browser (Undo brings them back)"
            title="Clear my labels and remove them from this browser (Undo brings them back)"
            disabled=move || mine.model.with(|m| m.spans().is_empty())
            on:click=move |_| {
                mine.edit(|m| { m.clear(); Ok(()) }, Some("Cleared: nothing of this take is stored any more (Undo brings the labels back)".into()));
            }>"Clear"</button>
    </div>
    }
}
