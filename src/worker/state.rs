//! The worker's side of the protocol ([`crate::protocol`]): the take it holds, what a request
//! may do, and each request's work — pure Rust, tested natively; `super::glue` (feature `web`)
//! only converts `postMessage` packets.

use crate::bvh::Bvh;
use crate::dtfcn::corpus::{class_labels, model_from, rows_without_takes, ModelMeta};
use crate::dtfcn::input::NetworkInput;
use crate::dtfcn::model::{data_hash, Model, ModelKind};
use crate::dtfcn::training::{TrainOptions, Trainer, TrainingTake};
use crate::image::MotionImage;
use crate::lma::classifier::EffortModel;
use crate::lma::corpus::{parse_labels, Corpus, CorpusConfig, EffortLabel};
use crate::lma::training::{train_family, TrainConfig};
use crate::method::{MethodError, RunOptions};
use crate::motion::Motion;
use crate::protocol::*;

/// The worker's side of the protocol: holds the take loaded last and answers requests. Pure
/// Rust (the wasm entry point in `super::glue` only converts packets), so the take checks
/// are tested natively.
#[derive(Debug, Default)]
pub struct WorkerState {
    /// The take loaded last: its id, its motion and its parsed file (clips are cut from it).
    held: Option<(TakeId, Motion, Bvh)>,
    /// How `train_lma` trains (the trainer's defaults).
    training: TrainConfig,
    /// The DT-FCN training under way (one at a time: a new one replaces it).
    dtfcn: Option<DtfcnJob>,
}

/// A DT-FCN training under way in the worker, between two epochs.
struct DtfcnJob {
    take: TakeId,
    run: RunId,
    trainer: Trainer,
    /// The takes trained on, without their motion images (what the model's provenance needs).
    takes: Vec<TrainingTake>,
    classes: Vec<String>,
    options: TrainOptions,
    name: String,
    command: String,
    data_hash: String,
    used_rows: usize,
    left_out: Vec<String>,
}

impl std::fmt::Debug for DtfcnJob {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "DtfcnJob(run {} of take {}, model {}, {} epochs done)",
            self.run,
            self.take,
            self.name,
            self.trainer.reports().len()
        )
    }
}

/// The longest model name accepted.
const MAX_MODEL_NAME: usize = 64;

/// Refuses a name a user model cannot be installed under (empty, too long, control characters,
/// a shipped model's).
fn check_model_name(name: &str) -> Result<(), String> {
    if name.is_empty() {
        return Err("the model needs a name".into());
    }
    if name.chars().count() > MAX_MODEL_NAME {
        return Err(format!("the model name has {} characters; at most {MAX_MODEL_NAME}", name.chars().count()));
    }
    if name.chars().any(char::is_control) {
        return Err("the model name has a control character".into());
    }
    if crate::dtfcn::shipped::NAMES.contains(&name) {
        return Err(format!("`{name}` is the name of a shipped model; choose another name"));
    }
    Ok(())
}

/// `text` as one shell word (quoted when it holds a space), as the command line's provenance shows it.
fn shell_word(text: &str) -> String {
    if text.is_empty() || text.contains(|c: char| c.is_whitespace() || "'\"$`\\".contains(c)) {
        format!("'{}'", text.replace('\'', "'\\''"))
    } else {
        text.to_string()
    }
}

/// The `mocapseg train-dtfcn` command that trains the same model natively.
fn train_command(takes: &[String], labels: &str, name: &str, o: &TrainOptions) -> String {
    let d = TrainOptions::default();
    let mut words = vec!["mocapseg train-dtfcn --bvh".to_string()];
    words.extend(takes.iter().map(|t| shell_word(t)));
    words.push(format!(
        "--labels {} --epochs {} --seed {} --noise {} --mask {} --augment {} --width {}",
        shell_word(labels),
        o.epochs,
        o.seed,
        o.label_noise,
        o.mask_frames,
        o.augment.describe(),
        o.width
    ));
    if o.crop_frames != d.crop_frames {
        words.push(format!("--crop {}", o.crop_frames));
    }
    if o.batch != d.batch {
        words.push(format!("--batch {}", o.batch));
    }
    if o.learning_rate != d.learning_rate {
        words.push(format!("--learning-rate {}", o.learning_rate));
    }
    if o.weight_decay != d.weight_decay {
        words.push(format!("--weight-decay {}", o.weight_decay));
    }
    words.push(format!("--name {} -o {}", shell_word(name), shell_word(&format!("{name}.model"))));
    let mut command = words.join(" ");
    command += " (trained in the browser";
    if o.filters != d.filters {
        let filters: Vec<String> = o.filters.iter().map(usize::to_string).collect();
        command += &format!(", filters {}", filters.join(","));
    }
    command += ")";
    command
}

impl WorkerState {
    /// A worker that trains LMA families with `training` instead of the defaults.
    pub fn with_training(training: TrainConfig) -> WorkerState {
        WorkerState { held: None, training, dtfcn: None }
    }

    /// The request the worker should send itself next (after a `setTimeout(0)`, so that the
    /// page's messages are read first): the next epoch of the DT-FCN training under way.
    pub fn next_step(&self) -> Option<Request> {
        let job = self.dtfcn.as_ref()?;
        (!job.trainer.done()).then_some(Request::ContinueTraining { take: job.take, run: job.run })
    }

    /// The take the worker holds.
    pub fn held(&self) -> Option<TakeId> {
        self.held.as_ref().map(|(t, _, _)| *t)
    }

    /// The held take if it is `take`, else the `not_loaded` message.
    fn motion(&self, take: TakeId) -> Result<&Motion, String> {
        self.held_take(take).map(|(motion, _)| motion)
    }

    /// The held take's motion and file if it is `take`, else the `not_loaded` message.
    fn held_take(&self, take: TakeId) -> Result<(&Motion, &Bvh), String> {
        match &self.held {
            Some((held, motion, bvh)) if *held == take => Ok((motion, bvh)),
            Some((held, _, _)) => Err(format!("take {take} is not loaded in the worker (it holds take {held})")),
            None => Err(format!("take {take} is not loaded in the worker (it holds none)")),
        }
    }

    /// Answers `request`, posting progress and the final response through `post`.
    pub fn handle(&mut self, request: Request, post: &mut dyn FnMut(Response)) {
        match request {
            Request::Load { take, name, restore, bytes, skeleton, skeleton_bytes } => {
                let mut progress =
                    |f: f64| post(Response::Progress { take, run: None, stage: "parsing".into(), fraction: Some(f) });
                let asf = skeleton.as_deref().map(|n| (n, &skeleton_bytes[..]));
                let response = match self.load(take, &name, &bytes, asf, &mut progress) {
                    Ok(motion) if restore => {
                        drop(motion);
                        Response::Restored { take }
                    }
                    Ok(motion) => Response::Loaded { take, motion },
                    Err(message) => {
                        Response::Failed { take, run: None, message, kind: FailureKind::Input, field: None }
                    }
                };
                post(response);
            }
            Request::Segment { take, run, method, params } => {
                let response = self.segment(take, run, &method, &params, post);
                post(response);
            }
            Request::TrainLma { take, run, name, labels } => {
                let response = self.train_lma(take, run, &name, &labels, post);
                post(response);
            }
            Request::UseLmaModel { take, run, model } => post(use_lma_model(take, run, model.as_deref())),
            Request::ProvideModel { take, run, file, bytes } => {
                post(match crate::method::shipped::provide(&file, bytes) {
                    Ok(()) => Response::ModelProvided { take, run, file },
                    Err(message) => {
                        Response::Failed { take, run: Some(run), message, kind: FailureKind::Input, field: None }
                    }
                })
            }
            Request::UseLabelModel { take, run, kind, file, bytes } => {
                post(use_label_model(take, run, kind, &file, &bytes))
            }
            Request::TrainDtfcn { take, run, name, labels_name, labels, takes, options, bytes } => {
                let ask = DtfcnAsk { name, labels_name, labels, takes, options, bytes };
                match self.start_dtfcn(take, run, ask, post) {
                    Ok(()) => self.dtfcn_epoch(post),
                    Err((message, field)) => {
                        post(Response::Failed { take, run: Some(run), message, kind: FailureKind::Input, field })
                    }
                }
            }
            Request::ContinueTraining { run, .. } => {
                if self.dtfcn.as_ref().is_some_and(|j| j.run == run) {
                    self.dtfcn_epoch(post);
                }
            }
            Request::StopTraining { run, .. } => {
                if let Some(job) = self.dtfcn.as_mut().filter(|j| j.run == run) {
                    job.trainer.stop();
                    self.finish_dtfcn(post);
                }
            }
            Request::Clips { take, run, segmentation, which, to_origin, only } => {
                post(self.clips(take, run, &segmentation, crate::clips::ClipOptions { which, to_origin }, only))
            }
        }
    }

