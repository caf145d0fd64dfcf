//! `#dtfcn-training`, inside the DT-FCN panel: the user's label CSV trains a DT-FCN in the worker,
//! one epoch per message (`train_dtfcn`, then `continue_training` until done), so the page stays
//! responsive and Stop is read between two epochs.
//!
//! * `#dtfcn-train-labels` picks the label CSV (`file,start_frame,end_frame,label`, 0-based file
//!   frames); `#dtfcn-train-takes` adds BVH takes besides the one on screen (their bytes go to the
//!   worker with it);
//! * the options: `#dtfcn-train-epochs` (20), `#dtfcn-train-noise` (label noise, 0–1),
//!   `#dtfcn-train-mask` (boundary mask frames), `#dtfcn-train-aug-<mirror|yaw|warp|scale|jitter>`,
//!   `#dtfcn-train-width` (kernel width 2 or 3), `#dtfcn-train-name` (the model's name), and under
//!   "Network size" `#dtfcn-train-filters` and `#dtfcn-train-crop`;
//! * `#dtfcn-train-start`, `#dtfcn-train-stop` (ends after the epoch under way and keeps the best
//!   model so far), `#dtfcn-train-progress` (epoch of epochs), `#dtfcn-train-plot` (loss and
//!   accuracy per epoch, redrawn after each), `#dtfcn-train-status`, and
//!   `#dtfcn-train-download` (the model file, `NAME.model`);
//! * a refusal shows at the input that is wrong: `#dtfcn-train-error-<field>` (`labels`, `takes`,
//!   `name`, `epochs`, `label_noise`, `mask_frames`, `width`, `filters`, `crop_frames`).
//!
//! The "my labels" row asks for a training through [`DtfcnTraining::request`] ([`TrainRequest`]):
//! its rows as the label CSV (shown as the chosen labels), trained with this form's options, or a
//! stop.
//!
//! The trained model is installed in the worker, becomes the DT-FCN method's model and DT-FCN runs
//! again on the take on screen. `document.body.dataset.dtfcnTraining` (`data-dtfcn-training`):
//! `idle`, `training`, `stopping`, `done` or `error`.

use super::label_models::{picked_files, read_bytes};
use super::loader::{Loader, MAX_FILE_BYTES};
use super::motion_image::{download, stem};
use super::AppState;
use crate::dtfcn::augment::Augment;
use crate::dtfcn::training::{EpochReport, TrainOptions};
use crate::protocol::TrainField;
use leptos::html::Canvas;
use leptos::prelude::*;
use std::sync::Arc;
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_futures::JsFuture;
use web_sys::{CanvasRenderingContext2d, HtmlCanvasElement};

/// The largest label CSV the page reads.
const MAX_LABELS_BYTES: f64 = 16.0 * 1024.0 * 1024.0;
/// Epochs the form starts with.
const DEFAULT_EPOCHS: usize = 20;

/// Where the training stands.
#[derive(Debug, Clone, PartialEq)]
pub enum TrainState {
    /// Nothing trained yet.
    Idle,
    /// The worker prepares (`stage`) or trains (`epoch` of `epochs` done).
    Training { stage: String, epoch: usize, epochs: usize },
    /// Stop was pressed: the worker ends after the epoch under way.
    Stopping,
    /// The last training ended with a model.
    Done,
    /// The last training was refused or failed.
    Failed,
}

impl TrainState {
    /// The value of `document.body.dataset.dtfcnTraining`.
    pub fn body_state(&self) -> &'static str {
        match self {
            TrainState::Idle => "idle",
            TrainState::Training { .. } => "training",
            TrainState::Stopping => "stopping",
            TrainState::Done => "done",
            TrainState::Failed => "error",
        }
    }

    pub fn busy(&self) -> bool {
        matches!(self, TrainState::Training { .. } | TrainState::Stopping)
    }
}

/// A trained model the page offers for download.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainedFile {
    pub name: String,
    pub bytes: Arc<Vec<u8>>,
}

/// A training asked from elsewhere on the page (the "my labels" row).
#[derive(Debug, Clone, PartialEq)]
pub enum TrainRequest {
    /// Train on `csv` (a label CSV named `labels_name`) with the form's options; `model_name`
    /// unless the user typed a name.
    Labels { labels_name: String, csv: String, model_name: String },
    /// Stop the training under way (as the Stop button).
    Stop,
}

