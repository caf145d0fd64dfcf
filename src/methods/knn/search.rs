//! The nearest training windows of a query by an exact scan, faster than the kd-tree in the
//! k-NN's 32 principal coordinates (a tree over a few thousand points that many dimensions deep
//! prunes little and pays for its traversal).
//!
//! The training points are kept sorted by their first principal coordinate, in blocks of
//! [`LANES`] points stored coordinate by coordinate, so that one block's squared distances are
//! summed lane by lane — each lane in the same order, from the same `0.0`, with the same
//! `(p − q)²` terms as kiddo's `SquaredEuclidean`, hence bit for bit the distances the tree
//! compares — four lanes to a vector ([`super::lanes`]: SSE natively, simd128 on wasm).
//! A search keeps the best `count` found so far, starting from `seeds` (the previous frame's
//! neighbours and the windows after them: consecutive frames have nearby windows), and skips:
//! * the blocks whose first coordinate alone is at least as far as the `count`-th best (blocks
//!   in order of first coordinate outward from the query's: once one is that far, so are all
//!   beyond it), and
//! * a block as soon as every lane's partial sum (every [`STEP`] coordinates) reaches the
//!   `count`-th best: the remaining terms are not negative, so the sums cannot come back under.
//!
//! The sums being those of the full scan, the skipped points are exactly the ones that could not
//! enter the result.

use super::lanes::F4;
use super::DIMS;

/// Points per block: two vectors of four lanes ([`super::lanes`]).
pub const LANES: usize = 8;

/// Coordinates summed between two checks of a block against the bound.
const STEP: usize = 8;

/// A training point found: its squared distance to the query and its index.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Found {
    pub distance: f32,
    pub item: u32,
}

/// The training points laid out for [`Scan::nearest`].
#[derive(Debug, Clone)]
pub struct Scan {
    /// Block `b`, coordinate `k`: the [`LANES`] points' values at `blocks[b * DIMS + k]`.
    blocks: Vec<[f32; LANES]>,
    /// The training index of each slot (block-major, lane-minor); [`u32::MAX`] for padding.
    items: Vec<u32>,
    /// Per block: the smallest and the largest first coordinate of its points.
    lowest: Vec<f32>,
    highest: Vec<f32>,
}

/// The squared distance of `a` to `b`, summed as kiddo's `SquaredEuclidean` sums it.
pub fn distance(a: &[f32; DIMS], b: &[f32; DIMS]) -> f32 {
    a.iter().zip(b).map(|(&x, &y)| (x - y) * (x - y)).fold(0.0, |s, t| s + t)
}

impl Scan {
    /// The layout of `points` (finite values).
    pub fn new(points: &[[f32; DIMS]]) -> Scan {
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        order.sort_by(|&a, &b| points[a as usize][0].total_cmp(&points[b as usize][0]).then(a.cmp(&b)));
        let blocks_n = points.len().div_ceil(LANES);
        let mut blocks = vec![[f32::INFINITY; LANES]; blocks_n * DIMS];
        let mut items = vec![u32::MAX; blocks_n * LANES];
        let (mut lowest, mut highest) = (vec![f32::INFINITY; blocks_n], vec![f32::NEG_INFINITY; blocks_n]);
        for (slot, &i) in order.iter().enumerate() {
            let (b, l) = (slot / LANES, slot % LANES);
            let p = &points[i as usize];
            for k in 0..DIMS {
                blocks[b * DIMS + k][l] = p[k];
            }
            items[slot] = i;
            lowest[b] = lowest[b].min(p[0]);
            highest[b] = highest[b].max(p[0]);
        }
        Scan { blocks, items, lowest, highest }
    }

