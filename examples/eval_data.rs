//! Lab tool, not part of the product: segments the labelled takes of the shared data folder
//! (CMU 86_01 with Barbič/Zhou labels, the four mocap6 takes with Fox/Hughes labels, then the
//! mocap6 takes joined into one 2-minute take) with any registered method and prints the scores
//! as one table with their mean. Says so and fails when the folder is absent.
//!
//! With `--grid NAME=V1,V2,…` (repeatable) it instead *chooses* parameters by leave-one-take-out:
//! for each take, the grid setting with the best mean F1@1s on the other takes is scored on the
//! held-out take, and the held-out mean is printed beside the in-sample one (the setting best on
//! all takes, scored on those same takes) — parameters are never tuned on the take reported.
//!
//! ```text
//! cargo run --release --example eval_data -- [--data ../shared/data] [--method sssm] [--param NAME=VALUE]… [--json]
//! cargo run --release --example eval_data -- --grid radius=13,16,19,22,25 --grid relative_gate=0,1.5
//! ```

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
#[allow(dead_code)] // each example uses part of it
mod common;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    use clap::Parser;
    common::exit(lab::eval_data(lab::Args::parse()))
}

#[cfg(not(target_arch = "wasm32"))]
mod lab {
    use std::path::{Path, PathBuf};
    use std::time::Instant;

    use mocapseg::load::load_path;
    use mocapseg::method::{self, NoProgress, RunOptions};
    use mocapseg::motion::Motion;
    use mocapseg::segment::metrics::evaluate;
    use mocapseg::segment::report::{self, Row};
    use mocapseg::segment::truth::Truth;

    #[derive(clap::Parser)]
    #[command(about = "Segment and score the labelled takes of the shared data folder")]
    pub struct Args {
        /// The shared data folder (with cmu/ and labels/).
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
        #[arg(long, default_value = "sssm")]
        method: String,
        /// Parameter overrides as NAME=VALUE (JSON value); repeatable.
        #[arg(long = "param", value_name = "NAME=VALUE")]
        params: Vec<String>,
        /// Print JSON instead of a markdown table.
        #[arg(long)]
        json: bool,
        /// Leave-one-take-out choice of parameters over this grid: NAME=V1,V2,… (JSON values); repeatable.
        #[arg(long = "grid", value_name = "NAME=V1,V2,…")]
        grid: Vec<String>,
        /// What the leave-one-take-out choice maximises: the mean F1@1s (`f1`) or the mean of
        /// F1@1s and covering (`f1+covering`), over the other takes.
        #[arg(long, default_value = "f1", value_parser = ["f1", "f1+covering"])]
        select: String,
        /// With --grid: also print every setting's per-take F1@1s / covering.
        #[arg(long)]
        all: bool,
        /// Without --grid: also print each take's true and found action boundaries (seconds).
        #[arg(long)]
        detail: bool,
    }

    /// The labelled takes that are present, with their motion and ground truth.
    fn load_takes(data: &Path) -> Result<Vec<(Motion, Truth)>, String> {
        let mut takes = Vec::new();
        for take in crate::common::labelled_takes(data)? {
            let loaded = load_path(&take.bvh).map_err(|e| e.to_string())?;
            takes.push((loaded.motion, take.truth));
        }
        Ok(takes)
    }

    /// Every combination of the grid's values, as `NAME=VALUE` overrides after `base`.
    fn grid_settings(base: &[String], grid: &[String]) -> Result<Vec<Vec<String>>, String> {
        let mut settings = vec![base.to_vec()];
        for g in grid {
            let (name, values) = g.split_once('=').ok_or_else(|| format!("--grid {g}: expected NAME=V1,V2,…"))?;
            let values: Vec<&str> = values.split(',').map(str::trim).filter(|v| !v.is_empty()).collect();
            if values.is_empty() {
                return Err(format!("--grid {g}: no values"));
            }
            settings = settings
                .iter()
                .flat_map(|s| values.iter().map(move |v| [s.clone(), vec![format!("{}={v}", name.trim())]].concat()))
                .collect();
        }
        Ok(settings)
    }

