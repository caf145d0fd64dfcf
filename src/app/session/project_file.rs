//! The project file on the page ([`crate::app::session::project`]): "Save project" writes the workspace — the record
//! the keeper keeps, the takes named by their SHA-256, my labels of those takes, the user's models the rows chose — as
//! one JSON file; "Open project" reads one picked together with its take files, finds each take among them by what it
//! holds, keeps its labels and models in this browser, and sets the workspace it holds in place of the one on screen
//! (the keeper keeps it from then on). What was done, or what is wrong, is said in `#workspace-status`.

use crate::app::library::state::Source;
use crate::app::loader::Loader;
use crate::app::models::model_jobs::ModelJobs;
use crate::app::session::keeper::Keeper;
use crate::app::session::project::{sha256_hex, KeptLabels, Project, ProjectModel, TakeRef, MAX_PROJECT_BYTES};
use crate::app::state::AppState;
use crate::app::take::fetch::blob_bytes;
use js_sys::Uint8Array;
use leptos::prelude::*;
use web_sys::{Blob, File};

/// A file's bytes, read by the browser.
async fn bytes_of(blob: &Blob) -> Result<Vec<u8>, String> {
    let buffer = blob_bytes(blob).await?;
    Ok(Uint8Array::new(&buffer).to_vec())
}

/// A take's file as a project names it (`skeleton`: an AMC motion's ASF).
async fn take_ref(name: String, motion: &Blob, skeleton: Option<(String, Vec<u8>)>) -> Result<TakeRef, String> {
    let bytes = bytes_of(motion).await.map_err(|e| format!("{name}: could not read the file: {e}"))?;
    let skeleton = skeleton.map(|(name, bytes)| {
        Box::new(TakeRef { name, sha256: sha256_hex(&bytes), bytes: bytes.len() as u64, skeleton: None })
    });
    Ok(TakeRef { name, sha256: sha256_hex(&bytes), bytes: bytes.len() as u64, skeleton })
}

/// The project of the workspace on screen.
async fn project_now(state: AppState, loader: &Loader, keeper: &Keeper) -> Result<Project, String> {
    let record = keeper.record_now();
    let take = match loader.shown_take_files() {
        Some((name, file, skeleton, false)) if state.library.open.get_untracked().is_none() => {
            Some(take_ref(name, &file, skeleton).await?)
        }
        _ => None,
    };
    let mut library = Vec::new();
    let count = record.library.as_ref().map_or(0, |l| l.takes.len());
    for i in 0..count {
        let source = state.library.source(i).ok_or("the library changed while it was saved")?;
        let skeleton = match &source.skeleton {
            Some(s) => Some((s.name(), bytes_of(s).await?)),
            None => None,
        };
        library.push(take_ref(source.motion.name(), &source.motion, skeleton).await?);
    }
    let names: Vec<String> = take.iter().chain(&library).map(|t| t.name.clone()).collect();
    let labels = crate::app::my_labels::browser_storage::kept_labels(&names)
        .into_iter()
        .map(|(key, json)| KeptLabels { key, json })
        .collect();
    let mut models = Vec::new();
    for slot in state.methods {
        let (Some(s), Some((chosen, _))) = (slot.supervised.as_ref(), slot.param("model")) else { continue };
        let chosen = chosen.get_untracked();
        if let Some(m) = s.models.with_untracked(|l| l.iter().find(|m| m.info.name == chosen).cloned()) {
            models.push(ProjectModel {
                method: slot.info.name.clone(),
                name: m.info.name.clone(),
                file: m.file.clone(),
                data: m.bytes.to_vec(),
            });
        }
    }
    Ok(Project { record, take, library, labels, models })
}

/// Saves the workspace on screen as a project file.
fn save(state: AppState, loader: Loader, keeper: Keeper) {
    let status = keeper.status();
    status.set(Some((false, "Saving the project…".into())));
    wasm_bindgen_futures::spawn_local(async move {
        let project = match project_now(state, &loader, &keeper).await {
            Ok(p) => p,
            Err(why) => return status.set(Some((true, format!("The project could not be saved: {why}")))),
        };
        let stem = project
            .take
            .as_ref()
            .or(project.library.first())
            .map(|t| crate::clips::stem_of(&t.name).to_string())
            .unwrap_or_else(|| "workspace".into());
        let file = format!("{stem}.mocapseg.json");
        let takes = project.take.iter().count() + project.library.len();
        let said = match crate::app::player::motion_image::download(project.to_json().as_bytes(), "application/json", &file) {
            Ok(()) => (
                false,
                format!(
                    "Saved {file}: the workspace, {} named by their SHA-256 (open them with it), my labels of {} and {}",
                    crate::method::counted(takes, "take"),
                    crate::method::counted(project.labels.len(), "take"),
                    crate::method::counted(project.models.len(), "model")
                ),
            ),
            Err(e) => (true, format!("The project could not be saved: {}", crate::app::dom::js_message(&e))),
        };
        status.set(Some(said));
    });
}

