//! Labels carried across the library on the page (issue 26, "Label transfer"), as plain data: the
//! source take's per-frame labels from my labels or its ground truth ([`frame_labels`]), the labels
//! the worker carried to every take ([`Carried`]: each take's share of labelled frames, its
//! "Carried labels" timeline row, the spans "Copy carried labels into my labels" copies) and which segmentation of each
//! take the library's "Labels CSV (all takes)" saves ([`export`]). The page
//! (`crate::app::library::panel`) asks the worker and draws; everything it decides is here, tested natively.
//! The two other routes, [`Route::Knn`] and [`Route::Dtfcn`], train that supervised method on the source's labels
//! ([`label_rows`]: the label CSV it trains on) and label every other take with it; [`Carried::by_model`] turns
//! those segmentations into carried labels like the matching routes'.

use crate::app::my_labels::vocabulary::{is_labelled, label_class};
use crate::labels::LabelRow;
use crate::library::{TransferRoute, Transferred};
use crate::segment::palette::class_colour;
use crate::segment::{Level, Segmentation};

/// The method name of a "Carried labels" row's segmentation.
pub const TRANSFERRED: &str = "transferred";

/// Every frame's label in `segmentation` (`frames` long): the label of the labelled segment over it
/// (not a transition, not empty, not `unknown` / `unlabelled` / `transition`), else `None`. Where
/// labelled segments overlap, the later one wins.
pub fn frame_labels(segmentation: &Segmentation, frames: usize) -> Vec<Option<String>> {
    let mut labels = vec![None; frames];
    for s in segmentation.segments.iter().filter(|s| s.level != Level::Transition && is_labelled(&s.label)) {
        let end = s.end.min(frames.saturating_sub(1));
        if s.start <= end && s.start < frames {
            labels[s.start..=end].iter_mut().for_each(|l| *l = Some(s.label.trim().to_string()));
        }
    }
    labels
}

/// The label rows of take `file` from its frame labels (one row per run of one label; frames
/// without a label left out): the label CSV the k-NN route trains on.
pub fn label_rows(file: &str, labels: &[Option<String>]) -> Vec<LabelRow> {
    runs(labels)
        .into_iter()
        .filter_map(|(start, end, label)| {
            label.map(|label| LabelRow { file: file.to_string(), start_frame: start, end_frame: end, label })
        })
        .collect()
}

/// The runs of equal labels of `labels`: (first frame, last frame, label).
fn runs(labels: &[Option<String>]) -> Vec<(usize, usize, Option<String>)> {
    let mut runs: Vec<(usize, usize, Option<String>)> = Vec::new();
    for (i, l) in labels.iter().enumerate() {
        match runs.last_mut() {
            Some(last) if last.2 == *l => last.1 = i,
            _ => runs.push((i, i, l.clone())),
        }
    }
    runs
}

/// How labels were carried: by the worker's matching ([`TransferRoute`]) or by a supervised method (the k-NN or
/// DT-FCN) trained on the source's labels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Route {
    Nearest,
    Clusters,
    Knn,
    Dtfcn,
}

impl Route {
    /// The worker's matching route (`None`: a supervised method's).
    pub fn transfer(self) -> Option<TransferRoute> {
        match self {
            Route::Nearest => Some(TransferRoute::Nearest),
            Route::Clusters => Some(TransferRoute::Clusters),
            Route::Knn | Route::Dtfcn => None,
        }
    }

    /// The registry name of the supervised method trained on the labels (`None`: a matching route).
    pub fn method(self) -> Option<&'static str> {
        match self {
            Route::Knn => Some("knn"),
            Route::Dtfcn => Some("dtfcn"),
            Route::Nearest | Route::Clusters => None,
        }
    }

    /// The value of `#library-route`'s option.
    pub fn value(self) -> &'static str {
        match self {
            Route::Nearest => "nearest",
            Route::Clusters => "clusters",
            Route::Knn => "knn",
            Route::Dtfcn => "dtfcn",
        }
    }

    /// The route of option `value` (anything else: the nearest labelled segment).
    pub fn from_value(value: &str) -> Route {
        match value {
            "clusters" => Route::Clusters,
            "knn" => Route::Knn,
            "dtfcn" => Route::Dtfcn,
            _ => Route::Nearest,
        }
    }

    /// How the status names it.
    pub fn text(self) -> &'static str {
        match self {
            Route::Nearest => "nearest labelled segment",
            Route::Clusters => "shared clusters",
            Route::Knn => "a k-NN trained on these labels",
            Route::Dtfcn => "a DT-FCN trained on these labels",
        }
    }
}