    /// Leave-one-take-out: for each take, the grid setting best (mean F1@1s) on the others,
    /// scored on it; then the held-out mean beside the in-sample one.
    fn leave_one_take_out(args: &Args) -> Result<(), String> {
        let takes = load_takes(&args.data)?;
        if takes.len() < 2 {
            return Err("leave-one-take-out needs at least two labelled takes".into());
        }
        let method = mocapseg::methods::find(&args.method).map_err(|e| e.to_string())?;
        let settings = grid_settings(&args.params, &args.grid)?;
        // scores[s][t] = (F1@1s, covering) of setting s on take t
        let mut scores = Vec::new();
        for overrides in &settings {
            let params = method::params_from_overrides(method, overrides).map_err(|e| e.to_string())?;
            let checked = method.check_json(&params).map_err(|e| format!("{}: {e}", overrides.join(" ")))?;
            let mut row = Vec::new();
            for (motion, truth) in &takes {
                let output = method
                    .run_checked(motion, &checked, &RunOptions::default(), &mut NoProgress)
                    .map_err(|e| format!("{}: {e}", motion.name))?;
                let s = evaluate(&output.segmentation, truth, &mocapseg::methods::scoring(&output.segmentation.method))
                    .map_err(|e| format!("{}: {e}", truth.trial))?;
                row.push((s.boundaries[1].f1, s.covering));
            }
            scores.push(row);
        }
        let n = takes.len();
        let with_covering = args.select == "f1+covering";
        let mean_of = |s: usize, skip: Option<usize>, pick: &dyn Fn((f64, f64)) -> f64| {
            let kept: Vec<f64> = (0..n).filter(|&t| Some(t) != skip).map(|t| pick(scores[s][t])).collect();
            kept.iter().sum::<f64>() / kept.len() as f64
        };
        let mean_f1 = |s: usize, skip: Option<usize>| mean_of(s, skip, &|(f1, _)| f1);
        let objective = |s: usize, skip: Option<usize>| {
            if with_covering {
                mean_of(s, skip, &|(f1, cov)| (f1 + cov) / 2.0)
            } else {
                mean_f1(s, skip)
            }
        };
        // ties go to the first setting of the grid
        let best = |skip: Option<usize>| {
            (0..settings.len()).fold(0, |b, s| if objective(s, skip) > objective(b, skip) + 1e-12 { s } else { b })
        };
        let label = |s: usize| {
            let grid_part = &settings[s][args.params.len()..];
            grid_part.join(" ")
        };
        println!(
            "leave-one-take-out over {} settings ({}), {} takes, method {}, choosing by mean {}",
            settings.len(),
            args.grid.join("; "),
            n,
            args.method,
            if with_covering { "(F1@1s + covering) / 2" } else { "F1@1s" }
        );
        if args.all {
            let header: Vec<&str> = takes.iter().map(|(_, t)| t.trial.as_str()).collect();
            println!("| setting | {} | mean |", header.join(" | "));
            println!("|---|{}---|", "---|".repeat(n));
            for (s, row) in scores.iter().enumerate() {
                let cells: Vec<String> = row.iter().map(|(f1, cov)| format!("{f1:.2} / {cov:.2}")).collect();
                let mean_cov = row.iter().map(|r| r.1).sum::<f64>() / n as f64;
                println!("| {} | {} | {:.3} / {mean_cov:.3} |", label(s), cells.join(" | "), mean_f1(s, None));
            }
            println!();
        }
        println!("| held-out take | chosen on the other takes | F1@1s held out | covering held out |");
        println!("|---|---|---|---|");
        let (mut held_f1, mut held_cov) = (0.0, 0.0);
        for t in 0..n {
            let s = best(Some(t));
            let (f1, cov) = scores[s][t];
            held_f1 += f1 / n as f64;
            held_cov += cov / n as f64;
            println!("| {} | {} | {f1:.2} | {cov:.2} |", takes[t].1.trial, label(s));
        }
        let s = best(None);
        let in_f1 = mean_f1(s, None);
        let in_cov = (0..n).map(|t| scores[s][t].1).sum::<f64>() / n as f64;
        println!("| **mean held out** | | **{held_f1:.2}** | **{held_cov:.2}** |");
        println!("| mean in-sample (best on all takes: {}) | | {in_f1:.2} | {in_cov:.2} |", label(s));
        Ok(())
    }

