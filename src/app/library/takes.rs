//! The library of takes on the page (issue 26), as plain data: which files dropped together make
//! which takes ([`group_files`], [`within_cap`]), the whole library's labels as one label CSV
//! ([`library_csv`]), the names the user gives the shared clusters and the labels they put on every
//! take's segments ([`crate::app::library::names`]), the shared clusters mapped to the library's takes for the
//! timeline's row, the playlists and the clips ([`Shared`]), the playlist of a cluster's occurrences
//! across takes ([`Playlist`]), and the clips' folder and file names in one zip ([`folder_name`],
//! [`make_unique`]). The queue the worker works through one take after another is
//! [`crate::app::library::queue`]. The page (`crate::app::library::panel`) keeps the files and draws;
//! everything it decides is here, tested natively.

use crate::app::library::names::{ClusterNames, NamedSpot};
use crate::labels::LabelRow;
use crate::segment::Segmentation;
use std::collections::BTreeMap;

/// The cluster list shows, unless asked for every cluster, those found in this many takes or more…
pub const LIST_MIN_TAKES: usize = 2;
/// …whose occurrences last this long on average, or longer (seconds).
pub const LIST_MIN_SECONDS: f64 = 0.5;

/// Whether cluster `c` is listed by default ([`LIST_MIN_TAKES`], [`LIST_MIN_SECONDS`]).
fn worth_listing(c: &crate::library::SharedCluster) -> bool {
    let mean = c.seconds / c.occurrences.len().max(1) as f64;
    c.takes >= LIST_MIN_TAKES && mean >= LIST_MIN_SECONDS
}

/// One take among files dropped or picked together: its motion file and, for a CMU AMC motion,
/// its ASF skeleton (indices into the names given).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TakeFiles {
    pub motion: usize,
    pub skeleton: Option<usize>,
}

/// The lower-case extension of a file name (empty when it has none).
fn extension(name: &str) -> String {
    name.rsplit_once('.').map(|(_, e)| e.to_ascii_lowercase()).unwrap_or_default()
}

/// The most bytes of take files a library holds in all (issue 49, "the library bounded"): its takes are read one at
/// a time, but every clip export and every segmenting after a reload reads them again.
pub const MAX_LIBRARY_BYTES: f64 = 4.0 * 1024.0 * 1024.0 * 1024.0;

/// `takes` (of files `names` with `sizes` in bytes, by index) without those whose motion or skeleton file is larger
/// than the page reads of one take ([`crate::app::embed::fetch_rules::MAX_FILE_BYTES`], 512 MiB) — a library holds no
/// file a take dropped alone could not be — and without those past [`MAX_LIBRARY_BYTES`] in all, counting the
/// `held` bytes the library holds already (the takes in order: the first ones fit); each left out is named with why.
pub fn within_cap(takes: Vec<TakeFiles>, names: &[&str], sizes: &[f64], held: f64) -> (Vec<TakeFiles>, Vec<String>) {
    let cap = crate::app::embed::fetch_rules::MAX_FILE_BYTES as f64;
    let mib = |b: f64| (b / 1024.0 / 1024.0).ceil();
    let mut kept = Vec::new();
    let mut refused = Vec::new();
    let mut total = held;
    let mut past_total = Vec::new();
    for t in takes {
        let files = || std::iter::once(t.motion).chain(t.skeleton);
        let size = |i: usize| sizes.get(i).copied().unwrap_or(0.0);
        if let Some(i) = files().find(|&i| size(i) > cap) {
            refused.push(format!(
                "{}: {:.0} MiB is more than the page reads of a take (512 MiB); left out of the library",
                names[i],
                mib(size(i))
            ));
            continue;
        }
        // a skeleton shared by several AMC takes counts once per take: an upper bound
        let bytes: f64 = files().map(size).sum();
        if total + bytes > MAX_LIBRARY_BYTES {
            past_total.push(names[t.motion].to_string());
            continue;
        }
        total += bytes;
        kept.push(t);
    }
    if !past_total.is_empty() {
        let shown: Vec<&str> = past_total.iter().take(3).map(String::as_str).collect();
        let more = past_total.len().saturating_sub(shown.len());
        refused.push(format!(
            "{}{}: left out of the library, which holds at most {:.0} GiB of takes in all ({:.0} MiB held); open them \
             in a library of their own",
            shown.join(", "),
            if more > 0 { format!(" and {more} more") } else { String::new() },
            MAX_LIBRARY_BYTES / 1024.0 / 1024.0 / 1024.0,
            mib(total)
        ));
    }
    (kept, refused)
}

