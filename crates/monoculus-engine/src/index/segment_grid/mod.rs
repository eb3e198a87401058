//! [`SegmentGrid`]: robots bucketed for line-of-sight queries in the plane.
//!
//! A line of sight across the swarm is long and thin: an R-tree's overlapping boxes make
//! such a query visit many nodes, and a plain grid costs one random access per bin. So
//! the robots are stored twice, in horizontal and in vertical bands, each band cut into
//! bins stored one after the other: a line is walked in the bands along its major axis,
//! and the bins it crosses in one band are one contiguous slice, read in one pass. The
//! measurements behind each choice are in docs/performance.md.
//!
//! Candidates pass a cheap perpendicular-distance filter before the exact predicate.
//! They are a superset of the blockers, and the decision is the shared
//! [`blocks`](monoculus_core::vision::blocks), so answers are those of the brute-force
//! oracle (tested, also with blockers placed at the edge of the
//! blocking cone across band edges).
//!
//! The grid in files: `bands` (the layout), the line-of-sight walk (`walk`), the
//! bins it reads in each band (`crossing`) and its single-precision filter
//! (`filter`), radius queries (`near`), the nearest-first iterator (`nearest`), robots
//! beyond a radius (`beyond`), the set of robots that moved since the grid was built
//! (`stale`), and the prefetch hint.

mod bands;
mod beyond;
mod crossing;
mod filter;
mod near;
mod nearest;
mod prefetch;
mod slots;
mod stale;
#[cfg(test)]
mod tests;
mod walk;

use monoculus_core::geometry::Point;

use super::SpatialOrder;

use bands::{BAND, BIN, Bands, Level, bins_of_both};
pub(crate) use prefetch::prefetch;
use rayon::prelude::*;
pub use stale::Stale;

/// The fewest robots whose bins one thread finds while another finds those of more
/// (in a smaller swarm, one pass on one thread takes less than handing half to another
/// thread could save: ASYNC makes a grid at every tick with Looks).
const BINS_STRETCH: usize = 1 << 14;
/// At most about this many bins per robot in each layout of a grid...
const MOST_BINS: f64 = 16.0;
/// A moving grid made again may size its bins as the one before did, at most this many
/// times in a row (see [`SegmentGrid::moving_again`]).
const KEEP_SIZING: u32 = 16;
/// ...and of a [moving](SegmentGrid::moving) one.
pub const MOST_MOVING_BINS: f64 = 4.0;

/// Robots bucketed for line-of-sight walks and radius queries over the first two
/// coordinates, about one robot per bin.
pub struct SegmentGrid {
    /// Horizontal bands (running along x): lines of sight with |dx| >= |dy|, radius
    /// queries.
    rows: Bands,
    /// Vertical bands (running along y): lines of sight with |dy| > |dx|.
    columns: Bands,
    /// The lower corner of the swarm, origin of the stored coordinates.
    lo: [f64; 2],
    /// The upper corner of the swarm.
    hi: [f64; 2],
    /// The largest rounding error of a stored coordinate.
    rounding: f64,
    /// Whether the stored coordinates are finite (else every robot is a candidate).
    single: bool,
    /// Whether its crowded core, if any, has nested parts.
    nested: bool,
    /// How many grids in a row, up to this one, were sized as the one before them (0:
    /// this one was sized afresh).
    kept: u32,
}

impl SegmentGrid {
    /// A grid over the first two coordinates of `points`.
    pub fn new<P: Point + Sync>(points: &[P]) -> Self {
        Self::build(None, points, false, MOST_BINS, true, false)
    }

    /// The same, its two layouts built at once on two threads of the current rayon
    /// pool. Not from inside a parallel section whose tasks may ask for this grid:
    /// a thread waiting on the second layout may run such a task meanwhile.
    pub fn new_parallel<P: Point + Sync>(points: &[P]) -> Self {
        Self::build(None, points, true, MOST_BINS, true, false)
    }

