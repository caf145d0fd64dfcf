//! The library of takes (issue 26): several files dropped or picked at once (or a folder, `#folder-input`)
//! become a list of takes in the side panel's "Library" tab (`#tab-library`, shown once the library
//! has a take). Each take (`#library-list li`, `data-status` = queued / running / done / failed /
//! cancelled) shows its name, duration and status; the worker segments them one after another with
//! the method chosen (`#library-method`) and its panel's parameters, `#library-cancel` drops the
//! rest, `#library-rerun` queues the failed and cancelled again. Clicking a take's name opens it
//! on screen as a dropped file opens (its `File` read again: takes not on screen keep their
//! segmentations, never their frames). `#library-export-csv` saves every take's labels as one label
//! CSV ([`crate::app::library::takes::library_csv`]). The take on screen, when it is one of the
//! library's, shows its library segmentation as the timeline's row `#row-library` ("Library"),
//! its segments labelled by their clusters' names.
//!
//! Once no take is left to segment, the worker matches the takes into clusters shared across takes
//! (`#library-matching` says where it stands). The cluster list (`#library-clusters`, `li` with
//! `data-cluster`, `data-takes`) shows each cluster's colour, its name (an editable field: renamed
//! once, named in every take's row, the CSV and the clips), its occurrences, takes and total
//! seconds; **Play** plays its occurrences one after another across takes (each take opened when
//! not on screen; `#library-playing` says which, `#library-previous` / `#library-next` /
//! `#library-stop`), **Clips** saves its occurrences as BVH clips of every take in one zip, and
//! `#library-export-clips` every cluster's (`#library-origin`: each clip at the origin).
//!
//! "Carry labels" ([`Carry`]): the take on screen's my labels (else its ground truth) carried to every
//! take by `#library-route` (`library_transfer`; or `knn` / `dtfcn`: a k-NN or a DT-FCN trained on them, with
//! that panel's training options, labels every other take; `#library-carry-cancel` stopping any); each take of the list then says its labelled share
//! (`.ms-lib-carried`), the timeline's `#row-transferred` ("Carried labels") shows a take's carried
//! labels, `#library-copy-carried` copies them into my labels, and the CSV saves them
//! ([`crate::app::library::carry`]). The state
//! is [`LibraryState`]; the workers' side is [`crate::app::library::jobs`]; the decisions are
//! [`crate::app::library::takes`]'s.

use crate::app::library::carry::Route;
use crate::app::library::library_jobs::LibraryJobs;
use crate::app::library::on_screen::source_labels;
use crate::app::library::queue::Queue;
use crate::app::library::state::LibraryState;
use crate::app::library::takes::{library_csv, playing_text, Shared, Spot};
use crate::app::player::motion_image::download;
use crate::app::state::AppState;
use crate::app::timeline::method_rows::SegmentRow;
use crate::protocol::MethodView;
use crate::segment::Level;
use leptos::prelude::*;
use std::sync::Arc;

/// The methods a library may segment with: those that need no model.
fn methods(state: AppState) -> Vec<(String, String)> {
    state
        .methods
        .iter()
        .filter(|s| s.supervised.is_none())
        .map(|s| (s.info.name.clone(), s.info.short.clone()))
        .collect()
}

