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
    // the method my labels train (the chosen one of k-NN and DT-FCN); without one its buttons stay hidden
    let loaded = move || state.frames() > 0;
    let train_text = move || {
        let Some((short, t)) = mine.chosen_trainer().filter(|_| mine.training.get()) else { return String::new() };
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
    // training begun: its status is brought into view (the tools sit under the timeline's minimap, below the fold of
    // the timeline's box; issue 48, "the training status under the minimap")
    Effect::new(move |was_shown: Option<bool>| {
        let shown = !train_text().is_empty();
        if shown && was_shown == Some(false) {
            crate::app::dom::reveal("my-labels-train-status");
        }
        shown
    });
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
            {boundary_group(mine)}
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

/// My labels' "Boundaries" group: snapping on or off, and the selected segment's first and last frames typed (as
/// the page counts them, from 1): a typed frame moves that boundary there, as far as the neighbours let it.
fn boundary_group(mine: MyRow) -> impl IntoView {
    let state = mine.state;
    let span = move || mine.model.with(|m| m.selected_span().map(|s| (s.start, s.end)));
    let set = move |first: bool, text: String| {
        let Some((start, end)) = mine.model.with_untracked(|m| m.selected_span().map(|s| (s.start, s.end))) else {
            return;
        };
        let frames = state.frames();
        let typed = text.trim().parse::<usize>().ok().filter(|f| (1..=frames).contains(f));
        let Some(f) = typed else {
            return mine.say(true, format!("Type a frame from 1 to {frames}"));
        };
        // frame f (from 1) is index f − 1; a segment's last frame f ends before cut f
        let (cut, to) = if first { (start, f - 1) } else { (end + 1, f) };
        let mut landed = cut;
        let moved = mine.edit(
            |m| {
                landed = m.move_boundary(cut, to)?;
                Ok(())
            },
            None,
        );
        let frame = if first { landed + 1 } else { landed };
        let which = if first { "first" } else { "last" };
        if landed != to {
            mine.say(true, format!("The segment's {which} frame is {frame}: as far as its neighbours let it go"));
        } else if moved {
            mine.say(false, format!("The segment's {which} frame is now {frame}"));
        }
    };
    // the selected segment's first (`first`) or last frame, as the page counts them
    let frame_field = move |first: bool| {
        let (id, text, which) =
            if first { ("my-labels-start", "From frame ", "First") } else { ("my-labels-end", " to ", "Last") };
        view! {
            <label class="ms-my-frame">
                {text}
                <input id=id type="number" min="1" max=move || state.frames()
                    aria-label=format!("{which} frame of the selected segment (the page counts frames from 1)")
                    disabled=move || span().is_none()
                    prop:value=move || span().map(|(s, e)| (if first { s } else { e } + 1).to_string()).unwrap_or_default()
                    on:change=move |ev| set(first, event_target_value(&ev))/>
            </label>
        }
    };
    view! {
    <div class="ms-my-group" role="group" aria-label="Boundaries of my segments">
        <label class="ms-my-snap" title="A dragged boundary snaps to the other rows' boundaries within 8 px (3 frames at most); hold Alt or Shift while dragging to place it freely">
            <input id="my-labels-snap" type="checkbox" aria-label="Snap a dragged boundary to the other rows' boundaries"
                prop:checked=move || mine.snapping.get()
                on:change=move |ev| mine.snapping.set(event_target_checked(&ev))/>
            " Snap"
        </label>
        {frame_field(true)}
        {frame_field(false)}
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
    // a gap lies between my segments: with none yet there is nothing to fill (Start empty does that)
    let can_fill = move || loaded() && in_segment().is_none() && mine.model.with(|m| !m.spans().is_empty());
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

/// My labels' "Use" group: train the chosen method (k-NN or DT-FCN) in one click (and stop it), clear them.
fn use_group(mine: MyRow) -> impl IntoView {
    let trainers = mine.state.my_labels_trainers();
    let none = trainers.is_empty();
    let short = move || mine.chosen_trainer().map_or("", |(short, _)| short);
    let t = move || mine.chosen_trainer().map(|(_, t)| t);
    let labelled = move || mine.model.with(|m| m.spans().iter().any(|s| !s.label.is_empty()));
    let busy = move || t().is_some_and(|t| t.state.with(TrainState::busy));
    let stopping = move || t().is_some_and(|t| t.state.with(|s| *s == TrainState::Stopping));
    let choices = trainers
        .iter()
        .enumerate()
        .map(|(i, (short, _))| {
            view! { <option value=i.to_string() prop:selected=move || mine.trainer.get() == i>{*short}</option> }
        })
        .collect_view();
    view! {
    <div class="ms-my-group" role="group" aria-label="Use my labels">
        <select id="my-labels-trainer" aria-label="The method my labels train in one click" hidden=trainers.len() < 2
            disabled=busy
            on:change=move |ev| mine.trainer.set(event_target_value(&ev).parse().unwrap_or_default())>
            {choices}
        </select>
        <button id="my-labels-train" class="ms-button" type="button"
            aria-label=move || format!("Train a {} model on my labels (with the {} panel's options)", short(), short())
            title=move || format!("Train a {} model on my labels, in this tab, with the {} panel's options", short(), short())
            hidden=none
            disabled=move || busy() || !labelled() on:click=move |_| mine.train()>{move || format!("Train {}", short())}</button>
        <button id="my-labels-train-stop" class="ms-button ms-button--quiet" type="button"
            aria-label=move || format!("Stop the {} training after the step under way", short())
            hidden=move || !(mine.training.get() && busy())
            disabled=stopping
            on:click=move |_| { if let Some(t) = t() { t.request.set(Some(TrainRequest::Stop)) } }>"Stop"</button>
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
