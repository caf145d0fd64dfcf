//! The ranked tables of the metrics panel ([`crate::app::truth::ranking`]): one per kind of row — finding actions,
//! labelling frames — each ranking its rows on one headline metric (`#ranking-<table>-metric` chooses it), best first,
//! with the rank; a row not ranked (my labels copied from the truth, a row that could not be scored) is listed
//! under the table with why. Every metric of every row stays one click away (`#metrics-compare-all`).

use crate::app::truth::ranking::{ranks, Compared, Table};
use leptos::prelude::*;

/// The id of `table` in the page (`ranking-actions`, `ranking-labels`).
fn table_id(table: Table) -> &'static str {
    match table {
        Table::Actions => "ranking-actions",
        Table::Labels => "ranking-labels",
    }
}

/// One ranked table over the rows of `table` among `compared`.
fn ranked(table: Table, compared: &[Compared], metric: RwSignal<String>) -> Option<impl IntoView> {
    let rows: Vec<&Compared> = compared.iter().filter(|c| c.table == table).collect();
    if rows.is_empty() {
        return None;
    }
    let key = metric.get();
    let line = |c: &Compared| c.scored.as_ref().ok().and_then(|ls| ls.iter().find(|l| l.key == key)).cloned();
    let first = rows.iter().find_map(|c| line(c));
    let (name, digits, hint) = first.as_ref().map_or(("", 3, String::new()), |l| (l.name, l.digits, l.hint.clone()));
    let values: Vec<Option<f64>> =
        rows.iter().map(|c| if c.unranked.is_some() { None } else { line(c).map(|l| l.value) }).collect();
    let ranked_of = ranks(&values, digits);
    let mut order: Vec<usize> = (0..rows.len()).filter(|&i| ranked_of[i].is_some()).collect();
    order.sort_by_key(|&i| ranked_of[i]);
    let body = order
        .iter()
        .map(|&i| {
            let (c, rank) = (rows[i], ranked_of[i].unwrap_or_default());
            let v = values[i].unwrap_or(f64::NAN);
            view! {
                <tr data-row=c.id.clone() data-rank=rank.to_string()>
                    <td class="ms-rank">{rank.to_string()}</td>
                    <th scope="row">{c.label.clone()}</th>
                    <td class="ms-metric-value" data-metric=key.clone() data-value=v.to_string()>{format!("{v:.digits$}")}</td>
                </tr>
            }
        })
        .collect_view();
    let left_out: Vec<String> = rows
        .iter()
        .enumerate()
        .filter(|(i, _)| ranked_of[*i].is_none())
        .map(|(_, c)| match (&c.unranked, &c.scored) {
            (Some(why), _) => format!("{}: {why}", c.label),
            (None, Err(e)) => format!("{}: not scored ({e})", c.label),
            (None, Ok(_)) => format!("{}: no {name}", c.label),
        })
        .collect();
    let options = table
        .metrics()
        .iter()
        .map(|&m| {
            let title = compared
                .iter()
                .find_map(|c| c.scored.as_ref().ok().and_then(|ls| ls.iter().find(|l| l.key == m)).map(|l| l.name))
                .unwrap_or(m);
            view! { <option value=m prop:selected=m == key>{title}</option> }
        })
        .collect_view();
    let id = table_id(table);
    Some(view! {
        <section class="ms-ranking" id=id aria-label=table.heading()>
            <h3 class="ms-ranking-heading">{table.heading()}</h3>
            <label class="ms-ranking-metric">
                "ranked by "
                <select id=format!("{id}-metric") on:change=move |ev| metric.set(event_target_value(&ev))>{options}</select>
            </label>
            <p class="ms-ranking-hint">{hint}</p>
            <table class="ms-metrics-table ms-ranking-table">
                <thead><tr><th scope="col">"Rank"</th><th scope="col">"Row"</th><th scope="col">{name}</th></tr></thead>
                <tbody>{body}</tbody>
            </table>
            {(!left_out.is_empty()).then(|| view! {
                <p class="ms-ranking-note" id=format!("{id}-unranked")>{format!("Not ranked — {}", left_out.join("; "))}</p>
            })}
        </section>
    })
}

/// The two ranked tables over `compared` (every row scored against the truth).
pub(super) fn ranked_tables(compared: Vec<Compared>) -> impl IntoView {
    let actions = RwSignal::new(Table::Actions.default_metric().to_string());
    let labels = RwSignal::new(Table::Labels.default_metric().to_string());
    let compared = StoredValue::new(compared);
    view! {
        <div id="metrics-ranking" class="ms-ranking-tables">
            {move || compared.with_value(|c| ranked(Table::Actions, c, actions))}
            {move || compared.with_value(|c| ranked(Table::Labels, c, labels))}
        </div>
    }
}