/// `#tabpanel-library`'s content: the list, the queue's controls and the exports.
#[component]
pub fn LibraryPanel(state: AppState, jobs: LibraryJobs) -> impl IntoView {
    let library = state.library;
    let busy = move || library.queue.with(Queue::busy);
    let rerunnable =
        move || library.queue.with(|q| q.entries.iter().any(|e| matches!(e.status.word(), "failed" | "cancelled")));
    let segmented = move || library.queue.with(|q| !q.segmented().is_empty());
    let cancel = {
        let jobs = jobs.clone();
        move |_| jobs.cancel_library()
    };
    let rerun = {
        let jobs = jobs.clone();
        move |_| jobs.rerun_library()
    };
    let export_csv = move |_| {
        let labelled = library.all_labelled();
        let csv = library_csv(&labelled);
        let rows = csv.lines().count().saturating_sub(1);
        let file = "library_labels.csv";
        library.status.set(Some(match download(csv.as_bytes(), "text/csv", file) {
            Ok(()) => {
                (false, format!("saved {file} ({rows} rows of {})", crate::method::counted(labelled.len(), "take")))
            }
            Err(e) => (true, format!("could not save {file}: {}", crate::app::dom::js_message(&e))),
        }));
    };
    let options = methods(state)
        .into_iter()
        .map(|(name, short)| view! { <option value=name.clone() selected=move || library.method.get() == name>{short}</option> })
        .collect_view();
    let jobs = StoredValue::new_local(jobs);
    let takes = move || {
        let open = library.open.get();
        library.queue.with(|q| {
            q.entries
                .iter()
                .enumerate()
                .map(|(i, e)| {
                    let duration = e.duration_s.map(|d| format!("{d:.1} s")).unwrap_or_default();
                    let failed = matches!(e.status.word(), "failed");
                    view! {
                        <li
                            class="ms-lib-take"
                            class:ms-lib-take--open=open == Some(i)
                            data-status=e.status.word()
                            data-index=i.to_string()
                            aria-current=(open == Some(i)).then_some("true")
                        >
                            <button
                                class="ms-lib-open"
                                type="button"
                                title="Open this take"
                                on:click=move |_| jobs.with_value(|l| l.open_library_take(i))
                            >
                                {e.name.clone()}
                            </button>
                            <span class="ms-lib-duration">{duration}</span>
                            <span class="ms-lib-status" class:ms-lib-status--failed=failed role=failed.then_some("alert")>
                                {e.status.text()}
                            </span>
                            <span class="ms-lib-carried">
                                {move || library.carried.with(|c| c.as_ref().and_then(|c| c.take_text(i)))}
                            </span>
                        </li>
                    }
                })
                .collect_view()
        })
    };
    view! {
        <section class="ms-library" aria-label="Library of takes">
            <p id="library-summary" class="ms-lib-summary" aria-live="polite">{move || library.queue.with(Queue::summary)}</p>
            <div class="ms-lib-controls">
                <label>
                    "Segment with "
                    <select id="library-method" on:change=move |ev| library.method.set(event_target_value(&ev))>
                        {options}
                    </select>
                </label>
                <button id="library-cancel" class="ms-button ms-button--small" type="button" disabled=move || !busy() on:click=cancel>
                    "Cancel"
                </button>
                <button id="library-rerun" class="ms-button ms-button--small ms-button--quiet" type="button" disabled=move || busy() || !rerunnable() on:click=rerun>
                    "Run again"
                </button>
                <button id="library-export-csv" class="ms-button ms-button--small" type="button" disabled=move || !segmented() on:click=export_csv>
                    "Labels CSV (all takes)"
                </button>
            </div>
            <p
                id="library-status"
                class="ms-lib-note"
                class:ms-lib-note--failed=move || library.status.with(|s| s.as_ref().is_some_and(|(f, _)| *f))
                hidden=move || library.status.with(Option::is_none)
            >
                {move || library.status.with(|s| s.as_ref().map(|(_, m)| m.clone()))}
            </p>
            <ol id="library-list" class="ms-lib-list">{takes}</ol>
            <Carry state=state jobs=jobs/>
            <Clusters state=state jobs=jobs/>
        </section>
    }
}