    /// The found action boundaries (first frame of every action but the first, transitions split
    /// at their middle, as the scores read them) beside the true ones, in seconds, with the
    /// found actions' kinds.
    fn print_boundaries(seg: &mocapseg::segment::Segmentation, truth: &Truth) {
        use mocapseg::segment::Level;
        let mut actions: Vec<(usize, usize, String)> = seg
            .segments
            .iter()
            .filter(|s| s.level == Level::Action)
            .map(|s| (s.start, s.end, s.label.clone()))
            .collect();
        actions.sort();
        let s = |f: usize| f as f64 / seg.fps;
        let mut found = Vec::new();
        for w in actions.windows(2) {
            let (a_end, b_start) = (w[0].1, w[1].0);
            let split = if b_start > a_end + 1 { a_end + 1 + (b_start - a_end - 1) / 2 } else { b_start };
            found.push(format!("{:.1}", s(split)));
        }
        let kinds: Vec<String> = actions.iter().map(|(a, b, l)| format!("{l}[{:.1}-{:.1}]", s(*a), s(*b))).collect();
        let true_b: Vec<String> =
            truth.segments.iter().filter(|t| t.start > 0).map(|t| format!("{:.1}", s(t.start))).collect();
        let true_l: Vec<String> =
            truth.segments.iter().map(|t| format!("{}[{:.1}-{:.1}]", t.label, s(t.start), s(t.end))).collect();
        println!("{}: true  {}", truth.trial, true_b.join(" "));
        println!("{}: found {}", truth.trial, found.join(" "));
        println!("{}: true actions  {}", truth.trial, true_l.join(" "));
        println!("{}: found actions {}", truth.trial, kinds.join(" "));
    }

    pub fn eval_data(args: Args) -> Result<(), String> {
        let data = &args.data;
        if !args.grid.is_empty() {
            return leave_one_take_out(&args);
        }
        let method = mocapseg::methods::find(&args.method).map_err(|e| e.to_string())?;
        let params = method::params_from_overrides(method, &args.params).map_err(|e| e.to_string())?;
        let checked = method.check_json(&params).map_err(|e| e.to_string())?;
        let score = |motion: &Motion, truth: &Truth| -> Result<Row, String> {
            let started = Instant::now();
            let output = method
                .run_checked(motion, &checked, &RunOptions::default(), &mut NoProgress)
                .map_err(|e| format!("{}: {e}", motion.name))?;
            let seconds = started.elapsed().as_secs_f64();
            let seg = output.segmentation;
            if args.detail {
                print_boundaries(&seg, truth);
            }
            let scores = evaluate(&seg, truth, &mocapseg::methods::scoring(&seg.method))
                .map_err(|e| format!("{}: {e}", truth.trial))?;
            Ok(Row { scores, found_actions: report::scored_segments(&seg), seconds: Some(seconds) })
        };
        let takes = load_takes(data)?;
        let mut rows = Vec::new();
        let mut mocap6 = Vec::new();
        for (motion, truth) in takes {
            rows.push(score(&motion, &truth)?);
            if truth.trial != "86_01" {
                mocap6.push((motion, truth));
            }
        }
        // The mocap6 takes one after another: one long take (about 2 minutes) whose activities
        // recur across the parts, so kinds are scored across far-apart actions too.
        let mut joined_rows = Vec::new();
        if mocap6.len() > 1 {
            let motions: Vec<Motion> = mocap6.iter().map(|(m, _)| m.clone()).collect();
            let truths: Vec<Truth> = mocap6.iter().map(|(_, t)| t.clone()).collect();
            let frames = motions.iter().map(Motion::frames).sum();
            let name = truths.iter().map(|t| t.trial.as_str()).collect::<Vec<_>>().join("+");
            let mut joined = Motion::concatenate(&motions, frames).map_err(|e| format!("{name}: {e}"))?;
            joined.name = name.clone();
            joined_rows.push(score(&joined, &Truth::concatenate(&name, &truths))?);
        }
        if args.json {
            let list: Vec<_> = rows.iter().chain(&joined_rows).map(|r| &r.scores).collect();
            println!("{}", serde_json::to_string_pretty(&list).map_err(|e| e.to_string())?);
        } else {
            print!("{}", report::markdown(&rows, &joined_rows));
        }
        Ok(())
    }
}