    /// Checks a DT-FCN training request and prepares its trainer (the job under way from now
    /// on); a refusal names the input that is wrong.
    fn start_dtfcn(
        &mut self,
        take: TakeId,
        run: RunId,
        ask: DtfcnAsk,
        post: &mut dyn FnMut(Response),
    ) -> Result<(), (String, Option<TrainField>)> {
        // a new training replaces the one under way
        self.dtfcn = None;
        let DtfcnAsk { name, labels_name, labels, takes: names, options, bytes } = ask;
        let name = name.trim().to_string();
        check_model_name(&name).map_err(|m| (m, Some(TrainField::Name)))?;
        let option_field = |m: String| {
            let field = TrainField::of_option_message(&m);
            (m, field)
        };
        options.check().map_err(option_field)?;
        let rows = crate::labels::read_csv(&labels, &labels_name).map_err(|m| (m, Some(TrainField::Labels)))?;
        if rows.is_empty() {
            return Err((format!("{labels_name} has no rows, only its header"), Some(TrainField::Labels)));
        }
        let takes_field = |m: String| (m, Some(TrainField::Takes));
        for (i, a) in names.iter().enumerate() {
            if names[..i].iter().any(|b| crate::lma::corpus::same_file(a, b)) {
                return Err(takes_field(format!("{a} is given twice")));
            }
        }
        // the takes some row names, parsed
        let mut motions: Vec<Motion> = Vec::new();
        let mut hashed: Vec<(String, Vec<u8>)> = Vec::new();
        let named: Vec<usize> = (0..names.len())
            .filter(|&i| rows.iter().any(|r| crate::lma::corpus::same_file(&r.file, &names[i])))
            .collect();
        if named.is_empty() {
            let files: Vec<&str> = rows.iter().map(|r| r.file.as_str()).collect();
            return Err((no_rows_for_takes(&labels_name, &names, &files), Some(TrainField::Labels)));
        }
        let mut bytes: Vec<Option<Vec<u8>>> = bytes.into_iter().map(Some).collect();
        for (k, &i) in named.iter().enumerate() {
            post(Response::Progress {
                take,
                run: Some(run),
                stage: format!("reading {}", names[i]),
                fraction: Some(k as f64 / named.len() as f64 * 0.5),
            });
            let file = bytes[i].take().unwrap_or_default();
            let loaded =
                crate::load::load_bytes(&names[i], &file, &mut |_| {}).map_err(|e| takes_field(e.to_string()))?;
            motions.push(loaded.motion);
            // kept for the data hash of the model's provenance
            hashed.push((names[i].clone(), file));
        }
        drop(bytes);
        let refs: Vec<&Motion> = motions.iter().collect();
        let left_out = rows_without_takes(&rows, &refs);
        let used_rows =
            rows.iter().filter(|r| refs.iter().any(|m| crate::lma::corpus::same_file(&m.name, &r.file))).count();
        let (classes, labels_per_take) =
            class_labels(&rows, &refs).map_err(|m| (format!("{labels_name}: {m}"), Some(TrainField::Labels)))?;
        options.network(classes.len()).check().map_err(option_field)?;
        post(Response::Progress { take, run: Some(run), stage: "motion images".into(), fraction: Some(0.5) });
        let mut training = Vec::with_capacity(motions.len());
        for (m, l) in motions.iter().zip(&labels_per_take) {
            training.push(TrainingTake::new(m, l).map_err(|e| takes_field(format!("{}: {e}", m.name)))?);
        }
        let light: Vec<TrainingTake> = training
            .iter()
            .map(|t| TrainingTake {
                name: t.name.clone(),
                input: NetworkInput { values: Vec::new(), frames: 0, source_frames: Vec::new() },
                labels: t.labels.clone(),
            })
            .collect();
        let trainer = Trainer::new(training, Vec::new(), classes.clone(), options.clone()).map_err(|m| {
            let field = TrainField::of_option_message(&m).or(Some(TrainField::Labels));
            (format!("{labels_name}: {m}"), field)
        })?;
        let used_names: Vec<String> = motions.iter().map(|m| m.name.clone()).collect();
        post(Response::Progress { take, run: Some(run), stage: "epoch 1".into(), fraction: Some(0.0) });
        self.dtfcn = Some(DtfcnJob {
            take,
            run,
            trainer,
            takes: light,
            classes,
            command: train_command(&used_names, &labels_name, &name, &options),
            options,
            data_hash: data_hash(&hashed, labels.as_bytes()),
            name,
            used_rows,
            left_out,
        });
        Ok(())
    }

    /// Runs the next epoch of the training under way and answers with its report; ends the run
    /// when it was the last.
    fn dtfcn_epoch(&mut self, post: &mut dyn FnMut(Response)) {
        let Some(job) = self.dtfcn.as_mut() else { return };
        let (take, run) = (job.take, job.run);
        match job.trainer.epoch() {
            Ok(report) => {
                let more = !job.trainer.done();
                post(Response::TrainingEpoch { take, run, report, more });
                if !more {
                    self.finish_dtfcn(post);
                }
            }
            Err(message) => {
                self.dtfcn = None;
                post(Response::Failed { take, run: Some(run), message, kind: FailureKind::Input, field: None });
            }
        }
    }

    /// Ends the training under way: its model (the best epoch's) is installed and sent.
    fn finish_dtfcn(&mut self, post: &mut dyn FnMut(Response)) {
        let Some(job) = self.dtfcn.take() else { return };
        let (take, run) = (job.take, job.run);
        let response = job.finish().unwrap_or_else(|message| Response::Failed {
            take,
            run: Some(run),
            message,
            kind: FailureKind::Input,
            field: None,
        });
        post(response);
    }

    fn load(
        &mut self,
        take: TakeId,
        name: &str,
        bytes: &[u8],
        asf: Option<(&str, &[u8])>,
        progress: &mut dyn FnMut(f64),
    ) -> Result<Box<LoadedMotion>, String> {
        let loaded = match asf {
            None => crate::load::load_bytes(name, bytes, progress),
            Some(asf) => crate::load::load_asf_amc(asf, (name, bytes), &crate::load::MemoryBudget::default()),
        }
        .map_err(|e| e.to_string())?;
        let crate::load::Loaded { bvh, motion } = loaded;
        let image = MotionImage::from_motion(&motion);
        let png = image.try_to_png().map_err(|e| format!("{name}: motion image: {e}"))?;
        let view = Box::new(LoadedMotion::new(&motion, &image, png));
        self.held = Some((take, motion, bvh));
        Ok(view)
    }

    /// Clips of the held take `take` cut at the segments of `segmentation`.
    fn clips(
        &self,
        take: TakeId,
        run: RunId,
        segmentation: &crate::segment::Segmentation,
        options: crate::clips::ClipOptions,
        only: Option<(usize, usize)>,
    ) -> Response {
        let fail = |message: String, kind| Response::Failed { take, run: Some(run), message, kind, field: None };
        let (motion, bvh) = match self.held_take(take) {
            Ok(held) => held,
            Err(message) => return fail(message, FailureKind::NotLoaded),
        };
        if let Err(e) = segmentation.validate() {
            return fail(format!("clips: {e}"), FailureKind::Input);
        }
        let stem = crate::clips::stem_of(&segmentation.file);
        match crate::clips::export(bvh, motion, segmentation, &stem, &options, only) {
            Ok(e) => Response::Clips { take, run, file: e.file, clips: e.clips, bytes: e.bytes },
            Err(e) => fail(format!("clips of {}: {e}", segmentation.file), FailureKind::Input),
        }
    }

