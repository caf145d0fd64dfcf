//! Lab tool, not part of the product: the DT-FCN experiments of docs/methods/dtfcn.md on the four mocap6
//! exercise takes of the shared data, every one leave-one-take-out with the epochs chosen on an
//! inner validation take (never on the held-out take, and with the same noise and masking as the
//! training labels), the k-NN beside the network under the same labels, its k chosen on the same
//! validation take:
//!
//! * `noise` — training-label noise 0–90 % (the paper's Table 3);
//! * `mask` — boundary masking w_transition 0/11/21/31 frames at the paper's 72 Hz (Table 4, lower half);
//! * `folds` — one setting's per-fold table: the held-out take, its validation take and what it chose,
//!   DT-FCN and the k-NN side by side (what `mocapseg train-dtfcn --cross-validate` printed before the
//!   command line's training became the page's one path);
//! * `ensemble` — a few-seed ensemble: per held-out take, the network trained (each with its own
//!   validation-chosen epoch) with every seed of `--seeds`, each seed's scores and those of the mean of
//!   their probabilities, raw and under the shipped exercises model's decoding (runs ≥ 2 s, switch
//!   cost 10);
//! * `unseen-every` — leave one class out, every class of every take in turn (a class some other take
//!   holds): five unknowns — the network's max-softmax, the k-NN's distance to its nearest training
//!   window over the take's median, either of them, the deep k-NN (the distance in the network's own
//!   feature space, Sun et al. 2022) and either of the two distances — each threshold set so that 10 %
//!   (5 % each for "either") of the fold's validation take's taught-class frames are called unknown,
//!   under the validation network and a k-NN fitted without the validation take (no unseen frames
//!   needed to choose them), never on the held-out take;
//! * `unseen` — leave one class out: each fold's held-out take's largest class is removed from
//!   training; mean confidence on its frames (never seen) against the other frames, and how well
//!   each unknown threshold separates them (what chose the default threshold).
//!
//! ```text
//! cargo run --release --example eval_dtfcn -- noise|mask|folds|ensemble|unseen|unseen-every [--seeds 1,2,3] [--data ../shared/data] [--width 3] [--layers 4 | --filters 64,128,256,512] [--padding edge]
//!     [--bvh TAKES… --labels L.csv] …
//! ```
//! Says so and fails when the shared data is absent.

#[cfg(target_arch = "wasm32")]
fn main() {}

#[cfg(not(target_arch = "wasm32"))]
#[allow(dead_code)] // each example uses part of it
mod common;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    use clap::Parser;
    common::exit(lab::run(lab::Args::parse()))
}

#[cfg(not(target_arch = "wasm32"))]
mod lab {
    use std::path::PathBuf;

    use mocapseg::labeller::corpus::class_labels;
    use mocapseg::labels::{from_truth_csv, LabelRow};
    use mocapseg::methods::dtfcn::augment::Augment;
    use mocapseg::methods::dtfcn::corpus::{leave_one_take_out, novelty_scores, predict_held_out, NO_EXTRA};
    use mocapseg::methods::dtfcn::training::{TrainOptions, Trained, TrainingTake};
    use mocapseg::methods::knn::training::knn_fold;
    use mocapseg::motion::Motion;
    use mocapseg::segment::truth::TruthOptions;

    #[derive(clap::Parser)]
    #[command(about = "DT-FCN experiments (noise, masking, unseen classes) on the mocap6 takes")]
    pub struct Args {
        /// noise, mask, folds or unseen.
        experiment: String,
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
        #[arg(long, default_value_t = 60)]
        epochs: usize,
        #[arg(long, default_value_t = 3)]
        width: usize,
        #[arg(long, default_value_t = 4)]
        layers: usize,
        /// Filters of each layer (their count is the layer count; overrides `--layers`), e.g. 32,64,128,256.
        #[arg(long, value_delimiter = ',')]
        filters: Vec<usize>,
        #[arg(long, default_value_t = 2)]
        batch: usize,
        #[arg(long, default_value_t = 128)]
        crop: usize,
        #[arg(long, default_value = "all")]
        augment: String,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// The final training keeps the mean weights of its last this many epochs (0: the last epoch's).
        #[arg(long, default_value_t = 0)]
        average_last: usize,
        /// Each take centred on its own median posture before the standardisation (`centre_on_take`).
        #[arg(long)]
        centre_on_take: bool,
        /// The seeds of `ensemble`.
        #[arg(long, value_delimiter = ',', default_value = "1,2,3")]
        seeds: Vec<u64>,
        /// zero or edge (default: the training's)
        #[arg(long)]
        padding: Option<String>,
        /// Other takes than mocap6's (BVH files and/or folders), with `--labels`.
        #[arg(long, num_args = 1.., requires = "labels")]
        bvh: Vec<PathBuf>,
        /// Their label CSV (`file,start_frame,end_frame,label`, 0-based file frames).
        #[arg(long)]
        labels: Option<PathBuf>,
    }

