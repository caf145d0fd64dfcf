//! What `mocapseg train-dtfcn`, `train-knn` and `train-lma` add to the table's flags (the research
//! flags: a validation take, leave-one-take-out, LMA's stand-in labels, several takes for LMA), and
//! `mocapseg model-info` (the training itself is the library's, `mocapseg::methods::…`).

use mocapseg::methods::dtfcn::decode::Decoding;
use mocapseg::methods::dtfcn::model::ModelKind;
use mocapseg::methods::dtfcn::supervised::options_from_json;
use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use mocapseg::labels::read_csv;
use mocapseg::load::load_path;
use mocapseg::methods::dtfcn::corpus::{
    class_labels, fit_knn_model, leave_one_take_out, rows_without_takes, train_model, ModelMeta,
};
use mocapseg::methods::dtfcn::model::{data_hash, take_hashes};
use mocapseg::methods::dtfcn::training::{EpochReport, TrainOptions, TrainingTake};
use mocapseg::methods::lma::corpus::same_file;
use mocapseg::motion::Motion;

/// The command line as typed (for the model's provenance).
fn command_line() -> String {
    let args: Vec<String> = std::env::args().collect();
    let mut shown = vec!["mocapseg".to_string()];
    shown.extend(args.into_iter().skip(1).map(|a| if a.contains(' ') { format!("'{a}'") } else { a }));
    shown.join(" ")
}

/// The network's shape in one line: receptive field in seconds and parameters, beside the paper's.
fn network_summary(options: &TrainOptions, classes: usize) -> String {
    use mocapseg::methods::dtfcn::input::NETWORK_FPS;
    let net = options.network(classes);
    let ten = options.network(10).parameter_count();
    format!(
        "network: w = {}, {} layers ({}), receptive field {} frames = {:.2} s at {NETWORK_FPS} Hz, {} padding, layer 1 reads {} values per frame{}; {} parameters ({ten} with the paper's 10 classes; the paper's network: 663562, reading 224 rows)",
        net.width,
        net.filters.len(),
        net.filters.iter().map(|f| f.to_string()).collect::<Vec<_>>().join(","),
        net.receptive_field(),
        net.receptive_field_s(NETWORK_FPS),
        net.padding.name(),
        net.first_layer_inputs(),
        net.image_rows.map(|r| format!(" (the image resized to {r} rows)")).unwrap_or_default(),
        net.parameter_count(),
    )
}

/// `command` (a `train-M` command made from M's table) with M's research flags.
pub fn research_flags(method: &str, command: clap::Command) -> clap::Command {
    use clap::{Arg, ArgAction};
    match method {
        "dtfcn" | "knn" => command
            .arg(
                Arg::new("validation")
                    .long("validation")
                    .value_name("TAKE")
                    .help("The take whose validation loss chooses the epoch (early stopping, --patience); default none"),
            )
            .arg(Arg::new("cross-validate").long("cross-validate").action(ArgAction::SetTrue).help(
                "Leave-one-take-out table instead of one model: the epochs chosen on the next take in turn, the k-NN's k \
                 on it too; frame accuracy, edit and F1@{10,25,50} per held-out take, network and k-NN side by side",
            ))
            .args((method == "dtfcn").then(|| {
                Arg::new("layers")
                    .long("layers")
                    .value_name("L")
                    .value_parser(clap::value_parser!(usize))
                    .conflicts_with("filters")
                    .help("Shorthand for --filters in the paper's pattern (doubling from 64 to 512): 4 = 64,128,256,512")
            })),
        "lma" => command.mut_arg("labels", |a| {
            a.help(
                "Your own Effort labels: CSV `file,start_frame,end_frame,space,time,weight,flow` (0-based inclusive \
                 file frames; indulging|neutral|condensing). Without it the labels are the stand-in Effort descriptors' \
                 terciles over the takes' segments between hand-speed minima (how models/lma-effort.json is made)",
            )
        }),
        _ => command,
    }
}

