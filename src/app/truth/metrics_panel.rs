//! `#metrics-panel`: any timeline row scored against the imported ground truth, with the core's
//! [`evaluate`] — the function `mocapseg eval` prints — so the page and the command line give the
//! same numbers for the same segmentation and truth.
//!
//! `#metrics-row` picks the row: `<method>-actions` scores the method's whole segmentation (what
//! its `#<method>-export` saves: actions with transitions split between them, strict/tolerant
//! accuracy on its primitives), `<method>-primitives` its primitives alone. `#metrics-table` has
//! one line per score (`data-metric`), its value rounded as shown and in full in `data-value`,
//! and a hint of what it means. The scores run on the page thread: they are linear in the frames
//! and the segments, except the Hungarian matching (cubic in the number of clusters, a few
//! dozen), cheaper than a round trip to the worker, which may be busy with a method's run.
//! `document.body.dataset.metrics` is `none` (no truth or no row), `done` or `error`, and
//! `data-metrics-row` names the row scored, `data-metrics-ms` how long the scores took.
//!
//! `#metrics-compare` scores every row of the menu at once with the same [`evaluate`]: one line
//! per row (`data-row`), one cell per metric of the single-row table (`data-metric`, the full value
//! in `data-value`), the best per column in bold with a hidden "(best)" for screen readers
//! (`data-best`, chosen by [`crate::app::truth::compare`]: every metric is better higher; there is no
//! chance row to leave out, neither the panel nor `mocapseg eval` computes one). A column heading's
//! button sorts the lines on it, best first, then worst first (`aria-sort`). It is recomputed when
//! a row is re-run or the truth changes; `data-compare` is `none` or `done`, `data-compare-rows` the
//! number of lines, `data-compare-ms` how long all the scores took.

use crate::app::dom::now_ms;
use crate::app::dom::set_body_data;
use crate::app::state::AppState;
use crate::app::take::summary::{is_bundled_sample, SAMPLE_TRAINED};
use crate::app::truth::compare::{best_in_column, sorted_order, Better};
use crate::app::truth::ranked::ranked_tables;
use crate::app::truth::ranking::{copy_of_the_truth, Compared, Line, Table};
use crate::method::supervised::IN_SAMPLE;
use crate::segment::metrics::{evaluate, Scores};
use crate::segment::{Level, Segmentation};
use leptos::prelude::*;

/// The scores of a row as lines; `labels`: the row labels frames by name (a labeller, my labels), so that its frame
/// accuracy by name means something — a row of clusters or gestures has only the Hungarian one (issue 48: "Frame
/// accuracy (labels)" is not shown for SSSM).
fn lines(s: &Scores, labels: bool) -> Vec<Line> {
    let mut out = Vec::new();
    for (key, b) in ["boundary_f1_0.5s", "boundary_f1_1s"].iter().zip(&s.boundaries) {
        out.push(Line {
            key,
            name: if b.tolerance_s == 0.5 { "Boundary F1 @ 0.5 s" } else { "Boundary F1 @ 1 s" },
            value: b.f1,
            digits: 3,
            hint: format!(
                "cuts within {} s of a true cut, matched one to one: precision {:.3}, recall {:.3} ({} of {} found, {} true)",
                b.tolerance_s, b.precision, b.recall, b.matched, s.predicted_boundaries, s.true_boundaries
            ),
        });
    }
    let l = &s.labelling;
    let seg = &s.segments;
    out.extend([
        Line {
            key: "covering",
            name: "Covering",
            value: s.covering,
            digits: 3,
            hint: "how well each true segment is covered by its best-overlapping found one (1 = the same segments)"
                .into(),
        },
        Line {
            key: "hungarian_accuracy",
            name: "Hungarian frame accuracy",
            value: s.hungarian_accuracy,
            digits: 3,
            hint: "share of frames right once each found cluster is matched to one true label".into(),
        },
        Line {
            key: "strict_accuracy",
            name: "Strict accuracy",
            value: s.strict_accuracy,
            digits: 3,
            hint: "share of frames whose primitive's cluster maps to their true label (many clusters may map to one)"
                .into(),
        },
        Line {
            key: "tolerant_accuracy",
            name: "Tolerant accuracy",
            value: s.tolerant_accuracy,
            digits: 3,
            hint: "strict accuracy that also accepts frames in the uncertainty window around a true cut".into(),
        },
    ]);
    if labels {
        out.push(Line {
            key: "frame_accuracy",
            name: "Frame accuracy (labels)",
            value: l.frame_accuracy,
            digits: 3,
            hint: "share of frames with the true label (labels by name, else by the Hungarian matching)".into(),
        });
    }
    out.extend([
        Line {
            key: "edit",
            name: "Edit score",
            value: l.edit,
            digits: 2,
            hint: "0–100: how close the order of labelled segments is to the truth's (100 = same sequence)".into(),
        },
        Line {
            key: "f1_10",
            name: "F1@10",
            value: l.f1[0],
            digits: 2,
            hint: "0–100: segments with the right label overlapping a true one by at least 10 % (IoU)".into(),
        },
        Line {
            key: "f1_25",
            name: "F1@25",
            value: l.f1[1],
            digits: 2,
            hint: "0–100: the same at 25 % overlap".into(),
        },
        Line {
            key: "f1_50",
            name: "F1@50",
            value: l.f1[2],
            digits: 2,
            hint: "0–100: the same at 50 % overlap".into(),
        },
        Line {
            key: "segment_score",
            name: "Segment score (Bouchard–Badler)",
            value: seg.similarity,
            digits: 1,
            hint: format!(
                "matched − (unmatched found + unmatched true) / 2, both ends within {} s: {} matched, {} found and {} true unmatched",
                seg.tolerance_s, seg.matched, seg.unmatched_found, seg.unmatched_true
            ),
        },
    ]);
    out
}

