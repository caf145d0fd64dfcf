//! Lab tool, not part of the product: the one table `make bench` ends with. Reads the JSON lines
//! that `bench_methods` (native) and the wasm benchmark's `methods_table` test (headless
//! Chromium, collected from the runner's output by the Makefile) wrote, and prints parse MB/s,
//! FK frames/s, every method's time on 1×, 2×, 4× a take (with the growth over 1×) and the batch
//! rate, native beside wasm with the wasm/native time ratio.
//!
//! ```text
//! cargo run --release --example bench_table -- target/bench/results-native.jsonl target/bench/results-wasm.jsonl
//! ```

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
#[allow(dead_code)] // each example uses part of it
mod common;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    common::exit(table::run(std::env::args().skip(1).collect()))
}

#[cfg(not(target_arch = "wasm32"))]
mod table {
    use serde_json::Value;

    fn num(v: &Value, k: &str) -> Option<f64> {
        v.get(k).and_then(Value::as_f64)
    }

    /// The record of `side` for which `pick` holds.
    fn find<'a>(records: &'a [Value], side: &str, pick: impl Fn(&Value) -> bool) -> Option<&'a Value> {
        records.iter().find(|r| r["side"] == side && pick(r))
    }

    fn ratio(native_ms: Option<f64>, wasm_ms: Option<f64>) -> String {
        match (native_ms, wasm_ms) {
            (Some(n), Some(w)) if n > 0.0 => format!("{:.2}×", w / n),
            _ => "–".into(),
        }
    }

    fn ms_text(ms: f64) -> String {
        if ms >= 1000.0 {
            format!("{:.2} s", ms / 1000.0)
        } else if ms >= 10.0 {
            format!("{ms:.1} ms")
        } else {
            format!("{ms:.2} ms")
        }
    }

    pub fn run(files: Vec<String>) -> Result<(), String> {
        if files.is_empty() {
            return Err("give the results files (JSON lines from bench_methods and the wasm bench)".into());
        }
        let mut records = Vec::new();
        let mut read = Vec::new();
        // when the newest results were written (not when the table is printed)
        let mut newest = std::time::UNIX_EPOCH;
        for f in &files {
            match std::fs::read_to_string(f) {
                Ok(text) => {
                    for (i, line) in text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty()) {
                        let v: Value = serde_json::from_str(line).map_err(|e| format!("{f}: line {}: {e}", i + 1))?;
                        records.push(v);
                    }
                    read.push(f.as_str());
                    if let Ok(t) = std::fs::metadata(f).and_then(|m| m.modified()) {
                        newest = newest.max(t);
                    }
                }
                Err(e) => eprintln!("note: {f}: {e} (its column stays empty)"),
            }
        }
        if records.is_empty() {
            return Err(format!("no results in {}", files.join(", ")));
        }
        let threads = find(&records, "native", |r| r["what"] == "batch").and_then(|r| num(r, "threads"));
        println!();
        println!(
            "## make bench — measured up to {} UTC, {} (native: release build, all cores; wasm: headless Chromium, one thread; medians)",
            utc_text(newest),
            match threads {
                Some(t) => format!("{t} cores"),
                None => format!("{} cores", std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1)),
            }
        );
        println!();
        println!("| what | native | wasm in Chromium | wasm / native (time) |");
        println!("|---|---|---|---|");
        // parse and FK
        for (what, label) in [("parse", "parse"), ("fk", "forward kinematics")] {
            let n = find(&records, "native", |r| r["what"] == what);
            let w = find(&records, "wasm", |r| r["what"] == what);
            let Some(any) = n.or(w) else { continue };
            let input = format!(
                "{} ({:.2} MB, {} frames)",
                any["input"].as_str().unwrap_or("?"),
                num(any, "bytes").unwrap_or(0.0) / 1e6,
                num(any, "frames").unwrap_or(0.0)
            );
            let cell =
                |r: Option<&Value>| match r.and_then(|r| Some((num(r, "ms")?, num(r, "bytes")?, num(r, "frames")?))) {
                    Some((ms, bytes, _)) if what == "parse" => {
                        format!("{:.0} MB/s ({})", bytes / 1e6 / (ms / 1e3), ms_text(ms))
                    }
                    Some((ms, _, frames)) => format!("{:.0} k frames/s ({})", frames / (ms / 1e3) / 1e3, ms_text(ms)),
                    None => "–".into(),
                };
            println!(
                "| {label}, {input} | {} | {} | {} |",
                cell(n),
                cell(w),
                ratio(n.and_then(|r| num(r, "ms")), w.and_then(|r| num(r, "ms")))
            );
        }
        // methods, in the order they were measured
        let mut methods: Vec<String> = Vec::new();
        for r in records.iter().filter(|r| r["what"] == "method") {
            let m = r["method"].as_str().unwrap_or("?").to_string();
            if !methods.contains(&m) {
                methods.push(m);
            }
        }
        for m in &methods {
            let at = |side: &str, factor: u64| {
                find(&records, side, |r| r["what"] == "method" && r["method"] == m.as_str() && r["factor"] == factor)
            };
            for factor in [1u64, 2, 4, 16] {
                let cell = |side: &str| match at(side, factor).and_then(|r| num(r, "ms")) {
                    Some(ms) if factor == 1 => ms_text(ms),
                    Some(ms) => match at(side, 1).and_then(|r| num(r, "ms")) {
                        Some(base) if base > 0.0 => format!("{} ({:.2}× the 1×)", ms_text(ms), ms / base),
                        _ => ms_text(ms),
                    },
                    None => "–".into(),
                };
                let frames = at("native", factor).or(at("wasm", factor)).and_then(|r| num(r, "frames")).unwrap_or(0.0);
                let label = if factor == 1 {
                    format!("**{m}** 1× ({frames} frames)")
                } else {
                    format!("{m} {factor}× ({frames} frames)")
                };
                println!(
                    "| {label} | {} | {} | {} |",
                    cell("native"),
                    cell("wasm"),
                    ratio(
                        at("native", factor).and_then(|r| num(r, "ms")),
                        at("wasm", factor).and_then(|r| num(r, "ms"))
                    )
                );
            }
        }
        match find(&records, "native", |r| r["what"] == "batch") {
            Some(b) => {
                let (takes, s) = (num(b, "takes").unwrap_or(0.0), num(b, "s").unwrap_or(f64::NAN));
                println!(
                    "| batch: `mocapseg segment --method {}` over {} ({takes} takes, {} failed; wall clock) | {:.1} takes/s ({:.2} s, {} threads) | – | – |",
                    b["method"].as_str().unwrap_or("?"),
                    b["input"].as_str().unwrap_or("?"),
                    num(b, "failed").unwrap_or(0.0),
                    takes / s,
                    s,
                    num(b, "threads").unwrap_or(0.0)
                );
            }
            None => println!("| batch | – (no shared data) | – | – |"),
        }
        println!();
        print_stages(&records, &methods);
        println!();
        println!(
            "1× = the first 1145 frames @30 Hz of the benchmark sequence (CMU 86_01 when the shared data is present); 2× and 4× \
             go on into the next CMU takes (distinct material); 16× (10.2 minutes) repeats the sequence. Default parameters. Ratios, not absolute times, are what carry \
             over: this machine is shared and noisy. Read from {}.",
            read.join(", ")
        );
        Ok(())
    }

    /// Where each method's time goes at 1× and 16×, native beside wasm: the stages it reported
    /// (`method::Stages`, the median run of each side) that took at least a tenth of either side's
    /// run, with the wasm / native ratio of each — the profile that says which stage makes a
    /// method slower in the browser.
    fn print_stages(records: &[Value], methods: &[String]) {
        let stages_of = |r: Option<&Value>| -> Vec<(String, f64)> {
            r.and_then(|r| r["stages"].as_array())
                .map(|a| {
                    a.iter().filter_map(|p| Some((p.get(0)?.as_str()?.to_string(), p.get(1)?.as_f64()?))).collect()
                })
                .unwrap_or_default()
        };
        println!("Where the time goes (the stages each method reports; those over a tenth of its run on either side):");
        println!();
        println!("| method, length | stage | native | wasm | wasm / native |");
        println!("|---|---|---|---|---|");
        for m in methods {
            for factor in [1u64, 16] {
                let at = |side: &str| {
                    find(records, side, |r| r["what"] == "method" && r["method"] == m.as_str() && r["factor"] == factor)
                };
                let (n, w) = (at("native"), at("wasm"));
                let (ns, ws) = (stages_of(n), stages_of(w));
                if ns.is_empty() && ws.is_empty() {
                    continue;
                }
                let total = |r: Option<&Value>| r.and_then(|r| num(r, "ms")).unwrap_or(f64::NAN);
                let (nt, wt) = (total(n), total(w));
                let mut names: Vec<&String> = Vec::new();
                for (name, _) in ns.iter().chain(&ws) {
                    if !names.contains(&name) {
                        names.push(name);
                    }
                }
                let get = |v: &[(String, f64)], name: &str| v.iter().find(|(n, _)| n == name).map(|p| p.1);
                for name in names {
                    let (a, b) = (get(&ns, name), get(&ws, name));
                    let big = a.is_some_and(|a| a >= 0.1 * nt) || b.is_some_and(|b| b >= 0.1 * wt);
                    if !big {
                        continue;
                    }
                    let cell = |ms: Option<f64>, t: f64| match ms {
                        Some(ms) => format!("{} ({:.0} %)", ms_text(ms), 100.0 * ms / t),
                        None => "–".into(),
                    };
                    println!("| {m} {factor}× | {name} | {} | {} | {} |", cell(a, nt), cell(b, wt), ratio(a, b));
                }
            }
        }
    }

    /// `t` in UTC as `YYYY-MM-DD HH:MM` (no date crate: days from the epoch, civil calendar).
    fn utc_text(t: std::time::SystemTime) -> String {
        let secs = t.duration_since(std::time::UNIX_EPOCH).map(|d| d.as_secs() as i64).unwrap_or(0);
        let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
        // Howard Hinnant's civil_from_days
        let z = days + 719_468;
        let era = z.div_euclid(146_097);
        let doe = z - era * 146_097;
        let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
        let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
        let mp = (5 * doy + 2) / 153;
        let d = doy - (153 * mp + 2) / 5 + 1;
        let m = if mp < 10 { mp + 3 } else { mp - 9 };
        let y = yoe + era * 400 + i64::from(m <= 2);
        format!("{y:04}-{m:02}-{d:02} {:02}:{:02}", rem / 3600, rem % 3600 / 60)
    }
}