    /// A grid with at most about `most` times as many bins per layout as robots, its
    /// crowded core in nested parts if `nested`; in the arrays of `spare` if given, and
    /// with its parts if `keep` and [they serve](SegmentGrid::kept_levels).
    fn build<P: Point + Sync>(
        spare: Option<SegmentGrid>,
        points: &[P],
        parallel: bool,
        most: f64,
        nested: bool,
        keep: bool,
    ) -> Self {
        let kept = spare
            .as_ref()
            .filter(|_| keep)
            .and_then(|g| g.kept_levels(points, nested));
        let (levels, kept) = kept.unwrap_or_else(|| {
            let (first, sample, quartile) = first_level(points, most, parallel);
            let levels = if nested {
                sample.levels(first, quartile)
            } else {
                vec![first]
            };
            (levels, 0)
        });
        let mut grid = Self::with_levels(spare, points, &levels, parallel);
        (grid.nested, grid.kept) = (nested, kept);
        grid
    }

    /// The levels of this grid's parts, for a grid of the same kind (`nested`) made
    /// again over `points`, with the number of grids in a row then sized alike; `None`
    /// where the grid is to be sized afresh: after [`KEEP_SIZING`] grids in a row sized
    /// alike, for another number of robots or kind, or where a point lies outside the
    /// first part's box (its bins are then those of a grid over points that moved
    /// within its box, which every query answers as one sized afresh: tested).
    fn kept_levels<P: Point>(&self, points: &[P], nested: bool) -> Option<(Vec<Level>, u32)> {
        if self.kept + 1 >= KEEP_SIZING || nested != self.nested || points.len() != self.len() {
            return None;
        }
        let within = points.iter().all(|p| self.covers(p.axis(0), p.axis(1)));
        within.then(|| (self.levels(), self.kept + 1))
    }

    /// The levels of the grid's parts, outermost first.
    fn levels(&self) -> Vec<Level> {
        (self.rows.parts.iter())
            .map(|p| Level {
                lo: p.origin,
                hi: p.top,
                spacing: p.spacing,
            })
            .collect()
    }

    /// The same as [`SegmentGrid::new_parallel`], for robots that then move: each may be
    /// given a disc it stays in ([`SegmentGrid::set_disc`]); until then its point. At
    /// most [`MOST_MOVING_BINS`] bins per robot: such a grid is made often, so that
    /// its bins cost time, and under ASYNC it shares the memory with the robots' clocks.
    /// With `nested`, a crowded core gets finer nested parts, as in [`SegmentGrid::new`];
    /// without, the bins are of one size, that of the grid's first part: the drift
    /// walks must be given widens them by as many of its bins (in a nested part, by
    /// many more of the finer ones).
    pub fn moving<P: Point + Sync>(points: &[P], nested: bool) -> Self {
        Self::build(None, points, true, MOST_MOVING_BINS, nested, false)
    }

    /// The same as [`SegmentGrid::moving`], made in the arrays of `self` (emptied and
    /// filled again, none allocated): the grid of ASYNC's Looks is made again every
    /// few ticks, and arrays freed and allocated each time were handed their pages
    /// afresh by the system (measured in docs/performance.md). The grid is that of
    /// [`SegmentGrid::moving`] (tested), unless `keep`: then its bins are sized as
    /// those of `self` wherever every point lies in its box, up to [`KEEP_SIZING`]
    /// grids in a row. The swarm hardly changes from one tick to the next, and sizing
    /// the bins (ranking a sample of the robots on both axes) was a few percent of an
    /// ASYNC run made of grids for one tick (measured in docs/performance.md).
    pub fn moving_again<P: Point + Sync>(self, points: &[P], nested: bool, keep: bool) -> Self {
        Self::build(Some(self), points, true, MOST_MOVING_BINS, nested, keep)
    }

    /// Robot `k` (of a [moving](SegmentGrid::moving) grid) stays within `reach` of
    /// `centre`: the grid's line filter tests that disc in place of its point. The
    /// robot stays in its bin, so walks must be given as their drift how far from the
    /// point the grid was built over the disc may reach.
    pub fn set_disc(&mut self, k: usize, centre: [f64; 2], reach: f64) {
        // Rounded up, with room for the single-precision sum the filter takes (see
        // `Line::any_within`).
        let mut r = (reach * (1.0 + 1e-6)) as f32;
        if f64::from(r) < reach * (1.0 + 1e-7) {
            r = r.next_up();
        }
        let stored = [
            (centre[0] - self.lo[0]) as f32,
            (centre[1] - self.lo[1]) as f32,
        ];
        for g in [&mut self.rows, &mut self.columns] {
            // Made when first needed: until then every robot is at its point.
            if g.reach.is_empty() {
                g.reach.resize(g.coords.len(), 0.0);
            }
            let s = g.place[k] as usize;
            g.coords[s] = stored;
            g.reach[s] = r;
        }
    }

