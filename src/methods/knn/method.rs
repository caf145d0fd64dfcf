//! The k-NN labeller behind the common [`crate::method::Method`] interface: the same labelling
//! method as DT-FCN — model files, shipped models, the unknown threshold, the class-probability
//! picture and training from a label CSV ([`crate::methods::dtfcn::method::Labelling`],
//! [`crate::methods::dtfcn::supervised`]) — over models whose labeller is this folder's
//! [`super::Knn`].

use crate::methods::dtfcn::method::Labelling;
use crate::methods::dtfcn::model::ModelKind;

/// The k-NN method (`knn`).
pub const KNN: Labelling = Labelling::of(ModelKind::Knn);
