//! A supervised method's models on the page: the model choice on its row and in its panel, the shipped model files,
//! the models kept in this browser, and training on the user's labels.
//!
//! Its pure part (natively tested) beside its components (built with the `web` feature).

pub mod kept_models;
pub mod model_card;
pub mod take_fit;
pub mod training_advice;

#[cfg(feature = "web")]
pub mod browser_models;
#[cfg(feature = "web")]
pub mod jobs;
#[cfg(feature = "web")]
pub mod model_files;
#[cfg(feature = "web")]
pub mod model_jobs;
#[cfg(feature = "web")]
pub mod picked;
#[cfg(feature = "web")]
pub mod row_model;
#[cfg(feature = "web")]
pub mod supervised;
#[cfg(feature = "web")]
pub mod train_form;
#[cfg(feature = "web")]
pub mod train_outcome;
#[cfg(feature = "web")]
pub mod training;
#[cfg(feature = "web")]
pub mod training_jobs;
