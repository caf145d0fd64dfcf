//! `make accuracy`: the scoreboard. Every registered method on every labelled take of the shared data, scored as it
//! is (`segment::metrics::evaluate`: actions as a tiling, gestures as given), **in-sample and nested leave-one-take-out
//! side by side**, beside the *chance* and *oracle-K* references (`segment::reference`). Written as one markdown table
//! per benchmark (`docs/accuracy.md`), one JSON (`docs/accuracy.json`), and blocks between `<!-- accuracy:begin -->`
//! and `<!-- accuracy:end -->`: in each method's page (`docs/methods/<method>.md`; the k-NN's rows go to `dtfcn.md`)
//! that method's rows beside the chance and oracle-K (equal parts) rows, with each fold's choice, and in the README
//! a summary (the held-out column of every method, linking to the pages). `--from-json docs/accuracy.json` writes
//! the markdown again from a saved JSON without evaluating anything (no data needed: seconds). With accuracy.json it
//! writes `models/cards.json`, the shipped models' cards with the held-out figures just measured
//! (`mocapseg::method::cards`; `mocapseg model-cards` writes the same from a saved accuracy.json).
//!
//! * **Actions** — CMU 86_01 (Barbič/Zhou labels) and the mocap6 takes 13_29, 13_30, 13_31, 14_14 (Fox/Hughes). Columns:
//!   - *defaults*: the method as shipped (its defaults; for DT-FCN and the k-NN the shipped models, trained on these
//!     takes — in-sample by construction);
//!   - *in-sample best*: the grid setting best on all takes, scored on those same takes (what tuning on the reported
//!     takes would claim);
//!   - *held out*: for each take, the grid setting best on the **other** takes scored on it (nested: nothing is
//!     chosen on the reported take); each fold's choice is printed and kept in the JSON. DT-FCN and the k-NN are
//!     trained on the other mocap6 takes, their settings chosen on inner validation takes of those
//!     (`dtfcn::corpus::predict_held_out`: receptive field (w and layers), padding, epochs, weight averaging
//!     (`dtfcn::corpus::averaged_fold`), and the unknown threshold on the validation
//!     take's labels; the k-NN's input (the joints, or DT-FCN's with the root's velocity and turning rows), window, k
//!     and unknown threshold by an inner leave-one-take-out); 86_01 has no other take with
//!     its labels, so they have no held-out score there.
//!   - *oracle-K*: per take, the grid setting whose number of segments is closest to the true one (a method told K).
//!   Selection: the mean of F1@1s and covering.
//!   - *consensus* (`segment::consensus`): the boundaries the five unsupervised methods (SSSM, PCA, velocity, KCS,
//!     LMA) agree on, scored as a tiling; its grid is the tolerance × the minimum agreement. Each column is the
//!     consensus of the methods' outputs of that column: their defaults; their in-sample best settings; held out,
//!     the methods' settings chosen without the take (LMA's family trained without it) and the consensus's own
//!     setting chosen, nested, on the other takes with those same method settings. The labellers are left out (their
//!     held-out outputs exist on the mocap6 takes only, and choosing on the other takes would need models trained
//!     without two takes). Every setting's scores on the methods' defaults are printed: the page's default is the
//!     best of them.
//! * **Gestures** — spliced takes with known boundaries (`mocapseg splice`): nested = leave one *source* take out
//!   (choose on splices of the other four, seeds 1–2, 30 pieces; score a splice of the held-out source, 20 pieces);
//!   in-sample = the best setting on splices of all five (seeds 1–3, 40 pieces), scored on them. Selection:
//!   Bouchard & Badler's s@0.5s.
//! * **LMA's classifier family** in every held-out column is one trained without the reported take (stand-in labels
//!   over every other CMU take of the shared data, the shipped recipe): the shipped family was trained on the motion of
//!   all of them, so its scores on them (defaults, in-sample) are in-sample twice over.
//!
//! Says what is missing and fails when the shared data is absent.
//!
//! ```text
//! cargo run --release --example accuracy -- [--data ../shared/data] [--out docs] [--readme README.md] [--seeds 20]
//!     [--methods docs/methods]
//! cargo run --example accuracy -- --from-json docs/accuracy.json   # the markdown again, from the saved JSON
//! cargo run --release --example accuracy -- --labeller knn          # one labeller's held-out rows, nothing written
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
    use std::fmt::Write as _;
    use std::path::{Path, PathBuf};
    use std::time::Instant;

    use mocapseg::bvh::{self, Bvh};
    use mocapseg::labeller::decode::{self, file_labels, Decoding, Judged, THRESHOLDS};
    use mocapseg::labeller::input::NETWORK_FPS;
    use mocapseg::labeller::method::runs;
    use mocapseg::labeller::probabilities::Probabilities;
    use mocapseg::method::{self, NoProgress, RunOptions};
    use mocapseg::methods::dtfcn::corpus::{
        averaged_fold, final_fold, predict_held_out, validation_fold, Extra, NO_EXTRA,
    };
    use mocapseg::methods::dtfcn::network::{paper_filters, Padding};
    use mocapseg::methods::dtfcn::training::TrainOptions;
    use mocapseg::methods::knn::training::{fit_knn, knn_fold};
    use mocapseg::methods::knn::{KnnInput, KnnParams};
    use mocapseg::methods::lma::classifier::EffortModel;
    use mocapseg::methods::lma::corpus::{Corpus, CorpusConfig};
    use mocapseg::methods::lma::method::{segment_with, LmaParams};
    use mocapseg::methods::lma::training::{train_family, TrainConfig as LmaTrain};
    use mocapseg::motion::Motion;
    use mocapseg::segment::consensus::{consensus, ConsensusOptions};
    use mocapseg::segment::labelling;
    use mocapseg::segment::metrics::evaluate;
    use mocapseg::segment::reference::{chance_scores, equal_parts, prior, MeanScores, Prior};
    use mocapseg::segment::report::scored_segments;
    use mocapseg::segment::truth::{load_csv, Truth, TruthOptions};
    use mocapseg::segment::{Level, Segmentation};
    use mocapseg::splice::{splice, Source, SpliceOptions};
    use serde_json::{json, Value};

    #[derive(clap::Parser)]
    #[command(about = "The scoreboard: every method in-sample and held out, beside chance")]
    pub struct Args {
        /// The shared data folder (with cmu/ and labels/).
        #[arg(long, default_value = "../shared/data")]
        data: PathBuf,
        /// Where accuracy.md and accuracy.json are written.
        #[arg(long, default_value = "docs")]
        out: PathBuf,
        /// The README whose `<!-- accuracy:begin -->…<!-- accuracy:end -->` block gets the summary ("" = none).
        #[arg(long, default_value = "README.md")]
        readme: String,
        /// The folder of the method pages (`<method>.md`, each with an accuracy block) ("" = none).
        #[arg(long, default_value = "docs/methods")]
        methods: String,
        /// The shipped models' cards written with the held-out figures just measured ("" = none: an experiment's
        /// run leaves the page's cards alone).
        #[arg(long, default_value = "models/cards.json")]
        cards: String,
        /// Write accuracy.md, the method pages' and the README's blocks from this saved accuracy.json instead of
        /// evaluating (accuracy.json itself is left as it is).
        #[arg(long)]
        from_json: Option<PathBuf>,
        /// Seeds the chance row is averaged over.
        #[arg(long, default_value_t = 20)]
        seeds: u64,
        /// Leave out the gesture benchmark (spliced takes).
        #[arg(long)]
        no_splice: bool,
        /// Offer DT-FCN's nested grid a few-seed ensemble of half-width networks beside the single networks (off by
        /// default: measured in docs/methods/dtfcn.md, it gained nothing on the validation takes and doubles the
        /// DT-FCN row's time).
        #[arg(long, conflicts_with = "inner_all")]
        ensembles: bool,
        /// Offer DT-FCN's nested grid every setting with each take centred on its own median posture
        /// (`centre_on_take`) beside the setting as it is (off by default: measured in docs/methods/dtfcn.md, it moved
        /// held-out frame accuracy by +0.004 and lowered F1@1s and edit, and doubles the DT-FCN row's time).
        #[arg(long, conflicts_with = "inner_all")]
        centring: bool,
        /// DT-FCN's settings chosen on every inner take in turn (three validation folds inside each outer fold, the
        /// epochs their median; the last epoch's weights) instead of on the take after the held-out one alone.
        #[arg(long)]
        inner_all: bool,
        /// DT-FCN's held-out column over the first this many seeds of 1, 2, 3 (1: a quick look, a third of the time;
        /// the scoreboard is made with 3).
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=3))]
        dtfcn_seeds: u64,
        /// A quick look at one labeller (`knn` or `dtfcn`): its rows only, printed with each take's score; nothing is
        /// written.
        #[arg(long, value_parser = ["knn", "dtfcn"])]
        labeller: Option<String>,
        /// With `--labeller`: more training data made from the takes in every fold (see [`Lever`]; DT-FCN's single
        /// networks' grid, not `--inner-all` or the ensembles).
        #[arg(long, value_enum, default_value = "none", requires = "labeller", conflicts_with_all = ["inner_all", "ensembles"])]
        lever: Lever,
    }

    /// One take of each subject of the shared data whose bones a take can be played on (`Lever::Retarget`): the
    /// labelled takes' and the locomotion clips', the first of each subject, those whose hierarchy is CMU's common one.
    fn carriers(data: &Path, takes: &[Take]) -> Result<Vec<(String, Bvh)>, String> {
        let mut out: Vec<(String, Bvh)> = Vec::new();
        let mut add = |name: &str, b: &Bvh| {
            let same = takes.first().is_some_and(|t| mocapseg::splice::retarget(name, b, &t.name, &t.bvh).is_ok());
            if same && !out.iter().any(|(n, _)| subject(n) == subject(name)) {
                out.push((name.to_string(), b.clone()));
            }
        };
        for t in takes {
            add(&t.name, &t.bvh);
        }
        let dir = data.join("cmu/locomotion");
        let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
            .map_err(|e| format!("{}: {e}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "bvh"))
            .collect();
        files.sort();
        for f in files {
            let text = std::fs::read_to_string(&f).map_err(|e| format!("{}: {e}", f.display()))?;
            let b = bvh::parse(&text).map_err(|e| format!("{}: {e}", f.display()))?;
            add(&f.file_stem().unwrap_or_default().to_string_lossy(), &b);
        }
        println!("carriers: {}", out.iter().map(|c| c.0.as_str()).collect::<Vec<_>>().join(", "));
        Ok(out)
    }

    /// A labelled take: its motion, its truth and the label set it belongs to.
    struct Take {
        name: String,
        motion: Motion,
        truth: Truth,
        set: &'static str,
        /// The file as read (what the data levers splice and play on other bones).
        bvh: Bvh,
    }

    /// More training data made from the takes we have (issue 50), beside the labelled takes of every fit of a fold (inner
    /// and outer): measured against none with `--labeller knn|dtfcn --lever …` before any ships.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
    pub enum Lever {
        /// The takes as they are.
        None,
        /// Two takes spliced from the fit's takes' labelled segments (`splice::splice`: pieces 2 s to the whole
        /// segment, new orders, cross-faded transitions in which both pieces keep moving, no exercise always first).
        Splice,
        /// Each fit take also played on the bones of every other subject of the shared data (`splice::retarget`): never
        /// the scored take's subject's.
        Retarget,
    }

    /// A take's subject: CMU's trial name before its `_`.
    fn subject(name: &str) -> &str {
        name.split('_').next().unwrap_or(name)
    }

    /// The takes `lever` adds to a fit on `fit` (indices into `takes`), labelled per file frame in `classes`' indices:
    /// made from those takes only, and never on the bones of a subject of the takes left out of the fit (the scored
    /// and the validation takes).
    fn lever_takes(
        lever: Lever,
        fit: &[usize],
        takes: &[&Take],
        carriers: &[(String, Bvh)],
        classes: &[String],
    ) -> Result<Vec<(Motion, Vec<Option<usize>>)>, String> {
        let class = |label: &str| classes.iter().position(|c| c == label);
        let mut out = Vec::new();
        match lever {
            Lever::None => {}
            Lever::Splice => {
                let sources: Vec<mocapseg::splice::Source> = fit
                    .iter()
                    .map(|&i| mocapseg::splice::Source {
                        name: &takes[i].name,
                        bvh: &takes[i].bvh,
                        truth: &takes[i].truth,
                    })
                    .collect();
                let segments: usize = fit.iter().map(|&i| takes[i].truth.segments.len()).sum();
                for copy in 0..2u64 {
                    // the seed follows the fit's takes, so every fold splices its own
                    let seed = fit.iter().fold(7 + copy, |h, &i| h * 31 + i as u64 + 1);
                    let options = mocapseg::splice::SpliceOptions {
                        pieces: segments,
                        seed,
                        min_s: 2.0,
                        max_s: 60.0,
                        blend_s: 0.25,
                    };
                    let spliced = mocapseg::splice::splice(&sources, &options).map_err(|e| e.to_string())?;
                    let name = format!("spliced-{copy}");
                    let motion = Motion::from_bvh(&name, &spliced.bvh).map_err(|e| format!("{name}: {e}"))?;
                    let mut labels = vec![None; motion.frames()];
                    for p in &spliced.pieces {
                        let c = class(&p.label).ok_or_else(|| format!("{name}: label {} of no class", p.label))?;
                        labels[p.start..=p.end.min(motion.frames() - 1)].iter_mut().for_each(|l| *l = Some(c));
                    }
                    out.push((motion, labels));
                }
            }
            Lever::Retarget => {
                let not: Vec<&str> =
                    (0..takes.len()).filter(|i| !fit.contains(i)).map(|i| subject(&takes[i].name)).collect();
                for &i in fit {
                    let t = takes[i];
                    let labels = t.truth.class_frames(&mut classes.to_vec());
                    let usable = |c: &str| !not.contains(&subject(c)) && subject(c) != subject(&t.name);
                    for (carrier, bvh) in carriers.iter().filter(|(c, _)| usable(c)) {
                        let moved =
                            mocapseg::splice::retarget(&t.name, &t.bvh, carrier, bvh).map_err(|e| e.to_string())?;
                        let name = format!("{}@{}", t.name, subject(carrier));
                        let motion = Motion::from_bvh(&name, &moved).map_err(|e| format!("{name}: {e}"))?;
                        out.push((motion, labels.clone()));
                    }
                }
            }
        }
        Ok(out)
    }

    /// One setting's result on one take.
    #[derive(Clone)]
    struct Cell {
        scores: MeanScores,
        found: usize,
        truth_segments: usize,
    }

    /// The grid each method's parameters are chosen over (the first setting is the defaults). Small on purpose: with
    /// five takes, a big grid overfits. SSSM's: its radius, and each departure from the paper that region growing
    /// depends on switched on or off (the relative gate, merging by poses).
    fn grid(method: &str) -> Vec<Vec<String>> {
        let axes: Vec<(&str, Vec<&str>)> = match method {
            "sssm" => vec![
                ("radius", vec!["19", "13", "25"]),
                ("relative_gate", vec!["1.5", "0"]),
                ("pose_merge", vec!["2", "0"]),
            ],
            "velocity" => {
                vec![("low_speed", vec!["12", "8", "16", "24"]), ("high_speed", vec!["30", "20", "45", "60"])]
            }
            "kcs" => vec![("drop", vec!["2", "4", "8", "16"]), ("min_segment_s", vec!["0.2", "0.5", "1.0", "2.0"])],
            "pca" => vec![("k_sigma", vec!["3", "2", "4"]), ("tau", vec!["0.9", "0.95"])],
            // LMA: its two searches, each over its own granularity (the union, not the product: the Effort search
            // reads only `quantile`, the deviance search only `min_rise` and `merge_s`)
            "lma" => {
                let effort = ["0.6", "0.5", "0.7", "0.8"].map(|q| vec![format!("quantile={q}")]);
                let mut settings: Vec<Vec<String>> = vec![vec![]];
                settings.extend(effort.into_iter().skip(1));
                for rise in ["0.4", "0.2", "0.6"] {
                    for merge in ["0.67", "0.33"] {
                        settings.push(vec![
                            "search=\"deviance\"".into(),
                            format!("min_rise={rise}"),
                            format!("merge_s={merge}"),
                        ]);
                    }
                }
                return settings;
            }
            _ => vec![],
        };
        let mut settings: Vec<Vec<String>> = vec![vec![]];
        for (name, values) in axes {
            settings = settings
                .iter()
                .flat_map(|s| values.iter().map(move |v| [s.clone(), vec![format!("{name}={v}")]].concat()))
                .collect();
        }
        // combinations the method refuses (a low speed above the high one) are left out
        let m = mocapseg::methods::find(method).ok();
        settings
            .retain(|s| m.is_none_or(|m| method::params_from_overrides(m, s).and_then(|p| m.check_json(&p)).is_ok()));
        settings
    }

    fn label(setting: &[String]) -> String {
        if setting.is_empty() {
            "defaults".into()
        } else {
            setting.join(" ")
        }
    }

    fn cell(seg: &Segmentation, truth: &Truth) -> Result<Cell, String> {
        let s = evaluate(seg, truth, &mocapseg::methods::scoring(&seg.method))
            .map_err(|e| format!("{}: {e}", truth.trial))?;
        let found = scored_segments(seg);
        Ok(Cell { scores: MeanScores::of(&s, found), found, truth_segments: truth.segments.len() })
    }

    /// The selection criterion of the action benchmark: the mean of F1@1s and covering.
    fn action_criterion(c: &Cell) -> f64 {
        0.5 * (c.scores.f1_1 + c.scores.covering)
    }

    /// The selection criterion of the gesture benchmark: Bouchard & Badler's s@0.5s.
    fn gesture_criterion(c: &Cell) -> f64 {
        c.scores.similarity
    }

    fn run_method(name: &str, setting: &[String], motion: &Motion) -> Result<Segmentation, String> {
        let m = mocapseg::methods::find(name).map_err(|e| e.to_string())?;
        let params = method::params_from_overrides(m, setting).map_err(|e| e.to_string())?;
        let out = m
            .run_json(motion, &params, &RunOptions::default(), &mut NoProgress)
            .map_err(|e| format!("{name} {} on {}: {e}", label(setting), motion.name))?;
        Ok(out.segmentation)
    }

    /// LMA's classifier families for the held-out columns: per labelled take, a family trained (stand-in labels, the
    /// shipped family's recipe) on every CMU take of the shared data *but* that one, so the take a fold reports is
    /// motion the family never saw — the shipped family was trained on all of them.
    #[derive(Default)]
    struct Families(Vec<(String, EffortModel)>);

    impl Families {
        fn train(data: &std::path::Path, names: &[String]) -> Result<Families, String> {
            let files = mocapseg::load::collect_files(&[data.join("cmu")], "bvh")?;
            let mut motions = Vec::new();
            for f in &files {
                let text = std::fs::read_to_string(f).map_err(|e| format!("{}: {e}", f.display()))?;
                let b = bvh::parse(&text).map_err(|e| format!("{}: {e}", f.display()))?;
                let stem = f.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default();
                motions.push(Motion::from_bvh(&stem, &b).map_err(|e| format!("{}: {e}", f.display()))?);
            }
            let mut out = Vec::new();
            for name in names {
                let started = Instant::now();
                let takes: Vec<&Motion> = motions.iter().filter(|m| m.name != *name).collect();
                let corpus = Corpus::from_descriptors(&takes, CorpusConfig::default())?;
                let (family, _) = train_family(&corpus, &LmaTrain::default(), &mut |_, _| Ok(()))?;
                println!(
                    "  lma: family without {name} trained on {} takes ({} segments) in {:.0} s",
                    takes.len(),
                    corpus.samples.len(),
                    started.elapsed().as_secs_f64()
                );
                out.push((name.clone(), family));
            }
            Ok(Families(out))
        }

        fn without(&self, take: &str) -> Option<&EffortModel> {
            self.0.iter().find(|(n, _)| n == take).map(|(_, f)| f)
        }
    }

    /// A held-out run: as [`run_method`], but LMA reads the family trained without `fold`'s take.
    fn run_held_out(
        name: &str,
        setting: &[String],
        motion: &Motion,
        fold: &str,
        families: &Families,
    ) -> Result<Segmentation, String> {
        match families.without(fold) {
            Some(family) if name == "lma" => {
                let m = mocapseg::methods::find(name).map_err(|e| e.to_string())?;
                let params = method::params_from_overrides(m, setting).map_err(|e| e.to_string())?;
                let params: LmaParams = serde_json::from_value(params).map_err(|e| e.to_string())?;
                let out = segment_with(family, motion, &params, &RunOptions::default(), &mut NoProgress)
                    .map_err(|e| format!("lma {} on {}: {e}", label(setting), motion.name))?;
                Ok(out.segmentation)
            }
            _ => run_method(name, setting, motion),
        }
    }

    /// `cells[s][t]` of every grid setting on every take.
    fn grid_cells(name: &str, settings: &[Vec<String>], takes: &[(&Motion, &Truth)]) -> Result<Vec<Vec<Cell>>, String> {
        Ok(grid_runs(name, settings, takes)?.0)
    }

    /// `cells[s][t]` and the segmentations `segs[s][t]` they score, of every grid setting on every take.
    #[allow(clippy::type_complexity)]
    fn grid_runs(
        name: &str,
        settings: &[Vec<String>],
        takes: &[(&Motion, &Truth)],
    ) -> Result<(Vec<Vec<Cell>>, Vec<Vec<Segmentation>>), String> {
        let (mut cells, mut segs) = (Vec::new(), Vec::new());
        for s in settings {
            let runs: Vec<Segmentation> =
                takes.iter().map(|(m, _)| run_method(name, s, m)).collect::<Result<_, _>>()?;
            cells.push(runs.iter().zip(takes).map(|(seg, (_, t))| cell(seg, t)).collect::<Result<_, _>>()?);
            segs.push(runs);
        }
        Ok((cells, segs))
    }

    /// The setting with the best mean criterion over the takes `among` (ties: the earlier, so the defaults win them).
    fn best(cells: &[Vec<Cell>], among: &[usize], criterion: fn(&Cell) -> f64) -> usize {
        let mean = |s: usize| among.iter().map(|&t| criterion(&cells[s][t])).sum::<f64>() / among.len().max(1) as f64;
        (0..cells.len()).fold(0, |b, s| if mean(s) > mean(b) + 1e-12 { s } else { b })
    }

    /// Oracle-K: per take, the cell of the setting whose number of segments is closest to the true one (ties: the
    /// earlier setting).
    fn oracle_k(cells: &[Vec<Cell>]) -> Vec<&Cell> {
        let takes = cells.first().map_or(0, Vec::len);
        (0..takes)
            .map(|t| {
                let s = (0..cells.len())
                    .min_by_key(|&s| cells[s][t].found.abs_diff(cells[s][t].truth_segments))
                    .unwrap_or(0);
                &cells[s][t]
            })
            .collect()
    }

    /// One method's row of a benchmark.
    #[derive(Clone)]
    struct MethodRow {
        method: String,
        defaults: Option<MeanScores>,
        in_sample: Option<(String, MeanScores)>,
        held_out: Option<MeanScores>,
        oracle_k: Option<MeanScores>,
        /// Per take: (take, held-out choice, held-out scores).
        folds: Vec<(String, String, MeanScores)>,
        /// A trained model's held-out scores per seed, per take (DT-FCN's runs; empty for one run): what the two-way
        /// bootstrap draws from ([`mocapseg::stats::bootstrap_grid_mean`]).
        seed_folds: Vec<Vec<(String, MeanScores)>>,
        note: String,
        seconds: f64,
    }

    fn mean_of(cells: &[&Cell]) -> MeanScores {
        MeanScores::mean(&cells.iter().map(|c| c.scores.clone()).collect::<Vec<_>>())
    }

    /// What a grid method produced on the action takes: the consensus row is made of it.
    struct Outputs {
        method: String,
        settings: Vec<Vec<String>>,
        /// `segs[s][t]`: setting `s` on take `t` (LMA: the shipped family).
        segs: Vec<Vec<Segmentation>>,
        /// The in-sample best setting.
        in_sample: usize,
        /// Per take: the setting chosen on the other takes, and its output on the take (LMA: the family trained
        /// without it).
        held_out: Vec<(usize, Segmentation)>,
    }

    /// Defaults, in-sample best, nested held-out choice and oracle-K of a grid method over `takes`, and its outputs.
    fn grid_row(
        name: &str,
        takes: &[(&Motion, &Truth)],
        criterion: fn(&Cell) -> f64,
        tuned_on: impl Fn(usize) -> Vec<usize>,
        families: &Families,
    ) -> Result<(MethodRow, Outputs), String> {
        let started = Instant::now();
        let settings = grid(name);
        let (cells, segs) = grid_runs(name, &settings, takes)?;
        let all: Vec<usize> = (0..takes.len()).collect();
        let defaults = mean_of(&all.iter().map(|&t| &cells[0][t]).collect::<Vec<_>>());
        let b = best(&cells, &all, criterion);
        let in_sample = mean_of(&all.iter().map(|&t| &cells[b][t]).collect::<Vec<_>>());
        let mut folds = Vec::new();
        let mut held_segs = Vec::new();
        for t in 0..takes.len() {
            let s = best(&cells, &tuned_on(t), criterion);
            println!("  {name}: held out {} — chose {} on the others", takes[t].1.trial, label(&settings[s]));
            let trial = &takes[t].1.trial;
            let (seg, scores) = match families.without(trial) {
                Some(_) if name == "lma" => {
                    let seg = run_held_out(name, &settings[s], takes[t].0, trial, families)?;
                    let scores = cell(&seg, takes[t].1)?.scores;
                    (seg, scores)
                }
                _ => (segs[s][t].clone(), cells[s][t].scores.clone()),
            };
            folds.push((trial.clone(), label(&settings[s]), scores));
            held_segs.push((s, seg));
        }
        let held_out = MeanScores::mean(&folds.iter().map(|f| f.2.clone()).collect::<Vec<_>>());
        let oracle = oracle_k(&cells);
        let outputs =
            Outputs { method: name.into(), settings: settings.clone(), segs, in_sample: b, held_out: held_segs };
        let row = MethodRow {
            seed_folds: Vec::new(),
            method: name.into(),
            defaults: Some(defaults),
            in_sample: Some((label(&settings[b]), in_sample)),
            held_out: Some(held_out),
            oracle_k: Some(mean_of(&oracle)),
            folds,
            note: format!("grid of {} settings", settings.len()),
            seconds: started.elapsed().as_secs_f64(),
        };
        Ok((row, outputs))
    }

    /// The consensus row's grid (`segment::consensus`): its tolerance and minimum agreement; the defaults first.
    fn consensus_grid() -> Vec<ConsensusOptions> {
        let mut settings = vec![ConsensusOptions::default()];
        for tolerance_s in [0.25, 0.5, 1.0, 2.0] {
            for min_methods in [2, 3, 4] {
                let o = ConsensusOptions { tolerance_s, min_methods };
                if !settings.contains(&o) {
                    settings.push(o);
                }
            }
        }
        settings
    }

    fn consensus_label(o: &ConsensusOptions) -> String {
        format!("tolerance_s={} min_methods={}", o.tolerance_s, o.min_methods)
    }

    /// The consensus of `outputs` (one take's segmentations, one per method) under `o`, scored against `truth`.
    fn consensus_cell(outputs: &[&Segmentation], o: ConsensusOptions, truth: &Truth) -> Result<Cell, String> {
        let agreed = consensus(outputs, o).map_err(|e| format!("consensus on {}: {e}", truth.trial))?;
        cell(&agreed.to_segmentation(&truth.trial), truth)
    }

    /// `cells[c][t]`: every consensus setting on every take, of the outputs `of(t)` gives.
    fn consensus_cells(
        settings: &[ConsensusOptions],
        takes: &[(&Motion, &Truth)],
        of: impl Fn(usize) -> Result<Vec<Segmentation>, String>,
    ) -> Result<Vec<Vec<Cell>>, String> {
        let outputs: Vec<Vec<Segmentation>> = (0..takes.len()).map(of).collect::<Result<_, _>>()?;
        settings
            .iter()
            .map(|&o| {
                takes
                    .iter()
                    .zip(&outputs)
                    .map(|((_, truth), segs)| consensus_cell(&segs.iter().collect::<Vec<_>>(), o, truth))
                    .collect()
            })
            .collect()
    }

    /// The consensus row: the boundaries the grid methods agree on, scored like a method. *defaults*: the consensus's
    /// defaults on the methods' defaults; *in-sample best*: the consensus setting best on all takes, on each method's
    /// in-sample best outputs; *held out*: for each take, the methods' settings chosen without it (their held-out
    /// outputs on it; LMA's family trained without it) and the consensus setting chosen, nested, on the other takes
    /// with those same method settings (LMA with that same family) — nothing is chosen on the reported take.
    fn consensus_row(
        takes: &[(&Motion, &Truth)],
        methods: &[Outputs],
        criterion: fn(&Cell) -> f64,
        families: &Families,
    ) -> Result<MethodRow, String> {
        let started = Instant::now();
        let settings = consensus_grid();
        let all: Vec<usize> = (0..takes.len()).collect();
        // every setting on the methods' defaults (the first: the consensus's defaults), the measurement behind them
        let on_defaults =
            consensus_cells(&settings, takes, |t| Ok(methods.iter().map(|m| m.segs[0][t].clone()).collect()))?;
        for (o, cells) in settings.iter().zip(&on_defaults) {
            let mean = mean_of(&cells.iter().collect::<Vec<_>>());
            println!(
                "  consensus on the defaults, {}: F1@1s {:.3}, covering {:.3}, criterion {:.3}, segments {:.1}",
                consensus_label(o),
                mean.f1_1,
                mean.covering,
                all.iter().map(|&t| criterion(&cells[t])).sum::<f64>() / all.len().max(1) as f64,
                mean.segments
            );
        }
        let in_cells = consensus_cells(&settings, takes, |t| {
            Ok(methods.iter().map(|m| m.segs[m.in_sample][t].clone()).collect())
        })?;
        let b = best(&in_cells, &all, criterion);
        let mut folds = Vec::new();
        for h in 0..takes.len() {
            let trial = &takes[h].1.trial;
            // every take's outputs under the settings the methods chose without `h` (on `h` itself: its held-out
            // outputs); LMA with the family trained without `h`
            let fold = consensus_cells(&settings, takes, |t| {
                methods
                    .iter()
                    .map(|m| {
                        let (s, held) = &m.held_out[h];
                        match families.without(trial) {
                            _ if t == h => Ok(held.clone()),
                            Some(_) if m.method == "lma" => {
                                run_held_out(&m.method, &m.settings[*s], takes[t].0, trial, families)
                            }
                            _ => Ok(m.segs[*s][t].clone()),
                        }
                    })
                    .collect()
            })?;
            let others: Vec<usize> = (0..takes.len()).filter(|&t| t != h).collect();
            let c = best(&fold, &others, criterion);
            println!("  consensus: held out {trial} — chose {} on the others", consensus_label(&settings[c]));
            folds.push((trial.clone(), consensus_label(&settings[c]), fold[c][h].scores.clone()));
        }
        let names: Vec<&str> = methods.iter().map(|m| m.method.as_str()).collect();
        Ok(MethodRow {
            seed_folds: Vec::new(),
            method: "consensus".into(),
            defaults: Some(mean_of(&on_defaults[0].iter().collect::<Vec<_>>())),
            in_sample: Some((
                consensus_label(&settings[b]),
                mean_of(&all.iter().map(|&t| &in_cells[b][t]).collect::<Vec<_>>()),
            )),
            held_out: Some(MeanScores::mean(&folds.iter().map(|f| f.2.clone()).collect::<Vec<_>>())),
            oracle_k: Some(mean_of(&oracle_k(&in_cells))),
            folds,
            note: format!(
                "the boundaries at least min_methods of {} agree on within tolerance_s; grid of {} settings; each \
                 column on the methods' outputs of that column (defaults, in-sample best, held out)",
                names.join(", "),
                settings.len()
            ),
            seconds: started.elapsed().as_secs_f64(),
        })
    }

    /// DT-FCN's final weights: the last epoch's (0) or their mean over the last 5 or 10 epochs (`average_last`,
    /// stochastic weight averaging), chosen per fold on the validation take (the last epoch's first: it wins ties).
    const AVERAGE_LAST: [usize; 3] = [0, 5, 10];
    /// The seeds DT-FCN's held-out column is the mean of (initial weights, crops, augmentation): one seed's score
    /// moves by ±0.03 from seed to seed (docs/methods/dtfcn.md). The first is the shipped models'.
    const DTFCN_SEEDS: [u64; 3] = [1, 2, 3];
    /// A DT-FCN ensemble candidate: this many half-width networks (seeds s, s + 1, …), w = 3, four layers — three
    /// full-width networks would not label 3000 frames in the 300 ms wasm budget, three half-width ones do
    /// (`make bench`).
    const ENSEMBLE_MEMBERS: u64 = 3;
    const HALF_FILTERS: [usize; 4] = [32, 64, 128, 256];
    const ENSEMBLE_PADDINGS: [Padding; 2] = [Padding::Zero, Padding::Edge];

    /// One network of an ensemble candidate in one fold: its validation and held-out labels, and its kept epoch.
    struct MemberFold {
        validation: Labelled,
        held: Labelled,
        epoch: usize,
    }

    /// What validation takes say of a candidate's labels of them (each by networks trained without it): the best
    /// mean raw frame accuracy over the thresholds (what chooses the candidate), and the threshold and decoding
    /// chosen with their criterion.
    fn validation_choice(takes: &[(&Motion, &Labelled, &[Option<usize>])]) -> (f64, f64, Decoding, f64) {
        let accuracy = THRESHOLDS
            .iter()
            .map(|&t| {
                takes
                    .iter()
                    .map(|(m, l, truth)| labelling::score(&l.labels(m, &Decoding::RAW, t), truth).frame_accuracy)
                    .sum::<f64>()
                    / takes.len().max(1) as f64
            })
            .fold(f64::MIN, f64::max);
        let (threshold, decoding, criterion) = best_decoding(takes);
        (accuracy, threshold, decoding, criterion)
    }

    /// A labeller's per-file-frame labels (`None`: unknown) as a segmentation, as the method turns them into segments.
    fn labelled_segmentation(
        motion: &Motion,
        file: &[(Option<usize>, f32)],
        classes: &[String],
        method: &str,
    ) -> Segmentation {
        Segmentation {
            file: motion.name.clone(),
            fps: motion.fps,
            frames: motion.frames(),
            method: method.into(),
            params: Value::Null,
            segments: runs(file, classes),
        }
    }

    /// A labeller's output on one take: per working frame every class's probability, each working frame's file
    /// position and the working rate.
    #[derive(Clone)]
    struct Labelled {
        probabilities: Probabilities,
        source: Vec<f64>,
        fps: f64,
    }

    impl Labelled {
        /// Per file frame of `motion`: the label (`None`: unknown) under `decoding` and `threshold`.
        fn file(&self, motion: &Motion, decoding: &Decoding, threshold: f64) -> Vec<(Option<usize>, f32)> {
            file_labels(&self.probabilities, &self.source, self.fps, motion.frames(), decoding, threshold)
        }

        fn labels(&self, motion: &Motion, decoding: &Decoding, threshold: f64) -> Vec<Option<usize>> {
            self.file(motion, decoding, threshold).into_iter().map(|x| x.0).collect()
        }
    }

    fn decoding_label(d: &Decoding) -> String {
        format!("min_duration_s={} switch_cost={}", d.min_duration_s, d.switch_cost)
    }

    /// The unknown threshold and decoding with the best mean criterion over `takes` (labelled by a model that never
    /// saw them), and that criterion ([`decode::choose`], what a training with a validation take chooses by).
    fn best_decoding(takes: &[(&Motion, &Labelled, &[Option<usize>])]) -> (f64, Decoding, f64) {
        let judged: Vec<Judged> = takes
            .iter()
            .map(|(m, l, truth)| {
                assert_eq!(m.frames(), truth.len(), "{}: the truth labels every file frame", m.name);
                Judged { probabilities: &l.probabilities, source: &l.source, fps: l.fps, truth }
            })
            .collect();
        decode::choose(&judged)
            .map_or((THRESHOLDS[0], Decoding::RAW, f64::MIN), |c| (c.threshold, c.decoding, c.criterion))
    }

    /// The k-NN's k: chosen per fold by leave-one-take-out frame accuracy on the training takes alone.
    const KS: [usize; 5] = [5, 1, 3, 9, 15];
    /// The k-NN's windows its nested choice is offered (issue 50: it was fixed at ±1 s): half a window and its stride,
    /// in working frames at 30 Hz — ±0.5 s, ±1 s (the shipped models'), ±2 s, every sixth of a second.
    const KNN_WINDOWS: [(i32, i32); 3] = [(30, 5), (15, 5), (60, 5)];
    /// The k-NN's inputs its nested choice is offered (issue 50: it read the joints alone): the hip-relative joints as
    /// they are (the shipped models'), and DT-FCN's input — with the root's velocity and turning rows, standardised.
    const KNN_INPUTS: [KnnInput; 2] = [KnnInput::Joints, KnnInput::Network];

    fn knn_labelled(
        train: &[(&Motion, &[Option<usize>])],
        params: KnnParams,
        motion: &Motion,
        classes: usize,
    ) -> Result<Labelled, String> {
        let (probabilities, source) = fit_knn(train, params)?.probabilities_at(motion, classes)?;
        Ok(Labelled { probabilities, source, fps: params.fps })
    }

    /// DT-FCN and k-NN rows on the mocap6 takes: the shipped models in-sample (`exercises`; `cmu-actions` on 86_01),
    /// and nested held-out predictions trained on the other mocap6 takes.
    /// DT-FCN's receptive fields of 1.07 s (w = 2, 5 layers), 2.13 s (2, 6) and 2.7 s (3, 4) at 30 Hz, with their
    /// padding.
    const DTFCN_SETTINGS: [(usize, usize, Padding); 4] =
        [(2, 5, Padding::Zero), (2, 6, Padding::Edge), (3, 4, Padding::Zero), (3, 4, Padding::Edge)];

    /// The training options of one of [`DTFCN_SETTINGS`] with `seed`.
    fn setting(width: usize, layers: usize, padding: Padding, seed: u64) -> TrainOptions {
        TrainOptions { width, filters: paper_filters(layers), padding, seed, ..TrainOptions::default() }
    }

    #[allow(clippy::too_many_arguments)]
    fn labeller_rows(
        names: &[&str],
        lever: Lever,
        carriers: &[(String, Bvh)],
        takes: &[Take],
        ensembles: bool,
        inner_all: bool,
        centring: bool,
        seeds: usize,
    ) -> Result<Vec<MethodRow>, String> {
        let centrings: &[bool] = if centring { &[false, true] } else { &[false] };
        let dtfcn_seeds = &DTFCN_SEEDS[..seeds.clamp(1, DTFCN_SEEDS.len())];
        let mocap6: Vec<&Take> = takes.iter().filter(|t| t.set == "mocap6").collect();
        let mut classes = Vec::new();
        let labels: Vec<Vec<Option<usize>>> = mocap6.iter().map(|t| t.truth.class_frames(&mut classes)).collect();
        let motions: Vec<Motion> = mocap6.iter().map(|t| t.motion.clone()).collect();
        let mut rows = Vec::new();
        for &name in names {
            let started = Instant::now();
            // in-sample: the shipped models on the takes they were trained on
            let shipped: Vec<Cell> = takes
                .iter()
                .map(|t| {
                    let model = if t.set == "mocap6" { "exercises" } else { "cmu-actions" };
                    cell(&run_method(name, &[format!("model=\"{model}\"")], &t.motion)?, &t.truth)
                })
                .collect::<Result<_, String>>()?;
            let defaults = mean_of(&shipped.iter().collect::<Vec<_>>());
            let mut folds = Vec::new();
            // every take's labels by the model its fold trained without it: what the shipped model's decoding is
            // chosen on (`train-dtfcn --min-duration-s --switch-cost`, models/README.md)
            let mut out_of_fold: Vec<(usize, Labelled)> = Vec::new();
            // each run's (seed's) held-out scores, take by take
            let mut by_seed: Vec<Vec<(String, MeanScores)>> = Vec::new();
            // a variance reducer fixed in advance (issue 50): the seeds' chosen networks' probabilities averaged, its
            // threshold and decoding chosen on the validation take by the same average; per take: (take, the
            // ensemble's scores, the mean of the seeds' scores, seed 1's)
            let mut reduced: Vec<(String, MeanScores, MeanScores, MeanScores)> = Vec::new();
            if mocap6.len() >= 3 {
                for h in 0..mocap6.len() {
                    // the seeds' chosen networks' (validation take, its labels, the held-out take's labels)
                    let mut averaged: Vec<(usize, Labelled, Labelled)> = Vec::new();
                    // (held-out labels, threshold, decoding, what was chosen): one for the k-NN, one per seed for DT-FCN
                    let runs: Vec<(Labelled, f64, Decoding, String)> = if name == "knn" {
                        let train: Vec<usize> = (0..mocap6.len()).filter(|&i| i != h).collect();
                        // the lever's takes for each inner fit (without its validation take) and for the fold's fit
                        let inner_extra: Vec<Vec<(Motion, Vec<Option<usize>>)>> = train
                            .iter()
                            .map(|&v| {
                                let fit: Vec<usize> = train.iter().copied().filter(|&i| i != v).collect();
                                lever_takes(lever, &fit, &mocap6, carriers, &classes)
                            })
                            .collect::<Result<_, _>>()?;
                        let extra = lever_takes(lever, &train, &mocap6, carriers, &classes)?;
                        if lever != Lever::None {
                            println!(
                                "    knn: held out {}, the lever {lever:?} adds {} takes ({} frames) to the fit",
                                mocap6[h].name,
                                extra.len(),
                                extra.iter().map(|e| e.0.frames()).sum::<usize>()
                            );
                        }
                        // (window and k, threshold, mean inner accuracy, the inner takes' labels) on the raw labels
                        let mut top: (KnnParams, f64, f64, Vec<Labelled>) =
                            (KnnParams::default(), THRESHOLDS[0], f64::MIN, Vec::new());
                        let candidates = KNN_INPUTS.iter().flat_map(|&input| {
                            KNN_WINDOWS.iter().flat_map(move |&(half_window, stride)| {
                                KS.iter().map(move |&k| KnnParams {
                                    half_window,
                                    stride,
                                    k,
                                    input,
                                    ..KnnParams::default()
                                })
                            })
                        });
                        for params in candidates {
                            let inner: Vec<Labelled> = train
                                .iter()
                                .zip(&inner_extra)
                                .map(|(&v, extra)| {
                                    let fit: Vec<(&Motion, &[Option<usize>])> = train
                                        .iter()
                                        .filter(|&&i| i != v)
                                        .map(|&i| (&motions[i], labels[i].as_slice()))
                                        .chain(extra.iter().map(|(m, l)| (m, l.as_slice())))
                                        .collect();
                                    knn_labelled(&fit, params, &motions[v], classes.len())
                                })
                                .collect::<Result<_, _>>()?;
                            let mut best_here = (THRESHOLDS[0], f64::MIN);
                            for t in THRESHOLDS {
                                let acc = train
                                    .iter()
                                    .zip(&inner)
                                    .map(|(&v, l)| {
                                        labelling::score(&l.labels(&motions[v], &Decoding::RAW, t), &labels[v])
                                            .frame_accuracy
                                    })
                                    .sum::<f64>()
                                    / train.len() as f64;
                                if acc > best_here.1 + 1e-12 {
                                    best_here = (t, acc);
                                }
                            }
                            if best_here.1 > top.2 + 1e-12 {
                                top = (params, best_here.0, best_here.1, inner);
                            }
                        }
                        // then the decoding, on the same inner predictions
                        let inner: Vec<(&Motion, &Labelled, &[Option<usize>])> =
                            train.iter().zip(&top.3).map(|(&v, l)| (&motions[v], l, labels[v].as_slice())).collect();
                        let (threshold, decoding, criterion) = best_decoding(&inner);
                        let fit: Vec<(&Motion, &[Option<usize>])> = train
                            .iter()
                            .map(|&i| (&motions[i], labels[i].as_slice()))
                            .chain(extra.iter().map(|(m, l)| (m, l.as_slice())))
                            .collect();
                        vec![(
                            knn_labelled(&fit, top.0, &motions[h], classes.len())?,
                            threshold,
                            decoding,
                            format!(
                                "input={} half_window={} stride={} k={} (inner accuracy {:.3}) \
                                 unknown_threshold={threshold} {} (inner criterion {criterion:.1})",
                                top.0.input.name(),
                                top.0.half_window,
                                top.0.stride,
                                top.0.k,
                                top.2,
                                decoding_label(&decoding)
                            ),
                        )]
                    } else {
                        // every seed of DTFCN_SEEDS: a network's held-out score is partly the luck of its seed
                        let mut runs = Vec::new();
                        // the lever's takes beside every training of the fold (the single networks' grid)
                        let made = |fit: &[usize]| lever_takes(lever, fit, &mocap6, carriers, &classes);
                        let extra: Extra = &made;
                        // the ensembles' networks, each trained once in this fold and shared by every seed's ensemble
                        // that holds it: (its seed, its padding) → its labels
                        let mut members: std::collections::HashMap<(u64, usize), MemberFold> = Default::default();
                        for &seed in dtfcn_seeds {
                            // (setting, average_last, epochs, threshold, decoding, what was chosen, validation accuracy,
                            // the held-out take's labels when the fold's networks already made them)
                            // … and the validation take with the candidate's labels of it (not for --inner-all)
                            type Candidate = (
                                TrainOptions,
                                usize,
                                f64,
                                Decoding,
                                String,
                                f64,
                                Option<Labelled>,
                                Option<(usize, Labelled)>,
                            );
                            let mut top: Option<Candidate> = None;
                            // every inner take validates in turn: each setting scored by its mean over them
                            for &(width, layers, padding) in DTFCN_SETTINGS.iter().filter(|_| inner_all) {
                                let options = setting(width, layers, padding, seed);
                                let mut inner = Vec::new();
                                for v in (0..motions.len()).filter(|&v| v != h) {
                                    let (probabilities, source, epoch) =
                                        validation_fold(&motions, &labels, h, v, &classes, &options)?;
                                    inner.push((v, Labelled { probabilities, source, fps: NETWORK_FPS }, epoch));
                                }
                                let judged: Vec<(&Motion, &Labelled, &[Option<usize>])> =
                                    inner.iter().map(|(v, l, _)| (&motions[*v], l, labels[*v].as_slice())).collect();
                                let (accuracy, threshold, decoding, criterion) = validation_choice(&judged);
                                let mut epochs: Vec<usize> = inner.iter().map(|r| r.2).collect();
                                let each = epochs.iter().map(|e| e.to_string()).collect::<Vec<_>>().join(",");
                                epochs.sort_unstable();
                                let epoch = epochs[epochs.len() / 2];
                                let what = format!(
                                    "width={width} layers={layers} padding={} epochs={epoch} average_last=0 unknown_threshold={threshold} {} (every inner take validating: epochs {each}, mean accuracy {accuracy:.3}, criterion {criterion:.1})",
                                    padding.name(),
                                    decoding_label(&decoding),
                                );
                                println!("    dtfcn: held out {}, seed {seed}, candidate {what}", mocap6[h].name);
                                if top.as_ref().is_none_or(|t| accuracy > t.5 + 1e-12) {
                                    let o = TrainOptions { epochs: epoch, ..options.clone() };
                                    top = Some((o, 0, threshold, decoding, what, accuracy, None, None));
                                }
                            }
                            let grid = DTFCN_SETTINGS
                                .iter()
                                .filter(|_| !inner_all)
                                .flat_map(|&(w, l, p)| centrings.iter().map(move |&c| (w, l, p, c)));
                            for (width, layers, padding, centre_on_take) in grid {
                                let options = TrainOptions { centre_on_take, ..setting(width, layers, padding, seed) };
                                let p = predict_held_out(
                                    &motions,
                                    &labels,
                                    h,
                                    &classes,
                                    &options,
                                    &knn_fold,
                                    extra,
                                    &mut |_| true,
                                )?;
                                let mut held = Some(Labelled {
                                    probabilities: p.network_probabilities,
                                    source: p.network_source,
                                    fps: NETWORK_FPS,
                                });
                                // the weights of the last epoch, or their mean over the last few (stochastic weight
                                // averaging): each retrained on the inner takes for the chosen epochs, scored on the
                                // validation take
                                for average_last in AVERAGE_LAST {
                                    let (probabilities, source) = if average_last == 0 {
                                        (p.validation_probabilities.clone(), p.validation_source.clone())
                                    } else {
                                        let o = TrainOptions { average_last, ..options.clone() };
                                        let a = averaged_fold(
                                            &motions,
                                            &labels,
                                            h,
                                            &classes,
                                            &o,
                                            p.best_epoch,
                                            false,
                                            extra,
                                        )?;
                                        (a.validation_probabilities, a.validation_source)
                                    };
                                    // the unknown threshold and the decoding, on the validation take's labels by the
                                    // network trained without it
                                    let val = Labelled { probabilities, source, fps: NETWORK_FPS };
                                    let vm = &motions[p.validation];
                                    let (accuracy, threshold, decoding, criterion) =
                                        validation_choice(&[(vm, &val, labels[p.validation].as_slice())]);
                                    let what = format!(
                                    "width={width} layers={layers} padding={}{} epochs={} average_last={average_last} unknown_threshold={threshold} {} (validation {} accuracy {:.3}, criterion {criterion:.1})",
                                    padding.name(),
                                    if centre_on_take { " centre_on_take=true" } else { "" },
                                    p.best_epoch,
                                    decoding_label(&decoding),
                                    vm.name,
                                    accuracy
                                );
                                    println!("    dtfcn: held out {}, seed {seed}, candidate {what}", mocap6[h].name);
                                    if top.as_ref().is_none_or(|t| accuracy > t.5 + 1e-12) {
                                        let o = TrainOptions { average_last, epochs: p.best_epoch, ..options.clone() };
                                        let known = if average_last == 0 { held.take() } else { None };
                                        let v = Some((p.validation, val.clone()));
                                        top = Some((o, average_last, threshold, decoding, what, accuracy, known, v));
                                    }
                                }
                            }
                            // a few-seed ensemble: seeds s, s + 1, s + 2, each network choosing its own epoch on the
                            // validation take (and retrained for it on the three training takes), their probabilities
                            // averaged
                            for (e, &padding) in ENSEMBLE_PADDINGS.iter().enumerate().filter(|_| ensembles) {
                                let member_seeds: Vec<u64> = (0..ENSEMBLE_MEMBERS).map(|m| seed + m).collect();
                                let options = TrainOptions {
                                    width: 3,
                                    filters: HALF_FILTERS.to_vec(),
                                    padding,
                                    ..TrainOptions::default()
                                };
                                for &s in &member_seeds {
                                    if !members.contains_key(&(s, e)) {
                                        let o = TrainOptions { seed: s, ..options.clone() };
                                        let p = predict_held_out(
                                            &motions,
                                            &labels,
                                            h,
                                            &classes,
                                            &o,
                                            &knn_fold,
                                            NO_EXTRA,
                                            &mut |_| true,
                                        )?;
                                        let network = |probabilities, source| Labelled {
                                            probabilities,
                                            source,
                                            fps: NETWORK_FPS,
                                        };
                                        members.insert(
                                            (s, e),
                                            MemberFold {
                                                validation: network(p.validation_probabilities, p.validation_source),
                                                held: network(p.network_probabilities, p.network_source),
                                                epoch: p.best_epoch,
                                            },
                                        );
                                    }
                                }
                                let runs: Vec<&MemberFold> = member_seeds.iter().map(|&s| &members[&(s, e)]).collect();
                                let mean = |of: &dyn Fn(&MemberFold) -> &Labelled| -> Result<Labelled, String> {
                                    let all: Vec<&Labelled> = runs.iter().map(|r| of(r)).collect();
                                    let probabilities =
                                        Probabilities::mean(&all.iter().map(|l| &l.probabilities).collect::<Vec<_>>())
                                            .ok_or("the ensemble's networks labelled different frames")?;
                                    Ok(Labelled { probabilities, source: all[0].source.clone(), fps: NETWORK_FPS })
                                };
                                let val = mean(&|r| &r.validation)?;
                                let validation = (h + 1) % motions.len();
                                let vm = &motions[validation];
                                let (accuracy, threshold, decoding, criterion) =
                                    validation_choice(&[(vm, &val, labels[validation].as_slice())]);
                                let mut epochs: Vec<usize> = runs.iter().map(|r| r.epoch).collect();
                                let what = format!(
                                    "members={ENSEMBLE_MEMBERS} (seeds {}) width=3 layers=4 filters={} padding={} epochs={} average_last=0 unknown_threshold={threshold} {} (validation {} accuracy {:.3}, criterion {criterion:.1})",
                                    member_seeds.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(","),
                                    HALF_FILTERS.iter().map(|f| f.to_string()).collect::<Vec<_>>().join(","),
                                    padding.name(),
                                    epochs.iter().map(|e| e.to_string()).collect::<Vec<_>>().join(","),
                                    decoding_label(&decoding),
                                    vm.name,
                                    accuracy
                                );
                                println!("    dtfcn: held out {}, seed {seed}, candidate {what}", mocap6[h].name);
                                if top.as_ref().is_none_or(|t| accuracy > t.5 + 1e-12) {
                                    epochs.sort_unstable();
                                    let o = TrainOptions {
                                        members: ENSEMBLE_MEMBERS as usize,
                                        seed,
                                        epochs: epochs[epochs.len() / 2],
                                        ..options.clone()
                                    };
                                    let held = Some(mean(&|r| &r.held)?);
                                    top = Some((
                                        o,
                                        0,
                                        threshold,
                                        decoding,
                                        what,
                                        accuracy,
                                        held,
                                        Some((validation, val)),
                                    ));
                                }
                            }
                            let (options, _, threshold, decoding, what, _, known, validation) =
                                top.ok_or("no DT-FCN setting")?;
                            let held = match known {
                                Some(l) => l,
                                None if inner_all => {
                                    let (probabilities, source) =
                                        final_fold(&motions, &labels, h, &classes, &options, options.epochs)?;
                                    Labelled { probabilities, source, fps: NETWORK_FPS }
                                }
                                None => {
                                    let a = averaged_fold(
                                        &motions,
                                        &labels,
                                        h,
                                        &classes,
                                        &options,
                                        options.epochs,
                                        true,
                                        extra,
                                    )?;
                                    let (probabilities, source) =
                                        a.network.ok_or("the averaged fold made no labels")?;
                                    Labelled { probabilities, source, fps: NETWORK_FPS }
                                }
                            };
                            if let Some((v, val)) = validation {
                                averaged.push((v, val, held.clone()));
                            }
                            runs.push((held, threshold, decoding, format!("seed {seed}: {what}")));
                        }
                        runs
                    };
                    // the take's scores: the mean over the runs (seeds) — each printed, each seed's mean kept
                    let (mut scores, mut chose) = (Vec::new(), Vec::new());
                    for (i, (labelled, threshold, decoding, chosen)) in runs.into_iter().enumerate() {
                        let file = labelled.file(&motions[h], &decoding, threshold);
                        let seg = labelled_segmentation(&motions[h], &file, &classes, name);
                        // the shipped model's decoding is chosen on the out-of-fold labels of its own seed (the first)
                        if i == 0 {
                            out_of_fold.push((h, labelled));
                        }
                        let c = cell(&seg, &mocap6[h].truth)?;
                        println!(
                            "  {name}: held out {} — chose {chosen} → frame accuracy {}",
                            mocap6[h].name,
                            format!("{:.3}", c.scores.frame_accuracy)
                        );
                        if by_seed.len() <= i {
                            by_seed.push(Vec::new());
                        }
                        by_seed[i].push((mocap6[h].name.clone(), c.scores.clone()));
                        scores.push(c.scores);
                        chose.push(chosen);
                    }
                    // the seeds' networks averaged, when every seed's validated on one take (the default protocol)
                    if averaged.len() > 1 && averaged.iter().all(|m| m.0 == averaged[0].0) {
                        let v = averaged[0].0;
                        let mean =
                            |of: &dyn Fn(&(usize, Labelled, Labelled)) -> &Labelled| -> Result<Labelled, String> {
                                let all: Vec<&Labelled> = averaged.iter().map(of).collect();
                                let probabilities =
                                    Probabilities::mean(&all.iter().map(|l| &l.probabilities).collect::<Vec<_>>())
                                        .ok_or("the seeds' networks labelled different frames")?;
                                Ok(Labelled { probabilities, source: all[0].source.clone(), fps: NETWORK_FPS })
                            };
                        let (val, held) = (mean(&|m| &m.1)?, mean(&|m| &m.2)?);
                        let (_, threshold, decoding, _) =
                            validation_choice(&[(&motions[v], &val, labels[v].as_slice())]);
                        let file = held.file(&motions[h], &decoding, threshold);
                        let c = cell(&labelled_segmentation(&motions[h], &file, &classes, name), &mocap6[h].truth)?;
                        println!(
                            "  {name}: held out {} — the {} seeds' networks averaged (fixed in advance), unknown_threshold={threshold} {} chosen on {} → frame accuracy {:.3}, F1@1s {:.2}, covering {:.2}",
                            mocap6[h].name,
                            averaged.len(),
                            decoding_label(&decoding),
                            motions[v].name,
                            c.scores.frame_accuracy,
                            c.scores.f1_1,
                            c.scores.covering
                        );
                        reduced.push((mocap6[h].name.clone(), c.scores, MeanScores::mean(&scores), scores[0].clone()));
                    }
                    folds.push((mocap6[h].name.clone(), chose.join("; "), MeanScores::mean(&scores)));
                }
            }
            if !out_of_fold.is_empty() {
                let all: Vec<(&Motion, &Labelled, &[Option<usize>])> =
                    out_of_fold.iter().map(|(h, l)| (&motions[*h], l, labels[*h].as_slice())).collect();
                let (t, d, c) = best_decoding(&all);
                println!(
                    "  {name}: the shipped exercises model's decoding, chosen on all {} takes' out-of-fold labels: \
                     unknown_threshold={t} {} (criterion {c:.1})",
                    all.len(),
                    decoding_label(&d)
                );
            }
            // the spread over seeds (issue 50): each seed's held-out means over the takes, kept in the row's note
            let mut by_seed_note = String::new();
            if by_seed.len() > 1 {
                let means: Vec<String> = dtfcn_seeds
                    .iter()
                    .zip(&by_seed)
                    .map(|(seed, s)| {
                        let m = MeanScores::mean(&s.iter().map(|x| x.1.clone()).collect::<Vec<_>>());
                        format!("seed {seed} {:.3} / {:.2} / {:.2}", m.frame_accuracy, m.f1_1, m.covering)
                    })
                    .collect();
                println!("  {name}: held-out frame accuracy / F1@1s / covering by seed: {}", means.join(", "));
                by_seed_note = format!("; held-out frame acc. / F1@1s / covering by seed: {}", means.join(", "));
            }
            if !reduced.is_empty() {
                print_reduced(name, &reduced);
            }
            let held_out =
                (!folds.is_empty()).then(|| MeanScores::mean(&folds.iter().map(|f| f.2.clone()).collect::<Vec<_>>()));
            let note = if name == "dtfcn" {
                format!(
                    "defaults: the shipped models (in-sample); held out: mocap6 takes only, trained on the other three, \
                     the mean of seeds {} (the shipped models are seed {}; each seed chooses its own settings)",
                    dtfcn_seeds.iter().map(|s| s.to_string()).collect::<Vec<_>>().join(", "),
                    dtfcn_seeds[0]
                ) + if ensembles { "; the grid also offered 3-seed ensembles of half-width networks (--ensembles)" } else { "" }
                    + if inner_all { "; settings chosen on every inner take in turn (--inner-all)" } else { "" }
                    + if centring { "; each setting offered as it is and with every take centred on its own median posture (centre_on_take, --centring)" } else { "" }
                    + &by_seed_note
            } else {
                "defaults: the shipped models (in-sample); held out: mocap6 takes only, trained on the other three, the \
                 input (the joints, or DT-FCN's with the root's velocity and turning), the window (±0.5, ±1 or ±2 s) \
                 and k chosen on inner folds"
                    .into()
            };
            rows.push(MethodRow {
                method: name.into(),
                defaults: Some(defaults),
                in_sample: None,
                held_out,
                oracle_k: None,
                folds,
                seed_folds: if by_seed.len() > 1 { by_seed } else { Vec::new() },
                note,
                seconds: started.elapsed().as_secs_f64(),
            });
        }
        Ok(rows)
    }

    /// The fixed reducer against the seeds it averages: per take and the mean, frame accuracy / F1@1s / covering, and
    /// the paired difference from the seeds' mean and from the first seed (the shipped models') with its bootstrap 95 %
    /// interval over the takes.
    fn print_reduced(name: &str, reduced: &[(String, MeanScores, MeanScores, MeanScores)]) {
        println!("  {name}: the seeds' networks averaged (a reducer fixed in advance) against the seeds one by one:");
        println!("  | held-out take | averaged | mean of the seeds | first seed |");
        println!("  |---|---|---|---|");
        let triple = |s: &MeanScores| format!("{:.3} / {:.2} / {:.2}", s.frame_accuracy, s.f1_1, s.covering);
        for (take, e, m, first) in reduced {
            println!("  | {take} | {} | {} | {} |", triple(e), triple(m), triple(first));
        }
        let n = reduced.len() as f64;
        let mean =
            |f: &dyn Fn(&(String, MeanScores, MeanScores, MeanScores)) -> f64| reduced.iter().map(f).sum::<f64>() / n;
        for (what, of) in [
            ("frame accuracy", (|s: &MeanScores| s.frame_accuracy) as fn(&MeanScores) -> f64),
            ("F1@1s", |s: &MeanScores| s.f1_1),
            ("covering", |s: &MeanScores| s.covering),
        ] {
            let interval = |other: &dyn Fn(&(String, MeanScores, MeanScores, MeanScores)) -> f64| {
                let d: Vec<f64> = reduced.iter().map(|r| of(&r.1) - other(r)).collect();
                mocapseg::stats::bootstrap_mean(&d, 2000, 50)
                    .map_or("—".into(), |(m, lo, hi)| format!("{m:+.3} [{lo:+.3}, {hi:+.3}]"))
            };
            println!(
                "  {name}: {what} averaged {:.3}, seeds' mean {:.3}, first seed {:.3}; averaged − seeds' mean {}, averaged − first seed {}",
                mean(&|r| of(&r.1)),
                mean(&|r| of(&r.2)),
                mean(&|r| of(&r.3)),
                interval(&|r| of(&r.2)),
                interval(&|r| of(&r.3))
            );
        }
    }

    fn reference_rows(
        takes: &[(&Motion, &Truth)],
        priors: &[Prior],
        level: Level,
        seeds: u64,
    ) -> Result<Vec<MethodRow>, String> {
        let mut chance = Vec::new();
        let mut oracle = Vec::new();
        for (i, (m, t)) in takes.iter().enumerate() {
            chance.push(chance_scores(t, m.fps, &priors[i], level, seeds).map_err(|e| e.to_string())?);
            oracle.push(cell(&equal_parts(t.frames, m.fps, t.segments.len(), level), t)?.scores);
        }
        let row = |method: &str, all: Vec<MeanScores>, note: String| MethodRow {
            seed_folds: Vec::new(),
            method: method.into(),
            defaults: None,
            in_sample: None,
            held_out: Some(MeanScores::mean(&all)),
            oracle_k: None,
            folds: takes.iter().zip(&all).map(|((_, t), s)| (t.trial.clone(), String::new(), s.clone())).collect(),
            note,
            seconds: 0.0,
        };
        Ok(vec![
            row(
                "chance",
                chance,
                format!(
                    "cuts every mean true segment length from a random phase, labels drawn from the training prior; \
                     mean of {seeds} seeds"
                ),
            ),
            row(
                "oracle-K (equal parts)",
                oracle,
                "the take cut into as many equal parts as it has true segments".into(),
            ),
        ])
    }

    fn num(v: Option<f64>, digits: usize) -> String {
        match v {
            Some(x) if x.is_finite() => format!("{x:.digits$}"),
            _ => "—".into(),
        }
    }

    fn table(heading: &str, title: &str, rows: &[MethodRow], gestures: bool) -> String {
        let mut out = format!("{heading} {title}\n\n");
        let (a, b, an, bn) = if gestures { ("s@0.5s", "F1@0.5s", 1, 2) } else { ("F1@1s", "covering", 2, 2) };
        let pick = |m: &MeanScores| if gestures { (m.similarity, m.f1_05) } else { (m.f1_1, m.covering) };
        let _ = writeln!(
            out,
            "| method | {a} defaults | {a} in-sample best | **{a} held out** | {a} oracle-K | {b} defaults | {b} in-sample best | **{b} held out** | frame acc. defaults | **frame acc. held out** | segments found (defaults) |"
        );
        out += "|---|---|---|---|---|---|---|---|---|---|---|\n";
        // s is a count: on the gesture benchmark each is also shown per piece of its splice
        let first = |x: Option<f64>| match (gestures, x) {
            (true, Some(v)) if v.is_finite() => format!("{v:.1} ({:+.2}/piece)", v / GESTURE_PIECES as f64),
            _ => num(x, an),
        };
        for r in rows {
            let d = r.defaults.as_ref().map(pick);
            let i = r.in_sample.as_ref().map(|x| pick(&x.1));
            let h = r.held_out.as_ref().map(pick);
            let o = r.oracle_k.as_ref().map(pick);
            let _ = writeln!(
                out,
                "| {} | {} | {} | **{}** | {} | {} | {} | **{}** | {} | **{}** | {} |",
                r.method,
                first(d.map(|x| x.0)),
                first(i.map(|x| x.0)),
                first(h.map(|x| x.0)),
                first(o.map(|x| x.0)),
                num(d.map(|x| x.1), bn),
                num(i.map(|x| x.1), bn),
                num(h.map(|x| x.1), bn),
                num(r.defaults.as_ref().map(|m| m.frame_accuracy), 2),
                num(r.held_out.as_ref().map(|m| m.frame_accuracy), 2),
                num(r.defaults.as_ref().map(|m| m.segments), 1),
            );
        }
        out += "\nWhat each held-out fold chose (never on the take it reports):\n\n";
        for r in rows.iter().filter(|r| r.folds.iter().any(|f| !f.1.is_empty())) {
            let _ = writeln!(out, "- **{}** ({}):", r.method, r.note);
            for (take, chose, s) in &r.folds {
                let (x, y) = pick(s);
                let _ = writeln!(out, "  - {take}: {chose} → {a} {x:.2}, {b} {y:.2}");
            }
        }
        out
    }

    /// The labellers' own scores (frame accuracy, edit, F1@50, segments found) on the takes they are held out on,
    /// beside chance on the same takes and each take's true segment count (empty without labeller rows).
    fn labeller_table(heading: &str, rows: &[MethodRow]) -> String {
        let labellers: Vec<&MethodRow> =
            rows.iter().filter(|r| matches!(r.method.as_str(), "knn" | "dtfcn") && r.held_out.is_some()).collect();
        let Some(first) = labellers.first() else { return String::new() };
        let takes: Vec<&str> = first.folds.iter().map(|f| f.0.as_str()).collect();
        // a reference row's mean over the labellers' takes only
        let over_takes = |method: &str| -> Option<MeanScores> {
            let r = rows.iter().find(|r| r.method == method)?;
            let picked: Vec<MeanScores> =
                r.folds.iter().filter(|f| takes.contains(&f.0.as_str())).map(|f| f.2.clone()).collect();
            (!picked.is_empty()).then(|| MeanScores::mean(&picked))
        };
        let truth = over_takes("oracle-K (equal parts)").map(|m| m.segments);
        let mut out = format!(
            "{heading} Labellers (per-frame labels, on the takes held out: {})\n\n\
             Segmental scores as MS-TCN reports them (edit, F1@50 in %). *defaults*: the shipped models with the \
             method's default parameters on the takes they were trained on; *held out*: trained on the other takes, \
             every setting (k, network, unknown threshold, decoding) chosen on inner folds. True segments per take: \
             {}.\n\n",
            takes.join(", "),
            num(truth, 1)
        );
        out += "| method | frame acc. defaults | **frame acc. held out** | edit defaults | **edit held out** | F1@50 defaults | **F1@50 held out** | segments (defaults) | **segments held out** |\n";
        out += "|---|---|---|---|---|---|---|---|---|\n";
        let line = |name: &str, d: Option<&MeanScores>, h: Option<&MeanScores>| {
            format!(
                "| {name} | {} | **{}** | {} | **{}** | {} | **{}** | {} | **{}** |\n",
                num(d.map(|m| m.frame_accuracy), 2),
                num(h.map(|m| m.frame_accuracy), 2),
                num(d.map(|m| m.edit), 0),
                num(h.map(|m| m.edit), 0),
                num(d.map(|m| m.f1_50), 0),
                num(h.map(|m| m.f1_50), 0),
                num(d.map(|m| m.segments), 1),
                num(h.map(|m| m.segments), 1),
            )
        };
        for r in &labellers {
            out += &line(&r.method, r.defaults.as_ref(), r.held_out.as_ref());
        }
        out += &line("chance", None, over_takes("chance").as_ref());
        out
    }

    /// Bootstrap resamples of a held-out mean's interval (over takes), and their seed (fixed: a regenerated table is
    /// the same table).
    const RESAMPLES: usize = 10_000;
    const BOOTSTRAP_SEED: u64 = 50;

    /// The takes every row of a like-for-like table is averaged over: the ones the labellers are held out on (the
    /// mocap6 takes, one label set), or every take when no labeller row is there.
    fn common_takes(rows: &[MethodRow]) -> Vec<String> {
        let of = |r: &MethodRow| r.folds.iter().map(|f| f.0.clone()).collect::<Vec<_>>();
        rows.iter().filter(|r| r.held_out.is_some()).map(of).min_by_key(|t| t.len()).unwrap_or_default()
    }

    /// A held-out figure over `takes` of row `r`: the mean and its bootstrap 95 % interval, and the per-take values
    /// (None when the row was not held out on every one of them).
    /// A row's mean over `takes` with its bootstrap interval, and its per-take values (over its seeds' means): the
    /// interval drawn over the takes and, for a row with several seeds' runs, over the seeds too.
    fn spread(r: &MethodRow, takes: &[String], pick: fn(&MeanScores) -> f64) -> Option<((f64, f64, f64), Vec<f64>)> {
        let values: Vec<f64> = takes
            .iter()
            .map(|t| r.folds.iter().find(|f| &f.0 == t).map(|f| pick(&f.2)))
            .collect::<Option<Vec<f64>>>()?;
        let grid: Option<Vec<Vec<f64>>> = r
            .seed_folds
            .iter()
            .map(|run| takes.iter().map(|t| run.iter().find(|f| &f.0 == t).map(|f| pick(&f.1))).collect())
            .collect();
        let interval = match grid {
            Some(grid) if grid.len() > 1 => mocapseg::stats::bootstrap_grid_mean(&grid, RESAMPLES, BOOTSTRAP_SEED)?,
            _ => mocapseg::stats::bootstrap_mean(&values, RESAMPLES, BOOTSTRAP_SEED)?,
        };
        Some((interval, values))
    }

    /// `0.86 [0.74, 0.95]`.
    fn with_interval(m: Option<(f64, f64, f64)>) -> String {
        m.map_or("—".into(), |(m, lo, hi)| format!("{m:.2} [{lo:.2}, {hi:.2}]"))
    }

    /// Held out, like for like: every row averaged over the same takes (`common_takes`), each figure with its bootstrap
    /// 95 % interval over the takes and its per-take values — a difference counts only where the intervals say so.
    fn spread_table(heading: &str, rows: &[MethodRow]) -> String {
        let takes = common_takes(rows);
        if takes.is_empty() {
            return String::new();
        }
        let mut out = format!(
            "{heading} Held out, like for like: every row on the same takes ({}), with its spread\n\n\
             Each figure is the mean over these takes of the held-out score and, in brackets, its bootstrap 95 % \
             interval over the takes ({RESAMPLES} resamples; with {} takes a coarse one): two rows differ only where \
             their intervals do not overlap. Per take: F1@1s / covering on {} in turn. *frame acc.*: a labeller's \
             classes by name (a class the take does not have, and unknown, are wrong); a segmenter's clusters matched \
             one-to-one to the true labels — so a segmenter's frame acc. compares with oracle-K (equal parts), also \
             matched, and a labeller's with chance, whose drawn labels are read by name. DT-FCN's per-take figures are \
             means over its seeds, and its intervals are drawn over the seeds too (each resample draws takes and seeds \
             with replacement: a seed's luck counts in the spread).\n\n",
            takes.join(", "),
            takes.len(),
            takes.join(", "),
        );
        out += "| method | **F1@1s held out** [95 % CI] | **covering held out** [95 % CI] | **frame acc. held out** [95 % CI] | per take: F1@1s / covering |\n";
        out += "|---|---|---|---|---|\n";
        for r in rows {
            let (f1, cov, acc) = (
                spread(r, &takes, |m| m.f1_1),
                spread(r, &takes, |m| m.covering),
                spread(r, &takes, |m| m.frame_accuracy),
            );
            let Some(((_, f1_takes), (_, cov_takes))) = f1.as_ref().zip(cov.as_ref()) else { continue };
            let per_take: Vec<String> =
                f1_takes.iter().zip(cov_takes).map(|(a, b)| format!("{a:.2} / {b:.2}")).collect();
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} | {} |",
                r.method,
                with_interval(f1.as_ref().map(|x| x.0)),
                with_interval(cov.as_ref().map(|x| x.0)),
                with_interval(acc.as_ref().map(|x| x.0)),
                per_take.join(" · "),
            );
        }
        out
    }

    fn scores_json(m: &Option<MeanScores>) -> Value {
        m.as_ref().map_or(Value::Null, |m| serde_json::to_value(m).unwrap_or(Value::Null))
    }

    fn rows_json(rows: &[MethodRow]) -> Value {
        Value::Array(
            rows.iter()
                .map(|r| {
                    json!({
                        "method": r.method,
                        "note": r.note,
                        "defaults": scores_json(&r.defaults),
                        "in_sample_best": r.in_sample.as_ref().map(|(s, m)| json!({"setting": s, "scores": m})),
                        "held_out": scores_json(&r.held_out),
                        "oracle_k": scores_json(&r.oracle_k),
                        "folds": r.folds.iter().map(|(t, c, s)| json!({"take": t, "chose": c, "scores": s})).collect::<Vec<_>>(),
                        "seed_folds": r.seed_folds.iter().map(|run| run.iter().map(|(t, s)| json!({"take": t, "scores": s})).collect::<Vec<_>>()).collect::<Vec<_>>(),
                        "seconds": r.seconds,
                    })
                })
                .collect(),
        )
    }

    /// A spliced take with its truth.
    fn spliced(sources: &[Source], seed: u64, pieces: usize) -> Result<(Motion, Truth), String> {
        let s = splice(sources, &SpliceOptions { pieces, seed, ..Default::default() }).map_err(|e| e.to_string())?;
        let name = format!("splice{seed}-{}", sources.iter().map(|s| s.name).collect::<Vec<_>>().join("+"));
        let truth = load_csv(&s.truth_csv(&name), &name, TruthOptions::default()).map_err(|e| e.to_string())?;
        let motion = Motion::from_bvh(&name, &s.bvh).map_err(|e| e.to_string())?;
        Ok((motion, truth))
    }

    /// Pieces of each source's test splice in the gesture benchmark (`s`, a count, is read per piece beside it).
    const GESTURE_PIECES: usize = 20;

    /// The gesture benchmark: leave one source take out on spliced takes.
    fn gesture_rows(
        loaded: &[(String, Bvh, Truth)],
        seeds: u64,
        families: &Families,
    ) -> Result<Vec<MethodRow>, String> {
        let sources: Vec<Source> = loaded.iter().map(|(n, b, t)| Source { name: n, bvh: b, truth: t }).collect();
        // one set of splices for every column (issue 50): each source's own splice of GESTURE_PIECES pieces, each of
        // its own seed (so the five do not share one rhythm of piece lengths); defaults, in-sample best and oracle-K
        // score those, and the held-out column chooses each one's setting on splices of the other sources
        let mut folds: Vec<(Vec<(Motion, Truth)>, (Motion, Truth))> = Vec::new();
        for k in 0..sources.len() {
            let others: Vec<Source> =
                sources.iter().enumerate().filter(|(i, _)| *i != k).map(|(_, s)| Source { ..*s }).collect();
            let tuning = [1, 2].iter().map(|&seed| spliced(&others, seed, 30)).collect::<Result<_, _>>()?;
            folds.push((tuning, spliced(&sources[k..=k], 101 + k as u64, GESTURE_PIECES)?));
        }
        let all: Vec<(Motion, Truth)> = folds.iter().map(|(_, test)| test.clone()).collect();
        let mut rows = Vec::new();
        for name in ["velocity", "kcs", "pca", "lma"] {
            let started = Instant::now();
            let settings = grid(name);
            let refs: Vec<(&Motion, &Truth)> = all.iter().map(|(m, t)| (m, t)).collect();
            let cells = grid_cells(name, &settings, &refs)?;
            let every: Vec<usize> = (0..all.len()).collect();
            let b = best(&cells, &every, gesture_criterion);
            let mut fold_rows = Vec::new();
            for (k, (tuning, test)) in folds.iter().enumerate() {
                let refs: Vec<(&Motion, &Truth)> = tuning.iter().map(|(m, t)| (m, t)).collect();
                let c = grid_cells(name, &settings, &refs)?;
                let s = best(&c, &(0..refs.len()).collect::<Vec<_>>(), gesture_criterion);
                let scored = cell(&run_held_out(name, &settings[s], &test.0, sources[k].name, families)?, &test.1)?;
                println!("  {name} (splices): held out {} — chose {}", sources[k].name, label(&settings[s]));
                fold_rows.push((sources[k].name.to_string(), label(&settings[s]), scored.scores));
            }
            let oracle = oracle_k(&cells);
            rows.push(MethodRow {
                seed_folds: Vec::new(),
                method: name.into(),
                defaults: Some(mean_of(&every.iter().map(|&t| &cells[0][t]).collect::<Vec<_>>())),
                in_sample: Some((
                    label(&settings[b]),
                    mean_of(&every.iter().map(|&t| &cells[b][t]).collect::<Vec<_>>()),
                )),
                held_out: Some(MeanScores::mean(&fold_rows.iter().map(|f| f.2.clone()).collect::<Vec<_>>())),
                oracle_k: Some(mean_of(&oracle)),
                folds: fold_rows,
                note: format!("grid of {} settings", settings.len()),
                seconds: started.elapsed().as_secs_f64(),
            });
        }
        // references on the held-out splices (the takes the held-out column scores)
        let tests: Vec<(&Motion, &Truth)> = folds.iter().map(|(_, (m, t))| (m, t)).collect();
        let priors: Vec<Prior> = tests.iter().map(|(_, t)| prior(&[t])).collect();
        rows.extend(reference_rows(&tests, &priors, Level::Primitive, seeds)?);
        Ok(rows)
    }

    fn replace_block(text: &str, block: &str) -> Option<String> {
        let (begin, end) = ("<!-- accuracy:begin -->", "<!-- accuracy:end -->");
        let a = text.find(begin)? + begin.len();
        let b = text[a..].find(end)? + a;
        Some(format!("{}\n{}\n{}", &text[..a], block.trim_end(), &text[b..]))
    }

    pub fn run(args: Args) -> Result<(), String> {
        if let Some(path) = &args.from_json {
            return from_json(&args, path);
        }
        let started = Instant::now();
        let listed = crate::common::labelled_takes(&args.data)?;
        let mut takes = Vec::new();
        let mut loaded: Vec<(String, Bvh, Truth)> = Vec::new();
        for t in listed {
            let text = std::fs::read_to_string(&t.bvh).map_err(|e| format!("{}: {e}", t.bvh.display()))?;
            let b = bvh::parse(&text).map_err(|e| format!("{}: {e}", t.bvh.display()))?;
            let motion = Motion::from_bvh(t.trial, &b).map_err(|e| format!("{}: {e}", t.bvh.display()))?;
            let set = if t.trial.starts_with("86_") { "cmu86" } else { "mocap6" };
            loaded.push((t.trial.to_string(), b.clone(), t.truth.clone()));
            takes.push(Take { name: t.trial.to_string(), motion, truth: t.truth, set, bvh: b });
        }
        let missing: Vec<&str> = ["86_01", "13_29", "13_30", "13_31", "14_14"]
            .into_iter()
            .filter(|n| !takes.iter().any(|t| t.name == *n))
            .collect();
        if !missing.is_empty() {
            eprintln!(
                "note: missing from {}: {} — the scoreboard covers the rest",
                args.data.display(),
                missing.join(", ")
            );
        }
        if let Some(name) = &args.labeller {
            let carriers = carriers(&args.data, &takes)?;
            let rows = labeller_rows(
                &[name],
                args.lever,
                &carriers,
                &takes,
                args.ensembles,
                args.inner_all,
                args.centring,
                args.dtfcn_seeds as usize,
            )?;
            for row in rows {
                for (take, chose, s) in &row.folds {
                    println!(
                        "{} held out {take}: {:.3} / {:.2} / {:.2} — {chose}",
                        row.method, s.frame_accuracy, s.f1_1, s.covering
                    );
                }
                if let Some(h) = &row.held_out {
                    println!(
                        "{}: held out frame accuracy {:.3} F1@1s {:.3} covering {:.3} ({:.0} s); nothing written",
                        row.method, h.frame_accuracy, h.f1_1, h.covering, row.seconds
                    );
                }
            }
            return Ok(());
        }
        let refs: Vec<(&Motion, &Truth)> = takes.iter().map(|t| (&t.motion, &t.truth)).collect();
        println!("lma: one classifier family per held-out take, trained without it");
        let families = Families::train(&args.data, &takes.iter().map(|t| t.name.clone()).collect::<Vec<_>>())?;
        // nested: a take's parameters are chosen on every other take
        let others = |t: usize| (0..takes.len()).filter(|&i| i != t).collect::<Vec<_>>();
        let mut actions = Vec::new();
        let mut outputs = Vec::new();
        for name in ["sssm", "pca", "velocity", "kcs", "lma"] {
            println!("actions: {name}");
            let (row, out) = grid_row(name, &refs, action_criterion, others, &families)?;
            actions.push(row);
            outputs.push(out);
        }
        println!("actions: consensus of {}", outputs.iter().map(|o| o.method.as_str()).collect::<Vec<_>>().join(", "));
        actions.push(consensus_row(&refs, &outputs, action_criterion, &families)?);
        println!("actions: knn, dtfcn");
        actions.extend(labeller_rows(
            &["knn", "dtfcn"],
            Lever::None,
            &[],
            &takes,
            args.ensembles,
            args.inner_all,
            args.centring,
            args.dtfcn_seeds as usize,
        )?);
        // the training prior: the labels of the other takes of the same label set (86_01 has none: its own)
        let priors: Vec<Prior> = (0..takes.len())
            .map(|t| {
                let same: Vec<&Truth> = takes
                    .iter()
                    .enumerate()
                    .filter(|(i, o)| *i != t && o.set == takes[t].set)
                    .map(|(_, o)| &o.truth)
                    .collect();
                if same.is_empty() {
                    prior(&[&takes[t].truth])
                } else {
                    prior(&same)
                }
            })
            .collect();
        actions.extend(reference_rows(&refs, &priors, Level::Action, args.seeds)?);
        let gestures = if args.no_splice {
            Vec::new()
        } else {
            println!("gestures (spliced takes)");
            gesture_rows(&loaded, args.seeds, &families)?
        };

        let take_names: Vec<String> = takes.iter().map(|t| t.name.clone()).collect();
        let seconds = started.elapsed().as_secs_f64();
        let json = json!({
            "takes": take_names,
            "actions": rows_json(&actions),
            "gestures": rows_json(&gestures),
            "seconds": seconds,
        });
        std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
        let json_path = args.out.join("accuracy.json");
        let text = serde_json::to_string_pretty(&json).map_err(|e| e.to_string())?;
        std::fs::write(&json_path, &text).map_err(|e| format!("{}: {e}", json_path.display()))?;
        // the shipped models' cards, with the held-out figures just measured (the page shows them)
        if !args.cards.is_empty() {
            let cards_path = Path::new(env!("CARGO_MANIFEST_DIR")).join(&args.cards);
            let cards = mocapseg::method::cards::cards_json(&text, "cargo run --example accuracy (make accuracy)")?;
            std::fs::write(&cards_path, cards).map_err(|e| format!("{}: {e}", cards_path.display()))?;
            eprintln!("wrote {}", cards_path.display());
        }
        let md = write_markdown(&args, &take_names, &actions, &gestures, seconds)?;
        print!("{md}");
        eprintln!("wrote {} and {}", args.out.join("accuracy.md").display(), json_path.display());
        Ok(())
    }

    /// Where a method's rows are shown: its own page (the k-NN shares DT-FCN's; the references have none).
    fn page_of(method: &str) -> Option<&str> {
        match method {
            "chance" | "oracle-K (equal parts)" => None,
            "knn" => Some("dtfcn"),
            m => Some(m),
        }
    }

    fn is_reference(r: &MethodRow) -> bool {
        page_of(&r.method).is_none()
    }

    /// `to` as a link from a file in `from_dir` (both relative to the working folder).
    fn link(from_dir: &Path, to: &Path) -> String {
        let (from, to): (Vec<_>, Vec<_>) = (from_dir.components().collect(), to.components().collect());
        let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
        let mut out = PathBuf::new();
        for _ in common..from.len() {
            out.push("..");
        }
        to[common..].iter().for_each(|c| out.push(c));
        out.to_string_lossy().replace('\\', "/")
    }

    fn parent(file: &Path) -> PathBuf {
        file.parent().map_or_else(PathBuf::new, Path::to_path_buf)
    }

    /// Replaces the block of `path` by `block`.
    fn write_block(path: &Path, block: &str) -> Result<(), String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let new = replace_block(&text, block)
            .ok_or_else(|| format!("{}: no <!-- accuracy:begin --> … <!-- accuracy:end --> block", path.display()))?;
        std::fs::write(path, new).map_err(|e| format!("{}: {e}", path.display()))
    }

    const GENERATED: &str = "<!-- generated by `make accuracy` (examples/accuracy.rs); do not edit by hand -->\n\n";

    /// The whole scoreboard (accuracy.md).
    fn full_markdown(take_names: &[String], actions: &[MethodRow], gestures: &[MethodRow], seconds: f64) -> String {
        let mut md = String::from(GENERATED);
        let _ = writeln!(
            md,
            "Takes: {}. Every score is a mean over takes; *held out* chooses each take's parameters (or trains its model) \
             on the other takes only. Actions are scored as a tiling, gestures as given (`mocapseg eval`). *frame acc.*: \
             per-frame labelling accuracy (a labeller's classes by name; other methods' clusters mapped one-to-one \
             onto the true labels).\n",
            take_names.join(", ")
        );
        md += &spread_table("####", actions);
        md += "\n";
        md += &table("####", "Actions (action labels of the shared takes)", actions, false);
        let labellers = labeller_table("####", actions);
        if !labellers.is_empty() {
            md += "\n";
            md += &labellers;
        }
        if !gestures.is_empty() {
            md += "\n";
            md += &table("####", "Gestures (spliced takes with known boundaries)", gestures, true);
        }
        let _ = writeln!(md, "\n({seconds:.0} s to generate.)");
        md
    }

    /// A method page's block: its rows of each benchmark it is in, beside the reference rows.
    fn page_markdown(
        page: &str,
        take_names: &[String],
        benchmarks: &[(&str, &[MethodRow], bool)],
        full: &str,
    ) -> String {
        let mut md = String::from(GENERATED);
        let _ = writeln!(
            md,
            "Takes: {}. This method's rows of [the scoreboard]({full}) beside the chance and oracle-K (equal parts) \
             references; every score is a mean over takes, *held out* (in bold) is the number to believe.\n",
            take_names.join(", ")
        );
        for (title, rows, gestures) in benchmarks {
            if !rows.iter().any(|r| page_of(&r.method) == Some(page)) {
                continue;
            }
            let mine: Vec<MethodRow> = rows
                .iter()
                .filter(|r| page_of(&r.method) == Some(page) || is_reference(r))
                .map(MethodRow::clone)
                .collect();
            md += &table("###", title, &mine, *gestures);
            md += "\n";
            if !*gestures {
                let labellers = labeller_table("###", &mine);
                if !labellers.is_empty() {
                    md += &labellers;
                    md += "\n";
                }
            }
        }
        md
    }

    /// The README's summary: every method's held-out figures, like for like (every row on the same takes, said in the
    /// table), each with its bootstrap 95 % interval over the takes, and where its page is.
    fn summary_markdown(actions: &[MethodRow], gestures: &[MethodRow], pages: &str, full: &str) -> String {
        let mut md = String::from(GENERATED);
        let takes = common_takes(actions);
        md += "| method | takes | actions: F1@1s [95 % CI] | covering [95 % CI] | frame acc. [95 % CI] | gestures: s@0.5s | F1@0.5s |\n";
        md += "|---|---|---|---|---|---|---|\n";
        let mut names: Vec<&str> = actions.iter().map(|r| r.method.as_str()).collect();
        for r in gestures {
            if !names.contains(&r.method.as_str()) {
                names.push(&r.method);
            }
        }
        names.sort_by_key(|n| page_of(n).is_none()); // the references last, otherwise as generated
        for name in names {
            let row = actions.iter().find(|r| r.method == name);
            let pick = |f: fn(&MeanScores) -> f64| row.and_then(|r| spread(r, &takes, f)).map(|x| x.0);
            let g = gestures.iter().find(|r| r.method == name).and_then(|r| r.held_out.clone());
            let shown = match page_of(name) {
                Some(p) if !pages.is_empty() => format!("[{name}]({pages}/{p}.md)"),
                _ => name.to_string(),
            };
            let _ = writeln!(
                md,
                "| {shown} | {} | {} | {} | {} | {} | {} |",
                if row.is_some() { takes.join(", ") } else { "—".into() },
                with_interval(pick(|m| m.f1_1)),
                with_interval(pick(|m| m.covering)),
                with_interval(pick(|m| m.frame_accuracy)),
                num(g.as_ref().map(|m| m.similarity), 1),
                num(g.as_ref().map(|m| m.f1_05), 2),
            );
        }
        let _ = writeln!(
            md,
            "\nHeld out: each take's parameters are chosen (a labeller's model trained) on the other takes only. The \
             action columns are means over the same {} takes for every row (the labellers' label set; the rows that \
             also run on 86_01 are in the full table), in brackets the bootstrap 95 % interval over those takes — rows \
             differ only where their intervals do not overlap. Frame acc.: a labeller's classes by name (compare \
             chance, whose drawn labels are read by name too), a segmenter's clusters matched one-to-one (compare \
             oracle-K). The gesture columns are on spliced takes. Defaults, in-sample figures, every \
             take and what each fold chose: [{full}]({full}).",
            takes.len()
        );
        md
    }

    /// Writes accuracy.md, the method pages' blocks and the README's; returns accuracy.md's text.
    fn write_markdown(
        args: &Args,
        take_names: &[String],
        actions: &[MethodRow],
        gestures: &[MethodRow],
        seconds: f64,
    ) -> Result<String, String> {
        std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
        let md_path = args.out.join("accuracy.md");
        let md = full_markdown(take_names, actions, gestures, seconds);
        std::fs::write(&md_path, &md).map_err(|e| format!("{}: {e}", md_path.display()))?;
        if !args.methods.is_empty() {
            let dir = Path::new(&args.methods);
            let benchmarks: [(&str, &[MethodRow], bool); 2] = [
                ("Actions (action labels of the shared takes)", actions, false),
                ("Gestures (spliced takes with known boundaries)", gestures, true),
            ];
            let mut pages: Vec<&str> = actions.iter().chain(gestures).filter_map(|r| page_of(&r.method)).collect();
            pages.sort_unstable();
            pages.dedup();
            for page in pages {
                let block = page_markdown(page, take_names, &benchmarks, &link(dir, &md_path));
                write_block(&dir.join(format!("{page}.md")), &block)?;
            }
        }
        if !args.readme.is_empty() {
            let from = parent(Path::new(&args.readme));
            let pages = if args.methods.is_empty() { String::new() } else { link(&from, Path::new(&args.methods)) };
            write_block(Path::new(&args.readme), &summary_markdown(actions, gestures, &pages, &link(&from, &md_path)))?;
        }
        Ok(md)
    }

    fn scores_from_json(v: &Value) -> Option<MeanScores> {
        // NaN is written as null: read it back as NaN
        let f = |k: &str| v.get(k).and_then(Value::as_f64).unwrap_or(f64::NAN);
        v.is_object().then(|| MeanScores {
            f1_05: f("f1_05"),
            f1_1: f("f1_1"),
            covering: f("covering"),
            similarity: f("similarity"),
            frame_accuracy: f("frame_accuracy"),
            edit: f("edit"),
            f1_50: f("f1_50"),
            segments: f("segments"),
        })
    }

    /// The rows `rows_json` wrote.
    /// The array a JSON value holds (none: empty).
    fn items(v: Option<&Value>) -> &[Value] {
        v.and_then(Value::as_array).map_or(&[][..], Vec::as_slice)
    }

    fn rows_from_json(v: Option<&Value>) -> Vec<MethodRow> {
        let text = |v: &Value, k: &str| v.get(k).and_then(Value::as_str).unwrap_or_default().to_string();
        let none = Value::Null;
        v.and_then(Value::as_array)
            .map_or(&[][..], Vec::as_slice)
            .iter()
            .map(|r| MethodRow {
                method: text(r, "method"),
                defaults: scores_from_json(r.get("defaults").unwrap_or(&none)),
                in_sample: r
                    .get("in_sample_best")
                    .and_then(|b| Some((text(b, "setting"), scores_from_json(b.get("scores").unwrap_or(&none))?))),
                held_out: scores_from_json(r.get("held_out").unwrap_or(&none)),
                oracle_k: scores_from_json(r.get("oracle_k").unwrap_or(&none)),
                folds: items(r.get("folds"))
                    .iter()
                    .filter_map(|f| {
                        Some((text(f, "take"), text(f, "chose"), scores_from_json(f.get("scores").unwrap_or(&none))?))
                    })
                    .collect(),
                seed_folds: items(r.get("seed_folds"))
                    .iter()
                    .map(|run| {
                        items(Some(run))
                            .iter()
                            .filter_map(|f| {
                                Some((text(f, "take"), scores_from_json(f.get("scores").unwrap_or(&none))?))
                            })
                            .collect()
                    })
                    .collect(),
                note: text(r, "note"),
                seconds: r.get("seconds").and_then(Value::as_f64).unwrap_or(0.0),
            })
            .collect()
    }

    /// `--from-json`: the markdown again from a saved accuracy.json, nothing evaluated.
    fn from_json(args: &Args, path: &Path) -> Result<(), String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let json: Value = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let take_names: Vec<String> = json
            .get("takes")
            .and_then(Value::as_array)
            .map_or(&[][..], Vec::as_slice)
            .iter()
            .filter_map(|t| t.as_str().map(str::to_string))
            .collect();
        let actions = rows_from_json(json.get("actions"));
        if actions.is_empty() {
            return Err(format!("{}: no action rows", path.display()));
        }
        let gestures = rows_from_json(json.get("gestures"));
        let seconds = json.get("seconds").and_then(Value::as_f64).unwrap_or(f64::NAN);
        write_markdown(args, &take_names, &actions, &gestures, seconds)?;
        eprintln!("wrote {} from {}", args.out.join("accuracy.md").display(), path.display());
        Ok(())
    }
}