/// Why a method's row on this take is in-sample, if it is: its run said so (the take is one of its model's
/// training takes), or the take is the bundled sample and the row is by a model it trained.
fn in_sample(view: &crate::protocol::MethodView, sample: bool) -> Option<String> {
    let summary = &view.details.summary;
    if let Some(at) = summary.find(IN_SAMPLE) {
        return Some(summary[at..].to_string());
    }
    let model = view.segmentation.params.get("model").and_then(|m| m.as_str());
    (sample && model == Some(SAMPLE_TRAINED)).then(|| {
        format!(
            "{IN_SAMPLE} the bundled sample (CMU 13_30) is one of the takes model `{SAMPLE_TRAINED}` was trained on, \
             so these scores are not what it does on a take it has not seen (held-out scores: docs/accuracy.md)"
        )
    })
}

/// A row that can be scored: id, label, the segmentation scored, why it is in-sample (if it is), and the ranked table
/// it belongs to.
type Row = (String, String, Segmentation, Option<String>, Table);

/// The rows that can be scored.
fn scorable_rows(state: AppState) -> Vec<Row> {
    let mut rows = Vec::new();
    if let Some(mine) = state.mine.get() {
        rows.push(("my-labels".to_string(), "My labels".to_string(), (*mine).clone(), None, Table::Labels));
    }
    let sample =
        state.motion.with(|m| m.as_ref().is_some_and(|m| is_bundled_sample(&m.summary.name, m.summary.frames)));
    for slot in state.methods {
        slot.view.with(|v| {
            let Some(v) = v else { return };
            let seg = &v.segmentation;
            let note = in_sample(v, sample);
            // the rows' names as the timeline gives them (view::rows)
            let name = |primitive| {
                crate::app::timeline::rows::row_name(
                    &slot.info.short,
                    crate::app::timeline::rows::row_kind(Some(&**v), primitive),
                )
            };
            let table = if crate::app::timeline::rows::is_labelling(v) { Table::Labels } else { Table::Actions };
            if seg.segments.iter().any(|s| s.level != Level::Primitive) {
                rows.push((format!("{}-actions", slot.info.name), name(false), seg.clone(), note.clone(), table));
            }
            if seg.segments.iter().any(|s| s.level == Level::Primitive) {
                let mut primitives = seg.clone();
                primitives.segments.retain(|s| s.level == Level::Primitive);
                rows.push((
                    format!("{}-primitives", slot.info.name),
                    name(true),
                    primitives,
                    note.clone(),
                    Table::Actions,
                ));
            }
        });
    }
    rows
}