/// "Carry labels": the source (the take on screen's my labels, else its ground truth), the route,
/// `#library-carry` (disabled with the reason as its title), where the carrying stands and "Copy
/// into my labels" for the take on screen.
#[component]
fn Carry(state: AppState, jobs: StoredValue<LibraryJobs, LocalStorage>) -> impl IntoView {
    let library = state.library;
    let source = Memo::new(move |_| source_labels(state).map(|(_, _, from)| from));
    let source_text = move || match source.get() {
        Ok(from) => {
            let name = state.motion.with(|m| m.as_ref().map(|m| m.summary.name.clone())).unwrap_or_default();
            format!("Source: {from} of {name}")
        }
        Err(why) => why,
    };
    let copyable = move || {
        let open = library.open_on_screen(state);
        library.carried.with(|c| c.as_ref().zip(open).is_some_and(|(c, i)| i != c.source && !c.spans(i).is_empty()))
    };
    let route_value = move || library.route.get().value();
    let set_route = move |ev: leptos::ev::Event| library.route.set(Route::from_value(&event_target_value(&ev)));
    view! {
        <section class="ms-lib-carry" aria-label="Carry labels">
            <h3 class="ms-lib-heading">"Carry labels"</h3>
            <p id="library-carry-source" class="ms-lib-note">{source_text}</p>
            <div class="ms-lib-controls">
                <label>
                    "Match by "
                    <select id="library-route" prop:value=route_value on:change=set_route>
                        <option value="nearest">"nearest labelled segment"</option>
                        <option value="clusters">"shared clusters"</option>
                        <option value="knn">"a k-NN trained on these labels"</option>
                        <option value="dtfcn">"a DT-FCN trained on these labels"</option>
                    </select>
                </label>
                <button
                    id="library-carry"
                    class="ms-button ms-button--small"
                    type="button"
                    disabled=move || source.with(Result::is_err) || library.carry_busy.get()
                    title=move || source.get().err()
                    on:click=move |_| jobs.with_value(|l| l.carry_labels())
                >
                    "Carry to every take"
                </button>
                <button
                    id="library-carry-cancel"
                    class="ms-button ms-button--small ms-button--quiet"
                    type="button"
                    hidden=move || !library.carry_busy.get()
                    on:click=move |_| jobs.with_value(|l| l.cancel_carry())
                >
                    "Cancel"
                </button>
                <button
                    id="library-copy-carried"
                    class="ms-button ms-button--small ms-button--quiet"
                    type="button"
                    disabled=move || !copyable()
                    title="Copy this take's carried labels into my labels (then edit them as usual)"
                    on:click=move |_| library.copy_asked.update(|n| *n += 1)
                >
                    "Copy carried labels into my labels"
                </button>
            </div>
            <p
                id="library-carrying"
                class="ms-lib-note"
                class:ms-lib-note--failed=move || library.carrying.with(|m| m.as_ref().is_some_and(|(f, _)| *f))
                hidden=move || library.carrying.with(Option::is_none)
                aria-live="polite"
            >
                {move || library.carrying.with(|m| m.as_ref().map(|(_, t)| t.clone()))}
            </p>
        </section>
    }
}

/// The most clusters the list shows (the others are exported with every cluster's clips).
const MAX_LISTED: usize = 200;

/// The colour of cluster `id` as the timeline draws its segments (primitives by cluster, actions
/// by their action colour), taken from its first occurrence.
fn colour(shared: &Shared, id: usize) -> String {
    let level = shared
        .clusters
        .clusters
        .iter()
        .find(|c| c.id == id)
        .and_then(|c| c.occurrences.first())
        .and_then(|o| shared.clusters.takes.get(o.take).and_then(|t| t.segments.get(o.segment)).map(|s| s.level));
    match level {
        Some(Level::Primitive) | None => crate::segment::palette::cluster_colour(id, None),
        Some(_) => {
            let [r, g, b] = crate::segment::palette::action_colour(id);
            format!("rgb({r}, {g}, {b})")
        }
    }
}

/// One cluster of the list (`name`, swatch `background`, the share of the library it covers): its name to edit, its
/// count, Play and Clips.
fn cluster_item(
    library: LibraryState,
    c: &crate::library::SharedCluster,
    name: String,
    background: String,
    coverage: f64,
    play: impl Fn(usize) + Copy + 'static,
    export: impl Fn(Option<usize>) + Copy + 'static,
) -> impl IntoView {
    let id = c.id;
    let count = format!(
        "{} in {} · {:.1} s · {:.0} % of the library",
        crate::method::counted(c.occurrences.len(), "occurrence"),
        crate::method::counted(c.takes, "take"),
        c.seconds,
        coverage * 100.0
    );
    view! {
        <li class="ms-lib-cluster" data-cluster=id.to_string() data-takes=c.takes.to_string()>
            <span class="ms-lib-swatch" style:background=background aria-hidden="true"></span>
            <input
                class="ms-lib-name"
                type="text"
                value=name.clone()
                aria-label=format!("Name of cluster C{id}")
                on:change=move |ev| library.rename(id, &event_target_value(&ev))
            />
            <span class="ms-lib-count">{count}</span>
            <button class="ms-button ms-button--small ms-lib-play" type="button" on:click=move |_| play(id)>
                "Play"
            </button>
            <button class="ms-button ms-button--small ms-button--quiet ms-lib-clips" type="button" on:click=move |_| export(Some(id))>
                "Clips"
            </button>
        </li>
    }
}