    /// The takes under `paths` (files, and the `.bvh` files of folders) that the label CSV names, and its rows.
    fn named_takes(paths: &[PathBuf], labels: &std::path::Path) -> Result<(Vec<Motion>, Vec<LabelRow>), String> {
        let text = std::fs::read_to_string(labels).map_err(|e| format!("{}: {e}", labels.display()))?;
        let rows = mocapseg::labels::read_csv(&text, &labels.display().to_string())?;
        let files = mocapseg::load::collect_files(paths, "bvh")?;
        let mut motions = Vec::new();
        for f in files {
            let name = f.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            if rows.iter().any(|r| mocapseg::labels::same_file(&r.file, &name)) {
                motions.push(mocapseg::load::load_path(&f).map_err(|e| e.to_string())?.motion);
            }
        }
        Ok((motions, rows))
    }

    fn takes(data: &std::path::Path) -> Result<(Vec<Motion>, Vec<LabelRow>), String> {
        let truth = data.join("labels/mocap6_gt.csv");
        let text = std::fs::read_to_string(&truth).map_err(|e| {
            format!("{}: {e} — the shared data (../shared/data) is needed for this experiment", truth.display())
        })?;
        let (rows, _) = from_truth_csv(&text, TruthOptions::default())?;
        let mut motions = Vec::new();
        for trial in ["13_29", "13_30", "13_31", "14_14"] {
            let path = data.join(format!("cmu/mocap6/{trial}.bvh"));
            let loaded = mocapseg::load::load_path(&path).map_err(|e| e.to_string())?;
            motions.push(loaded.motion);
        }
        Ok((motions, rows))
    }