    /// A grid over `points` in the box `[lo, hi]` (theirs) with bins `spacing` wide.
    #[cfg(test)]
    fn with_spacing<P: Point + Sync>(
        points: &[P],
        spacing: f64,
        lo: [f64; 2],
        hi: [f64; 2],
        parallel: bool,
    ) -> Self {
        Self::with_levels(None, points, &[Level { lo, hi, spacing }], parallel)
    }

    /// A grid over `points` with a part per level, the first over their box; in the
    /// arrays of `spare` if given.
    fn with_levels<P: Point + Sync>(
        spare: Option<SegmentGrid>,
        points: &[P],
        levels: &[Level],
        parallel: bool,
    ) -> Self {
        let Level { lo, hi, .. } = levels[0];
        let longest = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let (rows, columns) = spare.map_or_else(Default::default, |g| (g.rows, g.columns));
        let n = points.len();
        let (mut rows, mut columns) = (
            Bands::empty(rows, n, 0, levels),
            Bands::empty(columns, n, 1, levels),
        );
        // Each robot's bins in both layouts, in one pass (in stretches on all threads
        // if `parallel`), then the two layouts filed, one a thread if `parallel`.
        let (row_parts, column_parts) = (&rows.parts[..], &columns.parts[..]);
        let bins = |(a, b): (&mut [u32], &mut [u32]), p: &[P]| {
            bins_of_both(a, b, p, row_parts, column_parts, levels);
        };
        if parallel && n >= 2 * BINS_STRETCH {
            let stretch = n
                .div_ceil(2 * rayon::current_num_threads())
                .max(BINS_STRETCH);
            (rows.place.par_chunks_mut(stretch))
                .zip(columns.place.par_chunks_mut(stretch))
                .zip(points.par_chunks(stretch))
                .for_each(|(slots, p)| bins(slots, p));
        } else {
            bins((&mut rows.place, &mut columns.place), points);
        }
        if parallel {
            rayon::join(|| rows.sort(points, lo), || columns.sort(points, lo));
        } else {
            rows.sort(points, lo);
            columns.sort(points, lo);
        }
        SegmentGrid {
            rows,
            columns,
            lo,
            hi,
            // A relative coordinate r is stored as r(1 + e) with |e| <= 2^-24; the
            // filter trusts single precision only while coordinates are finite there.
            rounding: longest * 2f64.powi(-24),
            single: longest < 1e30,
            nested: true,
            kept: 0,
        }
    }

    /// Whether `(x, y)` lies in the box of the robots the grid was built over: a robot
    /// that moved there may be handled as [`Stale`] (every geometric bound of the
    /// walks holds for points in the box).
    pub fn covers(&self, x: f64, y: f64) -> bool {
        (self.lo[0] <= x) & (x <= self.hi[0]) & (self.lo[1] <= y) & (y <= self.hi[1])
    }

    /// The number of robots in the grid.
    pub fn len(&self) -> usize {
        self.rows.place.len()
    }

    /// Whether the grid holds no robot.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The side of the grid's smallest bins (the mean spacing between robots where
    /// they are densest): those of its innermost part, each nested part's being finer
    /// than the one around it.
    pub fn bin_size(&self) -> f64 {
        self.rows.parts.last().expect("a first part").spacing
    }

    /// Every robot once, as the horizontal bands hold them (part by part, band by band,
    /// bin by bin), with each robot's rank there.
    pub fn order(&self) -> SpatialOrder<'_> {
        let n = self.len();
        SpatialOrder {
            robots: &self.rows.items[..n],
            rank: &self.rows.place,
        }
    }

    /// The number of parts of each layout (1 unless the swarm is crowded).
    pub fn parts(&self) -> usize {
        self.rows.parts.len()
    }
}

