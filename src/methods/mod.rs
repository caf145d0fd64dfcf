//! The segmentation methods, one folder each, named as their papers name them, and the registry
//! that lists them: the only place that knows which methods exist. Everything else — the command
//! line, the worker, the page — goes through [`registry`] and [`find`] as
//! [`crate::method::DynMethod`] (the shape every method has: [`crate::method`]).
//!
//! | method | paper | folder |
//! |---|---|---|
//! | SSSM: sparse self-similarity segmentation | Krüger et al. 2017 | [`sssm`] |
//! | velocity baseline | (zero crossings of joint speeds) | [`velocity`] |
//! | KCS baseline | (kinematic chain space) | [`kcs`] |
//! | PCA baseline | Barbič et al. 2004 | [`pca`] |
//! | LMA Effort classifiers | Bouchard & Badler | [`lma`] |
//! | k-NN labeller | baseline for Cheema et al. 2019 | [`knn`] |
//! | DT-FCN | Cheema et al. 2019 | [`dtfcn`] |
//!
//! Adding a method: its folder here, `pub mod` below, and one line in [`registry`].

pub mod dtfcn;
pub mod kcs;
pub mod knn;
pub mod lma;
pub mod pca;
pub mod sssm;
pub mod velocity;

use crate::labeller::method::{Kind, Labelling};
use crate::method::unsupervised::Unsupervised;
use crate::method::{DynMethod, MethodError};

/// The labelling methods' kinds: the model files a labelling method may meet (another's, the fit check's windows).
pub const LABELLERS: [&dyn Kind; 2] = [&knn::method::KNN, &dtfcn::method::DTFCN];
/// The k-NN method (`knn`).
const KNN: Labelling = Labelling::new(&knn::method::KNN, &LABELLERS);
/// The DT-FCN method (`dtfcn`).
const DTFCN: Labelling = Labelling::new(&dtfcn::method::DTFCN, &LABELLERS);

/// Every method, in the order the page shows them. One line per method.
pub fn registry() -> &'static [&'static dyn DynMethod] {
    &[
        &Unsupervised(sssm::method::Sssm),
        &Unsupervised(velocity::method::Velocity),
        &Unsupervised(kcs::method::Kcs),
        &Unsupervised(pca::method::Pca),
        &lma::method::Lma,
        // the k-NN first: on clean labels it is the better labeller (docs/methods/dtfcn.md, "Accuracy")
        &KNN,
        &DTFCN,
    ]
}

/// The card of every shipped model of every supervised method, read by `models` (held-out figures not yet added:
/// [`crate::method::cards::with_held_out`]).
pub fn shipped_cards(models: &crate::method::ModelStore) -> Vec<crate::method::cards::ModelCard> {
    let mut cards = Vec::new();
    for m in registry() {
        let (Some(decl), Some(s)) = (m.supervision(), m.supervised()) else { continue };
        for name in &decl.shipped {
            if let Ok(loaded) = s.shipped_model(name, models) {
                let mut card = loaded.info.card;
                card.method = m.info().name;
                card.name = name.clone();
                cards.push(card);
            }
        }
    }
    cards
}

/// The method called `name`.
pub fn find(name: &str) -> Result<&'static dyn DynMethod, MethodError> {
    let name = name.trim().to_ascii_lowercase();
    registry().iter().copied().find(|m| m.info().name == name).ok_or_else(|| MethodError::Unknown {
        name,
        known: registry().iter().map(|m| m.info().name).collect::<Vec<_>>().join(", "),
    })
}

/// How a run of the method called `method` is scored against a truth: a labelling method's labels by their names,
/// always (a class the take does not have is wrong); any other's as [`Naming::Detect`] reads them (clusters by the
/// one-to-one matching, names that are the truth's by name).
///
/// [`Naming::Detect`]: crate::segment::metrics::Naming::Detect
pub fn scoring(method: &str) -> crate::segment::metrics::Tolerances {
    let labels = find(method).ok().and_then(|m| m.supervision()).is_some_and(|s| s.labels_classes);
    if labels {
        crate::segment::metrics::Tolerances::by_name()
    } else {
        crate::segment::metrics::Tolerances::default()
    }
}

#[cfg(test)]
mod scoring_tests {
    use crate::segment::metrics::Naming;

    /// The labellers' runs are scored by name whatever their names; the others' as their labels read.
    #[test]
    fn labellers_are_scored_by_name_and_the_rest_as_their_labels_read() {
        for m in super::registry() {
            let name = m.info().name;
            let labels = m.supervision().is_some_and(|s| s.labels_classes);
            let want = if labels { Naming::ByName } else { Naming::Detect };
            assert_eq!(super::scoring(&name).naming, want, "{name}");
        }
        assert_eq!(super::scoring("knn").naming, Naming::ByName);
        assert_eq!(super::scoring("dtfcn").naming, Naming::ByName);
        assert_eq!(super::scoring("sssm").naming, Naming::Detect);
        assert_eq!(super::scoring("my labels").naming, Naming::Detect);
    }
}