    pub fn run(args: Args) -> Result<(), String> {
        let (motions, rows) = match &args.labels {
            Some(labels) => named_takes(&args.bvh, labels)?,
            None => takes(&args.data)?,
        };
        let refs: Vec<&Motion> = motions.iter().collect();
        let (classes, labels) = class_labels(&rows, &refs)?;
        let base = TrainOptions {
            epochs: args.epochs,
            width: args.width,
            filters: if args.filters.is_empty() {
                mocapseg::methods::dtfcn::network::paper_filters(args.layers)
            } else {
                args.filters.clone()
            },
            batch: args.batch,
            crop_frames: args.crop,
            augment: Augment::parse(&args.augment)?,
            seed: args.seed,
            average_last: args.average_last,
            centre_on_take: args.centre_on_take,
            ..TrainOptions::default()
        };
        let base = match &args.padding {
            None => base,
            Some(p) => TrainOptions {
                padding: serde_json::from_value(serde_json::json!(p)).map_err(|e| format!("--padding {p}: {e}"))?,
                ..base
            },
        };
        println!(
            "{}, {} takes, leave one take out (epochs ≤ {} chosen on an inner validation take, then retrained on all \
             training takes); w = {}, {} layers, batch {}, crops {}, augmentation {}, seed {}",
            args.labels.as_ref().map_or("mocap6".to_string(), |l| l.display().to_string()),
            motions.len(),
            base.epochs,
            base.width,
            base.filters.len(),
            base.batch,
            base.crop_frames,
            base.augment.describe(),
            base.seed
        );
        match args.experiment.as_str() {
            "noise" | "mask" => {
                let noise = args.experiment == "noise";
                let levels: Vec<f64> =
                    if noise { (0..10).map(|i| i as f64 / 10.0).collect() } else { vec![0.0, 11.0, 21.0, 31.0] }; // w_transition in the paper's 72 Hz frames
                println!(
                    "| {} | DT-FCN acc | edit | F1@10 | F1@25 | F1@50 | k-NN acc | edit | F1@10 | F1@25 | F1@50 |",
                    if noise { "label noise" } else { "w_transition (frames at the paper's 72 Hz, masked)" }
                );
                println!("|---|---|---|---|---|---|---|---|---|---|---|");
                for level in levels {
                    let options = if noise {
                        TrainOptions { label_noise: level, ..base.clone() }
                    } else {
                        TrainOptions { mask_s: level / 72.0, ..base.clone() }
                    };
                    let folds = leave_one_take_out(&motions, &labels, &classes, &options, &knn_fold, &mut |_, _| true)?;
                    let n = folds.len() as f64;
                    let m = |f: &dyn Fn(&mocapseg::methods::dtfcn::corpus::Fold) -> f64| {
                        folds.iter().map(f).sum::<f64>() / n
                    };
                    println!(
                        "| {} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} |",
                        if noise { format!("{:.0} %", level * 100.0) } else { format!("{level}") },
                        m(&|f| f.network.frame_accuracy),
                        m(&|f| f.network.edit),
                        m(&|f| f.network.f1[0]),
                        m(&|f| f.network.f1[1]),
                        m(&|f| f.network.f1[2]),
                        m(&|f| f.knn.frame_accuracy),
                        m(&|f| f.knn.edit),
                        m(&|f| f.knn.f1[0]),
                        m(&|f| f.knn.f1[1]),
                        m(&|f| f.knn.f1[2]),
                    );
                }
                Ok(())
            }
            "folds" => folds(&motions, &labels, &classes, &base),
            "ensemble" => ensemble(&motions, &labels, &classes, &base, &args.seeds),
            "unseen" => unseen(&motions, &labels, &classes, &base),
            "unseen-every" => unseen_every(&motions, &labels, &classes, &base),
            other => Err(format!("unknown experiment `{other}`: noise, mask, folds, ensemble, unseen or unseen-every")),
        }
    }

    /// One setting, leave one take out: a row per held-out take (its validation take and that take's accuracy, the
    /// epoch it chose, DT-FCN's and the k-NN's scores, the k-NN's k), and the mean.
    fn folds(
        motions: &[Motion],
        labels: &[Vec<Option<usize>>],
        classes: &[String],
        options: &TrainOptions,
    ) -> Result<(), String> {
        let started = std::time::Instant::now();
        let folds = leave_one_take_out(motions, labels, classes, options, &knn_fold, &mut |take, r| {
            eprintln!(
                "[held out {take}] epoch {}/{}: loss {:.3}{}",
                r.epoch,
                r.epochs,
                r.loss,
                if r.best { " *" } else { "" }
            );
            true
        })?;
        println!(
            "{}; label noise {}, mask {} s",
            options.network(classes.len()).describe(mocapseg::labeller::input::NETWORK_FPS),
            options.label_noise,
            options.mask_s
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
            println!(
                "| {} | {} ({:.3}) | {} / {} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} | {:.2} | {} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} | {:.0} s |",
                f.take, f.validation_take, f.validation_accuracy, f.best_epoch, f.epochs_run, row[0], row[1], row[2], row[3],
                row[4], row[5], f.knn_k, row[6], row[7], row[8], row[9], row[10], f.seconds
            );
        }
        println!(
            "| **mean** | ({inner:.3}) | | **{:.3}** | **{:.1}** | **{:.1}** | **{:.1}** | **{:.1}** | **{:.2}** | | **{:.3}** | **{:.1}** | **{:.1}** | **{:.1}** | **{:.1}** | {:.0} s |",
            mean[0], mean[1], mean[2], mean[3], mean[4], mean[5], mean[6], mean[7], mean[8], mean[9], mean[10],
            started.elapsed().as_secs_f64()
        );
        Ok(())
    }