/// The shared clusters: where the matching stands, the list (name to rename, occurrences, total
/// duration, colour, Play, Clips), every cluster's clips, and the player of a cluster's occurrences.
#[component]
fn Clusters(state: AppState, jobs: StoredValue<LibraryJobs, LocalStorage>) -> impl IntoView {
    let library = state.library;
    let origin = RwSignal::new(false);
    let export = move |only: Option<usize>| {
        let Some(shared) = library.shared.get_untracked() else { return };
        let names = library.names.get_untracked();
        let takes = shared.clips(&names, only);
        let file = match only {
            Some(id) => format!("library_{}_clips.zip", crate::app::library::takes::folder_name(&names.name(id))),
            None => "library_clusters_clips.zip".to_string(),
        };
        jobs.with_value(|l| l.export_library_clips(file, takes, origin.get_untracked()));
    };
    let play = move |id: usize| {
        let playlist = library.shared.with_untracked(|s| s.as_ref().and_then(|s| s.playlist(id)));
        if let Some(p) = playlist {
            let spot = p.current();
            library.playlist.set(Some(p));
            jobs.with_value(|l| play_spot(state, l, spot));
        }
    };
    let step = move |forward: bool| {
        let mut spot = None;
        library.playlist.update(|p| {
            if let Some(p) = p {
                spot = Some(if forward { p.next() } else { p.previous() });
            }
        });
        if let Some(spot) = spot {
            jobs.with_value(|l| play_spot(state, l, spot));
        }
    };
    let stop = move |_| {
        library.playlist.set(None);
        state.occurrence.set(None);
        library.playing.set_value(false);
        library.pending.set_value(None);
        state.playing.set(false);
        state.play_until.set(None);
    };
    // a take opened for an occurrence: play it once the take is on screen
    Effect::new(move |_| {
        let shown = motion_address(state);
        let Some((spot, asked_on)) = library.pending.get_value() else { return };
        if shown != asked_on && library.on_screen(state, spot.take) {
            library.pending.set_value(None);
            // after the timeline's own reaction to the new take (it forgets where playback stops)
            gloo::timers::callback::Timeout::new(0, move || start(state, spot)).forget();
        }
    });
    // an occurrence played to its end: the next one, until the last
    Effect::new(move |_| {
        if state.playing.get() || !library.playing.get_value() {
            return;
        }
        library.playing.set_value(false);
        let Some(p) = library.playlist.get_untracked() else { return };
        let (at, count) = p.position();
        if state.frame.get_untracked() == p.current().end && at < count {
            step(true);
        }
    });
    let playing = move || {
        let p = library.playlist.get()?;
        let names = library.names.get();
        let take = library.queue.with(|q| q.entries.get(p.current().take).map(|e| e.name.clone()))?;
        Some(playing_text(&p, &names.name(p.cluster), &take))
    };
    suggest_names(library);
    let rows = cluster_list(library, play, export);
    view! {
        <section class="ms-lib-clusters" aria-label="Clusters across takes" hidden=move || library.matching.with(Option::is_none)>
            <h3 class="ms-lib-heading">"Clusters across takes"</h3>
            <p
                id="library-matching"
                class="ms-lib-note"
                class:ms-lib-note--failed=move || library.matching.with(|m| m.as_ref().is_some_and(|(f, _)| *f))
                aria-live="polite"
            >
                {move || library.matching.with(|m| m.as_ref().map(|(_, t)| t.clone()))}
            </p>
            <div class="ms-lib-controls" hidden=move || library.shared.with(Option::is_none)>
                <button id="library-export-clips" class="ms-button ms-button--small" type="button" on:click=move |_| export(None)>
                    "Clips of every cluster (zip)"
                </button>
                <label>
                    <input id="library-origin" type="checkbox" prop:checked=move || origin.get() on:change=move |ev| origin.set(event_target_checked(&ev))/>
                    " start each clip at the origin"
                </label>
            </div>
            <div id="library-player" class="ms-lib-controls" hidden=move || library.playlist.with(Option::is_none)>
                <button id="library-previous" class="ms-button ms-button--small" type="button" on:click=move |_| step(false)>"Previous"</button>
                <button id="library-next" class="ms-button ms-button--small" type="button" on:click=move |_| step(true)>"Next"</button>
                <button id="library-stop" class="ms-button ms-button--small ms-button--quiet" type="button" on:click=stop>"Stop"</button>
                <span
                    id="library-playing"
                    class="ms-lib-note"
                    aria-live="polite"
                    data-take=move || library.playlist.with(|p| p.as_ref().map(|p| p.current().take.to_string()))
                    data-start=move || library.playlist.with(|p| p.as_ref().map(|p| p.current().start.to_string()))
                >
                    {playing}
                </span>
            </div>
            {rows}
        </section>
    }
}

