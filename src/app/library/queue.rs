//! The library's queue, as plain data, tested natively: the takes the workers segment one after another,
//! as many at a time as the page has workers ([`Queue`]: queued → running → done / failed, cancel drops the
//! rest, "Run again" queues the cancelled and failed again), and where each stands ([`TakeStatus`], [`Entry`]).

use crate::segment::Segmentation;

/// Where a take of the library stands.
#[derive(Debug, Clone, PartialEq)]
pub enum TakeStatus {
    /// Waiting for its turn in the worker.
    Queued,
    /// The worker is at `stage`, `fraction` (0..1) done.
    Running { stage: String, fraction: f64 },
    /// Segmented: how many segments and (per-take) clusters it has.
    Done { segments: usize, clusters: usize },
    /// The worker refused it (the message says why, naming the file).
    Failed(String),
    /// The user cancelled the queue before (or while) it ran.
    Cancelled,
}

impl TakeStatus {
    /// The word `data-status` carries.
    pub fn word(&self) -> &'static str {
        match self {
            TakeStatus::Queued => "queued",
            TakeStatus::Running { .. } => "running",
            TakeStatus::Done { .. } => "done",
            TakeStatus::Failed(_) => "failed",
            TakeStatus::Cancelled => "cancelled",
        }
    }

    /// What the list shows.
    pub fn text(&self) -> String {
        match self {
            TakeStatus::Queued => "queued".into(),
            TakeStatus::Running { stage, fraction } => format!("{stage} {:.0} %", fraction * 100.0),
            TakeStatus::Done { segments, clusters } => format!(
                "{} · {}",
                crate::method::counted(*segments, "segment"),
                crate::method::counted(*clusters, "cluster")
            ),
            TakeStatus::Failed(message) => format!("failed: {message}"),
            TakeStatus::Cancelled => "cancelled".into(),
        }
    }
}

/// A take of the library as the list shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub name: String,
    pub status: TakeStatus,
    /// Seconds, once the worker read it.
    pub duration_s: Option<f64>,
    /// Its frames, once the worker read it.
    pub frames: Option<usize>,
    /// Its segmentation (kept for the rows, the CSV and the clusters; never its frames).
    pub segmentation: Option<Segmentation>,
}

/// The library's takes and the workers' queue over them: up to as many takes at a time as the
/// page has workers, started in the order they were added.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Queue {
    pub entries: Vec<Entry>,
}

impl Queue {
    /// Adds takes named `names`, queued; returns their indices.
    pub fn add(&mut self, names: impl IntoIterator<Item = String>) -> std::ops::Range<usize> {
        let from = self.entries.len();
        self.entries.extend(names.into_iter().map(|name| Entry {
            name,
            status: TakeStatus::Queued,
            duration_s: None,
            frames: None,
            segmentation: None,
        }));
        from..self.entries.len()
    }

    /// The takes running now.
    pub fn running(&self) -> usize {
        self.entries.iter().filter(|e| matches!(e.status, TakeStatus::Running { .. })).count()
    }

    /// The take to send to a worker next: none while `at_once` run, else the first queued. It is
    /// marked running.
    pub fn start_next(&mut self, at_once: usize) -> Option<usize> {
        if self.running() >= at_once {
            return None;
        }
        let next = self.entries.iter().position(|e| e.status == TakeStatus::Queued)?;
        self.entries[next].status = TakeStatus::Running { stage: "starting".into(), fraction: 0.0 };
        Some(next)
    }

    /// The running take `i` is at `stage`, `fraction` done (ignored for a take not running).
    pub fn progress(&mut self, i: usize, stage: &str, fraction: f64) {
        if let Some(e) = self.entries.get_mut(i).filter(|e| matches!(e.status, TakeStatus::Running { .. })) {
            e.status = TakeStatus::Running { stage: stage.to_string(), fraction: fraction.clamp(0.0, 1.0) };
        }
    }

    /// Take `i` is segmented: `frames` frames over `duration_s` seconds.
    pub fn done(&mut self, i: usize, frames: usize, duration_s: f64, segmentation: Segmentation) {
        let Some(e) = self.entries.get_mut(i) else { return };
        let mut clusters: Vec<usize> = segmentation.segments.iter().filter_map(|s| s.cluster).collect();
        clusters.sort_unstable();
        clusters.dedup();
        e.status = TakeStatus::Done { segments: segmentation.segments.len(), clusters: clusters.len() };
        e.frames = Some(frames);
        e.duration_s = Some(duration_s);
        e.segmentation = Some(segmentation);
    }

    /// Take `i` failed with `message`.
    pub fn failed(&mut self, i: usize, message: String) {
        if let Some(e) = self.entries.get_mut(i) {
            e.status = TakeStatus::Failed(message);
        }
    }