    /// A few-seed ensemble (see the module docs): a row per held-out take, each seed's frame accuracy, edit and
    /// F1@50 and the ensemble's, raw and decoded.
    fn ensemble(
        motions: &[Motion],
        labels: &[Vec<Option<usize>>],
        classes: &[String],
        base: &TrainOptions,
        seeds: &[u64],
    ) -> Result<(), String> {
        use mocapseg::labeller::decode::{file_labels, Decoding};
        use mocapseg::labeller::input::NETWORK_FPS;
        use mocapseg::labeller::probabilities::Probabilities;
        use mocapseg::segment::labelling;
        if seeds.is_empty() {
            return Err("--seeds: give at least one seed".into());
        }
        let started = std::time::Instant::now();
        println!("{}", base.network(classes.len()).describe(NETWORK_FPS));
        let decodings = [("raw", Decoding::RAW), ("decoded", Decoding { min_duration_s: 2.0, switch_cost: 10.0 })];
        let seed_names: Vec<String> = seeds.iter().map(|s| format!("seed {s}")).collect();
        let columns: Vec<String> = seed_names.iter().cloned().chain(["ensemble".to_string()]).collect();
        println!(
            "| held-out take | {} |",
            decodings
                .iter()
                .flat_map(|(d, _)| columns.iter().map(move |c| format!("{c} {d}: acc / edit / F1@50")))
                .collect::<Vec<_>>()
                .join(" | ")
        );
        println!("|---|{}", "---|".repeat(decodings.len() * columns.len()));
        let mut mean = vec![[0.0f64; 3]; decodings.len() * columns.len()];
        for held in 0..motions.len() {
            let mut runs: Vec<(Probabilities, Vec<f64>, usize)> = Vec::new();
            for &seed in seeds {
                let options = TrainOptions { seed, ..base.clone() };
                let p = predict_held_out(motions, labels, held, classes, &options, &knn_fold, NO_EXTRA, &mut |_| true)?;
                runs.push((p.network_probabilities, p.network_source, p.best_epoch));
            }
            let (first, source) = (&runs[0].0, runs[0].1.clone());
            let mut values = vec![0.0f32; first.values.len()];
            for (p, _, _) in &runs {
                if p.values.len() != values.len() {
                    return Err("the seeds' networks labelled different frames".into());
                }
                values.iter_mut().zip(&p.values).for_each(|(v, x)| *v += x / runs.len() as f32);
            }
            let together = Probabilities { frames: first.frames, classes: first.classes, values };
            let truth = &labels[held];
            let mut cells = Vec::new();
            for (d, (_, decoding)) in decodings.iter().enumerate() {
                let all = runs.iter().map(|r| (&r.0, &r.1)).chain(std::iter::once((&together, &source)));
                for (c, (p, src)) in all.enumerate() {
                    let file = file_labels(p, src, NETWORK_FPS, motions[held].frames(), decoding, 0.0);
                    let pred: Vec<Option<usize>> = file.iter().zip(truth).map(|(p, t)| t.and(p.0)).collect();
                    let s = labelling::score(&pred, truth);
                    let row = [s.frame_accuracy, s.edit, s.f1[2]];
                    let k = d * columns.len() + c;
                    for (m, v) in mean[k].iter_mut().zip(row) {
                        *m += v / motions.len() as f64;
                    }
                    cells.push(format!("{:.3} / {:.1} / {:.1}", row[0], row[1], row[2]));
                }
            }
            let epochs: Vec<String> = runs.iter().map(|r| r.2.to_string()).collect();
            println!("| {} (epochs {}) | {} |", motions[held].name, epochs.join(", "), cells.join(" | "));
        }
        println!(
            "| **mean** | {} |",
            mean.iter().map(|m| format!("**{:.3} / {:.1} / {:.1}**", m[0], m[1], m[2])).collect::<Vec<_>>().join(" | ")
        );
        println!("({:.0} s)", started.elapsed().as_secs_f64());
        Ok(())
    }