/// The training's state, as signals (part of [`AppState`]).
#[derive(Debug, Clone, Copy)]
pub struct DtfcnTraining {
    pub state: RwSignal<TrainState>,
    /// The status line.
    pub status: RwSignal<String>,
    /// The reports of the training under way or the last one.
    pub reports: RwSignal<Vec<EpochReport>>,
    /// What is wrong with which input (shown next to it).
    pub errors: RwSignal<Vec<(TrainField, String)>>,
    /// The last trained model.
    pub trained: RwSignal<Option<TrainedFile>>,
    /// What another part of the page asks (taken by the panel).
    pub request: RwSignal<Option<TrainRequest>>,
}

impl DtfcnTraining {
    pub fn new() -> DtfcnTraining {
        DtfcnTraining {
            state: RwSignal::new(TrainState::Idle),
            status: RwSignal::new(String::new()),
            reports: RwSignal::new(Vec::new()),
            errors: RwSignal::new(Vec::new()),
            trained: RwSignal::new(None),
            request: RwSignal::new(None),
        }
    }

    /// Shows `message` at `field`.
    pub fn refuse(&self, field: TrainField, message: String) {
        self.errors.update(|e| {
            e.retain(|(f, _)| *f != field);
            e.push((field, message));
        });
    }
}

/// What the user asked to train (the loader keeps it to send it again to a new worker).
#[derive(Debug, Clone)]
pub struct TrainAsk {
    pub name: String,
    pub labels_name: String,
    pub labels: String,
    /// Takes besides the one on screen: file names and bytes.
    pub extra: Vec<(String, Arc<Vec<u8>>)>,
    pub options: TrainOptions,
}

/// The element id suffix of a field's error line.
fn field_key(field: TrainField) -> String {
    serde_json::to_value(field).ok().and_then(|v| v.as_str().map(str::to_string)).unwrap_or_default()
}

/// A file name for the model `name` (characters a file name cannot hold replaced).
pub fn model_file_name(name: &str) -> String {
    let safe: String =
        name.chars().map(|c| if c.is_control() || "/\\:*?\"<>|".contains(c) { '_' } else { c }).collect();
    format!("{}.model", safe.trim_matches('.'))
}

/// `text` read as a `T`, or what was expected (`expected`, e.g. "a whole number").
fn read_field<T: std::str::FromStr>(text: &str, expected: &str) -> Result<T, String> {
    text.trim().parse().map_err(|_| format!("`{}` is not {expected}", text.trim()))
}