    /// Cancels the queue: the running take and every queued one are marked cancelled. Returns
    /// whether a take was running (the page then replaces the worker, which cannot be interrupted).
    pub fn cancel(&mut self) -> bool {
        let running = self.running() > 0;
        for e in &mut self.entries {
            if matches!(e.status, TakeStatus::Queued | TakeStatus::Running { .. }) {
                e.status = TakeStatus::Cancelled;
            }
        }
        running
    }

    /// Queues the cancelled and failed takes again (the list's "Run again").
    pub fn requeue(&mut self) {
        for e in &mut self.entries {
            if matches!(e.status, TakeStatus::Cancelled | TakeStatus::Failed(_)) {
                e.status = TakeStatus::Queued;
            }
        }
    }

    /// Whether the queue has work left (a take queued or running).
    pub fn busy(&self) -> bool {
        self.entries.iter().any(|e| matches!(e.status, TakeStatus::Queued | TakeStatus::Running { .. }))
    }

    /// The takes segmented, with their segmentations, in the list's order.
    pub fn segmented(&self) -> Vec<(usize, &Segmentation)> {
        self.entries.iter().enumerate().filter_map(|(i, e)| e.segmentation.as_ref().map(|s| (i, s))).collect()
    }

    /// One line for the whole list: how many takes are done, running, queued, failed.
    pub fn summary(&self) -> String {
        let count = |word: &str| self.entries.iter().filter(|e| e.status.word() == word).count();
        let mut parts =
            vec![format!("{} of {} done", count("done"), crate::method::counted(self.entries.len(), "take"))];
        for word in ["running", "queued", "failed", "cancelled"] {
            let n = count(word);
            if n > 0 {
                parts.push(format!("{n} {word}"));
            }
        }
        parts.join(" · ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::library::takes::tests::seg;

    #[test]
    fn the_queue_runs_its_takes_in_order_as_many_at_once_as_asked_and_cancel_drops_the_rest() {
        let mut q = Queue::default();
        assert_eq!(q.add(["a.bvh".to_string(), "b.bvh".into(), "c.bvh".into()]), 0..3);
        assert_eq!(q.start_next(1), Some(0));
        assert_eq!(q.start_next(1), None, "one take at a time when one worker runs them");
        q.progress(0, "segmenting", 0.5);
        assert_eq!(q.entries[0].status.text(), "segmenting 50 %");
        q.progress(1, "segmenting", 0.5);
        assert_eq!(q.entries[1].status, TakeStatus::Queued, "progress of a take not running is ignored");
        q.done(0, 120, 4.0, seg("a.bvh", 120, &[(0, 39, Some(0)), (40, 79, Some(1)), (80, 119, Some(0))]));
        assert_eq!(q.entries[0].status, TakeStatus::Done { segments: 3, clusters: 2 });
        assert_eq!(q.entries[0].status.text(), "3 segments · 2 clusters");
        assert_eq!((q.entries[0].frames, q.entries[0].duration_s), (Some(120), Some(4.0)));
        assert_eq!(q.start_next(1), Some(1));
        q.failed(1, "b.bvh line 3: not a BVH".into());
        assert_eq!(q.entries[1].status.text(), "failed: b.bvh line 3: not a BVH");
        assert_eq!(q.start_next(1), Some(2));
        q.add(["d.bvh".to_string()]);
        assert_eq!(q.summary(), "1 of 4 takes done · 1 running · 1 queued · 1 failed");
        assert!(q.busy());
        assert!(q.cancel(), "a take was running");
        let words: Vec<&str> = q.entries.iter().map(|e| e.status.word()).collect();
        assert_eq!(words, ["done", "failed", "cancelled", "cancelled"]);
        assert!(!q.busy());
        assert_eq!(q.start_next(1), None);
        assert!(!q.cancel(), "nothing runs any more");
        q.requeue();
        let words: Vec<&str> = q.entries.iter().map(|e| e.status.word()).collect();
        assert_eq!(words, ["done", "queued", "queued", "queued"]);
        assert_eq!(q.start_next(1), Some(1));
        assert_eq!(q.segmented().len(), 1);
        // two workers: two takes at once, in order; the third when one of them is done
        assert_eq!(q.start_next(2), Some(2));
        assert_eq!(q.start_next(2), None, "two running");
        assert_eq!(q.running(), 2);
        q.done(2, 10, 1.0, seg("c.bvh", 10, &[(0, 9, Some(0))]));
        assert_eq!(q.start_next(2), Some(3));
        assert_eq!(q.summary(), "2 of 4 takes done · 2 running");
    }
}