    /// Leave one class out, every class of every take (see the module docs): per fold the share of the class's frames
    /// and of the other frames called unknown by max-softmax, by the k-NN's distance and by either, and the AUROCs;
    /// by class and pooled.
    fn unseen_every(
        motions: &[Motion],
        labels: &[Vec<Option<usize>>],
        classes: &[String],
        base: &TrainOptions,
    ) -> Result<(), String> {
        use mocapseg::methods::dtfcn::novelty::auroc;
        use mocapseg::methods::knn::training::fit_knn;
        use mocapseg::methods::knn::{Knn, KnnParams};
        let started = std::time::Instant::now();
        let holds = |i: usize, c: usize| labels[i].contains(&Some(c));
        // per working frame (at `source`): the distance to `knn`'s nearest training window over the take's median
        let distances = |knn: &Knn, m: &Motion, source: &[f64]| -> Result<Vec<f32>, String> {
            let d = crate::common::over_median(&knn.nearest_distances(m)?);
            Ok(source.iter().map(|s| d[(s.round() as usize).min(d.len().saturating_sub(1))]).collect())
        };
        let quantile = crate::common::threshold_for_share;
        println!("| held-out take | class left out | validation take | max-softmax (10 %): unseen / seen called unknown | k-NN distance (10 %) | max-softmax or distance (5 % each) | deep k-NN (10 %) | distance or deep k-NN (5 % each) | AUROC max-softmax / distance / deep k-NN |");
        println!("|---|---|---|---|---|---|---|---|---|");
        let (mut pooled_c, mut pooled_d): (Vec<(f32, bool)>, Vec<(f32, bool)>) = (Vec::new(), Vec::new());
        let mut pooled_q: Vec<(f32, bool)> = Vec::new();
        let (mut sums, mut rows) = ([0.0f64; 10], 0usize);
        let mut per_class = vec![[0.0f64; 11]; classes.len()];
        for held in 0..motions.len() {
            for gone in 0..classes.len() {
                if !holds(held, gone) || !(0..motions.len()).any(|i| i != held && holds(i, gone)) {
                    continue;
                }
                let without: Vec<Vec<Option<usize>>> =
                    labels.iter().map(|l| l.iter().map(|x| x.filter(|&c| c != gone)).collect()).collect();
                let p = predict_held_out(motions, &without, held, classes, base, &knn_fold, NO_EXTRA, &mut |_| true)?;
                // thresholds from the validation take's frames of taught classes, under the validation network and a
                // k-NN fitted on the same takes (neither the held-out nor the validation take)
                let inner: Vec<(&Motion, &[Option<usize>])> = (0..motions.len())
                    .filter(|&i| i != held && i != p.validation)
                    .map(|i| (&motions[i], without[i].as_slice()))
                    .collect();
                let inner_knn = fit_knn(&inner, KnnParams::default())?;
                let val_distance = distances(&inner_knn, &motions[p.validation], &p.validation_source)?;
                let val = frames_of(
                    &p.validation_probabilities,
                    &val_distance,
                    &p.validation_source,
                    &labels[p.validation],
                    gone,
                );
                let seen_c: Vec<f32> = val.iter().filter(|f| !f.2).map(|f| f.0).collect();
                let seen_d: Vec<f32> = val.iter().filter(|f| !f.2).map(|f| f.1).collect();
                let (tc, td) = (quantile(seen_c.clone(), 0.10, true), quantile(seen_d.clone(), 0.10, false));
                let (tc5, td5) = (quantile(seen_c, 0.05, true), quantile(seen_d, 0.05, false));
                let held_distance = distances(&p.knn_model, &motions[held], &p.network_source)?;
                let out = frames_of(&p.network_probabilities, &held_distance, &p.network_source, &labels[held], gone);
                // the deep k-NN of each network, its bank the labelled frames of the takes it was trained on
                let takes = |skip: &[usize]| training_takes(motions, &without, skip);
                let k = classes.len();
                let val_deep =
                    deep_knn(&p.validation_network, &takes(&[held, p.validation])?, &motions[p.validation], k)?;
                let val_deep = frames_of(
                    &p.validation_probabilities,
                    &val_deep,
                    &p.validation_source,
                    &labels[p.validation],
                    gone,
                );
                let seen_q: Vec<f32> = val_deep.iter().filter(|f| !f.2).map(|f| f.1).collect();
                let (tq, tq5) = (quantile(seen_q.clone(), 0.10, false), quantile(seen_q, 0.05, false));
                let held_deep = deep_knn(&p.final_network, &takes(&[held])?, &motions[held], k)?;
                let deep = frames_of(&p.network_probabilities, &held_deep, &p.network_source, &labels[held], gone);
                // (distance, deep k-NN, unseen) per labelled frame: `out` and `deep` hold the same frames in turn
                let both: Vec<(f32, f32, bool)> = out.iter().zip(&deep).map(|(a, b)| (a.1, b.1, a.2)).collect();
                let r = [
                    rates(&out, &|f| f.0 < tc),
                    rates(&out, &|f| f.1 > td),
                    rates(&out, &|f| f.0 < tc5 || f.1 > td5),
                    rates(&deep, &|f| f.1 > tq),
                    rates(&both, &|f| f.0 > td5 || f.1 > tq5),
                ];
                let by_c: Vec<(f32, bool)> = out.iter().map(|f| (-f.0, f.2)).collect();
                let by_d: Vec<(f32, bool)> = out.iter().map(|f| (f.1, f.2)).collect();
                let by_q: Vec<(f32, bool)> = deep.iter().map(|f| (f.1, f.2)).collect();
                let pct = |(a, b): (f64, f64)| format!("{:.0} % / {:.0} %", a * 100.0, b * 100.0);
                println!(
                    "| {} | {} | {} | {} | {} | {} | {} | {} | {:.2} / {:.2} / {:.2} |",
                    motions[held].name,
                    classes[gone],
                    motions[p.validation].name,
                    pct(r[0]),
                    pct(r[1]),
                    pct(r[2]),
                    pct(r[3]),
                    pct(r[4]),
                    auroc(&by_c),
                    auroc(&by_d),
                    auroc(&by_q)
                );
                for (k, x) in r.iter().flat_map(|(a, b)| [*a, *b]).enumerate() {
                    sums[k] += x;
                    per_class[gone][k] += x;
                }
                rows += 1;
                per_class[gone][10] += 1.0;
                pooled_c.extend(by_c);
                pooled_d.extend(by_d);
                pooled_q.extend(by_q);
            }
        }
        let n = rows.max(1) as f64;
        let pct = |a: f64, b: f64| format!("**{:.0} % / {:.0} %**", 100.0 * a / n, 100.0 * b / n);
        println!(
            "| **mean** ({rows} folds) | | | {} | {} | {} | {} | {} | pooled **{:.2} / {:.2} / {:.2}** |",
            pct(sums[0], sums[1]),
            pct(sums[2], sums[3]),
            pct(sums[4], sums[5]),
            pct(sums[6], sums[7]),
            pct(sums[8], sums[9]),
            auroc(&pooled_c),
            auroc(&pooled_d),
            auroc(&pooled_q)
        );
        println!();
        crate::common::print_rates_by_class(
            &[
                "max-softmax: unseen / seen called unknown",
                "k-NN distance",
                "max-softmax or distance",
                "deep k-NN",
                "distance or deep k-NN",
            ],
            classes,
            &per_class,
        );
        println!("({:.0} s)", started.elapsed().as_secs_f64());
        Ok(())
    }

