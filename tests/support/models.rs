//! The shipped models as the page's worker gets them. On the page's build (wasm with `web`) they
//! are not built in but fetched from beside the page, so a test that uses one first hands them
//! over the way the page does (`mocapseg::method::shipped::provide`, which checks each file's
//! SHA-256); on every other build they are built in and this does nothing.

/// Hands every shipped model file over (on the page's build; a file already held is skipped).
pub fn provide() {
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
        if !mocapseg::method::shipped::available(file) {
            mocapseg::method::shipped::provide(file, bytes.to_vec()).expect("the shipped file as this build knows it");
        }
    }
}