impl From<TransferRoute> for Route {
    fn from(route: TransferRoute) -> Route {
        match route {
            TransferRoute::Nearest => Route::Nearest,
            TransferRoute::Clusters => Route::Clusters,
        }
    }
}

/// The labels carried last: from take `source` of the library by `route`, the takes sent (their
/// library indices, in the order of `transferred`) and each one's labels.
#[derive(Debug, Clone, PartialEq)]
pub struct Carried {
    pub route: Route,
    pub source: usize,
    pub takes: Vec<usize>,
    pub transferred: Vec<Transferred>,
}

impl Carried {
    /// The labels a supervised method (`route`: the k-NN or DT-FCN) trained on take `source`'s labels
    /// (`source_labels`, every frame's; the source's segmentation `file` at `fps`) gave the takes `labelled`
    /// (library index, the method's segmentation of it): each take's segments as the method labelled them
    /// (`unknown` where it said unknown, its mean probability the confidence), the source keeping its own labels
    /// (confidence 1, `unknown` where it has none). The source first, then the takes in order.
    pub fn by_model(
        route: Route,
        source: usize,
        file: &str,
        fps: f64,
        source_labels: Vec<Option<String>>,
        labelled: Vec<(usize, Segmentation)>,
    ) -> Carried {
        let segments = runs(&source_labels)
            .into_iter()
            .map(|(start, end, label)| crate::segment::Segment {
                start,
                end,
                score: label.as_ref().map(|_| 1.0),
                label: label.unwrap_or_else(|| crate::segment::UNKNOWN.to_string()),
                level: Level::Action,
                cluster: None,
                mirror_of: None,
                effort: None,
            })
            .collect();
        let own = Segmentation {
            file: file.to_string(),
            fps,
            frames: source_labels.len(),
            method: TRANSFERRED.into(),
            params: serde_json::json!({}),
            segments,
        };
        let mut takes = vec![source];
        let mut transferred = vec![Transferred { segmentation: own, frame_labels: source_labels }];
        for (i, segmentation) in labelled.into_iter().filter(|(i, _)| *i != source) {
            let frame_labels = frame_labels(&segmentation, segmentation.frames);
            takes.push(i);
            transferred.push(Transferred { segmentation, frame_labels });
        }
        Carried { route, source, takes, transferred }
    }

    /// The labels carried to take `library` (`None`: it was not in the library then).
    pub fn of(&self, library: usize) -> Option<&Transferred> {
        self.takes.iter().position(|&t| t == library).and_then(|i| self.transferred.get(i))
    }

    /// The share (0–1) of take `library`'s frames that got a label.
    pub fn labelled_share(&self, library: usize) -> Option<f64> {
        let t = self.of(library)?;
        let n = t.frame_labels.len();
        (n > 0).then(|| t.frame_labels.iter().filter(|l| l.is_some()).count() as f64 / n as f64)
    }

    /// What the take list says of take `library`: "source of the labels", or "73 % labelled".
    pub fn take_text(&self, library: usize) -> Option<String> {
        if library == self.source {
            return Some("source of the labels".into());
        }
        self.labelled_share(library).map(|s| format!("{:.0} % labelled", s * 100.0))
    }

    /// Take `library`'s labels as the timeline's "Carried labels" row draws them (a labelling row):
    /// every labelled segment's `cluster` its label's class, `params.colours` the class colours my
    /// labels give those labels (the same on every take), `unknown` without a class (drawn grey);
    /// `score` is the confidence (its shade on the row).
    pub fn row(&self, library: usize) -> Option<Segmentation> {
        let t = self.of(library)?;
        let mut segmentation = t.segmentation.clone();
        let mut colours = Vec::new();
        for s in &mut segmentation.segments {
            s.cluster = is_labelled(&s.label).then(|| {
                let class = label_class(&s.label);
                if colours.len() <= class {
                    colours.resize(class + 1, String::new());
                }
                colours[class] = class_colour(class);
                class
            });
        }
        segmentation.method = TRANSFERRED.into();
        segmentation.params = serde_json::json!({ "route": self.route, "colours": colours });
        Some(segmentation)
    }

    /// The spans "Copy carried labels into my labels" copies onto take `library`: its labelled segments
    /// (`unknown` left out: it becomes a gap).
    pub fn spans(&self, library: usize) -> Vec<(usize, usize, String)> {
        self.of(library).map_or_else(Vec::new, |t| {
            t.segmentation
                .segments
                .iter()
                .filter(|s| is_labelled(&s.label))
                .map(|s| (s.start, s.end, s.label.clone()))
                .collect()
        })
    }

