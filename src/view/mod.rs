//! The little maths the page needs, kept out of the web layer so it is tested natively:
//! the orbiting perspective camera, the playback clock and the timeline (window, ruler, readout,
//! segment navigation, keyboard), readable text on segment colours ([`contrast`]), segment labels that fit
//! their width ([`label_fit`]), the rows' export names
//! ([`export_names`]), the banner when every method fails ([`run_failures`]), the URL
//! parameters ([`url_params`]), the "my labels" row's edit model ([`my_labels`]) and the metrics
//! panel's comparison table ([`compare`]: best per column, sorting), one name per timeline row
//! ([`rows`]), a model's card beside its choice ([`model_card`]), the advice before a training
//! ([`training_advice`]), the question when a take is opened during a training and what forgetting a
//! model kept in the browser changes ([`kept_models`]), and a labelling row's badge when its model
//! does not fit the take ([`take_fit`]), the Effort bars under every row ([`effort`]), the
//! consensus row's settings and words ([`consensus`]), and the library of takes: its queue, its CSV,
//! the shared clusters' names and playlists ([`library`]).

pub mod camera;
pub mod carry;
pub mod clock;
pub mod compare;
pub mod consensus;
pub mod contrast;
pub mod effort;
pub mod export_names;
pub mod kept_models;
pub mod label_fit;
pub mod library;
pub mod model_card;
pub mod my_labels;
pub mod rows;
pub mod run_failures;
pub mod take_fit;
pub mod timeline;
pub mod training_advice;
pub mod url_params;