/// Names the clusters from the labels carried across the library, for those the user has not named (again whenever
/// the clusters or the carried labels change).
fn suggest_names(library: LibraryState) {
    Effect::new(move |_| {
        let Some(shared) = library.shared.get() else { return };
        let named = library.carried.with(|carried| {
            shared.label_names(|i| {
                let row = carried.as_ref()?.row(i)?;
                let spans: Vec<(usize, usize, String)> = row
                    .segments
                    .into_iter()
                    .filter(|s| crate::app::my_labels::vocabulary::is_labelled(&s.label))
                    .map(|s| (s.start, s.end, s.label))
                    .collect();
                (!spans.is_empty()).then_some(spans)
            })
        });
        library.names.update(|n| n.suggest(named));
    });
}

/// The cluster list: filtered by default ([`crate::app::library::takes::LIST_MIN_TAKES`], `LIST_MIN_SECONDS`;
/// `#library-all-clusters` shows every one), most of the library first, each with its name, colour, count, coverage,
/// Play and Clips.
fn cluster_list(
    library: LibraryState,
    play: impl Fn(usize) + Copy + 'static,
    export: impl Fn(Option<usize>) + Copy + 'static,
) -> impl Fn() -> Option<AnyView> {
    let every = RwSignal::new(false);
    move || {
        let shared = library.shared.get()?;
        let names = library.names.get();
        let all = shared.clusters.clusters.len();
        let listed = shared.listed(every.get());
        let shown = listed.len();
        let more = listed.len().saturating_sub(MAX_LISTED);
        let items = listed
            .into_iter()
            .take(MAX_LISTED)
            .map(|c| {
                let coverage = shared.coverage(c);
                cluster_item(library, c, names.name(c.id), colour(&shared, c.id), coverage, play, export)
            })
            .collect_view();
        let note = (more > 0)
            .then(|| view! { <p class="ms-lib-note">{format!("and {more} more (in every cluster's clips)")}</p> });
        let filter = format!(
            "{shown} of {all} clusters shown{}",
            if every.get() {
                String::new()
            } else {
                format!(
                    ": in {} takes or more, {:.1} s or longer on average",
                    crate::app::library::takes::LIST_MIN_TAKES,
                    crate::app::library::takes::LIST_MIN_SECONDS
                )
            }
        );
        Some(
            view! {
                <p class="ms-lib-controls">
                    <span id="library-cluster-filter" class="ms-lib-note">{filter}</span>
                    <label>
                        <input id="library-all-clusters" type="checkbox" prop:checked=move || every.get()
                            on:change=move |ev| every.set(event_target_checked(&ev))/>
                        " show every cluster"
                    </label>
                </p>
                <ol id="library-clusters" class="ms-lib-list">{items}</ol>
                {note}
            }
            .into_any(),
        )
    }
}

