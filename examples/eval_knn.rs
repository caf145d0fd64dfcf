//! Lab tool, not part of the product: the k-NN labeller (`mocapseg::methods::knn`, the baseline the DT-FCN
//! must beat) scored leave-one-take-out on the four mocap6 exercise takes of the shared data:
//! fit on three, label the fourth, score its frames against the ground truth (frame accuracy,
//! edit, F1@{10,25,50}, mean vote share). Nothing is tuned: the window (±1 s, every 5th frame),
//! k = 5 and 32 principal coordinates are the issue's prototype's. Says so and fails when the
//! shared data is absent.
//!
//! `unseen`: leave one class out, every class of every take in turn — can the k-NN tell frames of a
//! class it was never taught? Its score is the frame's distance to the nearest training window over
//! the model's own familiar distance (the median distance from a training window to the training
//! windows at least 2 s away, as the take fit measures it), so one threshold means the same for
//! models fitted on different takes; the threshold is chosen on inner folds (each other take that
//! holds the class, scored by a model fitted without it and without the class) as the one calling
//! the most of the class's frames unknown while calling at most 10 % of the other frames unknown
//! there, never on the reported take. Beside each fold's model-relative figures, *outlier exposure* (issue 50): the
//! share of the frames of the shared data's takes that hold no exercise (the locomotion clips, 86_01, the other
//! exporters' BVHs with the canonical joints) that the fold's threshold calls unknown, with the fold's model. A third score gives each frame the mean take-relative distance of its run
//! under the shipped exercises k-NN's decoding (runs ≥ 2 s, switch cost 150). The vote share's AUROC is printed
//! beside them. Four *class-relative* scores follow (per-class scales instead of one for the model): a frame's
//! distance to the nearest training window of each class over that class's own repeat distance
//! (`Knn::class_distances`, `Knn::class_familiar`), the least over the classes or the voted class's, each as it is
//! and over the take's own median; thresholds chosen on the same inner folds.
//!
//! ```text
//! cargo run --release --example eval_knn -- [--data ../shared/data] [unseen [--half-window-s 0.5 --k 9]]
//! ```

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
    use std::time::Instant;

    use mocapseg::labeller::openset::{choose_open_set, open_set_scores, OpenSetFrame, OpenSetScores};
    use mocapseg::methods::knn::{Knn, KnnParams, Labelled};
    use mocapseg::motion::Motion;
    use mocapseg::segment::labelling;

    #[derive(clap::Parser)]
    #[command(about = "Score the k-NN labeller leave-one-take-out on the mocap6 takes")]
    pub struct Args {
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
        /// `folds` (leave one take out) or `unseen` (leave one class out, see the module docs).
        #[arg(default_value = "folds")]
        experiment: String,
        /// `unseen`, the open-set unknown as models are made with it: the k-NN's half window in seconds (its training
        /// table's `half_window_s`) and votes (`k`); the defaults the shipped models'.
        #[arg(long, default_value_t = 1.0)]
        half_window_s: f64,
        #[arg(long, default_value_t = 5)]
        k: usize,
    }

    pub fn run(args: Args) -> Result<(), String> {
        let takes: Vec<_> =
            crate::common::labelled_takes(&args.data)?.into_iter().filter(|t| t.trial != "86_01").collect();
        if takes.len() < 2 {
            return Err("need at least two mocap6 takes".into());
        }
        let mut names: Vec<String> = Vec::new();
        let mut loaded: Vec<(String, Motion, Vec<usize>)> = Vec::new();
        for t in takes {
            let text = std::fs::read_to_string(&t.bvh).map_err(|e| format!("{}: {e}", t.bvh.display()))?;
            let b = mocapseg::bvh::parse(&text).map_err(|e| format!("{}: {e}", t.bvh.display()))?;
            let motion = Motion::from_bvh(t.trial, &b).map_err(|e| e.to_string())?;
            let mut labels = vec![0usize; motion.frames()];
            for s in &t.truth.segments {
                let k = names.iter().position(|n| *n == s.label).unwrap_or_else(|| {
                    names.push(s.label.clone());
                    names.len() - 1
                });
                for l in labels.iter_mut().take(s.end + 1).skip(s.start) {
                    *l = k;
                }
            }
            loaded.push((t.trial.to_string(), motion, labels));
        }
        match args.experiment.as_str() {
            "folds" => {}
            "unseen" => {
                let params = KnnParams {
                    half_window: (args.half_window_s * 30.0 / 5.0).round() as i32 * 5,
                    k: args.k,
                    ..KnnParams::default()
                };
                params.check()?;
                return unseen(&loaded, &names, &outliers(&args.data)?, params);
            }
            other => return Err(format!("unknown experiment `{other}`: folds or unseen")),
        }
        println!("k-NN (k 5, ±1 s window every 5th frame, 32 principal coordinates), leave one take out:");
        println!("| held-out take | frame accuracy | edit | F1@10 | F1@25 | F1@50 | mean vote share | fit + label |");
        println!("|---|---|---|---|---|---|---|---|");
        let mut sums = [0.0; 6];
        for k in 0..loaded.len() {
            let started = Instant::now();
            let train: Vec<Labelled> = loaded
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != k)
                .map(|(_, (_, m, l))| Labelled { motion: m, labels: l })
                .collect();
            let knn = Knn::fit(&train, KnnParams::default())?;
            let (name, motion, truth) = &loaded[k];
            let predicted = knn.predict(motion)?;
            let pred: Vec<Option<usize>> = predicted.iter().map(|p| Some(p.0)).collect();
            let truth: Vec<Option<usize>> = truth.iter().map(|&t| Some(t)).collect();
            let s = labelling::score(&pred, &truth);
            let confidence = predicted.iter().map(|p| p.1 as f64).sum::<f64>() / predicted.len().max(1) as f64;
            let row = [s.frame_accuracy, s.edit, s.f1[0], s.f1[1], s.f1[2], confidence];
            for (a, b) in sums.iter_mut().zip(row) {
                *a += b / loaded.len() as f64;
            }
            println!(
                "| {name} | {:.3} | {:.1} | {:.1} | {:.1} | {:.1} | {:.2} | {:.1} s |",
                row[0],
                row[1],
                row[2],
                row[3],
                row[4],
                row[5],
                started.elapsed().as_secs_f64()
            );
        }
        println!(
            "| **mean** | **{:.3}** | **{:.1}** | **{:.1}** | **{:.1}** | **{:.1}** | **{:.2}** | |",
            sums[0], sums[1], sums[2], sums[3], sums[4], sums[5]
        );
        Ok(())
    }

    /// Per file frame of `motion` under a k-NN fitted on `train` (labels without the class left out): its distance
    /// to the nearest training window over the model's median familiar distance, the same over the take's own median
    /// distance, and the vote share of the winning label.
    fn scores(
        train: &[(&Motion, Vec<Option<usize>>)],
        motion: &Motion,
        classes: usize,
    ) -> Result<(Vec<[f32; S]>, Vec<Option<usize>>), String> {
        use mocapseg::labeller::decode::{file_labels, Decoding};
        use mocapseg::labeller::fit::{FAMILIAR_GAP, FAMILIAR_SAMPLES};
        use mocapseg::methods::knn::training::fit_knn;
        let takes: Vec<(&Motion, &[Option<usize>])> = train.iter().map(|(m, l)| (*m, l.as_slice())).collect();
        let knn = fit_knn(&takes, KnnParams::default())?;
        let mut familiar = knn.familiar_distances(FAMILIAR_GAP, FAMILIAR_SAMPLES);
        let scale = mocapseg::stats::median(&mut familiar).filter(|d| *d > 0.0).unwrap_or(1.0);
        let distances = knn.nearest_distances(motion)?;
        let votes = knn.predict(motion)?;
        let own = crate::common::over_median(&distances);
        // the run each file frame belongs to under the shipped exercises k-NN's decoding (runs ≥ 2 s, switch cost 150)
        let (p, source) = knn.probabilities_at(motion, classes)?;
        let decoding = Decoding { min_duration_s: 2.0, switch_cost: 150.0 };
        let decoded = file_labels(&p, &source, KnnParams::default().fps, motion.frames(), &decoding, 0.0);
        let mut run_mean = vec![0.0f32; distances.len()];
        // the decoded run's mean probability (what the run's unknown threshold reads under this decoding)
        let mut run_prob = vec![0.0f32; distances.len()];
        let mut start = 0;
        for f in 1..=decoded.len() {
            if f == decoded.len() || decoded[f].0 != decoded[start].0 {
                let mean = own[start..f].iter().sum::<f32>() / (f - start) as f32;
                run_mean[start..f].iter_mut().for_each(|m| *m = mean);
                let prob = decoded[start..f].iter().map(|d| d.1).sum::<f32>() / (f - start) as f32;
                run_prob[start..f].iter_mut().for_each(|m| *m = prob);
                start = f;
            }
        }
        // class-relative: each class's nearest window over that class's own repeat distance
        let by_class = knn.class_distances(motion, classes)?;
        let class_scale = knn.class_familiar(classes, FAMILIAR_GAP, FAMILIAR_SAMPLES);
        let ratio = |f: usize, c: usize| match class_scale[c] {
            Some(s) if s > 0.0 => by_class[f][c] / s,
            _ => f32::INFINITY,
        };
        let min_ratio: Vec<f32> =
            (0..distances.len()).map(|f| (0..classes).map(|c| ratio(f, c)).fold(f32::INFINITY, f32::min)).collect();
        let voted: Vec<f32> = (0..distances.len()).map(|f| ratio(f, votes[f].0)).collect();
        let (min_own, voted_own) = (crate::common::over_median(&min_ratio), crate::common::over_median(&voted));
        let scores = (0..distances.len())
            .map(|f| {
                [
                    distances[f] / scale,
                    own[f],
                    votes[f].1,
                    run_mean[f],
                    min_ratio[f],
                    min_own[f],
                    voted[f],
                    voted_own[f],
                    -run_prob[f],
                ]
            })
            .collect();
        Ok((scores, decoded.iter().map(|d| d.0).collect()))
    }

    /// (score, whether the frame's class is `gone`) for every frame of a take.
    fn marked(scores: &[[f32; S]], labels: &[usize], gone: usize, pick: impl Fn(&[f32; S]) -> f32) -> Vec<(f32, bool)> {
        scores.iter().zip(labels).map(|(s, &l)| (pick(s), l == gone)).collect()
    }

    const S: usize = 9;

    /// Share of the unseen frames and of the seen frames scoring above `threshold`.
    fn rates(frames: &[(f32, bool)], threshold: f32) -> (f64, f64) {
        let count = |unseen: bool| frames.iter().filter(|f| f.1 == unseen).count().max(1) as f64;
        let above = |unseen: bool| frames.iter().filter(|f| f.1 == unseen && f.0 > threshold).count() as f64;
        (above(true) / count(true), above(false) / count(false))
    }

    /// The takes of the shared data that hold none of the exercises (outlier exposure, issue 50): the locomotion clips,
    /// 86_01 (walks, jumps, punches) and the other exporters' BVHs — those with the canonical joints (the k-NN cannot
    /// read the others at all; they are named and left out).
    fn outliers(data: &std::path::Path) -> Result<Vec<(String, Motion)>, String> {
        let mut files: Vec<std::path::PathBuf> = Vec::new();
        for dir in ["cmu/locomotion", "cmu/86", "misc-bvh"] {
            let dir = data.join(dir);
            let Ok(entries) = std::fs::read_dir(&dir) else {
                eprintln!("note: {} is absent: no outlier takes from it", dir.display());
                continue;
            };
            files.extend(
                entries.filter_map(|e| e.ok().map(|e| e.path())).filter(|p| p.extension().is_some_and(|x| x == "bvh")),
            );
        }
        files.sort();
        let mut out = Vec::new();
        for f in files {
            let name = f.file_stem().unwrap_or_default().to_string_lossy().to_string();
            let text = std::fs::read_to_string(&f).map_err(|e| format!("{}: {e}", f.display()))?;
            let motion = mocapseg::bvh::parse(&text)
                .map_err(|e| e.to_string())
                .and_then(|b| Motion::from_bvh(&name, &b).map_err(|e| e.to_string()));
            match motion {
                Ok(m) if m.joint_map().is_ok() && m.frames() >= 30 => out.push((name, m)),
                Ok(_) => {
                    eprintln!("note: {name} left out of the outlier takes: no canonical joints or under 30 frames")
                }
                Err(e) => eprintln!("note: {name} left out of the outlier takes: {e}"),
            }
        }
        Ok(out)
    }

    /// The share of the frames of `outliers` (takes of no taught class) whose distance to the nearest training window
    /// of a k-NN fitted on `train`, over its familiar distance, is above `threshold`: each take's share, then their
    /// mean (each take weighs the same, whatever its length).
    fn outlier_share(
        train: &[(&Motion, Vec<Option<usize>>)],
        outliers: &[(String, Motion)],
        threshold: f32,
    ) -> Result<f64, String> {
        use mocapseg::labeller::fit::{FAMILIAR_GAP, FAMILIAR_SAMPLES};
        use mocapseg::methods::knn::training::fit_knn;
        let takes: Vec<(&Motion, &[Option<usize>])> = train.iter().map(|(m, l)| (*m, l.as_slice())).collect();
        let knn = fit_knn(&takes, KnnParams::default())?;
        let mut familiar = knn.familiar_distances(FAMILIAR_GAP, FAMILIAR_SAMPLES);
        let scale = mocapseg::stats::median(&mut familiar).filter(|d| *d > 0.0).unwrap_or(1.0);
        let mut sum = 0.0;
        for (_, m) in outliers {
            let d = knn.nearest_distances(m)?;
            sum += d.iter().filter(|&&x| x / scale > threshold).count() as f64 / d.len().max(1) as f64;
        }
        Ok(sum / outliers.len().max(1) as f64)
    }

    /// The threshold calling the most unseen frames unknown while calling at most 10 % of the seen ones.
    fn choose(frames: &[(f32, bool)]) -> f32 {
        crate::common::threshold_for_share(frames.iter().filter(|f| !f.1).map(|f| f.0).collect(), 0.10, false)
    }

    fn unseen(
        loaded: &[(String, Motion, Vec<usize>)],
        names: &[String],
        outliers: &[(String, Motion)],
        shipped: KnnParams,
    ) -> Result<(), String> {
        use mocapseg::methods::dtfcn::novelty::auroc;
        let started = Instant::now();
        let without = |i: usize, gone: usize| -> Vec<Option<usize>> {
            loaded[i].2.iter().map(|&l| (l != gone).then_some(l)).collect()
        };
        let holds = |i: usize, c: usize| loaded[i].2.contains(&c);
        println!(
            "k-NN unknown, leave one class out: a frame is unknown when its distance to the nearest training window, over the model's familiar distance or over the take's own median distance, is above a threshold chosen on the inner takes:"
        );
        println!(
            "| held-out take | class left out | inner takes | model-relative: threshold → unseen / seen called unknown | take-relative: threshold → unseen / seen | decoded runs, take-relative | AUROC model-relative / take-relative / runs / vote share |"
        );
        println!("|---|---|---|---|---|---|---|");
        let mut pooled: [Vec<(f32, bool)>; 4] = Default::default();
        let mut class_sums = [[0.0f64; 2]; 4];
        let mut class_pooled: [Vec<(f32, bool)>; 4] = Default::default();
        let mut class_per_class: Vec<[f64; 9]> = vec![[0.0; 9]; names.len()];
        let (mut sums, mut rows) = ([0.0f64; 6], 0usize);
        // outlier exposure: per fold, the share of the outlier takes' frames the fold's model-relative threshold calls
        // unknown
        let mut outlier_sum = 0.0f64;
        println!(
            "outlier takes (no exercise; outlier exposure): {}",
            outliers.iter().map(|o| o.0.as_str()).collect::<Vec<_>>().join(", ")
        );
        let mut per_class: Vec<[f64; 7]> = vec![[0.0; 7]; names.len()];
        let mut open_folds: Vec<OpenSetFold> = Vec::new();
        for h in 0..loaded.len() {
            for gone in 0..names.len() {
                let others: Vec<usize> = (0..loaded.len()).filter(|&i| i != h).collect();
                if !holds(h, gone) || !others.iter().any(|&i| holds(i, gone)) {
                    continue;
                }
                // inner folds: every other take holding the class, scored by a model without it and without the class
                let (mut inner, mut inner_own, mut inner_run) = (Vec::new(), Vec::new(), Vec::new());
                let mut inner_class: [Vec<(f32, bool)>; 4] = Default::default();
                let mut inner_names = Vec::new();
                let mut inner_open: [Vec<OpenSetFrame>; 3] = Default::default();
                for &v in others.iter().filter(|&&v| holds(v, gone)) {
                    let train: Vec<(&Motion, Vec<Option<usize>>)> =
                        others.iter().filter(|&&i| i != v).map(|&i| (&loaded[i].1, without(i, gone))).collect();
                    let (s, decoded) = scores(&train, &loaded[v].1, names.len())?;
                    for (j, &(k, _)) in OPEN_SET.iter().enumerate() {
                        inner_open[j].extend(open_frames(&s, &decoded, &loaded[v].2, gone, k));
                    }
                    inner.extend(marked(&s, &loaded[v].2, gone, |x| x[0]));
                    inner_own.extend(marked(&s, &loaded[v].2, gone, |x| x[1]));
                    inner_run.extend(marked(&s, &loaded[v].2, gone, |x| x[3]));
                    for (k, c) in inner_class.iter_mut().enumerate() {
                        c.extend(marked(&s, &loaded[v].2, gone, |x| x[4 + k]));
                    }
                    inner_names.push(loaded[v].0.clone());
                }
                let (threshold, threshold_own, threshold_run) =
                    (choose(&inner), choose(&inner_own), choose(&inner_run));
                let train: Vec<(&Motion, Vec<Option<usize>>)> =
                    others.iter().map(|&i| (&loaded[i].1, without(i, gone))).collect();
                let (s, decoded) = scores(&train, &loaded[h].1, names.len())?;
                // the open-set objective: each score's threshold chosen on the inner folds' open-set accuracy
                let mut fold = OpenSetFold {
                    take: h,
                    never: open_set_scores(&open_frames(&s, &decoded, &loaded[h].2, gone, 0), f32::INFINITY),
                    chosen: Vec::new(),
                    outlier: 0.0,
                };
                for (j, &(k, _)) in OPEN_SET.iter().enumerate() {
                    let t = choose_open_set(&inner_open[j]);
                    let inner_at = open_set_scores(&inner_open[j], t).accuracy;
                    let held = open_set_scores(&open_frames(&s, &decoded, &loaded[h].2, gone, k), t);
                    fold.chosen.push((t, inner_at, held));
                }
                let t0 = fold.chosen[0].0;
                fold.outlier = if t0.is_finite() { outlier_share(&train, outliers, t0)? } else { 0.0 };
                open_folds.push(fold);
                let d = marked(&s, &loaded[h].2, gone, |x| x[0]);
                let o = marked(&s, &loaded[h].2, gone, |x| x[1]);
                let v = marked(&s, &loaded[h].2, gone, |x| -x[2]);
                let r = marked(&s, &loaded[h].2, gone, |x| x[3]);
                let (tpr_r, fpr_r) = rates(&r, threshold_run);
                for k in 0..4 {
                    let t = choose(&inner_class[k]);
                    let held = marked(&s, &loaded[h].2, gone, |x| x[4 + k]);
                    let (tp, fp) = rates(&held, t);
                    class_sums[k][0] += tp;
                    class_sums[k][1] += fp;
                    class_per_class[gone][2 * k] += tp;
                    class_per_class[gone][2 * k + 1] += fp;
                    class_pooled[k].extend(held);
                }
                let (tpr, fpr) = rates(&d, threshold);
                let (tpr_o, fpr_o) = rates(&o, threshold_own);
                let outlier = outlier_share(&train, outliers, threshold)?;
                outlier_sum += outlier;
                println!(
                    "| {} | {} | {} | {threshold:.2} → {:.0} % / {:.0} % (outlier takes {:.0} %) | {threshold_own:.2} → {:.0} % / {:.0} % | {threshold_run:.2} → {:.0} % / {:.0} % | {:.2} / {:.2} / {:.2} / {:.2} |",
                    loaded[h].0,
                    names[gone],
                    inner_names.join(", "),
                    tpr * 100.0,
                    fpr * 100.0,
                    outlier * 100.0,
                    tpr_o * 100.0,
                    fpr_o * 100.0,
                    tpr_r * 100.0,
                    fpr_r * 100.0,
                    auroc(&d),
                    auroc(&o),
                    auroc(&r),
                    auroc(&v)
                );
                for (k, x) in [tpr, fpr, tpr_o, fpr_o, tpr_r, fpr_r].into_iter().enumerate() {
                    sums[k] += x;
                    per_class[gone][k] += x;
                }
                rows += 1;
                per_class[gone][6] += 1.0;
                class_per_class[gone][8] += 1.0;
                pooled[0].extend(d);
                pooled[1].extend(o);
                pooled[2].extend(r);
                pooled[3].extend(v);
            }
        }
        let n = rows.max(1) as f64;
        println!(
            "| **mean** ({rows} folds) | | | → **{:.0} % / {:.0} %** (outlier takes **{:.0} %**) | → **{:.0} % / {:.0} %** | → **{:.0} % / {:.0} %** | pooled **{:.2} / {:.2} / {:.2} / {:.2}** |",
            100.0 * sums[0] / n,
            100.0 * sums[1] / n,
            100.0 * outlier_sum / n,
            100.0 * sums[2] / n,
            100.0 * sums[3] / n,
            100.0 * sums[4] / n,
            100.0 * sums[5] / n,
            auroc(&pooled[0]),
            auroc(&pooled[1]),
            auroc(&pooled[2]),
            auroc(&pooled[3])
        );
        for (k, name) in [
            "class-relative (min over classes)",
            "class-relative, over the take's median",
            "voted class's ratio",
            "voted class's ratio, over the take's median",
        ]
        .iter()
        .enumerate()
        {
            println!(
                "{name}: {:.0} % / {:.0} %, pooled AUROC {:.2}",
                100.0 * class_sums[k][0] / n,
                100.0 * class_sums[k][1] / n,
                auroc(&class_pooled[k])
            );
        }
        println!();
        crate::common::print_rates_by_class(
            &["model-relative: unseen / seen called unknown", "take-relative", "decoded runs"],
            names,
            &per_class,
        );
        println!();
        crate::common::print_rates_by_class(
            &[
                "class-relative: unseen / seen called unknown",
                "class-relative, take-relative",
                "voted class's ratio",
                "voted class's ratio, take-relative",
            ],
            names,
            &class_per_class,
        );
        println!();
        print_open_set(&open_folds, loaded);
        println!();
        shipped_open_set(loaded, names, outliers, shipped)?;
        println!("({:.0} s)", started.elapsed().as_secs_f64());
        Ok(())
    }

    /// The open-set unknown as a model is made with it (`choose_open_set_unknown`, what `train-knn` and the page's
    /// training do): for each held-out take and class left out of the training, the k-NN fitted on the other takes
    /// without the class chooses its ratio on *their* folds, leaving each of its own classes out in turn (it never
    /// learns which class will be missing), decoded as the shipped exercises k-NN (runs ≥ 2 s, switch cost 150,
    /// unknown below 0.5); the held-out take's frames scored at that ratio: the class left out is unseen.
    fn shipped_open_set(
        loaded: &[(String, Motion, Vec<usize>)],
        names: &[String],
        outliers: &[(String, Motion)],
        params: KnnParams,
    ) -> Result<(), String> {
        use mocapseg::labeller::decode::{file_labels, Decoding};
        use mocapseg::methods::knn::training::{choose_open_set_unknown, fit_knn};
        let decoding = Decoding { min_duration_s: 2.0, switch_cost: 150.0 };
        let threshold = 0.5;
        // per file frame of `motion` under `knn`: (score, decoded label), the score infinite where already unknown
        let scored = |knn: &Knn, motion: &Motion| -> Result<Vec<(f32, Option<usize>)>, String> {
            let (p, source) = knn.probabilities_at(motion, names.len())?;
            let labels: Vec<Option<usize>> =
                file_labels(&p, &source, params.fps, motion.frames(), &decoding, threshold)
                    .into_iter()
                    .map(|d| d.0)
                    .collect();
            let ratios = knn.voted_ratios_going(motion, &labels, &mut |_| true)?.ok_or("stopped")?;
            Ok(labels.iter().zip(&ratios).map(|(l, r)| (if l.is_some() { *r } else { f32::INFINITY }, *l)).collect())
        };
        println!(
            "The open-set unknown as models are made with it (choose_open_set_unknown: the ratio chosen on the training takes' own folds, each of their classes left out in turn), the k-NN with ±{} s windows and k = {}, held out:",
            params.half_window as f64 / 30.0,
            params.k
        );
        println!("| held-out take | class left out | ratio chosen (inner folds; open-set accuracy there / never) | open-set accuracy held out / never | unseen called unknown | taught called unknown | taught labelled right (never) | outlier takes' frames unknown |");
        println!("|---|---|---|---|---|---|---|---|");
        let mut folds: Vec<OpenSetFold> = Vec::new();
        for h in 0..loaded.len() {
            for gone in 0..names.len() {
                let others: Vec<usize> = (0..loaded.len()).filter(|&i| i != h).collect();
                if !loaded[h].2.contains(&gone) || !others.iter().any(|&i| loaded[i].2.contains(&gone)) {
                    continue;
                }
                let without: Vec<Vec<Option<usize>>> =
                    others.iter().map(|&i| loaded[i].2.iter().map(|&l| (l != gone).then_some(l)).collect()).collect();
                let train: Vec<(&Motion, &[Option<usize>])> =
                    others.iter().zip(&without).map(|(&i, l)| (&loaded[i].1, l.as_slice())).collect();
                let choice = choose_open_set_unknown(&train, names.len(), params, &decoding, threshold, &mut |_| true)?
                    .ok_or("no fold to choose the open-set unknown on")?;
                let knn = fit_knn(&train, params)?;
                let frames: Vec<OpenSetFrame> = scored(&knn, &loaded[h].1)?
                    .iter()
                    .zip(&loaded[h].2)
                    .map(|(&(score, l), &t)| OpenSetFrame { score, unseen: t == gone, right: l == Some(t) })
                    .collect();
                let held = open_set_scores(&frames, choice.ratio);
                let never = open_set_scores(&frames, f32::INFINITY);
                // the outlier takes: the share of their frames the model calls unknown (vote share or ratio)
                let mut outlier = 0.0;
                for (_, m) in outliers {
                    let s = scored(&knn, m)?;
                    outlier += s.iter().filter(|x| x.0 > choice.ratio || x.0 == f32::INFINITY).count() as f64
                        / s.len().max(1) as f64;
                }
                outlier /= outliers.len().max(1) as f64;
                println!(
                    "| {} | {} | {:.2} ({} folds; {:.3} / {:.3}) | {:.3} / {:.3} | {:.0} % | {:.0} % | {:.0} % ({:.0} %) | {:.0} % |",
                    loaded[h].0,
                    names[gone],
                    choice.ratio,
                    choice.folds,
                    choice.accuracy,
                    choice.never,
                    held.accuracy,
                    never.accuracy,
                    100.0 * held.unseen_unknown,
                    100.0 * held.taught_unknown,
                    100.0 * held.taught_right,
                    100.0 * never.taught_right,
                    100.0 * outlier
                );
                folds.push(OpenSetFold {
                    take: h,
                    never,
                    chosen: vec![(choice.ratio, choice.accuracy, held)],
                    outlier,
                });
            }
        }
        let n = folds.len().max(1) as f64;
        let mean = |f: &dyn Fn(&OpenSetFold) -> f64| folds.iter().map(f).sum::<f64>() / n;
        let ci = gain_over_takes(&folds, loaded.len(), 0);
        println!(
            "| **mean** ({} folds) | | inner {:.3} | **{:.3}** / {:.3}, Δ {ci} (95 % over the held-out takes) | **{:.0} %** | **{:.0} %** | {:.0} % ({:.0} %) | {:.0} % |",
            folds.len(),
            mean(&|f| f.chosen[0].1),
            mean(&|f| f.chosen[0].2.accuracy),
            mean(&|f| f.never.accuracy),
            100.0 * mean(&|f| f.chosen[0].2.unseen_unknown),
            100.0 * mean(&|f| f.chosen[0].2.taught_unknown),
            100.0 * mean(&|f| f.chosen[0].2.taught_right),
            100.0 * mean(&|f| f.never.taught_right),
            100.0 * mean(&|f| f.outlier)
        );
        Ok(())
    }

    /// The scores whose threshold the open-set objective chooses: (index into [`scores`]' rows, name).
    const OPEN_SET: [(usize, &str); 3] = [
        (0, "distance to the nearest training window, over the model's familiar distance"),
        (7, "voted class's ratio, over the take's median"),
        (8, "the decoded run's mean vote share (the run's unknown threshold)"),
    ];

    /// A leave-a-class-out fold under the open-set objective: the held-out take, its scores without any unknown, and
    /// per [`OPEN_SET`] score the threshold chosen on the inner folds, the inner folds' open-set accuracy there and the
    /// held-out take's scores; the outlier takes' share over the first score's threshold.
    struct OpenSetFold {
        take: usize,
        never: OpenSetScores,
        chosen: Vec<(f32, f64, OpenSetScores)>,
        outlier: f64,
    }

    /// Score `j`'s gain in held-out open-set accuracy over never saying unknown: each of the `takes` held-out takes'
    /// mean over its folds, their mean and bootstrap 95 % interval.
    fn gain_over_takes(folds: &[OpenSetFold], takes: usize, j: usize) -> String {
        let per_take: Vec<f64> = (0..takes)
            .filter_map(|h| {
                let d: Vec<f64> =
                    folds.iter().filter(|f| f.take == h).map(|f| f.chosen[j].2.accuracy - f.never.accuracy).collect();
                (!d.is_empty()).then(|| d.iter().sum::<f64>() / d.len() as f64)
            })
            .collect();
        mocapseg::stats::bootstrap_mean(&per_take, 2000, 50)
            .map_or("—".to_string(), |(m, a, b)| format!("{m:+.3} [{a:+.3}, {b:+.3}]"))
    }

    /// Per frame of a take: score `k` of its row, whether its class is `gone`, whether its decoded label is its class.
    fn open_frames(
        scores: &[[f32; S]],
        decoded: &[Option<usize>],
        labels: &[usize],
        gone: usize,
        k: usize,
    ) -> Vec<OpenSetFrame> {
        scores
            .iter()
            .zip(decoded)
            .zip(labels)
            .map(|((s, d), &l)| OpenSetFrame { score: s[k], unseen: l == gone, right: *d == Some(l) })
            .collect()
    }

    /// The open-set table: per score, the mean over the folds of the held-out open-set accuracy and the two rates,
    /// the inner folds' accuracy where the threshold was chosen (in-sample), and the paired difference from never
    /// saying unknown with its bootstrap 95 % interval over the held-out takes (each take: the mean of its folds).
    fn print_open_set(folds: &[OpenSetFold], loaded: &[(String, Motion, Vec<usize>)]) {
        let n = folds.len().max(1) as f64;
        let mean = |f: &dyn Fn(&OpenSetFold) -> f64| folds.iter().map(f).sum::<f64>() / n;
        println!(
            "Open-set objective (issue 50): each threshold chosen on the inner folds as the one with the best open-set frame accuracy (an unseen frame right when called unknown, a taught one when given its class; never unknown unless it pays), decoded as the shipped exercises k-NN (runs ≥ 2 s, switch cost 150); {} folds, takes {}:",
            folds.len(),
            loaded.iter().map(|l| l.0.as_str()).collect::<Vec<_>>().join(", ")
        );
        println!(
            "| unknown score | thresholds chosen (min–max; ∞ = never) | open-set accuracy, held out | Δ from never [95 % over takes] | inner folds (where chosen) | unseen called unknown | taught called unknown | taught labelled right |"
        );
        println!("|---|---|---|---|---|---|---|---|");
        let never = mean(&|f| f.never.accuracy);
        println!(
            "| never unknown | — | {never:.3} | — | — | 0 % | 0 % | {:.0} % |",
            100.0 * mean(&|f| f.never.taught_right)
        );
        for (j, (_, name)) in OPEN_SET.iter().enumerate() {
            let ts: Vec<f32> = folds.iter().map(|f| f.chosen[j].0).collect();
            let lo = ts.iter().copied().fold(f32::INFINITY, f32::min);
            let hi = ts.iter().copied().fold(f32::NEG_INFINITY, f32::max);
            let never_count = ts.iter().filter(|t| t.is_infinite()).count();
            let ci = gain_over_takes(folds, loaded.len(), j);
            println!(
                "| {name} | {lo:.2}–{hi:.2} ({never_count} never) | {:.3} | {ci} | {:.3} | {:.0} % | {:.0} % | {:.0} % |",
                mean(&|f| f.chosen[j].2.accuracy),
                mean(&|f| f.chosen[j].1),
                100.0 * mean(&|f| f.chosen[j].2.unseen_unknown),
                100.0 * mean(&|f| f.chosen[j].2.taught_unknown),
                100.0 * mean(&|f| f.chosen[j].2.taught_right),
            );
        }
        println!(
            "Outlier takes called unknown at the first score's open-set thresholds: {:.0} % (mean over the folds; 0 where never).",
            100.0 * mean(&|f| f.outlier)
        );
    }
}
