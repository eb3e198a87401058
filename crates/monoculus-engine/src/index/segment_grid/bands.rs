//! [`Bands`]: the layout of the grid, robots bucketed in bands across one axis, each band
//! cut into bins along the other.

use monoculus_core::geometry::Point;

use super::filter::LANES;
use super::slots::{clamped, slot};

/// Band height and bin width, in units of the mean spacing sqrt(area / n): thinner
/// bands test fewer robots per line in more slices (the choice is measured in
/// docs/performance.md).
pub(super) const BAND: f64 = 2.0;
pub(super) const BIN: f64 = 1.0;

/// A box of the plane and the size of its bins: a [`Bands`] layout holds one part per
/// level, the robots of a level's box (but those of the next, nested one) in its bins.
#[derive(Clone, Copy, Debug)]
pub(super) struct Level {
    /// The box's lower corner, (x, y).
    pub(super) lo: [f64; 2],
    /// Its upper corner.
    pub(super) hi: [f64; 2],
    /// The mean spacing its bins are made for.
    pub(super) spacing: f64,
}

impl Level {
    /// Whether `p` lies in the box (boundary included).
    pub(super) fn holds<P: Point>(&self, p: &P) -> bool {
        self.holds_xy(p.axis(0), p.axis(1))
    }

    /// Whether `(x, y)` lies in the box (boundary included).
    pub(super) fn holds_xy(&self, x: f64, y: f64) -> bool {
        (self.lo[0] <= x) & (x <= self.hi[0]) & (self.lo[1] <= y) & (y <= self.hi[1])
    }
}

/// One part of a layout: a box cut into bands across the run axis, each cut into bins
/// along it, its bins numbered from `offset` in the layout's `start`.
#[derive(Debug)]
pub(super) struct Part {
    /// The box's smallest coordinate on the run axis and across it.
    pub(super) origin: [f64; 2],
    /// The box's largest coordinate on the run axis and across it.
    pub(super) top: [f64; 2],
    pub(super) inv_width: f64,
    pub(super) height: f64,
    pub(super) inv_height: f64,
    pub(super) bins: usize,
    pub(super) bands: usize,
    /// The last bin and band, as floats.
    pub(super) last: [f64; 2],
    /// The number in `start` of the part's first bin.
    pub(super) offset: usize,
    /// The mean spacing its bins are made for.
    pub(super) spacing: f64,
}

impl Part {
    fn new(level: &Level, run: usize, offset: usize) -> Self {
        let across = 1 - run;
        let (lo, hi, spacing) = (level.lo, level.hi, level.spacing);
        let (width, height) = (BIN * spacing, BAND * spacing);
        let bins = ((hi[run] - lo[run]) / width) as usize + 1;
        let bands = ((hi[across] - lo[across]) / height) as usize + 1;
        Part {
            origin: [lo[run], lo[across]],
            top: [hi[run], hi[across]],
            inv_width: 1.0 / width,
            height,
            inv_height: 1.0 / height,
            bins,
            bands,
            last: [(bins - 1) as f64, (bands - 1) as f64],
            offset,
            spacing,
        }
    }

    /// The bin (along the run axis) of coordinate `v`, clamped to the part.
    #[inline]
    pub(super) fn bin(&self, v: f64) -> usize {
        clamped(self.bin_at(v), self.last[0])
    }

    /// Coordinate `v` on the run axis in units of bins from the part's origin,
    /// unclamped: [`Part::bin`] rounds it down.
    #[inline]
    pub(super) fn bin_at(&self, v: f64) -> f64 {
        (v - self.origin[0]) * self.inv_width
    }

    /// The band of coordinate `v` across the run axis, clamped to the part.
    #[inline]
    pub(super) fn band(&self, v: f64) -> usize {
        slot(v, self.origin[1], self.inv_height, self.last[1])
    }

    /// The number in `start` of the first bin of band `r`.
    #[inline]
    pub(super) fn row(&self, r: usize) -> usize {
        self.offset + r * self.bins
    }

    /// The lower edge of bin `c` on the run axis and of band `r` across it.
    #[inline]
    pub(super) fn corner(&self, c: usize, r: usize) -> (f64, f64) {
        (
            self.origin[0] + c as f64 / self.inv_width,
            self.origin[1] + r as f64 * self.height,
        )
    }

    /// Whether the box `[a0, a1] x [b0, b1]` (run axis, across) meets the part's box
    /// (`true` when unsure: a NaN bound).
    #[inline]
    pub(super) fn meets(&self, a0: f64, a1: f64, b0: f64, b1: f64) -> bool {
        !((a1 < self.origin[0]) | (a0 > self.top[0]) | (b1 < self.origin[1]) | (b0 > self.top[1]))
    }
}

/// Robots bucketed in bands across one axis, each band cut into bins along the other
/// (the run axis), in compressed rows: bin `c` of band `r` of a part holds
/// `items[start[k]..start[k + 1]]` with `k = part.row(r) + c`, ascending robot indices,
/// so consecutive bins of one band are one slice.
///
/// The first part covers the swarm's box. A crowded swarm has more, each over a box
/// nested in the one before with bins of its own, finer size; a robot is held in the
/// innermost part whose box holds it. A query asks every part whose box it meets.
#[derive(Default)]
pub(super) struct Bands {
    /// The axis a band runs along (0: x, 1: y); bands are stacked along the other.
    pub(super) run: usize,
    /// The parts, outermost first.
    pub(super) parts: Vec<Part>,
    pub(super) start: Vec<u32>,
    pub(super) items: Vec<u32>,
    /// Where each robot is in `items`: `items[place[k]] == k`.
    pub(super) place: Vec<u32>,
    /// The positions of `items`, in the same order, as (x, y) relative to the swarm's
    /// lower corner in single precision: half the memory to stream through, for a
    /// filter that widens its tolerance by the rounding (see [`SegmentGrid::blocked`]).
    /// Followed by [`LANES`] NaN points, so that a filter may read whole chunks.
    pub(super) coords: Vec<[f32; 2]>,
    /// For a grid over moving robots (empty otherwise): how far the robot of each place
    /// may be from its stored point, in the same order, padded like `coords` (see
    /// [`SegmentGrid::set_disc`]).
    pub(super) reach: Vec<f32>,
}

