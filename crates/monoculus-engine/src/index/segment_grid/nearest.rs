//! Robots in order of distance from an observer, expanding ring by ring.

use monoculus_core::geometry::Point;

use super::super::Locate;
use super::bands::{Bands, Part};
use super::{MOST_LEVELS, SegmentGrid, Stale};

impl SegmentGrid {
    /// Robots other than `i`, nearest to it first (ties in any order): rings of bins
    /// around its bin in each part, each robot given out once no unvisited bin can
    /// hold a nearer one. O(k log k) for the first k. The `stale` robots are skipped in
    /// the bins and queued at once from their current positions; every other robot is
    /// within `drift` of the point the grid was built over.
    pub fn nearest_first<'a, P: Point, L: Locate<P> + ?Sized>(
        &'a self,
        positions: &'a L,
        i: usize,
        stale: &'a Stale,
        drift: f64,
    ) -> impl Iterator<Item = usize> + 'a {
        let p = positions.at(i);
        let g = &self.rows;
        let heap = stale
            .iter()
            .filter(|&k| k != i)
            .map(|k| std::cmp::Reverse(((positions.at(k) - p).length().to_bits(), k)))
            .collect();
        // One per part, in place (no allocation: asked once per Look that counts
        // beyond its neighbours).
        let mut rings = [Rings::default(); MOST_LEVELS];
        for (rings, part) in rings.iter_mut().zip(&g.parts) {
            rings.bin = (part.bin(p.axis(0)), part.band(p.axis(1)));
        }
        Nearest {
            grid: g,
            positions,
            i,
            p,
            rings,
            heap,
            stale,
            drift,
        }
    }
}

/// The iterator of [`SegmentGrid::nearest_first`].
pub(super) struct Nearest<'a, P: Point, L: ?Sized> {
    pub(super) grid: &'a Bands,
    pub(super) positions: &'a L,
    pub(super) i: usize,
    pub(super) p: P,
    /// Per part (the first as many as the grid has), how far its rings have gone.
    pub(super) rings: [Rings; MOST_LEVELS],
    /// Visited robots not yet given out: (distance bits, robot), nearest on top.
    pub(super) heap: std::collections::BinaryHeap<std::cmp::Reverse<(u64, usize)>>,
    /// Robots whose bins are out of date (queued from the start).
    pub(super) stale: &'a Stale,
    /// How far the others may be from their bins' points.
    pub(super) drift: f64,
}

/// The rings of bins visited in one part.
#[derive(Clone, Copy, Default)]
pub(super) struct Rings {
    /// The observer's bin and band (clamped to the part).
    pub(super) bin: (usize, usize),
    /// The last ring visited (`None` before the first).
    pub(super) ring: Option<usize>,
    /// Every robot of the part nearer than this has been visited.
    pub(super) reach: f64,
    /// Whether every bin of the part has been visited.
    pub(super) exhausted: bool,
}

impl<P: Point, L: Locate<P> + ?Sized> Nearest<'_, P, L> {
    /// Visits the next ring of bins of part `x`.
    pub(super) fn expand(&mut self, x: usize) {
        let g = self.grid;
        let part: &Part = &g.parts[x];
        let rings = &mut self.rings[x];
        let (c, r) = rings.bin;
        let k = rings.ring.map_or(0, |k| k + 1);
        let (c0, c1) = (c.saturating_sub(k), (c + k).min(part.bins - 1));
        let (r0, r1) = (r.saturating_sub(k), (r + k).min(part.bands - 1));
        rings.ring = Some(k);
        let (i, p, positions, stale) = (self.i, self.p, self.positions, self.stale);
        let push = |range: std::ops::Range<usize>, heap: &mut std::collections::BinaryHeap<_>| {
            for s in range {
                let j = g.items[s] as usize;
                if j != i && !stale.contains(j) {
                    let d = (positions.at(j) - p).length();
                    heap.push(std::cmp::Reverse((d.to_bits(), j)));
                }
            }
        };
        for band in r0..=r1 {
            if k == 0 || band == r.wrapping_sub(k) || band == r + k {
                push(g.bins_range(part, band, c0, c1), &mut self.heap);
            } else {
                if c >= k {
                    push(g.bins_range(part, band, c - k, c - k), &mut self.heap);
                }
                if c + k < part.bins {
                    push(g.bins_range(part, band, c + k, c + k), &mut self.heap);
                }
            }
        }
        // Distance from the observer to the nearest unvisited bin (infinite past the
        // part's edge), less room for rounding. An observer outside a nested part's
        // box is nearer its edge bins than any other: the bounds hold as well.
        let (x, y) = (self.p.axis(0), self.p.axis(1));
        let (lo_x, lo_y) = part.corner(c.saturating_sub(k), r.saturating_sub(k));
        let (hi_x, hi_y) = part.corner(c + k + 1, r + k + 1);
        let gap = |inside: bool, d: f64| if inside { d } else { f64::INFINITY };
        let reach = gap(c > k, x - lo_x)
            .min(gap(c + k + 1 < part.bins, hi_x - x))
            .min(gap(r > k, y - lo_y))
            .min(gap(r + k + 1 < part.bands, hi_y - y));
        rings.exhausted = reach == f64::INFINITY;
        rings.reach = reach * (1.0 - 1e-9) - 1e-9 * (x.abs() + y.abs()) - self.drift;
    }
}

impl<P: Point, L: Locate<P> + ?Sized> Iterator for Nearest<'_, P, L> {
    type Item = usize;

    fn next(&mut self) -> Option<usize> {
        loop {
            // The part whose unvisited bins may hold the nearest robots.
            let mut next: Option<(usize, f64)> = None;
            let parts = self.grid.parts.len();
            for (x, rings) in self.rings[..parts].iter().enumerate() {
                if !rings.exhausted && next.is_none_or(|(_, reach)| rings.reach < reach) {
                    next = Some((x, rings.reach));
                }
            }
            let Some((x, reach)) = next else {
                return self.heap.pop().map(|std::cmp::Reverse((_, j))| j);
            };
            if let Some(&std::cmp::Reverse((d, j))) = self.heap.peek()
                && f64::from_bits(d) < reach
            {
                self.heap.pop();
                return Some(j);
            }
            self.expand(x);
        }
    }
}
