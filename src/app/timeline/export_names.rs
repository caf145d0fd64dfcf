//! The names of the page's saved files carry the row they come from, so that two rows' exports of
//! one take never share a name (issue 27: the SSSM zip and the ground truth's zip were both
//! `86_01_actions_clips.zip`): `86_01_sssm_actions_clips.zip`, `86_01_truth_actions_clips.zip`,
//! `86_01_my-labels_03_punch.bvh`. The worker names clips as `mocapseg clips` does
//! ([`crate::clips::export`]); the page puts the row in, and a zip of a method's row says what the
//! row holds in the row's own word ([`crate::app::timeline::rows::RowKind::word`]): the k-NN's actions are
//! its labels (`86_01_knn_labels_clips.zip`), LMA's primitives its gestures.

/// `file` (named by the worker after the take's `stem`) with `row` after the stem; a name that
/// does not start with the stem gets the row in front.
pub fn with_row(file: &str, stem: &str, row: &str) -> String {
    match file.strip_prefix(stem).and_then(|rest| rest.strip_prefix('_')) {
        Some(rest) if !stem.is_empty() => format!("{stem}_{row}_{rest}"),
        _ => format!("{row}_{file}"),
    }
}

/// [`with_row`] for a zip the worker named after the level it cut (`<stem>_actions_clips.zip`,
/// `<stem>_primitives_clips.zip`): with `word`, the row's word for that level, in its place
/// (`<stem>_<row>_<word>_clips.zip`). Other names (one clip's BVH, `…_all_clips.zip`) as
/// [`with_row`] gives them.
pub fn with_row_word(file: &str, stem: &str, row: &str, word: Option<&str>) -> String {
    let level = file.strip_prefix(stem).and_then(|r| r.strip_prefix('_')).and_then(|r| r.strip_suffix("_clips.zip"));
    match (level, word) {
        (Some("actions" | "primitives"), Some(word)) if !stem.is_empty() => format!("{stem}_{row}_{word}_clips.zip"),
        _ => with_row(file, stem, row),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_row_follows_the_stem() {
        assert_eq!(with_row("86_01_actions_clips.zip", "86_01", "sssm"), "86_01_sssm_actions_clips.zip");
        assert_eq!(with_row("86_01_actions_clips.zip", "86_01", "truth"), "86_01_truth_actions_clips.zip");
        assert_eq!(with_row("86_01_03_punch.bvh", "86_01", "my-labels"), "86_01_my-labels_03_punch.bvh");
        assert_eq!(with_row("sample_all_clips.zip", "sample", "dtfcn"), "sample_dtfcn_all_clips.zip");
        // two rows of one take: two names
        assert_ne!(
            with_row("86_01_actions_clips.zip", "86_01", "sssm"),
            with_row("86_01_actions_clips.zip", "86_01", "truth")
        );
        // a name without the stem (never made by the worker) still carries the row
        assert_eq!(with_row("clips.zip", "86_01", "knn"), "knn_clips.zip");
        assert_eq!(with_row("86_01x.zip", "86_01", "knn"), "knn_86_01x.zip");
    }

    #[test]
    fn a_method_rows_zip_says_what_the_row_holds() {
        assert_eq!(
            with_row_word("86_01_actions_clips.zip", "86_01", "knn", Some("labels")),
            "86_01_knn_labels_clips.zip"
        );
        assert_eq!(
            with_row_word("86_01_primitives_clips.zip", "86_01", "lma", Some("gestures")),
            "86_01_lma_gestures_clips.zip"
        );
        assert_eq!(
            with_row_word("86_01_actions_clips.zip", "86_01", "sssm", Some("actions")),
            "86_01_sssm_actions_clips.zip"
        );
        // every segment, one clip, or no word: as with_row
        assert_eq!(with_row_word("86_01_all_clips.zip", "86_01", "knn", Some("labels")), "86_01_knn_all_clips.zip");
        assert_eq!(with_row_word("86_01_03_punch.bvh", "86_01", "knn", Some("labels")), "86_01_knn_03_punch.bvh");
        assert_eq!(with_row_word("86_01_actions_clips.zip", "86_01", "truth", None), "86_01_truth_actions_clips.zip");
    }
}