/// The takes among files dropped or picked together (a folder's files included), in name order:
/// each `.bvh` is a take, each `.amc` a take with the `.asf` of its subject (`02_01.amc` →
/// `02.asf`; when the files are one ASF and one AMC, those two). Other files are left out; an AMC
/// without its skeleton is named in the second list, with why.
pub fn group_files(names: &[&str]) -> (Vec<TakeFiles>, Vec<String>) {
    let base = |name: &str| name.rsplit(['/', '\\']).next().unwrap_or(name).to_string();
    let asfs: Vec<usize> = (0..names.len()).filter(|&i| extension(names[i]) == "asf").collect();
    let amcs = names.iter().filter(|n| extension(n) == "amc").count();
    let mut order: Vec<usize> = (0..names.len()).collect();
    order.sort_by(|&a, &b| names[a].cmp(names[b]));
    let mut takes = Vec::new();
    let mut refused = Vec::new();
    for i in order {
        match extension(names[i]).as_str() {
            "bvh" => takes.push(TakeFiles { motion: i, skeleton: None }),
            "amc" => {
                let stem = base(names[i]);
                let subject = crate::clips::stem_of(&stem).split('_').next().unwrap_or_default().to_ascii_lowercase();
                let skeleton = asfs
                    .iter()
                    .copied()
                    .find(|&a| crate::clips::stem_of(names[a]).to_ascii_lowercase() == subject)
                    .or_else(|| (asfs.len() == 1 && amcs == 1).then(|| asfs[0]));
                match skeleton {
                    Some(asf) => takes.push(TakeFiles { motion: i, skeleton: Some(asf) }),
                    None => refused
                        .push(format!("{stem}: an AMC motion without its skeleton (add {subject}.asf to the files)")),
                }
            }
            _ => {}
        }
    }
    (takes, refused)
}

/// The whole library's labels as one label CSV ([`crate::labels`]): every segment of every
/// take's segmentation, take after take in the order given, each row naming its take's file.
pub fn library_csv<'a>(segmentations: impl IntoIterator<Item = &'a Segmentation>) -> String {
    let rows: Vec<LabelRow> =
        segmentations.into_iter().flat_map(|s| crate::labels::from_segmentation(s, crate::clips::Which::All)).collect();
    crate::labels::to_csv(&rows)
}

/// One occurrence of a cluster: take `take` (the library's index), file frames `start..=end`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Spot {
    pub take: usize,
    pub start: usize,
    pub end: usize,
}

/// A cluster's occurrences played one after another across takes: in take order, then frames.
#[derive(Debug, Clone, PartialEq)]
pub struct Playlist {
    pub cluster: usize,
    spots: Vec<Spot>,
    at: usize,
}

impl Playlist {
    /// The playlist of `cluster`'s occurrences (`None` when it has none).
    pub fn new(cluster: usize, mut spots: Vec<Spot>) -> Option<Playlist> {
        spots.sort_by_key(|s| (s.take, s.start, s.end));
        spots.dedup();
        (!spots.is_empty()).then_some(Playlist { cluster, spots, at: 0 })
    }

    /// The occurrence playing.
    pub fn current(&self) -> Spot {
        self.spots[self.at]
    }

    /// Its place: (1-based index, count).
    pub fn position(&self) -> (usize, usize) {
        (self.at + 1, self.spots.len())
    }

    /// Moves to the next occurrence (after the last: the first again) and gives it.
    pub fn next(&mut self) -> Spot {
        self.at = (self.at + 1) % self.spots.len();
        self.current()
    }

    /// Moves to the previous occurrence (before the first: the last) and gives it.
    pub fn previous(&mut self) -> Spot {
        self.at = (self.at + self.spots.len() - 1) % self.spots.len();
        self.current()
    }