/// The training of `method` with its research flags, or `None` for a method without any (it then
/// trains exactly as the page does). `options`: the table's flags, read.
pub fn research_training(
    method: &str,
    bvh: &[PathBuf],
    labels: Option<&Path>,
    options: &serde_json::Value,
    out: Option<&Path>,
    name: Option<String>,
    args: &clap::ArgMatches,
) -> Option<Result<(), String>> {
    let kind = match method {
        "dtfcn" => ModelKind::Dtfcn,
        "knn" => ModelKind::Knn,
        "lma" => {
            return Some((|| {
                let config = mocapseg::methods::lma::supervised::config_from_json(options).map_err(|e| e.to_string())?;
                crate::cli::train_lma(bvh, labels, config, out.ok_or("--out FILE is needed")?)
            })())
        }
        _ => return None,
    };
    Some((|| {
        let mut options = options.clone();
        let layers = args.try_get_one::<usize>("layers").ok().flatten();
        if let Some(&layers) = layers {
            if !(1..=6).contains(&layers) {
                return Err(format!("--layers {layers}: expected 1 to 6"));
            }
            options["filters"] = serde_json::json!(mocapseg::methods::dtfcn::network::paper_filters(layers));
        }
        let read = options_from_json(kind, &options).map_err(|e| match e.param_name() {
            Some(p) => format!("--{}: {e}", p.replace('_', "-")),
            None => e.to_string(),
        })?;
        train(
            bvh,
            labels.ok_or("--labels FILE is needed")?,
            read.train,
            read.decoding.unwrap_or(Decoding::RAW),
            out.map(Path::to_path_buf),
            kind.name(),
            name,
            args.get_one::<String>("validation").cloned(),
            args.get_flag("cross-validate"),
        )
    })())
}

