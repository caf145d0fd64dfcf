//! Where the worker script, the bundled sample and the shipped models are, relative to the page.

/// Where the worker script, the bundled sample and the shipped models are, relative to the page.
#[derive(Debug, Clone, PartialEq)]
pub struct Urls {
    pub worker: String,
    pub sample: String,
    /// The folder of the shipped model files.
    pub models: String,
    /// How many workers the page may start (`data-workers`; `None`: one per core, at least two).
    pub workers: Option<usize>,
}

impl Urls {
    /// The defaults, overridden by the root element's `data-worker-url` / `data-sample-url` /
    /// `data-models-url`.
    pub fn from_root(root: &web_sys::Element) -> Urls {
        let get = |name: &str, default: &str| root.get_attribute(name).unwrap_or_else(|| default.to_string());
        Urls {
            worker: get("data-worker-url", "./www/worker.js"),
            // the sample packed (src/bvh/pack.rs: half the download of www/sample.bvh, the same bytes)
            sample: get("data-sample-url", "./www/sample.bvh.pack"),
            models: get("data-models-url", "./models/"),
            workers: root.get_attribute("data-workers").and_then(|n| n.trim().parse().ok()),
        }
    }

    /// The file name at the end of the sample's URL (of the file a pack holds, for a pack).
    pub fn sample_name(&self) -> String {
        let name = self.sample.rsplit('/').next().unwrap_or("sample.bvh");
        crate::bvh::unpacked_name(name).unwrap_or(name).to_string()
    }

    /// Whether the sample's URL names a pack (`NAME.bvh.pack`), which the page unpacks.
    pub(super) fn sample_is_packed(&self) -> bool {
        let name = self.sample.rsplit('/').next().unwrap_or_default();
        crate::bvh::unpacked_name(name).is_some()
    }
}