/// Plays occurrence `spot`: at once when its take is on screen, else after opening it (its file
/// read again).
fn play_spot(state: AppState, jobs: &LibraryJobs, spot: Spot) {
    let library = state.library;
    let on_screen = untrack(|| library.on_screen(state, spot.take));
    if on_screen {
        library.pending.set_value(None);
        start(state, spot);
    } else {
        library.pending.set_value(Some((spot, untrack(|| motion_address(state)))));
        jobs.open_library_take(spot.take);
    }
}

/// The address of the take on screen (0: none), to tell a take opened since from the one before.
fn motion_address(state: AppState) -> usize {
    state.motion.with(|m| m.as_ref().map_or(0, |m| Arc::as_ptr(m) as usize))
}

/// Plays `spot` of the take on screen once, from its first frame to its last.
fn start(state: AppState, spot: Spot) {
    state.playing.set(false);
    state.selected.set(None);
    // highlighted on the library's row while it plays
    state.occurrence.set(Some(crate::app::state::Selection {
        row: "library".into(),
        start: spot.start,
        end: spot.end,
    }));
    state.frame.set(spot.start);
    state.play_until.set(Some(spot.end));
    state.library.playing.set_value(true);
    state.playing.set(true);
}

/// The timeline's `#row-library`: the library's segmentation of the take on screen, when it is one
/// of the library's, its segments labelled by their clusters' names.
#[component]
pub fn LibraryRow(state: AppState) -> impl IntoView {
    let library = state.library;
    let source = Signal::derive(move || {
        let i = library.open.get()?;
        // the take on screen must be that take (a load still under way shows nothing)
        if !library.on_screen(state, i) {
            return None;
        }
        let (mut segmentation, _) = library.labelled(i)?;
        let frames = state.frames();
        // one lane: the finest tiling (primitives and transitions where there are primitives)
        let primitives = segmentation.segments.iter().any(|s| s.level == Level::Primitive);
        segmentation.segments.retain(|s| (s.level == Level::Primitive) == primitives || s.level == Level::Transition);
        (frames == segmentation.frames).then(|| {
            Arc::new(MethodView { method: segmentation.method.clone(), segmentation, details: Default::default() })
        })
    });
    let label = Signal::derive(|| "Library".to_string());
    let tip = Signal::derive(|| "The library's segmentation of this take, its clusters named".to_string());
    view! { <SegmentRow state=state row_id="library".to_string() source=source levels=LEVELS label=label tip=tip/> }
}

/// The labels carried to the take on screen as a labelling row's view (tracked; `None` when it is
/// not one of the library's, got no labels or is their source).
pub(crate) fn transferred_view(state: AppState) -> Option<Arc<MethodView>> {
    let library = state.library;
    let i = library.open_on_screen(state)?;
    let segmentation = library.carried.with(|c| c.as_ref().filter(|c| c.source != i).and_then(|c| c.row(i)))?;
    (segmentation.frames == state.frames()).then(|| {
        Arc::new(MethodView { method: segmentation.method.clone(), segmentation, details: Default::default() })
    })
}

/// The timeline's `#row-transferred` ("Carried labels"): the labels carried to the take on screen,
/// each label in my labels' colour for it, shaded by its confidence, `unknown` grey.
#[component]
pub fn TransferredRow(state: AppState) -> impl IntoView {
    let source = Signal::derive(move || transferred_view(state));
    let label = Signal::derive(|| "Carried labels".to_string());
    let tip = Signal::derive(move || {
        let from = state.library.carried.with(|c| c.as_ref().map(|c| c.source));
        let name = from.and_then(|i| state.library.queue.with(|q| q.entries.get(i).map(|e| e.name.clone())));
        format!("Labels carried from {} (shade: confidence; grey: unknown)", name.unwrap_or_default())
    });
    view! { <SegmentRow state=state row_id="transferred".to_string() source=source levels=&[Level::Action] label=label tip=tip/> }
}

/// The levels the library's row shows (one of actions and primitives is left: the source keeps
/// the finest).
const LEVELS: &[Level] = &[Level::Action, Level::Primitive, Level::Transition];