impl Bands {
    /// An empty layout with a part per level (the first over the box of every point,
    /// each next one nested in the one before), sized for `n` robots, made in the arrays
    /// of `spare` (a layout made before, or an empty one): a grid made again and again
    /// (ASYNC's moving index) neither allocates its arrays nor has the system hand it
    /// their pages anew each time. [`bins_of_both`] then writes each robot's bin in
    /// `place`, and [`Bands::sort`] files the robots.
    pub(super) fn empty(spare: Bands, n: usize, run: usize, levels: &[Level]) -> Self {
        let Bands {
            mut parts,
            mut start,
            mut items,
            mut place,
            mut coords,
            mut reach,
            ..
        } = spare;
        parts.clear();
        let mut total = 0;
        for level in levels {
            let part = Part::new(level, run, total);
            total += part.bins * part.bands;
            parts.push(part);
        }
        refill(&mut start, total + 1, 0);
        // Every robot's entry of these is written by `sort`: only the padding is set
        // here (an array made again at every tick with Looks, not cleared first).
        // Padded like `coords`, with no robot.
        pad(&mut items, n, u32::MAX);
        place.resize(n, 0);
        // Padded (see [`LANES`]) with points that pass no filter.
        pad(&mut coords, n, [f32::NAN; 2]);
        // Until a robot is given a disc, every one is at its point.
        reach.clear();
        Bands {
            run,
            parts,
            start,
            items,
            place,
            coords,
            reach,
        }
    }

    /// Files the robots of `points` in their bins, which `place` holds (written by
    /// [`bins_of_both`]); `lo` (x, y) is the swarm's lower corner, origin of the stored
    /// coordinates. A counting sort with no second array of bins (a grid can have 16n
    /// of them): each bin's end, then its robots placed from the last one down, which
    /// leaves its start there and its robots ascending.
    pub(super) fn sort<P: Point>(&mut self, points: &[P], lo: [f64; 2]) {
        let total = self.start.len() - 1;
        for &k in &self.place {
            self.start[k as usize] += 1;
        }
        let mut end = 0;
        for c in &mut self.start[..total] {
            end += *c;
            *c = end;
        }
        self.start[total] = end;
        for (i, p) in points.iter().enumerate().rev() {
            let k = self.place[i] as usize;
            self.start[k] -= 1;
            let at = self.start[k] as usize;
            self.items[at] = i as u32;
            self.place[i] = at as u32;
            self.coords[at] = [(p.axis(0) - lo[0]) as f32, (p.axis(1) - lo[1]) as f32];
        }
    }

    /// The robots of band `r` of `part` in bins `c0..=c1`: indices into `items` and
    /// `coords`.
    #[inline]
    pub(super) fn bins_range(
        &self,
        part: &Part,
        r: usize,
        c0: usize,
        c1: usize,
    ) -> std::ops::Range<usize> {
        let row = part.row(r);
        self.start[row + c0] as usize..self.start[row + c1 + 1] as usize
    }
}

/// Each robot's bin in the two layouts of one grid, `rows` (bands running along x) and
/// `columns` (along y), [made empty](Bands::empty) over the same `levels`, written in
/// their `place` (or stretches of it, slot for slot with `points`). A robot is in the
/// innermost level whose box holds it. The two share their arithmetic: a band is two
/// bins high (`BAND` is twice `BIN`), so that a robot's band in one layout is its
/// bin across in the other halved, bit for bit as if computed on its own (tested):
/// the coordinate in units of bands is that in units of bins halved (a power of two,
/// exact), as are the last band and last bin, and rounding down commutes with the
/// halving.
pub(super) fn bins_of_both<P: Point>(
    rows: &mut [u32],
    columns: &mut [u32],
    points: &[P],
    row_parts: &[Part],
    column_parts: &[Part],
    levels: &[Level],
) {
    const { assert!(BAND == 2.0 * BIN) };
    let bins = |level: usize, p: &P| {
        let (r, c) = (&row_parts[level], &column_parts[level]);
        // Bins along x and along y, in each layout's part.
        let (cx, cy) = (r.bin(p.axis(0)), c.bin(p.axis(1)));
        ((r.row(cy >> 1) + cx) as u32, (c.row(cx >> 1) + cy) as u32)
    };
    let slots = rows.iter_mut().zip(columns.iter_mut()).zip(points);
    if let [_] = levels {
        for ((a, b), p) in slots {
            (*a, *b) = bins(0, p);
        }
    } else {
        for ((a, b), p) in slots {
            let level = levels[1..]
                .iter()
                .rposition(|l| l.holds(p))
                .map_or(0, |k| k + 1);
            (*a, *b) = bins(level, p);
        }
    }
}

/// `v` emptied and filled with `len` copies of `value`, in the memory it has.
fn refill<T: Copy>(v: &mut Vec<T>, len: usize, value: T) {
    v.clear();
    v.resize(len, value);
}

/// `v` made `n` + [`LANES`] long, its last [`LANES`] entries `value`, its first `n` as
/// they were (or `value` where it was shorter): for an array whose first `n` entries
/// are all written next.
fn pad<T: Copy>(v: &mut Vec<T>, n: usize, value: T) {
    v.truncate(n);
    v.resize(n + LANES, value);
}