/// The scores of row `id` as the metrics table (`labels`: see [`lines`]).
fn scores_table(id: &str, scores: &Scores, labels: bool) -> impl IntoView {
    let caption = format!("{} against {} — scored as {}", id, scores.trial, scores.scored_as.describe());
    let body = lines(scores, labels)
        .into_iter()
        .map(|l| {
            let shown = format!("{:.*}", l.digits, l.value);
            view! {
                <tr data-metric=l.key>
                    <th scope="row">{l.name}</th>
                    <td class="ms-metric-value" data-value=l.value.to_string() data-digits=l.digits.to_string()>{shown}</td>
                    <td class="ms-metric-hint">{l.hint}</td>
                </tr>
            }
        })
        .collect_view();
    view! {
        <table id="metrics-table" class="ms-metrics-table">
            <caption>{caption}</caption>
            <thead>
                <tr>
                    <th scope="col">"Metric"</th>
                    <th scope="col">"Value"</th>
                    <th scope="col">"What it means"</th>
                </tr>
            </thead>
            <tbody>{body}</tbody>
        </table>
    }
}

/// Row `id` (`label`, segmentation `seg`, of ranked table `table`) scored against `truth` for the comparison.
fn compared_row(
    id: &str,
    label: &str,
    seg: &Segmentation,
    truth: &crate::segment::truth::Truth,
    table: Table,
) -> Compared {
    let scored = evaluate(seg, truth, &crate::methods::scoring(&seg.method));
    // my labels that are the truth itself would top every table: they are shown, not ranked
    let unranked = match &scored {
        Ok(s) if id == "my-labels" && copy_of_the_truth(s.labelling.frame_accuracy, s.boundaries[0].f1) => {
            Some("the same as the ground truth (copied from it): not ranked".to_string())
        }
        _ => None,
    };
    Compared {
        id: id.to_string(),
        label: label.to_string(),
        scored: scored.map(|s| lines(&s, table == Table::Labels)).map_err(|e| format!("{id}: {e}")),
        table,
        unranked,
    }
}

/// Every row scored against the truth (`None`: no truth), its trial and how long the scores took (ms).
type AllScored = Option<(Vec<Compared>, String, f64)>;

/// The ranked tables and, one click away, the table of every metric of every row (nothing without a truth or rows).
fn comparison_view(
    compared: Memo<AllScored>,
    sort: RwSignal<Option<(String, bool)>>,
) -> impl Fn() -> Option<AnyView> + Copy {
    let every_metric = RwSignal::new(false);
    move || {
        compared.with(|c| match c {
            Some((lines, trial, _)) if !lines.is_empty() => Some(
                view! {
                    {ranked_tables(lines.clone())}
                    <details id="metrics-compare-all" class="ms-compare-all" prop:open=move || every_metric.get()
                        on:toggle=move |ev| every_metric.set(details_open(&ev))>
                        <summary>"Every metric of every row"</summary>
                        {compare_table(lines, trial, sort)}
                    </details>
                }
                .into_any(),
            ),
            _ => None,
        })
    }
}

/// Whether the `<details>` a toggle event is from is open.
fn details_open(ev: &leptos::ev::Event) -> bool {
    ev.target().and_then(|t| js_sys::Reflect::get(&t, &"open".into()).ok()).and_then(|v| v.as_bool()).unwrap_or(false)
}

/// What the panel shows.
#[derive(Clone, PartialEq)]
enum Outcome {
    /// Why there is nothing to score.
    Nothing(String),
    /// The row, its scores and how long they took (ms).
    Scored(String, std::sync::Arc<Scores>, f64),
    Failed(String),
}

/// Every metric of the single-row table is better higher (scores, accuracies, F1s, the segment
/// score's matched-minus-unmatched count).
const BETTER: Better = Better::Higher;