    /// Every take but those of `skip` as training takes under `labels` (what a network of a fold was trained on).
    fn training_takes(
        motions: &[Motion],
        labels: &[Vec<Option<usize>>],
        skip: &[usize],
    ) -> Result<Vec<TrainingTake>, String> {
        (0..motions.len()).filter(|i| !skip.contains(i)).map(|i| TrainingTake::new(&motions[i], &labels[i])).collect()
    }

    /// Deep k-NN (Sun et al. 2022; not in the paper): per working frame of `motion`, the cosine distance of its
    /// last-layer activations before NormReLU, L2-normalised, to the [`DEEP_K`]-th nearest of every third labelled
    /// working frame of `takes` (what `trained` was trained on) — a distance in the network's own feature space,
    /// without the one shared covariance of the Mahalanobis score. By brute force (a lab measurement).
    fn deep_knn(
        trained: &Trained,
        takes: &[TrainingTake],
        motion: &Motion,
        classes: usize,
    ) -> Result<Vec<f32>, String> {
        use mocapseg::labeller::input::{network_input, NetworkInput};
        use mocapseg::methods::dtfcn::infer::predict_with_features;
        let features = |input: &NetworkInput| -> (usize, Vec<f32>) {
            let (_, mut f) = predict_with_features(&trained.net, &trained.standardise, input, classes);
            let width = f.len() / input.frames.max(1);
            for row in f.chunks_mut(width.max(1)) {
                let norm = row.iter().map(|x| x * x).sum::<f32>().sqrt().max(1e-12);
                row.iter_mut().for_each(|x| *x /= norm);
            }
            (width, f)
        };
        let mut bank = Vec::new();
        let mut width = 0;
        for t in takes {
            let (w, f) = features(&t.input);
            width = w;
            for (i, l) in t.labels.iter().enumerate() {
                if l.is_some() && i % 3 == 0 {
                    bank.extend_from_slice(&f[i * w..(i + 1) * w]);
                }
            }
        }
        let n = bank.len() / width.max(1);
        if n <= DEEP_K {
            return Err(format!("deep k-NN: {n} training frames, fewer than k = {DEEP_K}"));
        }
        let (_, f) = features(&network_input(motion)?);
        Ok(f.chunks(width)
            .map(|q| {
                let mut d: Vec<f32> =
                    bank.chunks(width).map(|b| 1.0 - q.iter().zip(b).map(|(x, y)| x * y).sum::<f32>()).collect();
                d.select_nth_unstable_by(DEEP_K - 1, f32::total_cmp);
                d[DEEP_K - 1]
            })
            .collect())
    }