    /// The `count` points of `points` (the ones the scan was made of) nearest to `q` among those
    /// `accept` takes, nearest first (equal distances in no particular order), into `out`.
    /// `seeds` are tried first (any indices below the number of points; repeats are ignored).
    pub fn nearest(
        &self,
        points: &[[f32; DIMS]],
        q: &[f32; DIMS],
        count: usize,
        seeds: &[u32],
        accept: impl Fn(u32) -> bool,
        out: &mut Vec<Found>,
    ) {
        out.clear();
        if count == 0 {
            return;
        }
        let mut best = Best { count, out };
        for &s in seeds {
            if (s as usize) < points.len() && accept(s) && !best.holds(s) {
                best.offer(Found { distance: distance(&points[s as usize], q), item: s });
            }
        }
        let blocks_n = self.lowest.len();
        // the first block whose points' first coordinates are not all below the query's
        let start = self.highest.partition_point(|&h| h < q[0]).min(blocks_n.saturating_sub(1));
        let (mut up, mut down) = (start, start as isize - 1);
        loop {
            // the nearer of the next block up and the next block down, by first coordinate alone
            let up_bound = (up < blocks_n).then(|| {
                let gap = (self.lowest[up] - q[0]).max(0.0);
                gap * gap
            });
            let down_bound = (down >= 0).then(|| {
                let gap = (q[0] - self.highest[down as usize]).max(0.0);
                gap * gap
            });
            let b = match (up_bound, down_bound) {
                (Some(u), Some(d)) if u <= d => {
                    if u >= best.bound() {
                        break;
                    }
                    up += 1;
                    up - 1
                }
                (_, Some(d)) => {
                    if d >= best.bound() {
                        break;
                    }
                    down -= 1;
                    (down + 1) as usize
                }
                (Some(u), None) => {
                    if u >= best.bound() {
                        break;
                    }
                    up += 1;
                    up - 1
                }
                (None, None) => break,
            };
            self.block(b, q, &mut best, &accept);
        }
    }

    /// Offers the points of block `b` that can enter `best`.
    #[inline]
    fn block(&self, b: usize, q: &[f32; DIMS], best: &mut Best, accept: &impl Fn(u32) -> bool) {
        let columns = &self.blocks[b * DIMS..(b + 1) * DIMS];
        let (mut low, mut high) = (F4::splat(0.0), F4::splat(0.0));
        let bound = F4::splat(best.bound());
        for (step, chunk) in columns.chunks_exact(STEP).enumerate() {
            for (column, &qk) in chunk.iter().zip(&q[step * STEP..]) {
                let qk = F4::splat(qk);
                let (a, z) = column.split_at(4);
                let d = F4::load(a.try_into().expect("four lanes")).sub(qk);
                low = low.add(d.mul(d));
                let d = F4::load(z.try_into().expect("four lanes")).sub(qk);
                high = high.add(d.mul(d));
            }
            if low.all_ge(bound) && high.all_ge(bound) {
                return;
            }
        }
        let mut acc = [0f32; LANES];
        let (a, z) = acc.split_at_mut(4);
        low.store(a.try_into().expect("four lanes"));
        high.store(z.try_into().expect("four lanes"));
        for (l, &a) in acc.iter().enumerate() {
            let item = self.items[b * LANES + l];
            if a < best.bound() && item != u32::MAX && accept(item) && !best.holds(item) {
                best.offer(Found { distance: a, item });
            }
        }
    }
}

/// The best `count` found so far, nearest first.
struct Best<'a> {
    count: usize,
    out: &'a mut Vec<Found>,
}

impl Best<'_> {
    /// What a point must be nearer than to enter (infinite until `count` are found).
    fn bound(&self) -> f32 {
        if self.out.len() < self.count {
            f32::INFINITY
        } else {
            self.out.last().map_or(f32::INFINITY, |f| f.distance)
        }
    }

    fn holds(&self, item: u32) -> bool {
        self.out.iter().any(|f| f.item == item)
    }

    fn offer(&mut self, f: Found) {
        if self.out.len() == self.count {
            if !(f.distance < self.bound()) {
                return;
            }
            self.out.pop();
        }
        let at = self.out.partition_point(|g| g.distance <= f.distance);
        self.out.insert(at, f);
    }
}