/// At most this many parts to a layout.
pub(super) const MOST_LEVELS: usize = 4;
/// A nested part is made for a box whose robots would be at least this many times as
/// dense as the bins of the part around it are made for...
const CROWDED: f64 = 16.0;
/// ...and that holds at least this many robots.
const FEWEST_NESTED: f64 = 64.0;
/// The boxes tried for a nested part, widest first: a box between ranks `len / cut`
/// and `len - 1 - len / cut` of each coordinate (the 5th and 95th percentiles, then
/// the 10th and 90th).
const CUTS: [usize; 2] = [20, 10];

/// The first level of a grid over `points` with at most about `most` times as many
/// bins per layout as robots (the swarm's box), the robots sampled for the next ones,
/// and the area per robot of the swarm of its box between the first and third
/// quartiles of each coordinate (the two on two threads if `parallel`).
fn first_level<P: Point>(points: &[P], most: f64, parallel: bool) -> (Level, Sample, f64) {
    let n = points.len().max(1) as f64;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for a in 0..2 {
            lo[a] = lo[a].min(p.axis(a));
            hi[a] = hi[a].max(p.axis(a));
        }
    }
    if points.is_empty() {
        (lo, hi) = ([0.0; 2], [0.0; 2]);
    }
    let ext = [hi[0] - lo[0], hi[1] - lo[1]];
    let longest = ext[0].max(ext[1]);
    let first = Level {
        lo,
        hi,
        spacing: 0.0,
    };
    let sample = Sample::of(points, &first);
    // The mean spacing in the swarm's core (its interquartile box holds about a
    // quarter of the robots): a converging swarm is dense in the middle with a few
    // robots far out, and lines of sight cross the core. But never more than about
    // `most` n bins per layout (straggling swarms: memory against walk length, see
    // docs/performance.md), nor 4n for thin ones.
    let quartile = sample.quartile_box_area(parallel) / n;
    let spacing = (4.0 * quartile)
        .sqrt()
        .max((ext[0] * ext[1] / (most * n * BAND * BIN)).sqrt())
        .max(longest / (2.0 * n.sqrt()))
        .max(longest * 1e-9)
        .max(1e-300);
    (Level { spacing, ..first }, sample, quartile)
}

/// Robots sampled from a swarm, for the sizes of a grid's bins: at most 4096 (evenly
/// strided, so a function of the positions), those within the swarm's box.
struct Sample {
    /// Their first two coordinates.
    points: Vec<[f64; 2]>,
    /// Robots of the swarm per sampled one.
    per: f64,
}

impl Sample {
    fn of<P: Point>(points: &[P], first: &Level) -> Self {
        let stride = points.len().div_ceil(4096).max(1);
        let sampled = points.len().div_ceil(stride);
        let mut sample = Vec::with_capacity(sampled);
        for p in points.iter().step_by(stride) {
            let (x, y) = (p.axis(0), p.axis(1));
            if first.holds_xy(x, y) {
                sample.push([x, y]);
            }
        }
        Sample {
            points: sample,
            per: points.len() as f64 / sampled.max(1) as f64,
        }
    }

    /// The area of the box between the first and third quartiles of each coordinate.
    /// The sides on two threads if `parallel`: a grid made at every tick with Looks
    /// (ASYNC at coarse durations) would otherwise rank its sample on one.
    fn quartile_box_area(&self, parallel: bool) -> f64 {
        if self.points.len() < 4 {
            return 0.0;
        }
        let side = |a| {
            let [q1, q3] = ranked(&self.points, a, |len| [len / 4, 3 * len / 4]);
            q3 - q1
        };
        let (x, y) = if parallel {
            rayon::join(|| side(0), || side(1))
        } else {
            (side(0), side(1))
        };
        x * y
    }