    /// What the status says once the labels arrive.
    pub fn summary(&self, source_name: &str) -> String {
        let others: Vec<f64> =
            self.takes.iter().filter(|&&t| t != self.source).filter_map(|&t| self.labelled_share(t)).collect();
        let mean = if others.is_empty() { 0.0 } else { others.iter().sum::<f64>() / others.len() as f64 };
        let route = self.route.text();
        format!(
            "labels of {source_name} carried to {} by {route}: {:.0} % of their frames labelled; takes added later get \
             labels when you carry again",
            crate::method::counted(others.len(), "take"),
            mean * 100.0
        )
    }

    /// [`Carried::summary`] of a supervised route whose method is `short` (DT-FCN), followed by the takes its model
    /// does not fit (`misfits`, "name: why": the method's fit check labelled them unknown, which its panel's
    /// `fit_check` turns off) and those that could not be labelled (`failed`, "name: why").
    pub fn model_summary(&self, source_name: &str, short: &str, misfits: &[String], failed: &[String]) -> String {
        let mut summary = self.summary(source_name);
        if !misfits.is_empty() {
            summary = format!(
                "{summary}; all unknown where the model does not fit (the {short} panel's fit_check off labels them \
                 anyway): {}",
                misfits.join("; ")
            );
        }
        if !failed.is_empty() {
            summary = format!("{summary}; not labelled: {}", failed.join("; "));
        }
        summary
    }
}