    /// The takes the playlist goes through, each once, in order.
    pub fn takes(&self) -> Vec<usize> {
        let mut takes: Vec<usize> = self.spots.iter().map(|s| s.take).collect();
        takes.dedup();
        takes
    }

    /// Every occurrence, in playing order.
    pub fn spots(&self) -> &[Spot] {
        &self.spots
    }
}

/// What the status line says while `playlist` plays: which occurrence of how many, in which take.
pub fn playing_text(playlist: &Playlist, cluster_name: &str, take_name: &str) -> String {
    let (i, n) = playlist.position();
    let s = playlist.current();
    format!("{cluster_name}: occurrence {i} of {n} — {take_name}, frames {}–{}", s.start, s.end)
}

/// The library's shared clusters as the page keeps them: the core's answer
/// ([`crate::library::SharedClusters`], its takes in the order sent) and, for each of its takes,
/// the library's index of that take.
#[derive(Debug, Clone, PartialEq)]
pub struct Shared {
    pub clusters: crate::library::SharedClusters,
    pub takes: Vec<usize>,
}

impl Shared {
    /// Take `library`'s segmentation with the shared cluster ids, if it was matched.
    pub fn segmentation(&self, library: usize) -> Option<&Segmentation> {
        let k = self.takes.iter().position(|&t| t == library)?;
        self.clusters.takes.get(k)
    }

    /// The playlist of cluster `id`'s occurrences, as library takes.
    pub fn playlist(&self, id: usize) -> Option<Playlist> {
        let cluster = self.clusters.clusters.iter().find(|c| c.id == id)?;
        let spots = cluster
            .occurrences
            .iter()
            .filter_map(|o| Some(Spot { take: *self.takes.get(o.take)?, start: o.start, end: o.end }))
            .collect();
        Playlist::new(id, spots)
    }

    /// The clusters the list shows, most of the library first (their total seconds; then more takes, then id): every
    /// one with `all`, else those worth a look — found in [`LIST_MIN_TAKES`] takes or more, their occurrences lasting
    /// [`LIST_MIN_SECONDS`] on average or longer (a cluster of one take, or of fragments, is noise to a reader).
    pub fn listed(&self, all: bool) -> Vec<&crate::library::SharedCluster> {
        let mut listed: Vec<&crate::library::SharedCluster> =
            self.clusters.clusters.iter().filter(|c| all || worth_listing(c)).collect();
        listed.sort_by(|a, b| b.seconds.total_cmp(&a.seconds).then(b.takes.cmp(&a.takes)).then(a.id.cmp(&b.id)));
        listed
    }

    /// The share (0–1) of the matched takes' seconds that cluster `c`'s occurrences cover.
    pub fn coverage(&self, c: &crate::library::SharedCluster) -> f64 {
        let total: f64 = self.clusters.takes.iter().filter(|t| t.fps > 0.0).map(|t| t.frames as f64 / t.fps).sum();
        if total > 0.0 {
            (c.seconds / total).min(1.0)
        } else {
            0.0
        }
    }