#[allow(clippy::too_many_arguments)]
fn train(
    inputs: &[PathBuf],
    labels_path: &Path,
    options: TrainOptions,
    decoding: Decoding,
    out: Option<PathBuf>,
    method: &str,
    name: Option<String>,
    validation: Option<String>,
    cross_validate: bool,
) -> Result<(), String> {
    let started = Instant::now();
    let label_bytes = std::fs::read(labels_path).map_err(|e| format!("{}: {e}", labels_path.display()))?;
    let rows = read_csv(&String::from_utf8_lossy(&label_bytes), &labels_path.display().to_string())?;
    let files = crate::cli::collect_files(inputs, "bvh")?;
    let mut motions: Vec<Motion> = Vec::new();
    let mut hashed: Vec<(String, Vec<u8>)> = Vec::new();
    for f in &files {
        let fname = f.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        if !rows.iter().any(|r| same_file(&r.file, &fname)) {
            eprintln!("skipped {}: no label rows name it", f.display());
            continue;
        }
        let loaded = load_path(f).map_err(|e| e.to_string())?;
        hashed.push((fname, std::fs::read(f).map_err(|e| format!("{}: {e}", f.display()))?));
        motions.push(loaded.motion);
    }
    if motions.is_empty() {
        return Err(format!("none of the takes given is named in {}", labels_path.display()));
    }
    let refs: Vec<&Motion> = motions.iter().collect();
    let missing = rows_without_takes(&rows, &refs);
    if !missing.is_empty() {
        eprintln!("note: label rows of takes not given are left out: {}", missing.join(", "));
    }
    let (classes, labels) = class_labels(&rows, &refs)?;
    for warning in mocapseg::methods::dtfcn::corpus::labels_at_another_rate(&refs, &labels) {
        eprintln!("warning: {warning}");
    }
    let frames: usize = labels.iter().map(|l| l.iter().flatten().count()).sum();
    eprintln!("{} takes, {} labelled frames, {} classes: {}", motions.len(), frames, classes.len(), classes.join(", "));
    if method == "dtfcn" {
        eprintln!("{}", network_summary(&options, classes.len()));
    }
    let on_epoch = |bar: &ProgressBar, take: &str, r: &EpochReport| {
        bar.set_position(r.epoch as u64);
        let val = match (r.validation_loss, r.validation_accuracy) {
            (Some(l), Some(a)) => format!(" · validation loss {l:.3} accuracy {a:.3}"),
            _ => String::new(),
        };
        let line = format!(
            "{take}epoch {:>3}/{}: loss {:.3} · train accuracy {:.3}{val}{}",
            r.epoch,
            r.epochs,
            r.loss,
            r.train_accuracy,
            if r.best { " *" } else { "" }
        );
        bar.suspend(|| eprintln!("{line}"));
        true
    };
    let bar = ProgressBar::new(options.epochs as u64);
    bar.set_style(
        ProgressStyle::with_template("{elapsed_precise} [{bar:40}] epoch {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );

    if cross_validate {
        let folds = leave_one_take_out(&motions, &labels, &classes, &options, &mut |take, r| {
            if r.epoch == 1 {
                bar.reset();
            }
            on_epoch(&bar, &format!("[held out {take}] "), r)
        })?;
        bar.finish_and_clear();
        println!(
            "Leave one take out ({} takes; epochs chosen on the next take in turn, at most {}; augmentation {}; noise {}; mask {} s; w = {}, {} layers: receptive field {:.2} s, {} padding):",
            folds.len(),
            options.epochs,
            options.augment.describe(),
            options.label_noise,
            options.mask_s,
            options.width,
            options.filters.len(),
            options.network(2).receptive_field_s(mocapseg::methods::dtfcn::input::NETWORK_FPS),
            options.padding.name()
        );
        println!("| held-out take | validation take (its accuracy) | epoch kept / run | DT-FCN acc | edit | F1@10 | F1@25 | F1@50 | confidence | k-NN k | acc | edit | F1@10 | F1@25 | F1@50 | time |");
        println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
        let mut mean = [0.0f64; 11];
        let inner = folds.iter().map(|f| f.validation_accuracy).sum::<f64>() / folds.len().max(1) as f64;
        for f in &folds {
            let row = [
                f.network.frame_accuracy,
                f.network.edit,
                f.network.f1[0],
                f.network.f1[1],
                f.network.f1[2],
                f.confidence,
                f.knn.frame_accuracy,
                f.knn.edit,
                f.knn.f1[0],
                f.knn.f1[1],
                f.knn.f1[2],
            ];
            for (m, v) in mean.iter_mut().zip(row) {
                *m += v / folds.len() as f64;
            }
            let validation = format!("{} ({:.3})", f.validation_take, f.validation_accuracy);
            println!(
                "| {} | {} | {} / {} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} | {:.2} | {} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} | {:.0} s |",
                f.take, validation, f.best_epoch, f.epochs_run, row[0], row[1], row[2], row[3], row[4], row[5],
                f.knn_k, row[6], row[7], row[8], row[9], row[10], f.seconds
            );
        }
        println!(
            "| **mean** | ({inner:.3}) | | **{:.3}** | **{:.1}** | **{:.1}** | **{:.1}** | **{:.1}** | **{:.2}** | | **{:.3}** | **{:.1}** | **{:.1}** | **{:.1}** | **{:.1}** | {:.0} s |",
            mean[0], mean[1], mean[2], mean[3], mean[4], mean[5], mean[6], mean[7], mean[8], mean[9], mean[10],
            started.elapsed().as_secs_f64()
        );
        return Ok(());
    }

    let out = out.ok_or("--out FILE is needed (or --cross-validate)")?;
    // the take fit measures travel on what the model is taught (a validation take is not)
    let taught: Vec<(&Motion, &[Option<usize>])> = motions
        .iter()
        .zip(&labels)
        .filter(|(m, _)| method == "knn" || !validation.as_deref().is_some_and(|v| same_file(v, &m.name)))
        .map(|(m, l)| (m, l.as_slice()))
        .collect();
    let meta = ModelMeta {
        travel: mocapseg::methods::dtfcn::corpus::travel_of(&taught),
        name: name.unwrap_or_else(|| out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()),
        command: command_line(),
        data_hash: data_hash(&hashed, &label_bytes),
        decoding: (decoding.min_duration_s > 0.0 || decoding.switch_cost > 0.0).then_some(decoding),
    };
    let model = if method == "knn" {
        let takes: Vec<(&Motion, &[Option<usize>])> =
            motions.iter().zip(&labels).map(|(m, l)| (m, l.as_slice())).collect();
        fit_knn_model(&takes, &classes, &meta)?
    } else {
        let mut train_takes = Vec::new();
        let mut val_takes = Vec::new();
        for (m, l) in motions.iter().zip(&labels) {
            let t = TrainingTake::new(m, l)?;
            if validation.as_deref().is_some_and(|v| same_file(v, &m.name)) {
                val_takes.push(t);
            } else {
                train_takes.push(t);
            }
        }
        if let Some(v) = &validation {
            if val_takes.is_empty() {
                return Err(format!("--validation {v}: no such take among those given"));
            }
        }
        let m = train_model(&train_takes, &val_takes, &classes, &options, &meta, &mut |r| on_epoch(&bar, "", r))?;
        bar.finish_and_clear();
        eprintln!("kept the weights of epoch {} of {}", m.header.provenance.best_epoch, m.header.provenance.epochs_run);
        m
    };
    let mut model = model;
    model.header.provenance.take_sha256 = take_hashes(&model.header.provenance.takes, &hashed);
    let bytes = model.to_bytes()?;
    std::fs::write(&out, &bytes).map_err(|e| format!("{}: {e}", out.display()))?;
    eprintln!("wrote {} ({} bytes) in {:.1} s", out.display(), bytes.len(), started.elapsed().as_secs_f64());
    Ok(())
}

/// `mocapseg model-info FILE|NAME [--method M]`: a model file read by the supervised method
/// whose reader takes it (or `method`'s), or a shipped model by name — `exercises` (every method
/// shipping one of that name, or `method`'s), `dtfcn-exercises`, `dtfcn-exercises.model` — from
/// what each supervised method declares.
pub fn model_info(file: &Path, method: Option<&str>) -> Result<(), String> {
    use mocapseg::method::DynMethod;
    use mocapseg::methods::registry;
    let methods: Vec<&dyn DynMethod> = registry()
        .iter()
        .copied()
        .filter(|m| m.supervised().is_some() && method.is_none_or(|name| m.info().name == name))
        .collect();
    if methods.is_empty() {
        let known: Vec<String> =
            registry().iter().filter(|m| m.supervised().is_some()).map(|m| m.info().name).collect();
        return Err(format!(
            "--method {}: not a method with models; those are {}",
            method.unwrap_or(""),
            known.join(", ")
        ));
    }
    let mut details = Vec::new();
    if file.exists() {
        let bytes = std::fs::read(file).map_err(|e| format!("{}: {e}", file.display()))?;
        let shown = file.display().to_string();
        let mut refusals = Vec::new();
        let extension = file.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        for m in &methods {
            let (Some(s), Some(decl)) = (m.supervised(), m.supervision()) else { continue };
            match s.read_model(&shown, &bytes) {
                Ok(loaded) => {
                    details.push(s.model_details(&loaded));
                    break;
                }
                // the refusal of a method whose files have this extension says the most
                Err(e) if extension.as_deref() == Some(decl.model_extension.as_str()) => {
                    refusals.insert(0, e.to_string())
                }
                Err(e) => refusals.push(e.to_string()),
            }
        }
        if details.is_empty() {
            return Err(refusals.first().cloned().unwrap_or_else(|| format!("{shown}: not a model file")));
        }
    } else {
        let name = file.to_string_lossy();
        let mut shipped = Vec::new();
        for m in &methods {
            let (Some(s), Some(decl)) = (m.supervised(), m.supervision()) else { continue };
            let method = m.info().name;
            let stem = name.strip_suffix(&format!(".{}", decl.model_extension)).unwrap_or(&name);
            let own = stem.strip_prefix(&format!("{method}-")).filter(|n| decl.shipped.iter().any(|s| s == n));
            let bare = decl.shipped.iter().any(|s| s == stem).then_some(stem);
            if let Some(n) = own.or(bare) {
                details.push(s.model_details(&s.shipped_model(n).map_err(|e| e.to_string())?));
            }
            shipped.extend(decl.shipped.iter().map(|s| format!("{method}-{s}")));
        }
        if details.is_empty() {
            return Err(format!(
                "{name}: no such file, nor a shipped model (shipped: {}; a bare name, e.g. `exercises`, names every method's)",
                shipped.join(", ")
            ));
        }
    }
    let out = match &details[..] {
        [one] => serde_json::to_string_pretty(one),
        many => serde_json::to_string_pretty(many),
    };
    println!("{}", out.map_err(|e| e.to_string())?);
    Ok(())
}