    fn segment(
        &self,
        take: TakeId,
        run: RunId,
        method: &str,
        params: &serde_json::Value,
        post: &mut dyn FnMut(Response),
    ) -> Response {
        let fail = |message: String, kind| Response::Failed { take, run: Some(run), message, kind, field: None };
        let motion = match self.motion(take) {
            Ok(motion) => motion,
            Err(message) => return fail(message, FailureKind::NotLoaded),
        };
        let m = match crate::method::find(method) {
            Ok(m) => m,
            Err(e) => return fail(e.to_string(), FailureKind::Input),
        };
        let short = m.info().short;
        let mut progress = |stage: &str, fraction: f64| {
            post(Response::Progress { take, run: Some(run), stage: stage.into(), fraction: Some(fraction) })
        };
        match m.run_json(motion, params, &RunOptions { pictures: true }, &mut progress) {
            Ok(output) => Response::Segmented { take, run, view: Box::new(output.into()) },
            Err(MethodError::Cancelled) => fail(format!("{short}: cancelled"), FailureKind::Cancelled),
            Err(MethodError::Params { param, message }) => Response::Refused { take, run, message, param },
            Err(MethodError::NeedsModel { file }) => Response::NeedsModel { take, run, file },
            Err(e) => fail(format!("{short} on {}: {e}", motion.name), FailureKind::Input),
        }
    }

    /// Trains the LMA family on the rows of the labels file `name` that name the held take (the
    /// others are counted), reporting progress as run `run`, and makes it the family in use.
    /// Like a segment run it is stopped by replacing the worker, so its progress never cancels.
    fn train_lma(
        &self,
        take: TakeId,
        run: RunId,
        name: &str,
        labels: &str,
        post: &mut dyn FnMut(Response),
    ) -> Response {
        let fail = |message: String, kind| Response::Failed { take, run: Some(run), message, kind, field: None };
        let motion = match self.motion(take) {
            Ok(motion) => motion,
            Err(message) => return fail(message, FailureKind::NotLoaded),
        };
        let rows = match parse_labels(labels, name) {
            Ok(rows) => rows,
            Err(message) => return fail(message, FailureKind::Input),
        };
        let (used, ignored): (Vec<EffortLabel>, Vec<EffortLabel>) =
            rows.into_iter().partition(|row| crate::lma::corpus::same_file(&row.file, &motion.name));
        if used.is_empty() {
            return fail(no_rows_for(name, &motion.name, &ignored), FailureKind::Input);
        }
        let mut corpus = match Corpus::from_labels(&[motion], &used, CorpusConfig::default()) {
            Ok(corpus) => corpus,
            Err(message) => return fail(format!("{name}: {message}"), FailureKind::Input),
        };
        corpus.origin = format!("{} segments of {} labelled in {name}", corpus.samples.len(), motion.name);
        let mut progress = |stage: &str, fraction: f64| {
            post(Response::Progress { take, run: Some(run), stage: stage.into(), fraction: Some(fraction) });
            Ok(())
        };
        let (model, reports) = match train_family(&corpus, &self.training, &mut progress) {
            Ok(trained) => trained,
            Err(message) => return fail(format!("{name}: {message}"), FailureKind::Input),
        };
        let report = reports.iter().enumerate().map(|(f, r)| FactorSummary::new(r, &corpus.samples, f)).collect();
        let json = model.to_json();
        let origin = model.origin.clone();
        crate::lma::use_model(Some(model));
        Response::Trained { take, run, model: json, report, origin, used_rows: used.len(), ignored_rows: ignored.len() }
    }
}

/// What a `train_dtfcn` request asks, once its ids are taken out.
struct DtfcnAsk {
    name: String,
    labels_name: String,
    labels: String,
    takes: Vec<String>,
    options: TrainOptions,
    bytes: Vec<Vec<u8>>,
}

impl DtfcnJob {
    /// The model of the finished run, installed, as the answer to the page.
    fn finish(self) -> Result<Response, String> {
        let trained = self.trainer.finish()?;
        let (reports, best_epoch, stopped) = (trained.reports.clone(), trained.best_epoch, trained.stopped);
        let meta = ModelMeta { name: self.name.clone(), command: self.command, data_hash: self.data_hash };
        let model = model_from(trained, &self.takes, &self.classes, &self.options, &meta);
        let bytes = model.to_bytes()?;
        let info = LabelModelInfo::new(&self.name, &model);
        crate::dtfcn::method::install(&self.name, model)?;
        Ok(Response::DtfcnTrained {
            take: self.take,
            run: self.run,
            model: info,
            reports,
            best_epoch,
            stopped,
            used_rows: self.used_rows,
            left_out: self.left_out,
            bytes,
        })
    }
}

/// Installs the labelling model file `file` (its bytes) for the method of `kind`.
fn use_label_model(take: TakeId, run: RunId, kind: ModelKind, file: &str, bytes: &[u8]) -> Response {
    let fail =
        |message: String| Response::Failed { take, run: Some(run), message, kind: FailureKind::Input, field: None };
    let model = match Model::from_bytes(bytes, file) {
        Ok(model) => model,
        Err(message) => return fail(message),
    };
    if model.header.kind != kind {
        return fail(format!(
            "{file} holds a {} model, not a {} model: load it in the {} panel",
            kind_short(model.header.kind),
            kind_short(kind),
            kind_short(model.header.kind)
        ));
    }
    let inner = model.header.name.trim().to_string();
    let name = if check_model_name(&inner).is_ok() {
        inner
    } else {
        let base = file.rsplit(['/', '\\']).next().unwrap_or(file);
        let stem = base.rsplit_once('.').map_or(base, |(stem, _)| stem).trim().to_string();
        if let Err(message) = check_model_name(&stem) {
            return fail(format!("{file}: the model is called `{inner}` and the file `{stem}`: {message}"));
        }
        stem
    };
    let info = LabelModelInfo::new(&name, &model);
    match crate::dtfcn::method::install(&name, model) {
        Ok(()) => Response::LabelModelInUse { take, run, model: info },
        Err(message) => fail(format!("{file}: {message}")),
    }
}

/// Why a label CSV gives nothing to train on from the takes `takes`: its rows (naming `files`)
/// name none of them.
fn no_rows_for_takes(name: &str, takes: &[String], files: &[&str]) -> String {
    let mut named: Vec<&str> = Vec::new();
    for f in files {
        if !named.contains(f) {
            named.push(f);
        }
    }
    const SHOWN: usize = 5;
    let mut list = named.iter().take(SHOWN).map(|f| format!("`{f}`")).collect::<Vec<_>>().join(", ");
    if named.len() > SHOWN {
        list += &format!(" and {} more", named.len() - SHOWN);
    }
    let given = match takes {
        [] => "no take is given".to_string(),
        [one] => format!("no row is for the loaded take `{one}`"),
        [first, rest @ ..] => format!(
            "no row is for the loaded take `{first}` or the other takes given ({})",
            rest.iter().map(|t| format!("`{t}`")).collect::<Vec<_>>().join(", ")
        ),
    };
    format!("{name}: {given}; its rows name {list}")
}

/// Makes the family `model` (JSON text; `None`: the shipped one) the one `lma` runs use.
fn use_lma_model(take: TakeId, run: RunId, model: Option<&str>) -> Response {
    let fail =
        |message: String| Response::Failed { take, run: Some(run), message, kind: FailureKind::Input, field: None };
    match model.map(EffortModel::from_json).transpose() {
        Ok(model) => crate::lma::use_model(model),
        Err(message) => return fail(message),
    }
    match crate::lma::model_in_use() {
        Ok((model, shipped)) => Response::ModelInUse { take, run, origin: model.origin.clone(), shipped },
        Err(MethodError::NeedsModel { file }) => Response::NeedsModel { take, run, file },
        Err(e) => fail(e.to_string()),
    }
}