    /// The deep k-NN's k (Sun et al. use 50 of 50,000 training images; a tenth of a second of frames here).
    const DEEP_K: usize = 10;

    /// Per working frame of a take: (confidence, novelty, whether its true class is the one left out), for its
    /// labelled frames.
    fn frames_of(
        probabilities: &mocapseg::labeller::probabilities::Probabilities,
        novelty: &[f32],
        source: &[f64],
        truth: &[Option<usize>],
        gone: usize,
    ) -> Vec<(f32, f32, bool)> {
        (0..probabilities.frames)
            .filter_map(|t| {
                let f = (source[t].round() as usize).min(truth.len().saturating_sub(1));
                truth[f].map(|l| (probabilities.best(t).1, novelty[t], l == gone))
            })
            .collect()
    }

    /// Unseen frames called unknown, and seen frames called unknown, by `unknown(frame)`.
    fn rates(frames: &[(f32, f32, bool)], unknown: &dyn Fn(&(f32, f32, bool)) -> bool) -> (f64, f64) {
        let unseen = frames.iter().filter(|f| f.2).count().max(1) as f64;
        let seen = frames.iter().filter(|f| !f.2).count().max(1) as f64;
        let tp = frames.iter().filter(|f| f.2 && unknown(f)).count() as f64;
        let fp = frames.iter().filter(|f| !f.2 && unknown(f)).count() as f64;
        (tp / unseen, fp / seen)
    }

    /// The threshold of `grid` that calls the most unseen frames unknown while calling at most 10 % of the seen
    /// ones (the least false alarms if none does).
    fn choose(frames: &[(f32, f32, bool)], grid: &[f32], unknown: &dyn Fn(&(f32, f32, bool), f32) -> bool) -> f32 {
        let mut best: Option<(f64, f64, f32)> = None;
        for &t in grid {
            let (tpr, fpr) = rates(frames, &|f| unknown(f, t));
            let better = match best {
                None => true,
                Some((btpr, bfpr, _)) => {
                    if fpr <= 0.10 {
                        bfpr > 0.10 || tpr > btpr
                    } else {
                        bfpr > 0.10 && fpr < bfpr
                    }
                }
            };
            if better {
                best = Some((tpr, fpr, t));
            }
        }
        best.map_or(grid[0], |b| b.2)
    }