/// The comparison table: every row scored, the best per column marked, sorted on `sort` (a metric's
/// key and whether best comes first) when set.
fn compare_table(compared: &[Compared], trial: &str, sort: RwSignal<Option<(String, bool)>>) -> impl IntoView {
    // the columns: the metrics of the first row scored (every row scored has the same ones)
    // the columns: every metric of any row scored, in the order of the row that has the most (a row of clusters has
    // no frame accuracy by name: its cell says so)
    let columns: Vec<(&'static str, &'static str, usize, String)> = compared
        .iter()
        .filter_map(|c| c.scored.as_ref().ok())
        .max_by_key(|ls| ls.len())
        .map(|ls| ls.iter().map(|l| (l.key, l.name, l.digits, l.hint.clone())).collect())
        .unwrap_or_default();
    let value = |c: &Compared, key: &str| {
        c.scored.as_ref().ok().and_then(|ls| ls.iter().find(|l| l.key == key)).map(|l| l.value)
    };
    let best: Vec<Vec<bool>> = columns
        .iter()
        .map(|(key, _, digits, _)| {
            // a row left out of the ranks (my labels copied from the truth) is never marked best
            let values: Vec<Option<f64>> =
                compared.iter().map(|c| if c.unranked.is_some() { None } else { value(c, key) }).collect();
            best_in_column(&values, *digits, BETTER)
        })
        .collect();
    let current = sort.get();
    let order: Vec<usize> = match &current {
        Some((key, best_first)) => {
            let values: Vec<Option<f64>> = compared.iter().map(|c| value(c, key)).collect();
            sorted_order(&values, BETTER, *best_first)
        }
        None => (0..compared.len()).collect(),
    };
    let head = columns
        .iter()
        .map(|(key, name, _, _)| {
            let (key, name) = (*key, *name);
            let aria = match &current {
                Some((k, best_first)) if k == key => {
                    if *best_first == (BETTER == Better::Higher) { "descending" } else { "ascending" }
                }
                _ => "none",
            };
            let on_click = move |_| {
                sort.update(|s| {
                    *s = match s.take() {
                        Some((k, best_first)) if k == key => Some((k, !best_first)),
                        _ => Some((key.to_string(), true)),
                    }
                })
            };
            view! {
                <th scope="col" data-metric=key aria-sort=aria>
                    <button type="button" class="ms-sort" title="Sort the rows on this metric (again: reverse)" on:click=on_click>
                        {name}
                    </button>
                </th>
            }
        })
        .collect_view();
    let width = columns.len().max(1);
    let body = order
        .into_iter()
        .map(|i| {
            let c = &compared[i];
            let cells = match &c.scored {
                Ok(ls) => columns
                    .iter()
                    .enumerate()
                    .map(|(j, (key, _, digits, hint))| {
                        let value = ls.iter().find(|l| l.key == *key).map(|l| l.value);
                        compare_cell(key, value, *digits, best[j][i], hint)
                    })
                    .collect_view()
                    .into_any(),
                Err(e) => view! { <td class="ms-truth-error" colspan=width.to_string()>{e.clone()}</td> }.into_any(),
            };
            view! {
                <tr data-row=c.id.clone()>
                    <th scope="row">{c.label.clone()}</th>
                    {cells}
                </tr>
            }
        })
        .collect_view();
    view! {
        <div class="ms-compare-scroll">
            <table id="metrics-compare" class="ms-metrics-table ms-compare">
                <caption>
                    {format!("Every row against {trial} — the best per column in bold; a heading sorts the rows on it")}
                </caption>
                <thead>
                    <tr>
                        <th scope="col">"Row"</th>
                        {head}
                    </tr>
                </thead>
                <tbody>{body}</tbody>
            </table>
        </div>
    }
}

/// A cell of the comparison table: metric `key`'s `value` shown to `digits` (bold and said "(best)" when `best`), or,
/// for a row it does not apply to (`None`), a dash that says why.
fn compare_cell(key: &'static str, value: Option<f64>, digits: usize, best: bool, hint: &str) -> AnyView {
    let Some(v) = value else {
        let why = "not scored: this row's segments are clusters or gestures, not named labels (its Hungarian frame \
                   accuracy matches them to the truth's)";
        return view! {
            <td class="ms-metric-value ms-metric-none" data-metric=key title=why>
                "—"<span class="ms-visually-hidden">" (not scored)"</span>
            </td>
        }
        .into_any();
    };
    let shown = format!("{v:.digits$}");
    let content = if best {
        view! { <strong>{shown}</strong><span class="ms-visually-hidden">" (best)"</span> }.into_any()
    } else {
        shown.into_any()
    };
    view! {
        <td class="ms-metric-value" class:ms-best=best data-metric=key data-value=v.to_string()
            data-digits=digits.to_string() data-best=best.then_some("true") title=hint.to_string()>
            {content}
        </td>
    }
    .into_any()
}