#[component]
pub fn DtfcnTrainingPanel(state: AppState, loader: Loader) -> impl IntoView {
    let t = state.dtfcn;
    let labels = RwSignal::new(None::<(String, String)>);
    let extra = RwSignal::new(Vec::<(String, Arc<Vec<u8>>)>::new());
    let epochs = RwSignal::new(DEFAULT_EPOCHS.to_string());
    let noise = RwSignal::new("0".to_string());
    let mask = RwSignal::new("0".to_string());
    let width = RwSignal::new(TrainOptions::default().width.to_string());
    let name = RwSignal::new("my-dtfcn".to_string());
    let named = RwSignal::new(false); // the user typed a name
    let filters =
        RwSignal::new(TrainOptions::default().filters.iter().map(usize::to_string).collect::<Vec<_>>().join(","));
    let crop = RwSignal::new(TrainOptions::default().crop_frames.to_string());
    let default_aug = TrainOptions::default().augment;
    let aug = [
        ("mirror", RwSignal::new(default_aug.mirror), "mirror (left ↔ right)"),
        ("yaw", RwSignal::new(default_aug.yaw), "yaw ±15°"),
        ("warp", RwSignal::new(default_aug.time_warp), "time warp 0.8–1.2×"),
        ("scale", RwSignal::new(default_aug.scale), "scale 0.9–1.1×"),
        ("jitter", RwSignal::new(default_aug.jitter), "jitter"),
    ];
    let busy = move || t.state.with(TrainState::busy);

    Effect::new(move |_| {
        let value = t.state.with(TrainState::body_state);
        if let Some(body) = web_sys::window().and_then(|w| w.document()).and_then(|d| d.body()) {
            let _ = body.set_attribute("data-dtfcn-training", value);
        }
    });

    let clear = move |field: TrainField| t.errors.update(|e| e.retain(|(f, _)| *f != field));
    let on_labels = move |ev: leptos::ev::Event| {
        let Some(file) = picked_files(&ev).into_iter().next() else { return };
        clear(TrainField::Labels);
        wasm_bindgen_futures::spawn_local(async move {
            let name_of = file.name();
            let read = if file.size() > MAX_LABELS_BYTES {
                Err(format!("{name_of}: more than the page reads (16 MiB)"))
            } else {
                match JsFuture::from(file.text()).await {
                    Ok(text) => text.as_string().ok_or_else(|| format!("{name_of}: the file is not text")),
                    Err(e) => Err(format!("{name_of}: could not read the file: {e:?}")),
                }
            };
            match read {
                Ok(text) => {
                    if !named.get_untracked() {
                        name.set(format!("{}-dtfcn", stem(&name_of)));
                    }
                    labels.set(Some((name_of, text)));
                }
                Err(message) => {
                    labels.set(None);
                    t.refuse(TrainField::Labels, message);
                }
            }
        });
    };
    let on_takes = move |ev: leptos::ev::Event| {
        let files = picked_files(&ev);
        if files.is_empty() {
            return;
        }
        clear(TrainField::Takes);
        wasm_bindgen_futures::spawn_local(async move {
            let mut read = Vec::new();
            for file in files {
                match read_bytes(&file, MAX_FILE_BYTES).await {
                    Ok(bytes) => read.push((file.name(), Arc::new(bytes))),
                    Err(message) => {
                        t.refuse(TrainField::Takes, message);
                        return;
                    }
                }
            }
            extra.update(|list| {
                for (n, b) in read {
                    list.retain(|(m, _)| *m != n);
                    list.push((n, b));
                }
            });
        });
    };
    let on_clear_takes = move |_| {
        extra.set(Vec::new());
        clear(TrainField::Takes);
    };

    let start_loader = loader.clone();
    let start = move || {
        if busy() {
            return;
        }
        let Some((labels_name, text)) = labels.get_untracked() else {
            t.refuse(TrainField::Labels, "choose a label CSV first".into());
            return;
        };
        t.errors.set(Vec::new());
        let mut options = TrainOptions::default();
        let mut bad = false;
        let mut read =
            |field: TrainField, what: &str, text: String, into: &mut dyn FnMut(&str) -> Result<(), String>| {
                if let Err(message) = into(&text) {
                    t.refuse(field, format!("{what}: {message}"));
                    bad = true;
                }
            };
        read(TrainField::Epochs, "epochs", epochs.get_untracked(), &mut |s| {
            options.epochs = read_field(s, "a whole number")?;
            Ok(())
        });
        read(TrainField::LabelNoise, "label noise", noise.get_untracked(), &mut |s| {
            options.label_noise = read_field(s, "a share from 0 to 1")?;
            Ok(())
        });
        read(TrainField::MaskFrames, "boundary mask", mask.get_untracked(), &mut |s| {
            options.mask_frames = read_field(s, "a whole number of frames")?;
            Ok(())
        });
        read(TrainField::Width, "kernel width", width.get_untracked(), &mut |s| {
            options.width = read_field(s, "2 or 3")?;
            Ok(())
        });
        read(TrainField::CropFrames, "crop", crop.get_untracked(), &mut |s| {
            options.crop_frames = read_field(s, "a whole number of frames")?;
            Ok(())
        });
        read(TrainField::Filters, "filters", filters.get_untracked(), &mut |s| {
            let list: Result<Vec<usize>, _> =
                s.split(|c: char| c == ',' || c.is_whitespace()).filter(|w| !w.is_empty()).map(str::parse).collect();
            options.filters = list.map_err(|_| format!("`{}` is not whole numbers separated by commas", s.trim()))?;
            Ok(())
        });
        options.augment = Augment {
            mirror: aug[0].1.get_untracked(),
            yaw: aug[1].1.get_untracked(),
            time_warp: aug[2].1.get_untracked(),
            scale: aug[3].1.get_untracked(),
            jitter: aug[4].1.get_untracked(),
        };
        if bad {
            t.state.set(TrainState::Failed);
            t.status.set("Not trained: an option below cannot be read.".into());
            return;
        }
        start_loader.train_dtfcn(TrainAsk {
            name: name.get_untracked().trim().to_string(),
            labels_name,
            labels: text,
            extra: extra.get_untracked(),
            options,
        });
    };
    let on_start = {
        let start = start.clone();
        move |ev: leptos::ev::SubmitEvent| {
            ev.prevent_default();
            start();
        }
    };
    // the "my labels" row's requests: its rows as the chosen labels, trained at once; or Stop
    let request_loader = loader.clone();
    Effect::new(move |_| {
        let Some(request) = t.request.get() else { return };
        t.request.set(None);
        match request {
            TrainRequest::Labels { labels_name, csv, model_name } => {
                clear(TrainField::Labels);
                if !named.get_untracked() {
                    name.set(model_name);
                }
                labels.set(Some((labels_name, csv)));
                start();
            }
            TrainRequest::Stop => request_loader.stop_dtfcn_training(),
        }
    });
    let stop_loader = loader.clone();
    let on_stop = move |_| stop_loader.stop_dtfcn_training();
    let on_download = move |_| {
        if let Some(file) = t.trained.get_untracked() {
            let file_name = model_file_name(&file.name);
            if let Err(e) = download(&file.bytes, "application/octet-stream", &file_name) {
                state.show_error(format!("could not save {file_name}: {e:?}"));
            }
        }
    };

    let error = move |field: TrainField| {
        let id = format!("dtfcn-train-error-{}", field_key(field));
        let text = move || t.errors.with(|e| e.iter().find(|(f, _)| *f == field).map(|(_, m)| m.clone()));
        view! {
            <span id=id class="ms-field-error" role="alert" hidden=move || text().is_none()>
                {move || text().unwrap_or_default()}
            </span>
        }
    };
    let progress = move || {
        t.state.with(|s| match s {
            TrainState::Training { stage, epoch, epochs } => (stage.clone(), *epoch, *epochs),
            _ => (String::new(), 0, 1),
        })
    };
    let progress_label = move || {
        let (stage, epoch, epochs) = progress();
        let last = t.reports.with(|r| r.last().cloned());
        match (epoch, last) {
            (0, _) => format!("Training: {stage}…"),
            (_, Some(r)) => {
                format!("Epoch {epoch} of {epochs} · loss {:.3} · accuracy {:.0} %", r.loss, 100.0 * r.train_accuracy)
            }
            (_, None) => format!("Epoch {epoch} of {epochs}"),
        }
    };
    let stopping = move || t.state.with(|s| *s == TrainState::Stopping);
    let checkbox = move |(key, on, label): (&'static str, RwSignal<bool>, &'static str)| {
        let on_change = move |ev: leptos::ev::Event| {
            let checked =
                ev.target().and_then(|t| t.dyn_into::<web_sys::HtmlInputElement>().ok()).is_some_and(|i| i.checked());
            on.set(checked);
        };
        view! {
            <label>
                <input id=format!("dtfcn-train-aug-{key}") type="checkbox" prop:checked=move || on.get() on:change=on_change/>
                " "
                {label}
            </label>
        }
    };
    let takes_text = move || {
        extra.with(|list| {
            if list.is_empty() {
                "only the take on screen".to_string()
            } else {
                format!(
                    "the take on screen and {}",
                    list.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(", ")
                )
            }
        })
    };

    view! {
        <section id="dtfcn-training" class="ms-dtfcn-training" aria-label="Train a DT-FCN on your own labels">
            <h3>"Train a DT-FCN on your labels"</h3>
            <p class="ms-lma-help">
                "A CSV with the header " <code>"file,start_frame,end_frame,label"</code>
                ": frames of the file (0-based, inclusive), any label. Its rows for the take on screen and the takes \
                 you add train a network in this tab, one epoch at a time; the model then labels the take on screen."
            </p>
            <form id="dtfcn-train-form" class="ms-dtfcn-train-form" novalidate=true on:submit=on_start>
                <div class="ms-method-params">
                    <label class="ms-button ms-button--quiet" for="dtfcn-train-labels">"Label CSV…"</label>
                    <input id="dtfcn-train-labels" class="ms-visually-hidden" type="file" accept=".csv,text/csv" on:change=on_labels/>
                    <span id="dtfcn-train-labels-name" class="ms-lma-file">
                        {move || labels.with(|l| l.as_ref().map_or("no file chosen".to_string(), |(n, _)| n.clone()))}
                    </span>
                    {error(TrainField::Labels)}
                </div>
                <div class="ms-method-params">
                    <label class="ms-button ms-button--quiet" for="dtfcn-train-takes">"More takes…"</label>
                    <input id="dtfcn-train-takes" class="ms-visually-hidden" type="file" multiple=true accept=".bvh" on:change=on_takes/>
                    <span id="dtfcn-train-takes-names" class="ms-lma-file">{takes_text}</span>
                    <button
                        id="dtfcn-train-takes-clear"
                        class="ms-button ms-button--quiet"
                        type="button"
                        hidden=move || extra.with(Vec::is_empty)
                        on:click=on_clear_takes
                    >
                        "Only the take on screen"
                    </button>
                    {error(TrainField::Takes)}
                </div>
                <div class="ms-method-params">
                    <label title="Most epochs; Stop ends earlier.">
                        "epochs "
                        <input id="dtfcn-train-epochs" type="number" min="1" max="10000" step="1" bind:value=epochs/>
                    </label>
                    {error(TrainField::Epochs)}
                    <label title="Share of training frames given a random label (the paper's Table 3), 0–1.">
                        "label noise "
                        <input id="dtfcn-train-noise" type="number" min="0" max="1" step="any" bind:value=noise/>
                    </label>
                    {error(TrainField::LabelNoise)}
                    <label title="w_transition: frames around each label change whose loss is zeroed (the paper's Table 4; 0 = none).">
                        "boundary mask (frames) "
                        <input id="dtfcn-train-mask" type="number" min="0" max="301" step="1" bind:value=mask/>
                    </label>
                    {error(TrainField::MaskFrames)}
                    <label title="Kernel width w: the receptive field is w⁵ frames at 30 Hz.">
                        "kernel width "
                        <select id="dtfcn-train-width" bind:value=width>
                            <option value="2" prop:selected=move || width.get() == "2">"2"</option>
                            <option value="3" prop:selected=move || width.get() == "3">"3"</option>
                        </select>
                    </label>
                    {error(TrainField::Width)}
                    <label title="The model's name in the model choice, and its file's name.">
                        "model name "
                        <input
                            id="dtfcn-train-name"
                            type="text"
                            size="14"
                            bind:value=name
                            on:input=move |_| named.set(true)
                        />
                    </label>
                    {error(TrainField::Name)}
                </div>
                <div class="ms-method-params" role="group" aria-label="Augmentations">
                    <span class="ms-lma-file">"augment:"</span>
                    {aug.into_iter().map(checkbox).collect_view()}
                </div>
                <details class="ms-method-advanced">
                    <summary>"Network size"</summary>
                    <div class="ms-method-params">
                    <label title="Filters of each dilated layer (the paper's: 64,64,128,256,512).">
                        "filters per layer "
                        <input id="dtfcn-train-filters" type="text" size="16" bind:value=filters/>
                    </label>
                    {error(TrainField::Filters)}
                    <label title="Frames of each training crop the loss is taken on.">
                        "crop (frames) "
                        <input id="dtfcn-train-crop" type="number" min="16" max="4096" step="1" bind:value=crop/>
                    </label>
                    {error(TrainField::CropFrames)}
                    </div>
                </details>
                <div class="ms-method-params">
                    <button
                        id="dtfcn-train-start"
                        class="ms-button"
                        type="submit"
                        disabled=move || busy() || labels.with(Option::is_none) || state.motion.with(Option::is_none)
                    >
                        "Train"
                    </button>
                    <button
                        id="dtfcn-train-stop"
                        class="ms-button ms-button--quiet"
                        type="button"
                        hidden=move || !busy()
                        disabled=stopping
                        on:click=on_stop
                    >
                        "Stop"
                    </button>
                    <div id="dtfcn-train-progress" class="ms-progress" role="status" aria-live="polite" hidden=move || !busy()>
                        <progress
                            max=move || progress().2.max(1).to_string()
                            value=move || progress().1.to_string()
                        ></progress>
                        <span class="ms-progress-label">{move || if stopping() { "Stopping after this epoch…".to_string() } else { progress_label() }}</span>
                    </div>
                    <button
                        id="dtfcn-train-download"
                        class="ms-button ms-button--quiet"
                        type="button"
                        hidden=move || t.trained.with(Option::is_none)
                        on:click=on_download
                    >
                        {move || t.trained.with(|f| f.as_ref().map(|f| format!("Download {}", model_file_name(&f.name))).unwrap_or_default())}
                    </button>
                </div>
            </form>
            <p
                id="dtfcn-train-status"
                class="ms-lma-status"
                class:ms-lma-status--error=move || t.state.with(|s| *s == TrainState::Failed)
                role="status"
                aria-live="polite"
                hidden=move || t.status.with(String::is_empty)
            >
                {move || t.status.get()}
            </p>
            <TrainingPlot training=t/>
        </section>
    }
}