    /// Names for the clusters from the labels their takes carry (`labels`: a library take's labelled spans, frames
    /// inclusive, when it has any): the label that covers most of a cluster's frames, when it covers at least half of
    /// them, as "label · C<id>".
    pub fn label_names(
        &self,
        labels: impl Fn(usize) -> Option<Vec<(usize, usize, String)>>,
    ) -> BTreeMap<usize, String> {
        let by_take: Vec<Option<Vec<(usize, usize, String)>>> = self.takes.iter().map(|&t| labels(t)).collect();
        let mut names = BTreeMap::new();
        for c in &self.clusters.clusters {
            let mut frames: BTreeMap<&str, usize> = BTreeMap::new();
            let mut total = 0;
            for o in &c.occurrences {
                total += o.end + 1 - o.start.min(o.end + 1);
                let Some(Some(spans)) = by_take.get(o.take) else { continue };
                for (start, end, label) in spans {
                    let shared = (o.end.min(*end) + 1).saturating_sub(o.start.max(*start));
                    *frames.entry(label.as_str()).or_default() += shared;
                }
            }
            let best = frames.into_iter().max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(a.0)));
            if let Some((label, n)) = best.filter(|(_, n)| total > 0 && 2 * n >= total) {
                let _ = n;
                names.insert(c.id, format!("{label} · C{}", c.id));
            }
        }
        names
    }

    /// What to cut for the clips of cluster `only` (every cluster with `None`): per library take
    /// that has some, a segmentation of just those occurrences, each labelled with its cluster's
    /// name (the zip's folder), in take order.
    pub fn clips(&self, names: &ClusterNames, only: Option<usize>) -> Vec<(usize, Segmentation)> {
        let mut per_take: Vec<(usize, Segmentation)> = Vec::new();
        for c in self.clusters.clusters.iter().filter(|c| only.is_none_or(|id| c.id == id)) {
            for o in &c.occurrences {
                let (Some(&library), Some(take)) = (self.takes.get(o.take), self.clusters.takes.get(o.take)) else {
                    continue;
                };
                let Some(segment) = take.segments.get(o.segment) else { continue };
                let mut segment = segment.clone();
                segment.label = names.name(c.id);
                let at = match per_take.iter().position(|(t, _)| *t == library) {
                    Some(at) => at,
                    None => {
                        per_take.push((library, Segmentation { segments: Vec::new(), ..take.clone() }));
                        per_take.len() - 1
                    }
                };
                per_take[at].1.segments.push(segment);
            }
        }
        per_take.sort_by_key(|(t, _)| *t);
        for (_, s) in &mut per_take {
            s.segments.sort_by_key(|x| (x.start, x.end));
        }
        per_take
    }

    /// Every cluster's occurrences by its takes' names (`take_name`: a library take's name, by index): what the
    /// names given to clusters follow ([`ClusterNames::follow`]) and keep.
    pub fn named_spots(&self, take_name: impl Fn(usize) -> String) -> Vec<(usize, Vec<NamedSpot>)> {
        self.clusters
            .clusters
            .iter()
            .map(|c| {
                let spots = c
                    .occurrences
                    .iter()
                    .filter_map(|o| {
                        let library = *self.takes.get(o.take)?;
                        Some(NamedSpot { take: take_name(library), start: o.start, end: o.end })
                    })
                    .collect();
                (c.id, spots)
            })
            .collect()
    }

    /// A line about the clusters: how many, how many found in more than one take.
    pub fn summary(&self) -> String {
        let all = self.clusters.clusters.len();
        let shared = self.clusters.shared().count();
        format!(
            "{} across {}: {shared} found in more than one take",
            crate::method::counted(all, "cluster"),
            crate::method::counted(self.takes.len(), "take")
        )
    }
}

/// A zip folder's name for a cluster's clips: its name's letters, digits, `-` and `_`, the rest
/// `_` (`cluster` when nothing is left).
pub fn folder_name(label: &str) -> String {
    let safe: String =
        label.chars().map(|c| if c.is_alphanumeric() || c == '-' || c == '_' { c } else { '_' }).take(60).collect();
    if safe.trim_matches('_').is_empty() {
        "cluster".to_string()
    } else {
        safe
    }
}