#[component]
pub fn MetricsPanel(state: AppState) -> impl IntoView {
    let chosen = RwSignal::new(String::new());
    let rows = Memo::new(move |_| {
        scorable_rows(state)
            .into_iter()
            .map(|(id, label, seg, note, table)| (id, label, std::sync::Arc::new(seg), note, table))
            .collect::<Vec<_>>()
    });
    // the row scored: the one chosen while it exists, else the first
    let row_id = Memo::new(move |_| {
        let wanted = chosen.get();
        rows.with(|r| {
            r.iter().find(|(id, ..)| *id == wanted).or(r.first()).map(|(id, ..)| id.clone()).unwrap_or_default()
        })
    });
    let outcome = Memo::new(move |_| {
        let Some(imported) = state.truth.truth() else {
            return Outcome::Nothing("Import a ground truth above to score the rows against it.".into());
        };
        let id = row_id.get();
        let Some(seg) = rows.with(|r| r.iter().find(|(i, ..)| *i == id).map(|(_, _, s, ..)| s.clone())) else {
            return Outcome::Nothing("Run a method to score its rows against the ground truth.".into());
        };
        let started = now_ms();
        match evaluate(&seg, &imported.truth, &crate::methods::scoring(&seg.method)) {
            Ok(scores) => Outcome::Scored(id, std::sync::Arc::new(scores), now_ms() - started),
            Err(e) => Outcome::Failed(format!("{id}: {e}")),
        }
    });
    // every row scored at once, for the comparison table (None: no truth)
    let compared = Memo::new(move |_| {
        let imported = state.truth.truth()?;
        let started = now_ms();
        let lines_of: Vec<Compared> = rows.with(|r| {
            r.iter().map(|(id, label, seg, _, table)| compared_row(id, label, seg, &imported.truth, *table)).collect()
        });
        Some((lines_of, imported.truth.trial.clone(), now_ms() - started))
    });
    let sort = RwSignal::new(None::<(String, bool)>);
    Effect::new(move |_| {
        let (value, count, ms) = compared.with(|c| match c {
            Some((lines, _, ms)) => ("done", lines.len().to_string(), format!("{ms:.1}")),
            None => ("none", String::new(), String::new()),
        });
        set_body_data(&[("data-compare", value), ("data-compare-rows", &count), ("data-compare-ms", &ms)]);
    });
    let comparison = comparison_view(compared, sort);
    Effect::new(move |_| {
        let (value, row, ms) = outcome.with(|o| match o {
            Outcome::Nothing(_) => ("none", String::new(), String::new()),
            Outcome::Scored(id, _, ms) => ("done", id.clone(), format!("{ms:.1}")),
            Outcome::Failed(_) => ("error", String::new(), String::new()),
        });
        set_body_data(&[("data-metrics", value), ("data-metrics-row", &row), ("data-metrics-ms", &ms)]);
    });

    let options = move || {
        let current = row_id.get();
        rows.with(|r| {
            r.iter()
                .map(|(id, label, ..)| {
                    let selected = *id == current;
                    view! { <option value=id.clone() prop:selected=selected>{label.clone()}</option> }
                })
                .collect_view()
        })
    };
    let message = move || {
        outcome.with(|o| match o {
            Outcome::Nothing(m) | Outcome::Failed(m) => m.clone(),
            Outcome::Scored(..) => String::new(),
        })
    };
    let is_error = move || outcome.with(|o| matches!(o, Outcome::Failed(_)));
    // the scored row's in-sample warning, beside its scores
    let note = move || {
        let id = row_id.get();
        let scored = outcome.with(|o| matches!(o, Outcome::Scored(..)));
        rows.with(|r| r.iter().find(|(i, ..)| *i == id).and_then(|(_, _, _, n, _)| n.clone())).filter(|_| scored)
    };
    let table = move || {
        outcome.with(|o| match o {
            Outcome::Scored(id, scores, _) => {
                let labels = rows.with(|r| r.iter().any(|(i, .., t)| i == id && *t == Table::Labels));
                Some(scores_table(id, scores, labels))
            }
            _ => None,
        })
    };

    view! {
        <section id="metrics-panel" class="ms-panel-box ms-metrics" aria-label="Metrics against the ground truth">
            <div class="ms-timeline-head">
                <h2>"Metrics"</h2>
                <span class="ms-timeline-legend">"a row scored against the ground truth — the numbers " <code>"mocapseg eval"</code> " prints"</span>
            </div>
            <div class="ms-method-params">
                <label>
                    "Row to score "
                    <select
                        id="metrics-row"
                        disabled=move || rows.with(Vec::is_empty)
                        on:change=move |ev| chosen.set(event_target_value(&ev))
                    >
                        {options}
                    </select>
                </label>
            </div>
            <p id="metrics-status" class="ms-metrics-status" class:ms-truth-error=is_error role="status" hidden=move || message().is_empty()>
                {message}
            </p>
            <p id="metrics-in-sample" class="ms-metrics-status ms-in-sample" hidden=move || note().is_none()>
                {move || note().unwrap_or_default()}
            </p>
            {table}
            {comparison}
        </section>
    }
}