/// The segmentation of each take the library's "Labels CSV (all takes)" saves, from `segmented`
/// (library index, its segmentation as the library shows it): its carried labels when labels were
/// carried to it (the source take's own labels included; `unknown` stretches as `unknown` rows), else
/// its segmentation as before — clusters named.
pub fn export(segmented: Vec<(usize, Segmentation)>, carried: Option<&Carried>) -> Vec<Segmentation> {
    segmented
        .into_iter()
        .map(|(i, own)| match carried.and_then(|c| c.of(i)) {
            Some(t) => Segmentation { file: own.file.clone(), ..t.segmentation.clone() },
            None => own,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::segment::Segment;

    fn segment(start: usize, end: usize, label: &str, level: Level, score: Option<f64>) -> Segment {
        Segment { start, end, label: label.into(), level, cluster: None, score, mirror_of: None, effort: None }
    }

    fn segmentation(file: &str, frames: usize, segments: Vec<Segment>) -> Segmentation {
        Segmentation {
            file: file.into(),
            fps: 30.0,
            frames,
            method: "sssm".into(),
            params: serde_json::json!({}),
            segments,
        }
    }

    /// Take 2 got "walk" on frames 0–5 (0.8), nothing on 6–7, "run" on 8–9 (0.5); take 0 is the source.
    fn carried() -> Carried {
        let walk = Some("walk".to_string());
        let run = Some("run".to_string());
        let mut labels = vec![walk.clone(); 6];
        labels.extend([None, None, run.clone(), run]);
        let other = Transferred {
            segmentation: segmentation(
                "b.bvh",
                10,
                vec![
                    segment(0, 5, "walk", Level::Action, Some(0.8)),
                    segment(6, 7, "unknown", Level::Action, Some(0.0)),
                    segment(8, 9, "run", Level::Action, Some(0.5)),
                ],
            ),
            frame_labels: labels,
        };
        let source = Transferred {
            segmentation: segmentation("a.bvh", 4, vec![segment(0, 3, "walk", Level::Action, Some(1.0))]),
            frame_labels: vec![walk; 4],
        };
        Carried { route: Route::Nearest, source: 0, takes: vec![0, 2], transferred: vec![source, other] }
    }

    #[test]
    fn the_knn_route_trains_on_one_row_per_run_of_the_source_labels() {
        let l = |s: &str| (!s.is_empty()).then(|| s.to_string());
        let labels: Vec<Option<String>> = ["", "walk", "walk", "run", "", "", "walk"].iter().map(|s| l(s)).collect();
        let rows = label_rows("a.bvh", &labels);
        let got: Vec<(usize, usize, &str)> =
            rows.iter().map(|r| (r.start_frame, r.end_frame, r.label.as_str())).collect();
        assert_eq!(got, [(1, 2, "walk"), (3, 3, "run"), (6, 6, "walk")]);
        assert!(rows.iter().all(|r| r.file == "a.bvh"));
        assert_eq!(
            crate::labels::to_csv(&rows),
            "file,start_frame,end_frame,label\na.bvh,1,2,walk\na.bvh,3,3,run\na.bvh,6,6,walk\n"
        );
        assert!(label_rows("a.bvh", &[None, None]).is_empty());
    }

    #[test]
    fn a_knn_segmentation_becomes_carried_labels_with_its_probability_as_confidence() {
        let walk = Some("walk".to_string());
        let source_labels = vec![walk.clone(), walk.clone(), None, Some("run".to_string())];
        // the k-NN's labelling of take 2: walk (0.9), unknown (0.3), run (0.7)
        let knn = segmentation(
            "b.bvh",
            6,
            vec![
                Segment { cluster: Some(0), ..segment(0, 2, "walk", Level::Action, Some(0.9)) },
                segment(3, 3, "unknown", Level::Action, Some(0.3)),
                Segment { cluster: Some(1), ..segment(4, 5, "run", Level::Action, Some(0.7)) },
            ],
        );
        // the source itself among the takes the k-NN labelled is left out: it keeps its own labels
        let c = Carried::by_model(
            Route::Knn,
            0,
            "a.bvh",
            30.0,
            source_labels.clone(),
            vec![(0, knn.clone()), (2, knn.clone())],
        );
        assert_eq!((c.route, c.source, c.takes.clone()), (Route::Knn, 0, vec![0, 2]));
        let own = c.of(0).unwrap();
        assert_eq!(own.frame_labels, source_labels);
        let spans: Vec<(usize, usize, &str, Option<f64>)> =
            own.segmentation.segments.iter().map(|s| (s.start, s.end, s.label.as_str(), s.score)).collect();
        assert_eq!(spans, [(0, 1, "walk", Some(1.0)), (2, 2, "unknown", None), (3, 3, "run", Some(1.0))]);
        assert_eq!((own.segmentation.file.as_str(), own.segmentation.frames), ("a.bvh", 4));
        // take 2: the k-NN's labels frame by frame, unknown unlabelled
        let other = c.of(2).unwrap();
        let want: Vec<Option<String>> =
            ["walk", "walk", "walk", "", "run", "run"].iter().map(|s| (!s.is_empty()).then(|| s.to_string())).collect();
        assert_eq!(other.frame_labels, want);
        assert_eq!(c.labelled_share(2), Some(5.0 / 6.0));
        assert_eq!(c.take_text(2).as_deref(), Some("83 % labelled"));
        // its row: my labels' classes, unknown grey, the k-NN's probability as the confidence
        let row = c.row(2).unwrap();
        assert_eq!(
            row.segments.iter().map(|s| s.cluster).collect::<Vec<_>>(),
            [Some(label_class("walk")), None, Some(label_class("run"))]
        );
        assert_eq!(row.segments.iter().map(|s| s.score).collect::<Vec<_>>(), [Some(0.9), Some(0.3), Some(0.7)]);
        assert_eq!(row.params["route"], "knn");
        assert_eq!(c.spans(2), [(0, 2, "walk".to_string()), (4, 5, "run".to_string())]);
        assert!(c
            .summary("a.bvh")
            .starts_with("labels of a.bvh carried to 1 take by a k-NN trained on these labels: 83 %"));
        assert_eq!(c.model_summary("a.bvh", "k-NN", &[], &[]), c.summary("a.bvh"));
        let told = c.model_summary("a.bvh", "k-NN", &["b.bvh: it jogs".into()], &["c.bvh: not a BVH".into()]);
        assert!(
            told.starts_with(&c.summary("a.bvh"))
                && told.ends_with(
                    "; all unknown where the model does not fit (the k-NN panel's fit_check off labels them anyway): \
                     b.bvh: it jogs; not labelled: c.bvh: not a BVH"
                ),
            "{told}"
        );
        // the CSV saves the source's labels and the k-NN's
        let own_seg = |file: &str, n| segmentation(file, n, vec![segment(0, n - 1, "C1", Level::Action, None)]);
        let csv = crate::app::library::takes::library_csv(&export(
            vec![(0, own_seg("a.bvh", 4)), (2, own_seg("b.bvh", 6))],
            Some(&c),
        ));
        assert_eq!(
            csv,
            "file,start_frame,end_frame,label\na.bvh,0,1,walk\na.bvh,2,2,unknown\na.bvh,3,3,run\nb.bvh,0,2,walk\n\
             b.bvh,3,3,unknown\nb.bvh,4,5,run\n"
        );
    }

    #[test]
    fn the_routes_read_and_name_their_choice() {
        for route in [Route::Nearest, Route::Clusters, Route::Knn, Route::Dtfcn] {
            assert_eq!(Route::from_value(route.value()), route);
            // a route either matches in the worker or trains a method, never both
            assert!(route.transfer().is_some() != route.method().is_some());
        }
        assert_eq!(Route::from_value("?"), Route::Nearest);
        assert_eq!(Route::Knn.transfer(), None);
        assert_eq!((Route::Knn.method(), Route::Dtfcn.method()), (Some("knn"), Some("dtfcn")));
        // every supervised route names a method of the registry that can be trained
        for route in [Route::Knn, Route::Dtfcn] {
            let name = route.method().unwrap();
            let method = crate::methods::find(name).unwrap_or_else(|e| panic!("{name} is registered: {e}"));
            assert!(method.supervised().is_some(), "{name} can be trained");
        }
        assert_eq!(Route::from(TransferRoute::Clusters).transfer(), Some(TransferRoute::Clusters));
    }

    #[test]
    fn the_source_labels_are_its_labelled_segments_frame_by_frame() {
        let mine = segmentation(
            "a.bvh",
            8,
            vec![
                segment(0, 2, "walk", Level::Action, None),
                segment(3, 4, "unlabelled", Level::Transition, None),
                segment(5, 6, " unknown ", Level::Action, None),
                segment(7, 20, "jump ", Level::Action, None),
            ],
        );
        let labels = frame_labels(&mine, 8);
        let want: Vec<Option<String>> = ["walk", "walk", "walk", "", "", "", "", "jump"]
            .iter()
            .map(|l| (!l.is_empty()).then(|| l.to_string()))
            .collect();
        assert_eq!(labels, want);
        assert!(frame_labels(&segmentation("a.bvh", 3, vec![]), 3).iter().all(Option::is_none));
    }

    #[test]
    fn each_take_says_how_much_of_it_got_a_label() {
        let c = carried();
        assert_eq!(c.labelled_share(2), Some(0.8));
        assert_eq!(c.take_text(2).as_deref(), Some("80 % labelled"));
        assert_eq!(c.take_text(0).as_deref(), Some("source of the labels"));
        // a take added after the labels were carried has none
        assert_eq!((c.of(1), c.take_text(1)), (None, None));
        assert_eq!(
            c.summary("a.bvh"),
            "labels of a.bvh carried to 1 take by nearest labelled segment: 80 % of their frames labelled; takes \
             added later get labels when you carry again"
        );
    }

    #[test]
    fn the_transferred_row_colours_labels_as_my_labels_do_and_leaves_unknown_grey() {
        let row = carried().row(2).unwrap();
        assert_eq!(row.method, TRANSFERRED);
        let (walk, run) = (label_class("walk"), label_class("run"));
        let classes: Vec<Option<usize>> = row.segments.iter().map(|s| s.cluster).collect();
        assert_eq!(classes, [Some(walk), None, Some(run)]);
        let colours = &row.params["colours"];
        assert_eq!(colours[walk].as_str(), Some(class_colour(walk).as_str()));
        assert_eq!(colours[run].as_str(), Some(class_colour(run).as_str()));
        // the confidence stays each segment's score (the row's shade, the tooltip)
        assert_eq!(row.segments.iter().map(|s| s.score).collect::<Vec<_>>(), [Some(0.8), Some(0.0), Some(0.5)]);
        assert!(carried().row(1).is_none());
    }

    #[test]
    fn copying_into_my_labels_takes_the_labelled_spans_only() {
        let spans = carried().spans(2);
        assert_eq!(spans, [(0, 5, "walk".to_string()), (8, 9, "run".to_string())]);
        let mut mine = crate::app::my_labels::edits::MyLabels::new(10);
        mine.copy_from(&spans).unwrap();
        let labels = frame_labels(&mine.to_segmentation("b.bvh", 30.0), 10);
        assert_eq!(labels, carried().of(2).unwrap().frame_labels, "my labels are then the carried ones");
        assert!(carried().spans(5).is_empty());
    }

    #[test]
    fn the_csv_saves_carried_labels_where_there_are_some_and_the_segmentation_elsewhere() {
        let own = |file: &str| segmentation(file, 10, vec![segment(0, 9, "C3", Level::Action, None)]);
        let segmented = vec![(0, own("a.bvh")), (1, own("c.bvh")), (2, own("b.bvh"))];
        let c = carried();
        let csv = crate::app::library::takes::library_csv(&export(segmented.clone(), Some(&c)));
        assert_eq!(
            csv,
            "file,start_frame,end_frame,label\na.bvh,0,3,walk\nc.bvh,0,9,C3\nb.bvh,0,5,walk\nb.bvh,6,7,unknown\n\
             b.bvh,8,9,run\n"
        );
        let plain = export(segmented.clone(), None);
        assert_eq!(plain, segmented.into_iter().map(|(_, s)| s).collect::<Vec<_>>());
    }
}