/// `#dtfcn-train-plot`: the loss (left axis) and the training accuracy (right axis, 0–1) of every
/// epoch so far, redrawn after each.
#[component]
fn TrainingPlot(training: DtfcnTraining) -> impl IntoView {
    let canvas_ref = NodeRef::<Canvas>::new();
    Effect::new(move |_| {
        let Some(canvas) = canvas_ref.get() else { return };
        training.reports.with(|reports| {
            let epochs = training.state.with(|s| match s {
                TrainState::Training { epochs, .. } => *epochs,
                _ => 0,
            });
            if let Err(e) = draw_plot(&canvas, reports, epochs) {
                web_sys::console::error_2(&"could not draw the training plot".into(), &e);
            }
        });
    });
    view! {
        <figure class="ms-method-figure" hidden=move || training.reports.with(Vec::is_empty)>
            <canvas id="dtfcn-train-plot" class="ms-train-plot" width="560" height="200" node_ref=canvas_ref
                aria-label="Training loss and accuracy per epoch"></canvas>
            <figcaption class="ms-method-legend">
                <strong>"Training. "</strong>
                "Epochs across. Blue: the mean cross-entropy of the epoch's batches (left axis); orange: the share of \
                 the crops' labelled frames whose most probable class is their label (right axis, 0–100 %). A dot marks \
                 the epoch whose weights are kept."
            </figcaption>
        </figure>
    }
}