    /// The levels of a grid's parts, the first given (the swarm's box), for a swarm
    /// whose [quartile box](Sample::quartile_box_area) has area `quartile` per robot.
    /// Where the robots of a box between two percentiles of each coordinate (of the
    /// robots of the last box) are [`CROWDED`] times as dense as its bins are made
    /// for, that box becomes the next level, its bins sized for its own robots; and so
    /// on, up to [`MOST_LEVELS`]. The boxes tried are those of
    /// [`CUTS`], the widest first. A converging swarm packs most robots in a core a few
    /// units across while stragglers hold its box wide: bins sized for the box would
    /// hold hundreds of robots each. Its density falls off around the core, so that a
    /// box around only the core would leave a dense ring in the coarse bins around it.
    fn levels(&self, first: Level, quartile: f64) -> Vec<Level> {
        let mut levels = vec![first];
        // Every box tried holds the quartile box and at most every robot, so the first
        // is crowded only if the first bins are made for [`CROWDED`] times `quartile`
        // (one less leaves room for rounding).
        if first.spacing * first.spacing < (CROWDED - 1.0) * quartile {
            return levels;
        }
        // The sample within the last level's box (after the first).
        let mut nested: Option<Vec<[f64; 2]>> = None;
        let mut outer = None;
        while levels.len() < MOST_LEVELS {
            let sample = nested.as_deref().unwrap_or(&self.points);
            if sample.len() < 10 {
                break;
            }
            let around = levels.last().expect("the first level").spacing;
            let Some((level, inside)) = CUTS
                .iter()
                .find_map(|&cut| self.crowded(sample, cut, around))
            else {
                break;
            };
            levels.push(level);
            outer.get_or_insert((sample.len() - inside.len()) as f64 * self.per);
            nested = Some(inside);
        }
        // The first part then holds only the robots outside the second: bins for as
        // many.
        if let Some(m) = outer {
            let longest = (first.hi[0] - first.lo[0]).max(first.hi[1] - first.lo[1]);
            levels[0].spacing = first.spacing.max(longest / (2.0 * m.max(1.0).sqrt()));
        }
        levels
    }

    /// The box of `sample` between the ranks `len / cut` and `len - 1 - len / cut` of
    /// each coordinate as a level, with the sampled robots it holds, if it holds
    /// [`FEWEST_NESTED`] robots and they are [`CROWDED`] times as dense as bins of
    /// spacing `around` are made for.
    fn crowded(
        &self,
        sample: &[[f64; 2]],
        cut: usize,
        around: f64,
    ) -> Option<(Level, Vec<[f64; 2]>)> {
        let bounds = |a| ranked(sample, a, |len| [len / cut, len - 1 - len / cut]);
        let ([x0, x1], [y0, y1]) = (bounds(0), bounds(1));
        let level = Level {
            lo: [x0, y0],
            hi: [x1, y1],
            spacing: 0.0,
        };
        let inside: Vec<[f64; 2]> = sample
            .iter()
            .copied()
            .filter(|&[x, y]| level.holds_xy(x, y))
            .collect();
        let m = inside.len() as f64 * self.per;
        let ext = [x1 - x0, y1 - y0];
        let longest = ext[0].max(ext[1]);
        let spacing = (ext[0] * ext[1] / m)
            .sqrt()
            .max(longest / (2.0 * m.sqrt()))
            .max(longest * 1e-9)
            .max(1e-300);
        // (A NaN spacing is no crowding.)
        let crowded = (spacing * spacing * CROWDED).partial_cmp(&(around * around));
        if m < FEWEST_NESTED || crowded.is_none_or(|o| o.is_gt()) {
            return None;
        }
        Some((Level { spacing, ..level }, inside))
    }
}

/// The values of ranks `ranks(len)` (ascending, below `len`) of coordinate `a` of
/// `points`, each selected among the values ranked below the next one.
fn ranked<const K: usize>(
    points: &[[f64; 2]],
    a: usize,
    ranks: impl Fn(usize) -> [usize; K],
) -> [f64; K] {
    let mut v: Vec<f64> = points.iter().map(|p| p[a]).collect();
    let ranks = ranks(v.len());
    let mut out = [0.0; K];
    let mut end = v.len();
    for k in (0..K).rev() {
        if ranks[k] < end {
            out[k] = *v[..end].select_nth_unstable_by(ranks[k], f64::total_cmp).1;
            end = ranks[k];
        } else {
            // The same rank as the next one.
            out[k] = out[k + 1];
        }
    }
    out
}