/// Makes file names unique: a name met before gets `-2`, `-3`, … before its extension (two takes
/// of the same name in different folders give clips of the same name).
pub fn make_unique(names: &mut [String]) {
    let mut seen = std::collections::HashSet::new();
    for name in names.iter_mut() {
        if seen.insert(name.clone()) {
            continue;
        }
        let base = name.rfind('/').map_or(0, |i| i + 1);
        let (stem, ext) = match name[base..].rfind('.') {
            Some(dot) if dot > 0 => (name[..base + dot].to_string(), name[base + dot..].to_string()),
            _ => (name.clone(), String::new()),
        };
        let mut n = 2;
        while !seen.insert(format!("{stem}-{n}{ext}")) {
            n += 1;
        }
        *name = format!("{stem}-{n}{ext}");
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A file past the page's cap of one take is left out of the library, named with its size, whether it is the
    /// motion or the skeleton of its take; the rest are kept, in order.
    #[test]
    fn files_past_a_takes_cap_are_left_out_of_the_library() {
        let names = ["a.bvh", "big.bvh", "02.asf", "02_01.amc", "c.bvh"];
        let cap = crate::app::embed::fetch_rules::MAX_FILE_BYTES as f64;
        let (takes, _) = group_files(&names);
        assert_eq!(takes.len(), 4);
        let (kept, refused) = within_cap(takes.clone(), &names, &[10.0, cap + 1.0, 2.0 * cap, 5.0, cap], 0.0);
        let kept: Vec<&str> = kept.iter().map(|t| names[t.motion]).collect();
        assert_eq!(kept, ["a.bvh", "c.bvh"], "a file of exactly the cap is read");
        assert_eq!(
            refused,
            [
                "02.asf: 1024 MiB is more than the page reads of a take (512 MiB); left out of the library",
                "big.bvh: 513 MiB is more than the page reads of a take (512 MiB); left out of the library",
            ],
            "in the takes' order (by name)"
        );
        let (all, none) = within_cap(takes, &names, &[1.0; 5], 0.0);
        assert_eq!((all.len(), none.len()), (4, 0));
    }

    /// Takes past the library's total are left out, the first ones kept, the bytes it already holds counted, and
    /// the message names the first few and how many more.
    #[test]
    fn takes_past_the_librarys_total_are_left_out_and_counted() {
        let names: Vec<String> = (0..12).map(|i| format!("{i:02}.bvh")).collect();
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let (takes, _) = group_files(&refs);
        let gib = 1024.0 * 1024.0 * 1024.0;
        // 12 takes of 0.5 GiB: 8 fit in 4 GiB
        let (kept, refused) = within_cap(takes.clone(), &refs, &[0.5 * gib; 12], 0.0);
        assert_eq!(kept.len(), 8);
        assert_eq!(
            refused,
            ["08.bvh, 09.bvh, 10.bvh and 1 more: left out of the library, which holds at most 4 GiB of takes in all \
              (4096 MiB held); open them in a library of their own"]
        );
        // a library holding 3.9 GiB already takes none of them
        let (kept, refused) = within_cap(takes.clone(), &refs, &[0.5 * gib; 12], 3.9 * gib);
        assert_eq!((kept.len(), refused.len()), (0, 1));
        assert!(refused[0].starts_with("00.bvh, 01.bvh, 02.bvh and 9 more"), "{refused:?}");
        // small takes: every one
        let (kept, refused) = within_cap(takes, &refs, &[1e6; 12], 3.0 * gib);
        assert_eq!((kept.len(), refused.len()), (12, 0));
    }
    use crate::segment::{Level, Segment};

    /// A segmentation of `file` with `spans` (start, end, cluster); the queue's tests use it too.
    pub(crate) fn seg(file: &str, frames: usize, spans: &[(usize, usize, Option<usize>)]) -> Segmentation {
        Segmentation {
            file: file.into(),
            method: "sssm".into(),
            fps: 30.0,
            frames,
            segments: spans
                .iter()
                .map(|&(start, end, cluster)| Segment {
                    start,
                    end,
                    label: String::new(),
                    level: Level::Action,
                    cluster,
                    score: None,
                    mirror_of: None,
                    effort: None,
                })
                .collect(),
            params: serde_json::Value::Null,
        }
    }

    #[test]
    fn files_dropped_together_group_into_takes_with_their_skeletons() {
        let names = ["b.bvh", "02_02.amc", "notes.txt", "02.asf", "a.BVH", "02_01.amc", "35_01.amc"];
        let (takes, refused) = group_files(&names);
        let motions: Vec<&str> = takes.iter().map(|t| names[t.motion]).collect();
        assert_eq!(motions, ["02_01.amc", "02_02.amc", "a.BVH", "b.bvh"]);
        assert_eq!(takes[0].skeleton, Some(3));
        assert_eq!(takes[1].skeleton, Some(3));
        assert_eq!(takes[2].skeleton, None);
        assert_eq!(refused, ["35_01.amc: an AMC motion without its skeleton (add 35.asf to the files)"]);
        // a folder's paths: the subject's ASF is found by its stem
        let (takes, refused) = group_files(&["cmu/35.asf", "cmu/35_01.amc", "cmu/02.asf"]);
        assert_eq!(takes, [TakeFiles { motion: 1, skeleton: Some(0) }]);
        assert!(refused.is_empty());
        // one ASF and one AMC go together, whatever their names
        let (takes, _) = group_files(&["skel.asf", "walk.amc"]);
        assert_eq!(takes, [TakeFiles { motion: 1, skeleton: Some(0) }]);
    }

    #[test]
    fn the_library_csv_holds_every_take_s_segments_in_one_label_csv() {
        let names = ClusterNames::default();
        let a = names.label(&seg("a.bvh", 100, &[(0, 49, Some(0)), (50, 99, Some(1))]));
        let b = names.label(&seg("b.bvh", 60, &[(0, 59, Some(1))]));
        let csv = library_csv([&a, &b]);
        assert_eq!(csv, "file,start_frame,end_frame,label\na.bvh,0,49,C0\na.bvh,50,99,C1\nb.bvh,0,59,C1\n");
        let rows = crate::labels::read_csv(&csv, "library.csv").unwrap();
        assert_eq!(rows.len(), 3);
        assert_eq!(rows[2].file, "b.bvh");
    }

    #[test]
    fn renaming_a_cluster_once_labels_its_segments_in_every_take() {
        let mut names = ClusterNames::default();
        names.rename(1, "walk cycle", Vec::new());
        let takes = [seg("a.bvh", 100, &[(0, 49, Some(0)), (50, 99, Some(1))]), seg("b.bvh", 60, &[(0, 59, Some(1))])];
        let labelled: Vec<Segmentation> = takes.iter().map(|t| names.label(t)).collect();
        assert_eq!(labelled[0].segments[1].label, "walk cycle");
        assert_eq!(labelled[1].segments[0].label, "walk cycle");
        assert_eq!(labelled[0].segments[0].label, "C0");
        assert!(library_csv(&labelled).contains("b.bvh,0,59,walk cycle"));
    }

    #[test]
    fn clip_folders_are_safe_names_and_clip_files_unique() {
        assert_eq!(folder_name("walk cycle/2"), "walk_cycle_2");
        assert_eq!(folder_name(" ?? "), "cluster");
        let mut names = vec![
            "a/t_01_x.bvh".to_string(),
            "a/t_01_x.bvh".into(),
            "a/t_01_x.bvh".into(),
            "b/README".into(),
            "b/README".into(),
        ];
        make_unique(&mut names);
        assert_eq!(names, ["a/t_01_x.bvh", "a/t_01_x-2.bvh", "a/t_01_x-3.bvh", "b/README", "b/README-2"]);
    }

    /// Two takes' shared clusters: C0 in both, C1 in the second only.
    fn shared() -> Shared {
        use crate::library::{Occurrence, SharedCluster, SharedClusters};
        let a = seg("a.bvh", 100, &[(0, 49, Some(0)), (50, 99, None)]);
        let b = seg("b.bvh", 90, &[(0, 29, Some(1)), (30, 59, Some(0)), (60, 89, Some(0))]);
        let occ = |take, segment, start, end| Occurrence { take, segment, start, end };
        Shared {
            clusters: SharedClusters {
                takes: vec![a, b],
                clusters: vec![
                    SharedCluster {
                        id: 0,
                        occurrences: vec![occ(0, 0, 0, 49), occ(1, 1, 30, 59), occ(1, 2, 60, 89)],
                        seconds: 11.0 / 3.0,
                        takes: 2,
                    },
                    SharedCluster { id: 1, occurrences: vec![occ(1, 0, 0, 29)], seconds: 1.0, takes: 1 },
                ],
                cross_links: 2,
            },
            // the library's takes 3 and 5 were matched (4 failed)
            takes: vec![3, 5],
        }
    }

    #[test]
    fn shared_clusters_map_to_library_takes_for_rows_playlists_lists_and_clips() {
        let s = shared();
        assert_eq!(s.segmentation(5).unwrap().file, "b.bvh");
        assert!(s.segmentation(4).is_none());
        let mut p = s.playlist(0).unwrap();
        assert_eq!(p.current(), Spot { take: 3, start: 0, end: 49 });
        assert_eq!(p.next(), Spot { take: 5, start: 30, end: 59 });
        assert_eq!(p.takes(), [3, 5]);
        assert!(s.playlist(7).is_none());
        assert_eq!(
            s.listed(true).iter().map(|c| c.id).collect::<Vec<_>>(),
            [0, 1],
            "every cluster, most covered first"
        );
        assert_eq!(s.listed(false).iter().map(|c| c.id).collect::<Vec<_>>(), [0], "C1 is in one take only");
        // 100 + 90 frames at 30 fps: 6.33 s; C0 covers 11/3 s of it
        assert!((s.coverage(&s.clusters.clusters[0]) - (11.0 / 3.0) / (190.0 / 30.0)).abs() < 1e-9);
        // named from the labels the takes carry: C0's frames are mostly "hop"
        let names = s.label_names(|t| match t {
            3 => Some(vec![(0, 49, "hop".to_string()), (50, 99, "walk".into())]),
            5 => Some(vec![(0, 45, "walk".into()), (46, 89, "hop".into())]),
            _ => None,
        });
        assert_eq!(names.get(&0).map(String::as_str), Some("hop · C0"));
        assert_eq!(names.get(&1).map(String::as_str), Some("walk · C1"));
        assert!(s.label_names(|_| None).is_empty(), "no labels, no names");
        assert_eq!(s.summary(), "2 clusters across 2 takes: 1 found in more than one take");
        let mut names = ClusterNames::default();
        names.rename(0, "walk", Vec::new());
        let clips = s.clips(&names, Some(0));
        assert_eq!(
            clips.iter().map(|(t, c)| (*t, c.file.as_str(), c.segments.len())).collect::<Vec<_>>(),
            [(3, "a.bvh", 1), (5, "b.bvh", 2)]
        );
        assert!(clips.iter().flat_map(|(_, c)| &c.segments).all(|x| x.label == "walk"));
        let every = s.clips(&names, None);
        assert_eq!(every[1].1.segments.iter().map(|x| x.label.as_str()).collect::<Vec<_>>(), ["C1", "walk", "walk"]);
        // the CSV of the library: the shared segmentations, named
        let csv = library_csv(s.clusters.takes.iter().map(|t| names.label(t)).collect::<Vec<_>>().iter());
        assert!(csv.contains("b.bvh,30,59,walk") && csv.contains("b.bvh,0,29,C1"), "{csv}");
        // the clusters' occurrences by take name, for the names to follow
        let spots = s.named_spots(|i| format!("take{i}.bvh"));
        assert_eq!(spots[1], (1, vec![NamedSpot { take: "take5.bvh".into(), start: 0, end: 29 }]));
        assert_eq!(spots[0].1.len(), 3);
    }

    #[test]
    fn a_cluster_s_playlist_goes_through_its_occurrences_across_takes_and_wraps() {
        assert!(Playlist::new(3, Vec::new()).is_none());
        let spots = vec![
            Spot { take: 2, start: 10, end: 20 },
            Spot { take: 0, start: 50, end: 60 },
            Spot { take: 0, start: 5, end: 9 },
            Spot { take: 0, start: 5, end: 9 },
        ];
        let mut p = Playlist::new(3, spots).unwrap();
        assert_eq!(p.position(), (1, 3));
        assert_eq!(p.current(), Spot { take: 0, start: 5, end: 9 });
        assert_eq!(p.takes(), [0, 2]);
        assert_eq!(p.next(), Spot { take: 0, start: 50, end: 60 });
        assert_eq!(p.next(), Spot { take: 2, start: 10, end: 20 });
        assert_eq!(playing_text(&p, "jump", "c.bvh"), "jump: occurrence 3 of 3 — c.bvh, frames 10–20");
        assert_eq!(p.next(), Spot { take: 0, start: 5, end: 9 }, "after the last, the first");
        assert_eq!(p.previous(), Spot { take: 2, start: 10, end: 20 }, "before the first, the last");
        assert_eq!(p.spots().len(), 3);
    }
}