/// Opens a project picked with its take files.
fn open(state: AppState, keeper: Keeper, models: ModelJobs, files: Vec<File>) {
    let status = keeper.status();
    let projects: Vec<&File> = files.iter().filter(|f| f.name().to_ascii_lowercase().ends_with(".json")).collect();
    let project_file = match projects.as_slice() {
        [one] => (*one).clone(),
        [] => return status.set(Some((true, "Open a project file (.mocapseg.json) with its takes".into()))),
        _ => return status.set(Some((true, "Open one project file at a time (with its takes)".into()))),
    };
    if project_file.size() > MAX_PROJECT_BYTES {
        let why = format!("{} is larger than a project file can be (64 MiB)", project_file.name());
        return status.set(Some((true, why)));
    }
    let takes: Vec<File> = files.into_iter().filter(|f| !f.name().to_ascii_lowercase().ends_with(".json")).collect();
    status.set(Some((false, format!("Opening {}…", project_file.name()))));
    wasm_bindgen_futures::spawn_local(async move {
        let from = project_file.name();
        let text = match bytes_of(&project_file).await {
            Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
            Err(why) => return status.set(Some((true, format!("{from} could not be read: {why}")))),
        };
        let project = match Project::from_json(&from, &text) {
            Ok(p) => p,
            Err(why) => return status.set(Some((true, why))),
        };
        let mut hashed = Vec::new();
        for f in &takes {
            match bytes_of(f).await {
                Ok(bytes) => hashed.push((f.name(), sha256_hex(&bytes))),
                Err(why) => return status.set(Some((true, format!("{}: could not read the file: {why}", f.name())))),
            }
        }
        let found = project.find(&hashed);
        // a take opened under another name is that take: its labels, place and cluster names follow the new name
        let names: Vec<String> = hashed.iter().map(|(n, _)| n.clone()).collect();
        let project = project.renamed(&found, &names);
        for l in &project.labels {
            if let Err(why) = crate::app::my_labels::browser_storage::keep_labels(&l.key, &l.json) {
                return status.set(Some((true, format!("{from}: my labels could not be kept in this browser: {why}"))));
            }
        }
        for m in project.models {
            if let Some(index) = state.methods.iter().position(|s| s.info.name == m.method && s.supervised.is_some()) {
                models.use_model(index, m.file, m.data);
            }
        }
        let files_of = |(motion, skeleton): (usize, Option<usize>)| {
            let mut files = vec![takes[motion].clone()];
            files.extend(skeleton.map(|s| takes[s].clone()));
            files
        };
        let library = found
            .library
            .iter()
            .map(|at| at.map(|(m, s)| Source { motion: takes[m].clone(), skeleton: s.map(|s| takes[s].clone()) }))
            .collect();
        let mut missing = found.missing;
        missing.extend(found.differ.iter().map(|d| format!("{d} (a file of that name holds something else)")));
        keeper.open_project(&from, project.record, found.take.map(files_of), library, missing);
    });
}

/// "Save project" and "Open project" (the project file with its takes, picked together).
#[component]
pub fn ProjectFile(state: AppState, loader: Loader, keeper: Keeper, models: ModelJobs) -> impl IntoView {
    let (saving, opening) = (keeper.clone(), keeper);
    let models = StoredValue::new_local(models);
    let opening = StoredValue::new_local(opening);
    view! {
        <div class="ms-project" role="group" aria-label="Project file">
            <button id="project-save" class="ms-button ms-button--quiet ms-button--small" type="button"
                title="Save the workspace as a project file a colleague opens with the same takes: the takes named by their SHA-256, the ground truth, my labels, the rows' settings and chosen models, the library and its cluster names"
                on:click=move |_| save(state, loader.clone(), saving.clone())>
                "Save project"
            </button>
            <input id="project-open" class="ms-visually-hidden" type="file" multiple accept=".json,.bvh,.amc,.asf"
                on:change=move |ev| {
                    let files = crate::app::models::picked::picked_files(&ev);
                    if !files.is_empty() {
                        open(state, opening.get_value(), models.get_value(), files);
                    }
                }/>
            <label class="ms-button ms-button--quiet ms-button--small" for="project-open"
                title="Open a project file (.mocapseg.json) picked together with its take files: each take is found by what it holds">
                "Open project…"
            </label>
        </div>
    }
}
