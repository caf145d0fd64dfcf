//! One name per timeline row, used everywhere a row is named (issue 27: the timeline said
//! "k-NN · labels" where the metrics menu said "k-NN · actions"): the timeline's row labels, the
//! metrics menu and the comparison table, the "my labels" copy menu, and the legend that says what
//! each kind of row is. A row is one level of one method's run, and its kind follows from what the
//! run holds, never from the method's name:
//!
//! * **actions** — a method's long stretches of one kind of motion, named by cluster (SSSM's `A0`,
//!   PCA's `B1`), with hatched transitions between them;
//! * **labels** — a labelling method's per-frame classes (DT-FCN, the k-NN: `jumping jacks`…),
//!   shaded by confidence, `unknown` hatched;
//! * **primitives** — the short motions inside a method's actions (SSSM's `P2`; `P2 mirrors P3` is
//!   the same motion by the other side of the body);
//! * **gestures** — a method that finds only short strokes and no actions (the kinematic
//!   baselines' `gesture` and `swing`, LMA's `left arm` / `right arm` / `both arms`: which arm moves).

use crate::clips::Which;
use crate::protocol::MethodView;
use crate::segment::Level;

/// What a row holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowKind {
    Actions,
    Labels,
    Primitives,
    Gestures,
}

impl RowKind {
    /// The kind of a method's row: its primitives row (`primitive`) or its actions row, for a run
    /// that is a labelling method's (`labelling`) and has segments above the primitive level
    /// (`has_actions`: actions or transitions).
    pub fn of(primitive: bool, labelling: bool, has_actions: bool) -> RowKind {
        match (primitive, labelling, has_actions) {
            (true, _, true) => RowKind::Primitives,
            (true, _, false) => RowKind::Gestures,
            (false, true, _) => RowKind::Labels,
            (false, false, _) => RowKind::Actions,
        }
    }

    /// The word that names the kind in a row's name ("SSSM · actions").
    pub fn word(self) -> &'static str {
        match self {
            RowKind::Actions => "actions",
            RowKind::Labels => "labels",
            RowKind::Primitives => "primitives",
            RowKind::Gestures => "gestures",
        }
    }

    /// What a row of this kind shows, in a sentence (the row's tooltip and the legend).
    pub fn meaning(self) -> &'static str {
        match self {
            RowKind::Actions => {
                "long stretches of one kind of motion, found without labels: A0, A1… (or B1, B2…) name groups of \
                 alike stretches, not what they are; hatched grey: a transition between two actions"
            }
            RowKind::Labels => {
                "a class from the model's list on every frame (jumping jacks, walk…), paler the less sure the model \
                 is; hatched grey: unknown (no class fits)"
            }
            RowKind::Primitives => {
                "the short motions inside the actions: P0, P1… name groups of alike motions; \"P2 mirrors P3\": the \
                 same motion as P3 done by the other side of the body"
            }
            RowKind::Gestures => {
                "short strokes between rests, no actions: \"gesture\" or \"swing\" (a limb's stroke), or which arm \
                 moves (left arm, right arm, both arms)"
            }
        }
    }
}

/// A method's row name: its short name and its kind ("k-NN · labels").
pub fn row_name(short: &str, kind: RowKind) -> String {
    format!("{short} · {}", kind.word())
}

/// A method's row's tooltip: what the row is (its name is beside it already).
pub fn row_tooltip(short: &str, kind: RowKind) -> String {
    format!("{short}'s {}: {}", kind.word(), kind.meaning())
}

/// The level a row's selected segment `(start, end)` of `v` has, as the clips' choice: an action
/// among the actions, a primitive among the primitives, a transition among every segment.
pub fn which_of(v: &MethodView, start: usize, end: usize) -> Option<Which> {
    let s = v.segmentation.segments.iter().find(|s| s.start == start && s.end == end)?;
    Some(match s.level {
        Level::Action => Which::Actions,
        Level::Primitive => Which::Primitives,
        Level::Transition => Which::All,
    })
}

/// What the row of `v` calls the segments `w` chooses, for the export's menu and file names:
/// the row's word ([`RowKind::word`]: a labelling method's actions are its
/// "labels", LMA's primitives its "gestures"), "all" for every segment.
pub fn which_word(v: Option<&MethodView>, w: Which) -> &'static str {
    match w {
        Which::Actions => row_kind(v, false).word(),
        Which::Primitives => row_kind(v, true).word(),
        Which::All => "all",
    }
}

/// What a method's row holds (actions, labels, primitives, gestures), from its run.
pub fn row_kind(v: Option<&MethodView>, primitive: bool) -> RowKind {
    let labelling = v.is_some_and(is_labelling);
    let has_actions = v.is_some_and(|v| v.segmentation.segments.iter().any(|s| s.level != Level::Primitive));
    RowKind::of(primitive, labelling, has_actions)
}

/// Whether `v` is a labelling method's run (DT-FCN, k-NN): its segments are per-frame class labels.
pub fn is_labelling(v: &MethodView) -> bool {
    labels_classes(&v.method) || v.segmentation.params.get("colours").is_some()
}

/// Levels shown in a method's actions row and in its primitives row.
pub const ACTION_LEVELS: &[Level] = &[Level::Action, Level::Transition];

/// Whether the method called `method` labels every frame with its model's classes (as it declares).
pub fn labels_classes(method: &str) -> bool {
    crate::methods::find(method).ok().and_then(|m| m.supervision()).is_some_and(|s| s.labels_classes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_labelling_methods_actions_row_is_named_labels_everywhere() {
        assert_eq!(row_name("k-NN", RowKind::of(false, true, true)), "k-NN · labels");
        assert_eq!(row_name("SSSM", RowKind::of(false, false, true)), "SSSM · actions");
        assert_eq!(row_name("SSSM", RowKind::of(true, false, true)), "SSSM · primitives");
    }

    #[test]
    fn primitives_without_actions_are_gestures() {
        assert_eq!(RowKind::of(true, false, false), RowKind::Gestures);
        assert_eq!(row_name("LMA", RowKind::of(true, false, false)), "LMA · gestures");
    }

    #[test]
    fn a_tooltip_says_what_the_row_is_not_its_name() {
        let tip = row_tooltip("SSSM", RowKind::Primitives);
        assert!(tip.contains("mirrors"), "{tip}");
        assert_ne!(tip, row_name("SSSM", RowKind::Primitives));
        for kind in [RowKind::Actions, RowKind::Labels, RowKind::Primitives, RowKind::Gestures] {
            assert!(kind.meaning().len() > 40);
        }
    }
}