fn draw_plot(canvas: &HtmlCanvasElement, reports: &[EpochReport], epochs: usize) -> Result<(), JsValue> {
    let ctx: CanvasRenderingContext2d = canvas.get_context("2d")?.ok_or("no 2d context")?.dyn_into()?;
    let (w, h) = (canvas.width() as f64, canvas.height() as f64);
    let (left, right, top, bottom) = (44.0, w - 44.0, 12.0, h - 26.0);
    ctx.set_fill_style_str("#ffffff");
    ctx.fill_rect(0.0, 0.0, w, h);
    if reports.is_empty() {
        return Ok(());
    }
    let n = epochs.max(reports.len()).max(2);
    let max_loss = reports.iter().map(|r| r.loss).filter(|l| l.is_finite()).fold(0.0f64, f64::max).max(1e-6) * 1.1;
    let x = |epoch: usize| left + (epoch as f64 - 1.0) / (n as f64 - 1.0) * (right - left);
    let y = |share: f64| bottom - share.clamp(0.0, 1.0) * (bottom - top);
    // axes and grid
    ctx.set_stroke_style_str("#d7dbe2");
    ctx.set_line_width(1.0);
    for k in 0..=4 {
        let yy = y(k as f64 / 4.0);
        ctx.begin_path();
        ctx.move_to(left, yy);
        ctx.line_to(right, yy);
        ctx.stroke();
    }
    ctx.set_font("11px sans-serif");
    ctx.set_fill_style_str("#1d4ed8");
    ctx.set_text_align("right");
    ctx.fill_text(&format!("{max_loss:.2}"), left - 4.0, top + 4.0)?;
    ctx.fill_text("0", left - 4.0, bottom + 4.0)?;
    ctx.set_fill_style_str("#c2410c");
    ctx.set_text_align("left");
    ctx.fill_text("100 %", right + 4.0, top + 4.0)?;
    ctx.fill_text("0 %", right + 4.0, bottom + 4.0)?;
    ctx.set_fill_style_str("#555b66");
    ctx.set_text_align("center");
    ctx.fill_text("1", x(1), h - 8.0)?;
    ctx.fill_text(&format!("epoch {n}"), x(n), h - 8.0)?;
    // the two curves
    let line = |colour: &str, value: &dyn Fn(&EpochReport) -> f64, kept: Option<usize>| {
        ctx.set_stroke_style_str(colour);
        ctx.set_fill_style_str(colour);
        ctx.set_line_width(2.0);
        ctx.begin_path();
        for (i, r) in reports.iter().enumerate() {
            let (xx, yy) = (x(r.epoch), y(value(r)));
            if i == 0 {
                ctx.move_to(xx, yy);
            } else {
                ctx.line_to(xx, yy);
            }
        }
        ctx.stroke();
        for r in reports {
            ctx.begin_path();
            let radius = if Some(r.epoch) == kept { 4.0 } else { 2.0 };
            let _ = ctx.arc(x(r.epoch), y(value(r)), radius, 0.0, std::f64::consts::TAU);
            ctx.fill();
        }
    };
    let kept = reports.iter().rev().find(|r| r.best).map(|r| r.epoch);
    let line = |colour: &str, value: &dyn Fn(&EpochReport) -> f64| line(colour, value, kept);
    line("#1d4ed8", &|r| r.loss / max_loss);
    line("#c2410c", &|r| r.train_accuracy);
    Ok(())
}