/// Why a labels file gives nothing to learn from the take `take`: no rows at all, or only rows
/// for other files (a few of which it names).
fn no_rows_for(name: &str, take: &str, others: &[EffortLabel]) -> String {
    if others.is_empty() {
        return format!("{name} has no rows, only its header");
    }
    let mut files: Vec<&str> = Vec::new();
    for row in others {
        if !files.contains(&row.file.as_str()) {
            files.push(&row.file);
        }
    }
    const SHOWN: usize = 5;
    let mut named = files.iter().take(SHOWN).map(|f| format!("`{f}`")).collect::<Vec<_>>().join(", ");
    if files.len() > SHOWN {
        named += &format!(" and {} more", files.len() - SHOWN);
    }
    format!("{name}: no row is for the loaded take `{take}`; its rows name {named}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dtfcn::training::EpochReport;

    fn take_bytes() -> Vec<u8> {
        include_bytes!("../../tests/fixtures/12_01.bvh").to_vec()
    }

    /// Runs `request` on `worker`, returning everything it posted.
    fn ask(worker: &mut WorkerState, request: Request) -> Vec<Response> {
        let mut posted = Vec::new();
        worker.handle(request, &mut |r| posted.push(r));
        posted
    }

    fn segment(take: TakeId, run: RunId) -> Request {
        Request::Segment { take, run, method: "sssm".into(), params: serde_json::json!({}) }
    }

    /// The page hands a shipped model file over as buffer 0; the worker checks it against this
    /// build's SHA-256 and answers `model_provided`, or `failed` naming the file.
    #[test]
    fn a_shipped_model_file_crosses_as_a_buffer_and_is_checked() {
        let file = "knn-cmu-actions.model".to_string();
        let good = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/models/knn-cmu-actions.model")).unwrap();
        let request = Request::ProvideModel { take: 3, run: 4, file: file.clone(), bytes: good.clone() };
        let packet = request.clone().into_packet();
        assert_eq!(packet.buffers, vec![good.clone()]);
        assert!(!packet.json.contains("bytes"), "the bytes travel as a buffer, not in the JSON");
        assert_eq!(Request::from_packet(packet).unwrap(), request);
        let mut worker = WorkerState::default();
        assert_eq!(ask(&mut worker, request), vec![Response::ModelProvided { take: 3, run: 4, file: file.clone() }]);
        let mut bad = good;
        bad.truncate(1000);
        let refused = ask(&mut worker, Request::ProvideModel { take: 3, run: 5, file, bytes: bad });
        assert!(
            matches!(&refused[..], [Response::Failed { run: Some(5), kind: FailureKind::Input, message, .. }]
                if message.starts_with("models/knn-cmu-actions.model: 1000 bytes")),
            "{refused:?}"
        );
        let unknown =
            ask(&mut worker, Request::ProvideModel { take: 3, run: 6, file: "x.model".into(), bytes: vec![] });
        assert!(
            matches!(&unknown[..], [Response::Failed { message, .. }] if message.contains("not a shipped model file"))
        );
    }

    #[test]
    fn an_amc_load_carries_its_asf_skeleton_as_a_second_buffer_and_the_worker_cuts_clips_of_it() {
        let asf = include_bytes!("../../tests/fixtures/02.asf").to_vec();
        let amc = include_bytes!("../../tests/fixtures/02_01.amc").to_vec();
        let load = Request::Load {
            take: 1,
            name: "02_01.amc".into(),
            restore: false,
            bytes: amc.clone(),
            skeleton: Some("02.asf".into()),
            skeleton_bytes: asf.clone(),
        };
        let packet = load.clone().into_packet();
        assert_eq!(packet.buffers, vec![amc.clone(), asf]);
        assert_eq!(Request::from_packet(packet.clone()).unwrap(), load);
        let lost = Packet { buffers: vec![amc], ..packet };
        assert!(Request::from_packet(lost).unwrap_err().contains("without its ASF skeleton's bytes"));

        let mut w = WorkerState::default();
        let Some(Response::Loaded { take: 1, motion }) = ask(&mut w, load).pop() else { panic!("not loaded") };
        let frames = motion.summary.frames;
        let Some(Response::Segmented { view, .. }) = ask(&mut w, segment(1, 2)).pop() else { panic!("not segmented") };
        let seg = view.segmentation.clone();
        assert!(seg.level(crate::segment::Level::Action).count() >= 1, "{seg:?}");
        let clips = |take, which, only| Request::Clips {
            take,
            run: 3,
            segmentation: Box::new(seg.clone()),
            which,
            to_origin: false,
            only,
        };
        // the request travels (no buffers), the answer's bytes in buffer 0
        let asked = clips(1, crate::clips::Which::Actions, None);
        assert_eq!(Request::from_packet(asked.clone().into_packet()).unwrap(), asked);
        let Some(zipped) = ask(&mut w, asked).pop() else { panic!() };
        let back = Response::from_packet(zipped.clone().into_packet()).unwrap();
        assert_eq!(back, zipped);
        let Response::Clips { file, clips: n, bytes, .. } = zipped else { panic!("{zipped:?}") };
        assert_eq!((file.as_str(), n), ("02_01_actions_clips.zip", seg.level(crate::segment::Level::Action).count()));
        assert!(bytes.starts_with(b"PK\x03\x04"));
        // one segment: its BVH, as many frames as it spans
        let first = seg.level(crate::segment::Level::Action).min_by_key(|s| s.start).unwrap().clone();
        let Some(Response::Clips { file, bytes, clips: 1, .. }) =
            ask(&mut w, clips(1, crate::clips::Which::Actions, Some((first.start, first.end)))).pop()
        else {
            panic!("no clip")
        };
        assert!(file.starts_with("02_01_01_") && file.ends_with(".bvh"), "{file}");
        let clip = crate::bvh::parse(std::str::from_utf8(&bytes).unwrap()).unwrap();
        assert_eq!(clip.frames(), first.end - first.start + 1);
        // another take: not loaded; frames no segment has: a message
        let other = ask(&mut w, clips(9, crate::clips::Which::Actions, None));
        assert!(matches!(other.last(), Some(Response::Failed { kind: FailureKind::NotLoaded, run: Some(3), .. })));
        let none = ask(&mut w, clips(1, crate::clips::Which::Actions, Some((0, frames - 1))));
        let Some(Response::Failed { kind: FailureKind::Input, message, .. }) = none.last() else { panic!("{none:?}") };
        assert!(
            message.starts_with("clips of 02_01.amc: the segmentation has no action segment at frames 0–"),
            "{message}"
        );
    }

    #[test]
    fn the_worker_segments_only_the_take_a_request_names() {
        let mut w = WorkerState::default();
        let none = ask(&mut w, segment(1, 1));
        assert!(matches!(&none[..], [Response::Failed { kind: FailureKind::NotLoaded, run: Some(1), .. }]), "{none:?}");

        let load = ask(
            &mut w,
            Request::Load {
                take: 1,
                name: "12_01.bvh".into(),
                restore: false,
                bytes: take_bytes(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
        );
        assert!(matches!(load.first(), Some(Response::Progress { take: 1, run: None, .. })));
        assert!(matches!(load.last(), Some(Response::Loaded { take: 1, .. })));
        assert_eq!(w.held(), Some(1));

        // a bad file (take 2) fails and leaves take 1 held
        let bad = ask(
            &mut w,
            Request::Load {
                take: 2,
                name: "bad.bvh".into(),
                restore: false,
                bytes: b"HIERARCHY\nROOT".to_vec(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
        );
        let Some(Response::Failed { take: 2, run: None, message, kind: FailureKind::Input, .. }) = bad.last() else {
            panic!("{bad:?}")
        };
        assert!(message.starts_with("bad.bvh: line "), "{message}");
        assert_eq!(w.held(), Some(1));

        // a segment request for another take is refused, for the held one answered
        let other = ask(&mut w, segment(3, 2));
        assert!(matches!(other.last(), Some(Response::Failed { take: 3, kind: FailureKind::NotLoaded, .. })));
        let done = ask(&mut w, segment(1, 3));
        assert!(done.iter().any(|r| matches!(r, Response::Progress { run: Some(3), .. })));
        let Some(Response::Segmented { take: 1, run: 3, view }) = done.last() else { panic!("{:?}", done.last()) };
        assert_eq!(view.segmentation.file, "12_01.bvh");
        assert_eq!(view.details.pictures.len(), 1);

        // a restore answers without the bulk data; a bad parameter names itself
        let restored = ask(
            &mut w,
            Request::Load {
                take: 4,
                name: "12_01.bvh".into(),
                restore: true,
                bytes: take_bytes(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
        );
        assert_eq!(restored.last(), Some(&Response::Restored { take: 4 }));
        let bad = ask(
            &mut w,
            Request::Segment { take: 4, run: 5, method: "sssm".into(), params: serde_json::json!({"radius": -1}) },
        );
        let Some(Response::Refused { run: 5, message, param, .. }) = bad.last() else { panic!("{bad:?}") };
        assert!(message.contains("radius = -1"), "{message}");
        assert_eq!(param.as_deref(), Some("radius"), "the refusal names its parameter, as data");
        let packet = bad.last().unwrap().clone().into_packet();
        assert_eq!(Response::from_packet(packet).as_ref(), Ok(bad.last().unwrap()));
        let unknown =
            ask(&mut w, Request::Segment { take: 4, run: 6, method: "nope".into(), params: serde_json::json!({}) });
        assert!(matches!(unknown.last(), Some(Response::Failed { kind: FailureKind::Input, .. })));
    }

    #[test]
    fn lma_families_travel_as_buffers_and_labels_as_text() {
        let train = Request::TrainLma { take: 2, run: 3, name: "e.csv".into(), labels: "file,start_frame\n".into() };
        let packet = train.clone().into_packet();
        assert!(packet.buffers.is_empty());
        assert_eq!(Request::from_packet(packet).unwrap(), train);
        assert_eq!(train.take(), 2);

        let family = r#"{"fps": 30.0, "factors": []}"#.to_string();
        let mine = Request::UseLmaModel { take: 2, run: 4, model: Some(family.clone()) };
        let packet = mine.clone().into_packet();
        assert_eq!(packet.buffers, vec![family.clone().into_bytes()]);
        assert!(!packet.json.contains("factors"), "the family travels as a buffer: {}", packet.json);
        assert_eq!(Request::from_packet(packet).unwrap(), mine);
        let shipped = Request::UseLmaModel { take: 2, run: 5, model: None };
        let packet = shipped.clone().into_packet();
        assert!(packet.buffers.is_empty(), "no buffer: the shipped family");
        assert_eq!(Request::from_packet(packet).unwrap(), shipped);
        let garbled =
            Packet { json: r#"{"type":"use_lma_model","take":2,"run":5}"#.into(), buffers: vec![vec![0xff, 0xfe]] };
        assert!(Request::from_packet(garbled).unwrap_err().contains("the LMA family is not UTF-8"));

        let report = vec![FactorSummary {
            factor: "space".into(),
            segments: [4, 5, 3],
            hidden: 3,
            train_error: 0.1,
            validation_error: 0.5,
            shifted_validation_error: 0.45,
        }];
        let trained = Response::Trained {
            take: 2,
            run: 3,
            model: family.clone(),
            report,
            origin: "12 segments".into(),
            used_rows: 12,
            ignored_rows: 1,
        };
        let packet = trained.clone().into_packet();
        assert_eq!(packet.buffers, vec![family.into_bytes()]);
        assert!(!packet.json.contains("factors"), "{}", packet.json);
        let v: serde_json::Value = serde_json::from_str(&packet.json).unwrap();
        assert_eq!((v["type"].as_str(), v["report"][0]["segments"][1].as_u64()), (Some("trained"), Some(5)));
        assert_eq!(Response::from_packet(packet.clone()).unwrap(), trained);
        let mut missing = packet;
        missing.buffers.clear();
        assert!(Response::from_packet(missing).unwrap_err().contains("no buffer for the trained family"));
    }

    /// Effort labels CSV rows `file,start,end,class×4`, classes cycling through the three elements.
    fn label_rows(file: &str, rows: usize, step: usize, length: usize) -> String {
        (0..rows)
            .map(|k| {
                let classes = [0, 1, 2, k].map(|f| ["indulging", "neutral", "condensing"][(k + f) % 3]).join(",");
                format!("{file},{},{},{classes}\n", step * k, step * k + length)
            })
            .collect()
    }

    const HEADER: &str = "file,start_frame,end_frame,space,time,weight,flow\n";

    fn train(take: TakeId, run: RunId, labels: String) -> Request {
        Request::TrainLma { take, run, name: "mine.csv".into(), labels }
    }

    fn failure(posted: Vec<Response>) -> (FailureKind, String) {
        match posted.last() {
            Some(Response::Failed { kind, message, .. }) => (*kind, message.clone()),
            other => panic!("expected a failure, got {other:?}"),
        }
    }

    fn lma_summary(worker: &mut WorkerState, take: TakeId, run: RunId) -> String {
        let posted = ask(worker, Request::Segment { take, run, method: "lma".into(), params: serde_json::json!({}) });
        let Some(Response::Segmented { view, .. }) = posted.last() else { panic!("{:?}", posted.last()) };
        view.details.summary.clone()
    }

    /// The only test in this process that changes the LMA family in use (it is per process,
    /// as it is per worker in the browser).
    #[test]
    fn the_worker_trains_an_lma_family_on_the_rows_for_its_take_and_uses_it_until_told_otherwise() {
        let quick =
            crate::lma::network::TrainOptions { max_epochs: 40, learning_rate: 0.02, weight_decay: 1e-4, patience: 10 };
        let config = TrainConfig {
            restarts: 2,
            saliency_rounds: 4,
            options: quick,
            shift_options: crate::lma::network::TrainOptions { max_epochs: 3, ..quick },
            ..TrainConfig::default()
        };
        let mut w = WorkerState::with_training(config);
        let mine = format!("{HEADER}{}", label_rows("12_01.bvh", 12, 30, 120));
        assert_eq!(failure(ask(&mut w, train(1, 1, mine.clone()))).0, FailureKind::NotLoaded);
        ask(
            &mut w,
            Request::Load {
                take: 1,
                name: "12_01.bvh".into(),
                restore: false,
                bytes: take_bytes(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
        );

        // what the user gets wrong is named: the line, the take and the files the rows name, too few rows
        let typo = mine.replacen("neutral", "nuetral", 1);
        let (kind, message) = failure(ask(&mut w, train(1, 2, typo)));
        assert_eq!(kind, FailureKind::Input);
        assert!(message.contains("mine.csv line 2") && message.contains("`nuetral`"), "{message}");
        let elsewhere = format!("{HEADER}{}{}", label_rows("35_01.bvh", 9, 20, 90), label_rows("nope", 1, 0, 50));
        let (kind, message) = failure(ask(&mut w, train(1, 3, elsewhere)));
        assert_eq!(kind, FailureKind::Input);
        assert!(message.contains("loaded take `12_01.bvh`") && message.contains("`35_01.bvh`, `nope`"), "{message}");
        let (_, message) = failure(ask(&mut w, train(1, 4, HEADER.to_string())));
        assert!(message.contains("no rows"), "{message}");
        let (_, message) = failure(ask(&mut w, train(1, 5, format!("{HEADER}{}", label_rows("12_01", 5, 30, 120)))));
        assert!(message.contains("too few to train on"), "{message}");
        let long =
            format!("{HEADER}{}12_01,400,600,neutral,neutral,neutral,neutral\n", label_rows("12_01", 9, 30, 120));
        let (_, message) = failure(ask(&mut w, train(1, 6, long)));
        assert!(message.contains("line 11") && message.contains("do not fit"), "{message}");
        assert!(!lma_summary(&mut w, 1, 7).contains("your classifiers"), "failed trainings leave the shipped family");

        // rows for the take (named in any case, with or without folder and extension) train the
        // family; the other file's rows are counted and left out
        let rows = label_rows("12_01.bvh", 12, 30, 120).replacen("12_01.bvh", "takes/12_01.BVH", 1).replacen(
            "12_01.bvh",
            "12_01",
            1,
        );
        let labels = format!("{HEADER}{rows}{}", label_rows("35_01.bvh", 3, 20, 90));
        let posted = ask(&mut w, train(1, 8, labels));
        let stages: Vec<&str> = posted
            .iter()
            .filter_map(|r| match r {
                Response::Progress { run: Some(8), stage, fraction: Some(f), .. } if (0.0..=1.0).contains(f) => {
                    Some(stage.as_str())
                }
                _ => None,
            })
            .collect();
        assert!(stages.contains(&"space saliency") && stages.contains(&"flow shifted networks"), "{stages:?}");
        let Some(Response::Trained { take: 1, run: 8, model, report, origin, used_rows: 12, ignored_rows: 3 }) =
            posted.last()
        else {
            panic!("{:?}", posted.last())
        };
        assert_eq!(report.iter().map(|r| r.factor.as_str()).collect::<Vec<_>>(), ["space", "time", "weight", "flow"]);
        for r in report {
            assert_eq!(r.segments.iter().sum::<usize>(), 12, "{r:?}");
            assert!((0.0..=1.0).contains(&r.validation_error) && r.hidden >= 1, "{r:?}");
        }
        assert_eq!(report[0].segments, [4, 4, 4]);
        assert_eq!(origin, "12 segments of 12_01.bvh labelled in mine.csv");
        let family = EffortModel::from_json(model).unwrap();
        assert_eq!((family.samples, &family.origin), (12, origin));
        let yours = format!(" · your classifiers ({origin})");
        assert!(lma_summary(&mut w, 1, 9).ends_with(&yours), "{}", lma_summary(&mut w, 1, 9));

        // a bad family file is refused with what is wrong, and the family in use stays
        let not_json = ask(&mut w, Request::UseLmaModel { take: 1, run: 10, model: Some("{\"fps\": 30".into()) });
        let (kind, message) = failure(not_json);
        assert!(kind == FailureKind::Input && message.contains("not an LMA effort model"), "{message}");
        let mut three: serde_json::Value = serde_json::from_str(model).unwrap();
        three["factors"].as_array_mut().unwrap().pop();
        let short = ask(&mut w, Request::UseLmaModel { take: 1, run: 11, model: Some(three.to_string()) });
        assert!(failure(short).1.contains("3 factors, expected 4"));
        assert!(lma_summary(&mut w, 1, 12).ends_with(&yours));

        // back to the shipped family, and the saved one again (whatever take the worker holds)
        let shipped = ask(&mut w, Request::UseLmaModel { take: 1, run: 13, model: None });
        let Some(Response::ModelInUse { shipped: true, origin: shipped_origin, .. }) = shipped.last() else {
            panic!("{shipped:?}")
        };
        assert!(shipped_origin.starts_with("stand-in labels"), "{shipped_origin}");
        assert!(!lma_summary(&mut w, 1, 14).contains("your classifiers"));
        let again = ask(&mut w, Request::UseLmaModel { take: 99, run: 15, model: Some(model.clone()) });
        assert_eq!(
            again.last(),
            Some(&Response::ModelInUse { take: 99, run: 15, origin: origin.clone(), shipped: false })
        );
        assert!(lma_summary(&mut w, 1, 16).ends_with(&yours));
        ask(&mut w, Request::UseLmaModel { take: 1, run: 17, model: None });
    }

    // ---- DT-FCN / k-NN models and training ------------------------------------------------

    fn tiny_options(epochs: usize) -> TrainOptions {
        TrainOptions { filters: vec![8, 8], crop_frames: 64, epochs, ..Default::default() }
    }

    const LABELS_HEADER: &str = "file,start_frame,end_frame,label\n";

    /// Label rows for 12_01.bvh (524 frames): three classes in turn.
    fn walk_labels() -> String {
        format!("{LABELS_HEADER}12_01.bvh,0,179,stand\n12_01.bvh,180,359,walk\n12_01.bvh,360,523,<b>turn</b>\n")
    }

    fn train_dtfcn(
        run: RunId,
        name: &str,
        labels: String,
        options: TrainOptions,
        takes: Vec<(&str, Vec<u8>)>,
    ) -> Request {
        let (names, bytes): (Vec<String>, Vec<Vec<u8>>) = takes.into_iter().map(|(n, b)| (n.to_string(), b)).unzip();
        Request::TrainDtfcn {
            take: 1,
            run,
            name: name.into(),
            labels_name: "labels.csv".into(),
            labels,
            takes: names,
            options,
            bytes,
        }
    }

    fn refusal(posted: Vec<Response>) -> (String, Option<TrainField>) {
        match posted.last() {
            Some(Response::Failed { kind: FailureKind::Input, message, field, .. }) => (message.clone(), *field),
            other => panic!("expected a refusal, got {other:?}"),
        }
    }

    #[test]
    fn label_model_requests_and_answers_carry_their_bytes_as_buffers() {
        let use_model = Request::UseLabelModel {
            take: 2,
            run: 3,
            kind: ModelKind::Knn,
            file: "mine.model".into(),
            bytes: b"mocapseg-model\n\x01".to_vec(),
        };
        let packet = use_model.clone().into_packet();
        assert_eq!(packet.buffers, vec![b"mocapseg-model\n\x01".to_vec()]);
        let v: serde_json::Value = serde_json::from_str(&packet.json).unwrap();
        assert_eq!((v["type"].as_str(), v["kind"].as_str()), (Some("use_label_model"), Some("knn")));
        assert_eq!(Request::from_packet(packet).unwrap(), use_model);
        let without = Packet {
            json: r#"{"type":"use_label_model","take":2,"run":3,"kind":"dtfcn","file":"x"}"#.into(),
            buffers: vec![],
        };
        assert!(Request::from_packet(without).unwrap_err().contains("without its bytes"));

        let train =
            train_dtfcn(4, "mine", walk_labels(), tiny_options(2), vec![("12_01.bvh", vec![1, 2]), ("b.bvh", vec![3])]);
        let packet = train.clone().into_packet();
        assert_eq!(packet.buffers, vec![vec![1, 2], vec![3]]);
        let v: serde_json::Value = serde_json::from_str(&packet.json).unwrap();
        assert_eq!(v["options"]["filters"], serde_json::json!([8, 8]));
        assert_eq!(v["takes"], serde_json::json!(["12_01.bvh", "b.bvh"]));
        assert_eq!(Request::from_packet(packet.clone()).unwrap(), train);
        assert_eq!(train.take(), 1);
        let mut short = packet;
        short.buffers.pop();
        assert!(Request::from_packet(short).unwrap_err().contains("2 takes but the bytes of 1"));
        // the page may leave options out: the defaults
        let bare = Packet {
            json: r#"{"type":"train_dtfcn","take":1,"run":2,"name":"m","labels_name":"l.csv","labels":"","takes":[],"options":{"epochs":3}}"#.into(),
            buffers: vec![],
        };
        let Request::TrainDtfcn { options, .. } = Request::from_packet(bare).unwrap() else { panic!() };
        assert_eq!(options, TrainOptions { epochs: 3, ..TrainOptions::default() });
        for r in [Request::ContinueTraining { take: 1, run: 5 }, Request::StopTraining { take: 1, run: 5 }] {
            let packet = r.clone().into_packet();
            assert!(packet.buffers.is_empty());
            assert_eq!(Request::from_packet(packet).unwrap(), r);
        }

        let info = LabelModelInfo {
            name: "mine".into(),
            kind: ModelKind::Dtfcn,
            classes: vec!["a".into(), "b".into()],
            colours: vec!["#ff0000".into(), "#00ff00".into()],
            unknown_threshold: 0.5,
            takes: vec!["12_01.bvh".into()],
            frames: 131,
            epochs_run: 2,
            best_epoch: 2,
            command: "mocapseg train-dtfcn".into(),
        };
        let report = EpochReport {
            epoch: 1,
            epochs: 2,
            loss: 1.1,
            train_accuracy: 0.4,
            validation_loss: None,
            validation_accuracy: None,
            best: true,
        };
        for r in [
            Response::LabelModelInUse { take: 1, run: 2, model: info.clone() },
            Response::TrainingEpoch { take: 1, run: 2, report: report.clone(), more: true },
            Response::Failed {
                take: 1,
                run: Some(2),
                message: "epochs 0".into(),
                kind: FailureKind::Input,
                field: Some(TrainField::Epochs),
            },
        ] {
            let packet = r.clone().into_packet();
            assert!(packet.buffers.is_empty());
            assert_eq!(Response::from_packet(packet).unwrap(), r);
        }
        let failed =
            Response::Failed { take: 1, run: None, message: "x".into(), kind: FailureKind::Input, field: None };
        assert!(!failed.into_packet().json.contains("field"), "no field: left out");
        let v: serde_json::Value = serde_json::from_str(
            &Response::Failed {
                take: 1,
                run: Some(2),
                message: "x".into(),
                kind: FailureKind::Input,
                field: Some(TrainField::LabelNoise),
            }
            .into_packet()
            .json,
        )
        .unwrap();
        assert_eq!(v["field"], "label_noise");
        // worker.js's own failure message has no field
        let glue = Packet {
            json: r#"{"type":"failed","take":0,"run":7,"message":"internal error: x","kind":"internal"}"#.into(),
            buffers: vec![],
        };
        assert!(matches!(
            Response::from_packet(glue).unwrap(),
            Response::Failed { field: None, kind: FailureKind::Internal, .. }
        ));

        let trained = Response::DtfcnTrained {
            take: 1,
            run: 2,
            model: info.clone(),
            reports: vec![report],
            best_epoch: 1,
            stopped: true,
            used_rows: 3,
            left_out: vec!["86_01.bvh".into()],
            bytes: b"mocapseg-model\nweights".to_vec(),
        };
        let packet = trained.clone().into_packet();
        assert_eq!(packet.buffers, vec![b"mocapseg-model\nweights".to_vec()]);
        assert!(!packet.json.contains("weights"), "{}", packet.json);
        assert_eq!(Response::from_packet(packet.clone()).unwrap(), trained);
        let mut missing = packet;
        missing.buffers.clear();
        assert!(Response::from_packet(missing).unwrap_err().contains("no buffer for the trained model"));
        let mut odd = info;
        odd.colours.pop();
        let bad = Response::LabelModelInUse { take: 1, run: 2, model: odd }.into_packet();
        assert!(Response::from_packet(bad).unwrap_err().contains("2 classes but 1 colours"));
    }

    #[test]
    fn option_refusals_name_their_field() {
        let field = |o: TrainOptions| TrainField::of_option_message(&o.check().unwrap_err());
        assert_eq!(field(TrainOptions { epochs: 0, ..Default::default() }), Some(TrainField::Epochs));
        assert_eq!(field(TrainOptions { label_noise: 1.5, ..Default::default() }), Some(TrainField::LabelNoise));
        assert_eq!(field(TrainOptions { mask_frames: 999, ..Default::default() }), Some(TrainField::MaskFrames));
        assert_eq!(field(TrainOptions { crop_frames: 1, ..Default::default() }), Some(TrainField::CropFrames));
        assert_eq!(field(TrainOptions { learning_rate: 0.0, ..Default::default() }), Some(TrainField::LearningRate));
        let network = |o: TrainOptions| TrainField::of_option_message(&o.network(3).check().unwrap_err());
        assert_eq!(network(TrainOptions { width: 9, ..Default::default() }), Some(TrainField::Width));
        assert_eq!(network(TrainOptions { filters: vec![], ..Default::default() }), Some(TrainField::Filters));
        assert_eq!(network(TrainOptions { filters: vec![0, 4], ..Default::default() }), Some(TrainField::Filters));
    }

    /// Trains through the worker as the page does: the request, then every `continue_training`
    /// the worker asks for, until it asks for none.
    fn train_to_the_end(w: &mut WorkerState, request: Request) -> Vec<Response> {
        let mut posted = ask(w, request);
        while let Some(next) = w.next_step() {
            assert!(matches!(next, Request::ContinueTraining { .. }), "{next:?}");
            posted.extend(ask(w, next));
        }
        posted
    }

    #[test]
    fn the_worker_trains_a_dtfcn_one_epoch_per_message_installs_it_and_sends_the_file() {
        let mut w = WorkerState::default();
        assert!(w.next_step().is_none(), "nothing to continue before a training");
        let labels = format!("{}86_01.bvh,0,99,walk\n", walk_labels());
        let first =
            ask(&mut w, train_dtfcn(7, "tiny-trained", labels, tiny_options(2), vec![("12_01.bvh", take_bytes())]));
        // epoch 1 answers, and the worker asks for epoch 2 (it does not run it by itself)
        let Some(Response::TrainingEpoch { take: 1, run: 7, report, more: true }) = first.last() else {
            panic!("{first:?}")
        };
        assert_eq!((report.epoch, report.epochs), (1, 2));
        assert!(report.loss.is_finite() && (0.0..=1.0).contains(&report.train_accuracy), "{report:?}");
        assert!(first.iter().any(|r| matches!(r, Response::Progress { run: Some(7), .. })));
        assert_eq!(w.next_step(), Some(Request::ContinueTraining { take: 1, run: 7 }));
        // a continue for another training is ignored
        assert!(ask(&mut w, Request::ContinueTraining { take: 1, run: 99 }).is_empty());
        let second = ask(&mut w, Request::ContinueTraining { take: 1, run: 7 });
        assert!(
            matches!(&second[0], Response::TrainingEpoch { run: 7, more: false, report, .. } if report.epoch == 2),
            "{second:?}"
        );
        let Some(Response::DtfcnTrained {
            run: 7,
            model,
            reports,
            best_epoch,
            stopped: false,
            used_rows: 3,
            left_out,
            bytes,
            ..
        }) = second.last()
        else {
            panic!("{second:?}")
        };
        assert!(w.next_step().is_none(), "the training is over");
        assert_eq!(reports.len(), 2);
        assert_eq!(*best_epoch, 2, "without validation takes the last epoch is kept");
        assert_eq!(left_out, &vec!["86_01.bvh".to_string()]);
        assert_eq!((model.name.as_str(), model.kind), ("tiny-trained", ModelKind::Dtfcn));
        assert_eq!(model.classes, vec!["stand", "walk", "<b>turn</b>"]);
        assert_eq!(model.colours.len(), 3);
        assert_eq!(model.takes, vec!["12_01.bvh"]);
        assert!(
            model.command.starts_with("mocapseg train-dtfcn --bvh 12_01.bvh --labels labels.csv --epochs 2"),
            "{}",
            model.command
        );
        assert!(model.command.contains("filters 8,8"), "{}", model.command);
        assert!(bytes.starts_with(b"mocapseg-model\n"));
        let back = Model::from_bytes(bytes, "tiny-trained.model").unwrap();
        assert_eq!(back.header.classes, model.classes);
        assert_eq!(back.header.provenance.epochs_run, 2);

        // the installed model labels the held take by its name
        ask(
            &mut w,
            Request::Load {
                take: 1,
                name: "12_01.bvh".into(),
                restore: false,
                bytes: take_bytes(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
        );
        let run = ask(
            &mut w,
            Request::Segment {
                take: 1,
                run: 8,
                method: "dtfcn".into(),
                params: serde_json::json!({"model": "tiny-trained"}),
            },
        );
        let Some(Response::Segmented { view, .. }) = run.last() else { panic!("{:?}", run.last()) };
        assert_eq!(view.segmentation.params["model"], "tiny-trained");
        for s in &view.segmentation.segments {
            let label = s.cluster.map_or("unknown", |c| model.classes[c].as_str());
            assert_eq!(s.label, label, "{s:?}");
        }
        assert!(view.details.pictures.iter().any(|p| p.id == "probabilities"));

        // the file loads back (under the name in it), not as a k-NN model
        let again = ask(
            &mut w,
            Request::UseLabelModel {
                take: 5,
                run: 9,
                kind: ModelKind::Dtfcn,
                file: "renamed.model".into(),
                bytes: bytes.clone(),
            },
        );
        let Some(Response::LabelModelInUse { take: 5, run: 9, model: loaded }) = again.last() else {
            panic!("{again:?}")
        };
        assert_eq!(loaded, model);
        let (message, _) = refusal(ask(
            &mut w,
            Request::UseLabelModel {
                take: 5,
                run: 10,
                kind: ModelKind::Knn,
                file: "renamed.model".into(),
                bytes: bytes.clone(),
            },
        ));
        assert!(message.contains("renamed.model holds a DT-FCN model, not a k-NN model"), "{message}");

        // bad files are refused with the core's message, and the worker goes on answering
        let truncated = bytes[..bytes.len() / 2].to_vec();
        let json = br#"{"fps": 30.0, "factors": []}"#.to_vec();
        let mut rng = crate::stats::Rng::new(5);
        let random: Vec<u8> = (0..4096).map(|_| rng.below(256) as u8).collect();
        for (file, bad, says) in [
            ("half.model", truncated, "half.model: truncated"),
            ("family.json", json, "family.json: not a mocapseg model file"),
            ("noise.bin", random, "noise.bin: not a mocapseg model file"),
            ("empty.model", Vec::new(), "empty.model: not a mocapseg model file"),
        ] {
            let (message, field) = refusal(ask(
                &mut w,
                Request::UseLabelModel { take: 5, run: 11, kind: ModelKind::Dtfcn, file: file.into(), bytes: bad },
            ));
            assert!(message.starts_with(says), "{message}");
            assert_eq!(field, None);
        }
        let run = ask(
            &mut w,
            Request::Segment {
                take: 1,
                run: 12,
                method: "dtfcn".into(),
                params: serde_json::json!({"model": "tiny-trained", "unknown_threshold": 0.99}),
            },
        );
        assert!(matches!(run.last(), Some(Response::Segmented { .. })), "{:?}", run.last());
    }

    #[test]
    fn a_stopped_training_keeps_the_model_of_its_epochs_so_far() {
        let mut w = WorkerState::default();
        let first = ask(
            &mut w,
            train_dtfcn(3, "tiny-stopped", walk_labels(), tiny_options(50), vec![("12_01.bvh", take_bytes())]),
        );
        assert!(matches!(first.last(), Some(Response::TrainingEpoch { more: true, .. })), "{first:?}");
        // the page's stop is read before the worker's own continue
        assert!(
            ask(&mut w, Request::StopTraining { take: 1, run: 99 }).is_empty(),
            "another training's stop is ignored"
        );
        let stopped = ask(&mut w, Request::StopTraining { take: 1, run: 3 });
        let [Response::DtfcnTrained { stopped: true, reports, best_epoch: 1, model, bytes, .. }] = &stopped[..] else {
            panic!("{stopped:?}")
        };
        assert_eq!(reports.len(), 1);
        assert_eq!(model.epochs_run, 1);
        assert!(Model::from_bytes(bytes, "s.model").is_ok());
        assert!(w.next_step().is_none());
        assert!(
            ask(&mut w, Request::ContinueTraining { take: 1, run: 3 }).is_empty(),
            "the continue after a stop is ignored"
        );
        assert!(ask(&mut w, Request::StopTraining { take: 1, run: 3 }).is_empty(), "a second stop is ignored");
        // and the stopped model is installed
        ask(
            &mut w,
            Request::Load {
                take: 1,
                name: "12_01.bvh".into(),
                restore: false,
                bytes: take_bytes(),
                skeleton: None,
                skeleton_bytes: Vec::new(),
            },
        );
        let run = ask(
            &mut w,
            Request::Segment {
                take: 1,
                run: 4,
                method: "dtfcn".into(),
                params: serde_json::json!({"model": "tiny-stopped"}),
            },
        );
        assert!(matches!(run.last(), Some(Response::Segmented { .. })), "{:?}", run.last());
        // a whole run after a stop: a new request replaces nothing left over
        let posted = train_to_the_end(
            &mut w,
            train_dtfcn(5, "tiny-stopped", walk_labels(), tiny_options(1), vec![("12_01.bvh", take_bytes())]),
        );
        assert!(
            matches!(posted.last(), Some(Response::DtfcnTrained { run: 5, stopped: false, .. })),
            "{:?}",
            posted.last()
        );
    }

    #[test]
    fn training_refusals_name_the_input_that_is_wrong() {
        let mut w = WorkerState::default();
        let walk = || vec![("12_01.bvh", take_bytes())];
        let mut check = |request: Request, field: TrainField, says: &[&str]| {
            let (message, f) = refusal(ask(&mut w, request));
            assert_eq!(f, Some(field), "{message}");
            for s in says {
                assert!(message.contains(s), "{message} should say {s}");
            }
            assert!(w.next_step().is_none(), "no training after a refusal");
        };
        let bad_line = walk_labels().replace("180,359", "180,abc");
        check(
            train_dtfcn(1, "m", bad_line, tiny_options(2), walk()),
            TrainField::Labels,
            &["labels.csv line 3", "`abc`"],
        );
        let elsewhere = format!("{LABELS_HEADER}86_01.bvh,0,99,walk\n86_01.bvh,100,199,run\n");
        check(
            train_dtfcn(1, "m", elsewhere, tiny_options(2), walk()),
            TrainField::Labels,
            &["no row is for the loaded take `12_01.bvh`", "`86_01.bvh`"],
        );
        check(train_dtfcn(1, "m", LABELS_HEADER.into(), tiny_options(2), walk()), TrainField::Labels, &["no rows"]);
        let one = format!("{LABELS_HEADER}12_01.bvh,0,523,walk\n");
        check(train_dtfcn(1, "m", one, tiny_options(2), walk()), TrainField::Labels, &["1 class", "at least 2"]);
        let past = format!("{LABELS_HEADER}12_01.bvh,0,99,walk\n12_01.bvh,100,900,run\n");
        check(
            train_dtfcn(1, "m", past, tiny_options(2), walk()),
            TrainField::Labels,
            &["past the take's last frame 523"],
        );
        check(train_dtfcn(1, "m", walk_labels(), tiny_options(0), walk()), TrainField::Epochs, &["epochs 0"]);
        check(
            train_dtfcn(1, "m", walk_labels(), TrainOptions { label_noise: 2.0, ..tiny_options(2) }, walk()),
            TrainField::LabelNoise,
            &["label noise 2"],
        );
        check(
            train_dtfcn(1, "m", walk_labels(), TrainOptions { mask_frames: 1000, ..tiny_options(2) }, walk()),
            TrainField::MaskFrames,
            &["mask 1000"],
        );
        check(
            train_dtfcn(1, "m", walk_labels(), TrainOptions { width: 1, ..tiny_options(2) }, walk()),
            TrainField::Width,
            &["kernel width 1"],
        );
        check(train_dtfcn(1, "  ", walk_labels(), tiny_options(2), walk()), TrainField::Name, &["needs a name"]);
        check(
            train_dtfcn(1, "exercises", walk_labels(), tiny_options(2), walk()),
            TrainField::Name,
            &["shipped model"],
        );
        let broken = vec![("12_01.bvh", b"HIERARCHY\nROOT".to_vec())];
        check(train_dtfcn(1, "m", walk_labels(), tiny_options(2), broken), TrainField::Takes, &["12_01.bvh: line"]);
        let twice = vec![("12_01.bvh", take_bytes()), ("takes/12_01.BVH", take_bytes())];
        check(train_dtfcn(1, "m", walk_labels(), tiny_options(2), twice), TrainField::Takes, &["given twice"]);
    }
}
