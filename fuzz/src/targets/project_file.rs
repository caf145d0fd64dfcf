//! The project file (`app::session::project::Project::from_json`: what the page's "Open project" reads, from anyone)
//! and what opening one does before any take is read: finding its takes among the files opened with it by SHA-256
//! (`Project::find`) and following a take opened under another name (`Project::renamed`).
//!
//! A project that reads must write back and read to the same value; finding its takes among files named otherwise
//! (and one holding something else) must place each take at a file that holds it, and following the new names must
//! keep every label and model, and change nothing when the names are the project's own.

use mocapseg::app::library::names::{Named, NamedSpot};
use mocapseg::app::session::project::{sha256_hex, KeptLabels, Project, ProjectModel, TakeRef};
use mocapseg::app::session::record::{KeptLibrary, KeptLibraryTake, KeptTake, Record};

fn take(name: &str, bytes: &[u8]) -> TakeRef {
    TakeRef { name: name.into(), sha256: sha256_hex(bytes), bytes: bytes.len() as u64, skeleton: None }
}

pub fn seeds() -> Vec<(String, Vec<u8>)> {
    // a take on screen with my labels, a library of two (an AMC with its skeleton), a cluster named, a user's model
    let mut record = Record::new();
    record.take = Some(KeptTake { name: "35_01.bvh".into(), sample: false, kept: true, library: None });
    record.library = Some(KeptLibrary {
        method: "sssm".into(),
        takes: vec![
            KeptLibraryTake { name: "02_01.bvh".into(), kept: true },
            KeptLibraryTake { name: "02_02.amc".into(), kept: true },
        ],
        names: vec![Named {
            name: "hop step".into(),
            spots: vec![NamedSpot { take: "02_01.bvh".into(), start: 10, end: 80 }],
        }],
    });
    let mut amc = take("02_02.amc", b"motion");
    amc.skeleton = Some(Box::new(take("02.asf", b"skeleton")));
    let full = Project {
        record,
        take: Some(take("35_01.bvh", b"take")),
        library: vec![take("02_01.bvh", b"walk"), amc],
        labels: vec![KeptLabels {
            key: "mocapseg.my-labels.v1:35_01.bvh:298f:120.000fps:31j:0badf00d".into(),
            json: r#"{"segments":[{"start":0,"end":119,"label":"walk"}]}"#.into(),
        }],
        models: vec![ProjectModel {
            method: "knn".into(),
            name: "mine".into(),
            file: "mine.model".into(),
            data: vec![1, 2, 3],
        }],
    };
    let empty =
        Project { record: Record::new(), take: None, library: Vec::new(), labels: Vec::new(), models: Vec::new() };
    vec![("project.json".into(), full.to_json().into_bytes()), ("empty.json".into(), empty.to_json().into_bytes())]
}

/// One input of the target (what `fuzz_targets/project_file.rs` hands libFuzzer's bytes to).
pub fn run(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let Ok(project) = Project::from_json("fuzz.mocapseg.json", &text) else { return };
    let again = Project::from_json("again.mocapseg.json", &project.to_json())
        .unwrap_or_else(|e| panic!("its own JSON does not read: {e}"));
    assert_eq!(project, again, "a project written and read again is the same project");
    // the files opened with it: every take renamed, each skeleton under its own name, and a file of another content
    let mut files: Vec<(String, String)> = Vec::new();
    for (i, t) in project.take.iter().chain(&project.library).enumerate() {
        files.push((format!("renamed {i} {}", t.name), t.sha256.clone()));
        if let Some(s) = &t.skeleton {
            files.push((s.name.clone(), s.sha256.clone()));
        }
    }
    files.push(("other.bvh".into(), sha256_hex(b"something else")));
    let found = project.find(&files);
    assert_eq!(found.library.len(), project.library.len(), "one place per library take");
    let holds = |at: usize, t: &TakeRef| files.get(at).is_some_and(|(_, h)| *h == t.sha256);
    if let (Some((m, s)), Some(t)) = (found.take, &project.take) {
        assert!(holds(m, t), "the take is found at a file that holds it");
        if let (Some(s), Some(k)) = (s, &t.skeleton) {
            assert!(holds(s, k), "its skeleton too");
        }
    }
    for (at, t) in found.library.iter().zip(&project.library) {
        if let Some((m, _)) = at {
            assert!(holds(*m, t), "a library take is found at a file that holds it");
        }
    }
    let names: Vec<String> = files.iter().map(|(n, _)| n.clone()).collect();
    let renamed = project.clone().renamed(&found, &names);
    assert_eq!(renamed.labels.len(), project.labels.len(), "no label is lost following a new name");
    assert_eq!(renamed.models, project.models);
    assert_eq!(renamed.library.len(), project.library.len());
    // opened with its own names, nothing moves
    let own: Vec<(String, String)> = project
        .take
        .iter()
        .chain(&project.library)
        .flat_map(|t| std::iter::once(t).chain(t.skeleton.as_deref()))
        .map(|t| (t.name.clone(), t.sha256.clone()))
        .collect();
    let own_names: Vec<String> = own.iter().map(|(n, _)| n.clone()).collect();
    let same = project.clone().renamed(&project.find(&own), &own_names);
    assert_eq!(same, project, "opened under its own names, the project is unchanged");
}