    /// Leave one class out (see the module docs): in each fold the held-out take's largest class is removed from
    /// training altogether. Two unknowns are compared on the held-out take: max-softmax below a threshold, and the
    /// novelty score (Mahalanobis distance before NormReLU, `dtfcn::novelty`) above one — each threshold chosen on
    /// the fold's validation take (whose frames of the removed class the validation network never saw either),
    /// never on the held-out take. AUROC pooled over the held-out takes.
    fn unseen(
        motions: &[Motion],
        labels: &[Vec<Option<usize>>],
        classes: &[String],
        base: &TrainOptions,
    ) -> Result<(), String> {
        use mocapseg::methods::dtfcn::novelty::auroc;
        let confidence_grid: Vec<f32> = (1..=39).map(|i| i as f32 * 0.025).collect();
        let novelty_grid: Vec<f32> = (0..=80).map(|i| 0.5 + i as f32 * 0.05).collect();
        let mut pooled: Vec<(f32, f32, bool)> = Vec::new();
        let mut knn_pooled: Vec<(f32, bool)> = Vec::new();
        let mut distance_pooled: Vec<(f32, bool)> = Vec::new();
        // (take, class left out, chosen confidence threshold, its TPR, FPR, chosen novelty threshold, its TPR, FPR)
        println!("| held-out take | class left out | max-softmax: threshold (chosen on) → unseen / seen called unknown | novelty: threshold → unseen / seen called unknown | AUROC max-softmax / novelty |");
        println!("|---|---|---|---|---|");
        let (mut tpr_c, mut fpr_c, mut tpr_n, mut fpr_n) = (0.0, 0.0, 0.0, 0.0);
        for held in 0..motions.len() {
            let mut counts = vec![0usize; classes.len()];
            labels[held].iter().flatten().for_each(|&c| counts[c] += 1);
            let gone = (0..classes.len()).max_by_key(|&c| counts[c]).unwrap_or(0);
            let without: Vec<Vec<Option<usize>>> =
                labels.iter().map(|l| l.iter().map(|x| x.filter(|&c| c != gone)).collect()).collect();
            let p = predict_held_out(motions, &without, held, classes, base, &knn_fold, NO_EXTRA, &mut |_| true)?;
            // the novelty of each network, fitted on the takes it was trained on (labels without the class)
            let takes = |skip: &[usize]| training_takes(motions, &without, skip);
            let k = classes.len();
            let validation_novelty =
                novelty_scores(&p.validation_network, &takes(&[held, p.validation])?, k, &motions[p.validation])?;
            let held_novelty = novelty_scores(&p.final_network, &takes(&[held])?, k, &motions[held])?;
            let knn_distance = p.knn_model.nearest_distances(&motions[held])?;
            let val = frames_of(
                &p.validation_probabilities,
                &validation_novelty,
                &p.validation_source,
                &labels[p.validation],
                gone,
            );
            let out = frames_of(&p.network_probabilities, &held_novelty, &p.network_source, &labels[held], gone);
            let conf = |f: &(f32, f32, bool), t: f32| f.0 < t;
            let nov = |f: &(f32, f32, bool), t: f32| f.1 > t;
            let tc = choose(&val, &confidence_grid, &conf);
            let tn = choose(&val, &novelty_grid, &nov);
            let (a, b) = rates(&out, &|f| conf(f, tc));
            let (c, d) = rates(&out, &|f| nov(f, tn));
            let auc_c = auroc(&out.iter().map(|f| (-f.0, f.2)).collect::<Vec<_>>());
            let auc_n = auroc(&out.iter().map(|f| (f.1, f.2)).collect::<Vec<_>>());
            println!(
                "| {} | {} | {tc:.3} ({}) → {:.0} % / {:.0} % | {tn:.2} → {:.0} % / {:.0} % | {auc_c:.2} / {auc_n:.2} |",
                motions[held].name,
                classes[gone],
                motions[p.validation].name,
                a * 100.0,
                b * 100.0,
                c * 100.0,
                d * 100.0
            );
            let n = motions.len() as f64;
            tpr_c += a / n;
            fpr_c += b / n;
            tpr_n += c / n;
            fpr_n += d / n;
            pooled.extend(out);
            for (f, l) in labels[held].iter().enumerate() {
                if let Some(l) = l {
                    knn_pooled.push((-p.knn[f].1, *l == gone));
                    distance_pooled.push((knn_distance[f], *l == gone));
                }
            }
        }
        let auc_c = auroc(&pooled.iter().map(|f| (-f.0, f.2)).collect::<Vec<_>>());
        let auc_n = auroc(&pooled.iter().map(|f| (f.1, f.2)).collect::<Vec<_>>());
        println!(
            "| **mean** | | → **{:.0} % / {:.0} %** | → **{:.0} % / {:.0} %** | pooled **{auc_c:.2} / {auc_n:.2}** |",
            tpr_c * 100.0,
            fpr_c * 100.0,
            tpr_n * 100.0,
            fpr_n * 100.0
        );
        println!();
        println!(
            "k-NN, pooled over the held-out takes: AUROC of the vote share {:.2}, of the distance to the nearest \
             training window {:.2}",
            auroc(&knn_pooled),
            auroc(&distance_pooled)
        );
        Ok(())
    }
}
