//! The shipped models as the page's worker gets them. On the page's build (wasm with `web`) they
//! are not built in but fetched from beside the page, so a test that uses one first hands them
//! over the way the page does (`ModelStore::provide`, which checks each file's SHA-256) to the
//! store it runs with; on every other build they are built in and the store reads them itself.

/// A model store holding every shipped model file (handed over on the page's build).
pub fn store() -> mocapseg::method::ModelStore {
    let store = mocapseg::method::ModelStore::new();
    #[cfg(all(target_arch = "wasm32", feature = "web"))]
    for (file, bytes) in [
        ("dtfcn-cmu-actions.model", &include_bytes!("../../models/dtfcn-cmu-actions.model")[..]),
        ("dtfcn-exercises.model", &include_bytes!("../../models/dtfcn-exercises.model")[..]),
        ("dtfcn-locomotion.model", &include_bytes!("../../models/dtfcn-locomotion.model")[..]),
        ("knn-cmu-actions.model", &include_bytes!("../../models/knn-cmu-actions.model")[..]),
        ("knn-exercises.model", &include_bytes!("../../models/knn-exercises.model")[..]),
        ("knn-locomotion.model", &include_bytes!("../../models/knn-locomotion.model")[..]),
        ("lma-effort.json", &include_bytes!("../../models/lma-effort.json")[..]),
    ] {
        store.provide(file, bytes.to_vec()).expect("the shipped file as this build knows it");
    }
    store
}
