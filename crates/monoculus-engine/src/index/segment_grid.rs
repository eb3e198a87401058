//! [`SegmentGrid`]: bucketed robots for line-of-sight queries in the plane.
//!
//! Measured (`monoculus stress`, n = 10^5, density 1): three quarters of a
//! ConvergeLocality round went to R-tree traversals of the thin tubes along lines of
//! sight across the swarm, whose overlapping boxes make a long thin query visit many
//! nodes. A uniform grid visits only the cells the tube crosses; after that, most of
//! the time went to waiting for memory, cell by cell. So the robots are stored twice,
//! in horizontal and in vertical bands, each band cut into cells stored one after the
//! other: a line of sight is walked in the bands running along its major axis, and the
//! cells it crosses in one band are one contiguous slice of robots, read in one pass
//! (a few slices per line instead of one random access per cell).
//!
//! Candidates pass a cheap perpendicular-distance filter before the exact predicate.
//! They are a superset of the blockers, and the decision is the shared
//! [`blocks`](monoculus_core::vision::blocks), so answers are those of the R-tree and
//! of the brute-force oracle (tested, also with blockers placed at the edge of the
//! blocking cone across band edges).

use monoculus_core::geometry::Point;
use monoculus_core::vision::{VisionParams, blocks};

use super::{IndexPoint, Tube};

/// Band height and cell width, in units of the mean spacing sqrt(area / n), chosen with
/// `monoculus stress --n 100000` (thinner bands test fewer robots per line in more
/// slices; measured best of 0.7 to 3 bands and 0.5 to 2 cells: 2 x 1).
const BAND: f64 = 2.0;
const CELL: f64 = 1.0;

/// Robots tested at once by the line filter of [`SegmentGrid::blocked`] (a chunk may
/// run past a slice into the next robots: a false alarm, never a miss).
const LANES: usize = 8;

/// The slot of width `1 / inv` starting at `origin` that holds `v`, clamped to
/// `0..=last` (truncation equals floor here: negative values and NaN give 0). Signed
/// conversion of a clamped value: a third of the instructions of `as usize`.
#[inline]
fn slot(v: f64, origin: f64, inv: f64, last: f64) -> usize {
    let k = (v - origin) * inv;
    if k > 0.0 {
        (if k < last { k } else { last }) as i64 as usize
    } else {
        0
    }
}

/// `b` if it is above `a`, else `a`: a bound only ever narrowed, never by a NaN (and
/// cheaper than `f64::max`, which must pick the number out of a NaN either side).
#[inline(always)]
fn raise(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// `b` if it is below `a`, else `a` (see [`raise`]).
#[inline(always)]
fn lower(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// `i` as a float, for grid indices (at most a few times the number of robots, far
/// below 2^32): a cheaper conversion than from `usize`.
#[inline]
fn float(i: usize) -> f64 {
    debug_assert!(i <= u32::MAX as usize);
    f64::from(i as u32)
}

/// Robots bucketed in bands across one axis, each band cut into cells along the other
/// (the run axis), in compressed rows: cell `c` of band `r` holds
/// `items[start[k]..start[k + 1]]` with `k = r * cells + c`, ascending robot indices, so
/// consecutive cells of one band are one slice.
struct Bands {
    /// The axis a band runs along (0: x, 1: y); bands are stacked along the other.
    run: usize,
    /// The smallest coordinate on the run axis and across it.
    origin: [f64; 2],
    inv_width: f64,
    height: f64,
    inv_height: f64,
    cells: usize,
    bands: usize,
    /// The last cell and band, as floats.
    last: [f64; 2],
    start: Vec<u32>,
    items: Vec<u32>,
    /// Where each robot is in `items`: `items[place[k]] == k`.
    place: Vec<u32>,
    /// The positions of `items`, in the same order, as (x, y) relative to the swarm's
    /// lower corner in single precision: half the memory to stream through, for a
    /// filter that widens its tolerance by the rounding (see [`SegmentGrid::blocked`]).
    /// Followed by [`LANES`] NaN points, so that a filter may read whole chunks.
    coords: Vec<[f32; 2]>,
}

impl Bands {
    /// `lo` and `hi` in (x, y) order.
    fn new<P: Point>(points: &[P], run: usize, lo: [f64; 2], hi: [f64; 2], spacing: f64) -> Self {
        let across = 1 - run;
        let (width, height) = (CELL * spacing, BAND * spacing);
        let cells = ((hi[run] - lo[run]) / width) as usize + 1;
        let bands = ((hi[across] - lo[across]) / height) as usize + 1;
        let mut grid = Bands {
            run,
            origin: [lo[run], lo[across]],
            inv_width: 1.0 / width,
            height,
            inv_height: 1.0 / height,
            cells,
            bands,
            last: [(cells - 1) as f64, (bands - 1) as f64],
            start: vec![0; cells * bands + 1],
            // Padded like `coords`, with no robot.
            items: vec![u32::MAX; points.len() + LANES],
            place: vec![0; points.len()],
            // Padded (see [`LANES`]) with points that pass no filter.
            coords: vec![[f32::NAN; 2]; points.len() + LANES],
        };
        let slot: Vec<u32> = points
            .iter()
            .map(|p| {
                let (c, r) = (grid.cell(p.axis(run)), grid.band(p.axis(across)));
                (r * cells + c) as u32
            })
            .collect();
        for &k in &slot {
            grid.start[k as usize + 1] += 1;
        }
        for k in 0..cells * bands {
            grid.start[k + 1] += grid.start[k];
        }
        let mut fill = grid.start.clone();
        for (i, &k) in slot.iter().enumerate() {
            let at = fill[k as usize] as usize;
            grid.items[at] = i as u32;
            grid.place[i] = at as u32;
            grid.coords[at] = [
                (points[i].axis(0) - lo[0]) as f32,
                (points[i].axis(1) - lo[1]) as f32,
            ];
            fill[k as usize] += 1;
        }
        grid
    }

    /// The cell (along the run axis) of coordinate `v`, clamped to the grid.
    #[inline]
    fn cell(&self, v: f64) -> usize {
        slot(v, self.origin[0], self.inv_width, self.last[0])
    }

    /// The band of coordinate `v` across the run axis, clamped to the grid.
    #[inline]
    fn band(&self, v: f64) -> usize {
        slot(v, self.origin[1], self.inv_height, self.last[1])
    }

    /// The robots of band `r` in cells `c0..=c1`: indices into `items` and `coords`.
    #[inline]
    fn cells_range(&self, r: usize, c0: usize, c1: usize) -> std::ops::Range<usize> {
        let row = r * self.cells;
        self.start[row + c0] as usize..self.start[row + c1 + 1] as usize
    }

    /// The lower edge of cell `c` on the run axis and of band `r` across it.
    #[inline]
    fn corner(&self, c: usize, r: usize) -> (f64, f64) {
        (
            self.origin[0] + c as f64 / self.inv_width,
            self.origin[1] + r as f64 * self.height,
        )
    }

    /// The robots of band `r` in the cells meeting `[lo, hi]` on the run axis: indices
    /// into `items` and `coords`.
    #[inline]
    fn slice(&self, r: usize, lo: f64, hi: f64) -> std::ops::Range<usize> {
        let row = r * self.cells;
        self.start[row + self.cell(lo)] as usize..self.start[row + self.cell(hi) + 1] as usize
    }
}

/// Robots bucketed for line-of-sight walks and radius queries over the first two
/// coordinates, about one robot per cell.
pub struct SegmentGrid {
    /// Horizontal bands (running along x): lines of sight with |dx| >= |dy|, radius
    /// queries.
    rows: Bands,
    /// Vertical bands (running along y): lines of sight with |dy| > |dx|.
    columns: Bands,
    spacing: f64,
    /// The lower corner of the swarm, origin of the stored coordinates.
    lo: [f64; 2],
    /// The upper corner of the swarm.
    hi: [f64; 2],
    /// The largest rounding error of a stored coordinate.
    rounding: f64,
    /// Whether the stored coordinates are finite (else every robot is a candidate).
    single: bool,
}

impl SegmentGrid {
    /// A grid over the first two coordinates of `points`.
    pub fn new<P: Point>(points: &[P]) -> Self {
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
        // The mean spacing in the swarm's core (its interquartile box holds about a
        // quarter of the robots): a converging swarm is dense in the middle with a few
        // robots far out, and lines of sight cross the core. But never more than about
        // 16n cells per layout (straggling swarms; measured on the late rounds of
        // configs/bench/locality_1e5_rejection.toml: 4n 81 s, 16n 74 s, 64n 69 s), nor
        // 4n for thin ones.
        let core = quartile_box_area(points) / (0.25 * n);
        let spacing = core
            .sqrt()
            .max((ext[0] * ext[1] / (16.0 * n * BAND * CELL)).sqrt())
            .max(longest / (2.0 * n.sqrt()))
            .max(longest * 1e-9)
            .max(1e-300);
        Self::with_spacing(points, spacing, lo, hi)
    }

    /// A grid over `points` in the box `[lo, hi]` (theirs) with cells `spacing` wide.
    fn with_spacing<P: Point>(points: &[P], spacing: f64, lo: [f64; 2], hi: [f64; 2]) -> Self {
        let longest = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        SegmentGrid {
            rows: Bands::new(points, 0, lo, hi, spacing),
            columns: Bands::new(points, 1, lo, hi, spacing),
            spacing,
            lo,
            hi,
            // A relative coordinate r is stored as r(1 + e) with |e| <= 2^-24; the
            // filter trusts single precision only while coordinates are finite there.
            rounding: longest * 2f64.powi(-24),
            single: longest < 1e30,
        }
    }

    /// Whether `(x, y)` lies in the box of the robots the grid was built over: a robot
    /// that moved there may be handled as [`Stale`] (every geometric bound of the
    /// walks holds for points in the box).
    pub fn covers(&self, x: f64, y: f64) -> bool {
        (self.lo[0] <= x) & (x <= self.hi[0]) & (self.lo[1] <= y) & (y <= self.hi[1])
    }

    /// Asks for what [`SegmentGrid::isolated`] reads first about robot `k` (a hint).
    #[inline]
    pub fn prefetch_isolated(&self, k: usize) {
        prefetch(&self.rows.place[k]);
    }

    /// Asks for the cell bounds [`SegmentGrid::for_each_near`] reads first around
    /// `(x, y)` within `radius` (a hint).
    #[inline]
    pub fn prefetch_near(&self, x: f64, y: f64, radius: f64) {
        let g = &self.rows;
        let c = g.cell(x - radius);
        for r in g.band(y - radius)..=g.band(y + radius) {
            prefetch(&g.start[r * g.cells + c]);
        }
    }

    /// The mean spacing between robots (the side of a cell).
    pub fn cell_size(&self) -> f64 {
        self.spacing
    }

    /// Calls `f` with every robot whose cell meets the square of half-side `radius`
    /// around `(x, y)` (a superset of the robots within `radius`).
    pub fn for_each_near(&self, x: f64, y: f64, radius: f64, f: &mut dyn FnMut(usize)) {
        let g = &self.rows;
        for r in g.band(y - radius)..=g.band(y + radius) {
            for s in g.slice(r, x - radius, x + radius) {
                f(g.items[s] as usize);
            }
        }
    }

    /// Whether certainly no other robot lies within `radius` of robot `k`, where the
    /// grid was built: the robots of the cells near its stored point, tested on stored
    /// coordinates with room for their rounding. `false` when unsure (a radius not
    /// below a cell's size, coordinates not finite in single precision).
    pub fn isolated(&self, k: usize, radius: f64) -> bool {
        let g = &self.rows;
        // Two stored coordinates are each off by at most `rounding` plus the double
        // rounding of the shift to the swarm's corner, and so is the point rebuilt
        // from them; twice that leaves room.
        let extent = self.lo[0].abs() + self.lo[1].abs() + self.hi[0].abs() + self.hi[1].abs();
        let reach = radius + 4.0 * self.rounding + 16.0 * f64::EPSILON * extent;
        if !self.single || reach.is_nan() || reach >= self.spacing {
            return false;
        }
        let s = g.place[k] as usize;
        let [x, y] = g.coords[s].map(f64::from);
        let (ax, ay) = (x + self.lo[0], y + self.lo[1]);
        (g.band(ay - reach)..=g.band(ay + reach)).all(|r| {
            g.slice(r, ax - reach, ax + reach).all(|t| {
                let [u, v] = g.coords[t].map(f64::from);
                t == s || (u - x).abs() > reach || (v - y).abs() > reach
            })
        })
    }

    /// Robots other than `i`, nearest to it first (ties in any order): rings of cells
    /// around its cell, each robot given out once no unvisited cell can hold a nearer
    /// one. O(k log k) for the first k. The `stale` robots are skipped in the cells
    /// and queued at once from their current positions.
    pub fn nearest_first<'a, P: Point>(
        &'a self,
        positions: &'a [P],
        i: usize,
        stale: &'a Stale,
    ) -> impl Iterator<Item = usize> + 'a {
        let p = positions[i];
        let g = &self.rows;
        let heap = stale
            .iter()
            .filter(|&k| k != i)
            .map(|k| std::cmp::Reverse(((positions[k] - p).length().to_bits(), k)))
            .collect();
        Nearest {
            grid: g,
            positions,
            i,
            p,
            cell: (g.cell(p.axis(0)), g.band(p.axis(1))),
            ring: None,
            reach: 0.0,
            exhausted: false,
            heap,
            stale,
        }
    }

    /// Calls `f` with every robot farther than `radius` from robot `i`: per band, the
    /// cells wholly within the disc are skipped. O(bands + robots beyond + boundary).
    pub fn for_each_beyond<P: Point>(
        &self,
        positions: &[P],
        i: usize,
        radius: f64,
        f: &mut dyn FnMut(usize),
    ) {
        let p = positions[i];
        let (x, y) = (p.axis(0), p.axis(1));
        let g = &self.rows;
        // Room for the rounding of cell edges and of robots' cells.
        let room = 1e-9 * (x.abs() + y.abs() + self.spacing);
        let mut emit = |range: std::ops::Range<usize>| {
            for s in range {
                let k = g.items[s] as usize;
                if (positions[k] - p).length() > radius {
                    f(k);
                }
            }
        };
        for r in 0..g.bands {
            let (_, y0) = g.corner(0, r);
            let dy = (y - y0).abs().max((y0 + g.height - y).abs()) + room;
            // The band's robots within `inner` of x on the run axis are within the disc.
            let inner = if dy < radius {
                (radius * radius - dy * dy).sqrt() * (1.0 - 1e-9) - room
            } else {
                -1.0
            };
            let last = g.cells - 1;
            if inner <= 0.0 {
                emit(g.cells_range(r, 0, last));
                continue;
            }
            let (ca, cb) = (g.cell(x - inner), g.cell(x + inner));
            if cb <= ca + 1 {
                emit(g.cells_range(r, 0, last));
            } else {
                emit(g.cells_range(r, 0, ca));
                emit(g.cells_range(r, cb, last));
            }
        }
    }

    /// Whether some robot other than `i` and `j` blocks the view from `positions[i]` to
    /// `positions[j]`.
    pub fn blocked<P: IndexPoint>(
        &self,
        positions: &[P],
        i: usize,
        j: usize,
        v: &VisionParams,
    ) -> bool {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above), all `blocked_avx2` needs. One
            // of the workspace's two unsafe blocks (the other: `prefetch`).
            #[allow(
                unsafe_code,
                reason = "calling code compiled for a detected CPU feature"
            )]
            return unsafe { self.blocked_avx2(positions, i, j, v) };
        }
        self.walk(positions, i, j, v)
    }

    /// [`Self::walk`] compiled for AVX2: the line filter tests eight robots per
    /// instruction instead of four (measured: see docs/performance.md).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn blocked_avx2<P: IndexPoint>(
        &self,
        positions: &[P],
        i: usize,
        j: usize,
        v: &VisionParams,
    ) -> bool {
        self.walk(positions, i, j, v)
    }

    /// The body of [`Self::blocked`].
    #[inline(always)]
    fn walk<P: IndexPoint>(&self, positions: &[P], i: usize, j: usize, v: &VisionParams) -> bool {
        let (p, q) = (positions[i], positions[j]);
        let tube = Tube::new(p, q, v.eps_ang);
        // Every blocker lies within `tol` of the segment (the blocking cone and room for
        // rounding in the exact test).
        let tol = tube.tolerance();
        let d = q - p;
        let len = d.length();
        let (px, py, dx, dy) = (p.axis(0), p.axis(1), d.axis(0), d.axis(1));
        // The filter below works on stored coordinates, each off by at most `rounding`
        // (plus double rounding of the shift to the swarm's corner): that moves `along`
        // and the cross product by at most `slack`.
        let err = self.rounding
            + 8.0
                * f64::EPSILON
                * (px.abs() + py.abs() + self.lo[0].abs() + self.lo[1].abs() + len);
        let slack = 2.0 * err * (dx.abs() + dy.abs());
        let (along_max, band) = (len * len + slack, 2.0 * tol * len + slack);
        let (rpx, rpy) = (px - self.lo[0], py - self.lo[1]);
        // Walk the bands running along the major axis `a`.
        let g = if dx.abs() >= dy.abs() {
            &self.rows
        } else {
            &self.columns
        };
        // Read only before the first filter pass (below): asked for now, the two
        // places (random robots, a cache and TLB miss each at 10^6) arrive while the
        // first batch of bands is laid out.
        prefetch(&g.place[i]);
        prefetch(&g.place[j]);
        let (a, b) = (g.run, 1 - g.run);
        let (pa, pb, da, db) = (p.axis(a), p.axis(b), d.axis(a), d.axis(b));
        // A blocker lies within `tol` of the segment, so within `tol` of its extent on
        // either axis. Where the line crosses a band edge, a blocker just across the
        // edge lies within `tol_b * cos / sin` of the crossing along the major axis
        // (tested); `tol_b = tol` would do, twice that leaves room.
        let tol_b = 2.0 * tol;
        let (a_lo, a_hi) = (pa.min(pa + da) - tol, pa.max(pa + da) + tol);
        let (b_lo, b_hi) = (pb.min(pb + db) - tol_b, pb.max(pb + db) + tol_b);
        let (r0, r1) = (g.band(b_lo), g.band(b_hi));
        // Rounding in the inverse below is covered by this much room on the major axis.
        let scale = pa
            .abs()
            .max((pa + da).abs())
            .max(pb.abs())
            .max((pb + db).abs())
            + len;
        let steep = db.abs() * 1e12 >= da.abs();
        let inv_slope = da / db;
        // Cheap filter: within twice the tube's radius of the line, strictly between p
        // and q (widened by the rounding of stored coordinates).
        let extent = self.hi[0] - self.lo[0] + self.hi[1] - self.lo[1];
        let filter = Filter {
            origin: [rpx, rpy],
            d: [dx, dy],
            slack,
            along_max,
            band,
            single: self.single,
            line: Line::new([rpx, rpy], [dx, dy], len, tol + 2.0 * err, extent),
        };
        let near = |c: &[f32; 2]| filter.near(c);
        // The ends lie on the line: the line filter leaves out their places in the
        // layout (for a robot that moved since, its old place), sparing an exact pass
        // over the first and last slices without reading which robot each place holds.
        let mut ends = None;
        // Bands are taken a batch at a time: first where the line crosses each, then
        // its slice's bounds, then its robots, each step prefetching what the next one
        // reads, so that the cache misses of a batch overlap instead of adding up.
        const BATCH: usize = 32;
        let mut cells = [(0usize, 0usize); BATCH];
        let mut r = r0;
        while r <= r1 {
            let mut m = 0;
            while r <= r1 && m < BATCH {
                let (mut lo, mut hi) = (a_lo, a_hi);
                if r0 < r1 && steep {
                    // Where the line crosses band r, widened by `tol_b` (robots near a
                    // band edge may sit in either band after rounding: `tol` includes
                    // room for it).
                    let edge0 = g.origin[1] + float(r) * g.height - tol_b;
                    let edge1 = g.origin[1] + float(r + 1) * g.height + tol_b;
                    let (t0, t1) = ((edge0 - pb) * inv_slope, (edge1 - pb) * inv_slope);
                    let room = 64.0 * f64::EPSILON * (scale + t0.abs() + t1.abs());
                    let (t_lo, t_hi) = if t1 < t0 { (t1, t0) } else { (t0, t1) };
                    lo = raise(lo, pa + t_lo - room);
                    hi = lower(hi, pa + t_hi + room);
                }
                if lo <= hi {
                    let row = r * g.cells;
                    cells[m] = (row + g.cell(lo), row + g.cell(hi) + 1);
                    prefetch(&g.start[cells[m].0]);
                    prefetch(&g.start[cells[m].1]);
                    m += 1;
                }
                r += 1;
            }
            let mut slices = [(0usize, 0usize); BATCH];
            for (slice, &(c0, c1)) in slices.iter_mut().zip(&cells[..m]) {
                *slice = (g.start[c0] as usize, g.start[c1] as usize);
                // A slice is a few robots: its first and last cache lines (the padding
                // keeps both indices valid; the hardware streams longer slices).
                prefetch(&g.coords[slice.0]);
                prefetch(&g.coords[slice.1]);
            }
            for &(s0, s1) in &slices[..m] {
                // Candidates are rare: one branch-free pass over the slice first.
                let ends = *ends.get_or_insert_with(|| [g.place[i], g.place[j]]);
                if !filter.line.any(&g.coords, s0, s1, ends) {
                    continue;
                }
                for s in s0..s1 {
                    let k = g.items[s] as usize;
                    if near(&g.coords[s]) && k != i && k != j && blocks(p, positions[k], q, v) {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// Robots that moved since a grid was built (to points it [covers](SegmentGrid::covers)):
/// their cells are out of date, so queries skip them in the cells, where that matters,
/// and test them one by one at their current positions. A set of robot indices: a
/// list, and a bit per robot.
#[derive(Debug, Default)]
pub struct Stale {
    list: Vec<u32>,
    bits: Vec<u64>,
}

impl Stale {
    /// No robot, for a swarm of `n`.
    pub fn none(n: usize) -> Self {
        Stale {
            list: Vec::new(),
            bits: vec![0; n.div_ceil(64)],
        }
    }

    /// Whether robot `k` is in the set.
    #[inline]
    pub fn contains(&self, k: usize) -> bool {
        self.bits
            .get(k / 64)
            .is_some_and(|w| w & (1u64 << (k % 64)) != 0)
    }

    /// Adds robot `k` (which must be below the swarm size given to [`Stale::none`]).
    pub fn insert(&mut self, k: usize) {
        if !self.contains(k) {
            self.bits[k / 64] |= 1u64 << (k % 64);
            self.list.push(k as u32);
        }
    }

    /// How many robots are in the set.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// Whether the set is empty.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The robots, in the order they were added.
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.list.iter().map(|&k| k as usize)
    }
}

/// The area of the box between the first and third quartiles of each coordinate,
/// estimated from at most 4096 robots (evenly strided: a function of the positions).
fn quartile_box_area<P: Point>(points: &[P]) -> f64 {
    let stride = points.len().div_ceil(4096).max(1);
    let mut area = 1.0;
    for a in 0..2 {
        let mut v: Vec<f64> = points.iter().step_by(stride).map(|p| p.axis(a)).collect();
        if v.len() < 4 {
            return 0.0;
        }
        let (q1, q3) = (v.len() / 4, 3 * v.len() / 4);
        let x3 = *v.select_nth_unstable_by(q3, f64::total_cmp).1;
        let x1 = *v[..q3].select_nth_unstable_by(q1, f64::total_cmp).1;
        area *= x3 - x1;
    }
    area
}

/// The cheap test of [`SegmentGrid::blocked`] on stored coordinates.
struct Filter {
    /// The observer, relative to the swarm's corner.
    origin: [f64; 2],
    /// The line of sight.
    d: [f64; 2],
    slack: f64,
    along_max: f64,
    band: f64,
    single: bool,
    line: Line,
}

impl Filter {
    #[inline(always)]
    fn near(&self, &[x, y]: &[f32; 2]) -> bool {
        let (rx, ry) = (f64::from(x) - self.origin[0], f64::from(y) - self.origin[1]);
        let [dx, dy] = self.d;
        let along = rx * dx + ry * dy;
        !self.single
            | ((along > -self.slack)
                & (along < self.along_max)
                & ((rx * dy - ry * dx).abs() <= self.band))
    }
}

/// The first test of [`SegmentGrid::blocked`]: whether a stored point lies within `w`
/// of the line of sight, in single precision, in chunks of [`LANES`] robots (four times
/// the robots per instruction of the double-precision [`Filter`]).
///
/// The point at distance `d` from the line gives `|n . s - c| <= d` for the exact unit
/// normal `n` and offset `c`. Rounding `n` and `c` to single precision moves that by at
/// most `u (|s_x| + |s_y| + |c|)` (u = 2^-24, stored coordinates are relative to the
/// swarm's corner so `|s| <= extent`), and evaluating it in single precision by at
/// most `3 u (|s_x| + |s_y| + |c|)` more (fused or not). A blocker lies within `tol`
/// of the segment, its stored point within `tol + 2 err` of the line; `w` adds
/// `8 u (extent + |c| + 1 ulp)` to that.
struct Line {
    n: [f32; 2],
    c: f32,
    w: f32,
    /// Whether the bound holds (finite, not degenerate); else every robot passes.
    sound: bool,
}

impl Line {
    /// The line through `origin` along `d` of length `len`; `w` bounds the distance of
    /// a stored blocker to it; `extent` bounds |s_x| + |s_y| for stored points.
    fn new(origin: [f64; 2], d: [f64; 2], len: f64, w: f64, extent: f64) -> Self {
        let n = [d[1] / len, -d[0] / len];
        let c = n[0] * origin[0] + n[1] * origin[1];
        let u = 2f64.powi(-24);
        // `n` is a unit vector up to a few ulps of double precision, covered by the
        // factor on `w`.
        let w = (w * (1.0 + 1e-12) + 8.0 * u * (extent + c.abs()) * (1.0 + 1e-6)) * (1.0 + 2.0 * u);
        let sound = len > 0.0 && (extent + c.abs() + w).is_finite() && extent < 1e30 && w < 1e30;
        Line {
            n: [n[0] as f32, n[1] as f32],
            c: c as f32,
            w: w as f32,
            sound,
        }
    }

    /// Whether some point of `coords[s0..s1]` other than those at the two `ends` (the
    /// places of the observer and the observed in the layout, if found there) may lie
    /// within `w` of the line. Reads whole chunks of
    /// [`LANES`] (the padding), so may raise a false alarm.
    #[inline(always)]
    fn any(&self, coords: &[[f32; 2]], s0: usize, s1: usize, ends: [u32; 2]) -> bool {
        if !self.sound {
            return s0 < s1;
        }
        let ([nx, ny], c, w) = (self.n, self.c, self.w);
        let mut s = s0;
        while s < s1 {
            let Some(chunk) = coords.get(s..s + LANES) else {
                return true;
            };
            let mut hit = false;
            for (at, &[x, y]) in (s as u32..).zip(chunk) {
                hit |= ((nx * x + ny * y - c).abs() <= w) & (at != ends[0]) & (at != ends[1]);
            }
            if hit {
                return true;
            }
            s += LANES;
        }
        false
    }
}

/// The iterator of [`SegmentGrid::nearest_first`].
struct Nearest<'a, P: Point> {
    grid: &'a Bands,
    positions: &'a [P],
    i: usize,
    p: P,
    /// The observer's cell and band.
    cell: (usize, usize),
    /// The last ring of cells visited (`None` before the first).
    ring: Option<usize>,
    /// Every robot nearer than this has been visited.
    reach: f64,
    /// Whether every cell has been visited.
    exhausted: bool,
    /// Visited robots not yet given out: (distance bits, robot), nearest on top.
    heap: std::collections::BinaryHeap<std::cmp::Reverse<(u64, usize)>>,
    /// Robots whose cells are out of date (queued from the start).
    stale: &'a Stale,
}

impl<P: Point> Nearest<'_, P> {
    /// Visits the next ring of cells; `false` if the grid is exhausted.
    fn expand(&mut self) -> bool {
        let g = self.grid;
        let (c, r) = self.cell;
        if self.exhausted {
            return false;
        }
        let k = self.ring.map_or(0, |k| k + 1);
        let (c0, c1) = (c.saturating_sub(k), (c + k).min(g.cells - 1));
        let (r0, r1) = (r.saturating_sub(k), (r + k).min(g.bands - 1));
        self.ring = Some(k);
        let push = |range: std::ops::Range<usize>, heap: &mut std::collections::BinaryHeap<_>| {
            for s in range {
                let j = g.items[s] as usize;
                if j != self.i && !self.stale.contains(j) {
                    let d = (self.positions[j] - self.p).length();
                    heap.push(std::cmp::Reverse((d.to_bits(), j)));
                }
            }
        };
        for band in r0..=r1 {
            if k == 0 || band == r.wrapping_sub(k) || band == r + k {
                push(g.cells_range(band, c0, c1), &mut self.heap);
            } else {
                if c >= k {
                    push(g.cells_range(band, c - k, c - k), &mut self.heap);
                }
                if c + k < g.cells {
                    push(g.cells_range(band, c + k, c + k), &mut self.heap);
                }
            }
        }
        // Distance from the observer to the nearest unvisited cell (infinite past the
        // grid's edge), less room for rounding.
        let (x, y) = (self.p.axis(0), self.p.axis(1));
        let (lo_x, lo_y) = g.corner(c.saturating_sub(k), r.saturating_sub(k));
        let (hi_x, hi_y) = g.corner(c + k + 1, r + k + 1);
        let gap = |inside: bool, d: f64| if inside { d } else { f64::INFINITY };
        let reach = gap(c > k, x - lo_x)
            .min(gap(c + k + 1 < g.cells, hi_x - x))
            .min(gap(r > k, y - lo_y))
            .min(gap(r + k + 1 < g.bands, hi_y - y));
        self.exhausted = reach == f64::INFINITY;
        self.reach = reach * (1.0 - 1e-9) - 1e-9 * (x.abs() + y.abs());
        true
    }
}

impl<P: Point> Iterator for Nearest<'_, P> {
    type Item = usize;

    fn next(&mut self) -> Option<usize> {
        loop {
            if let Some(&std::cmp::Reverse((d, j))) = self.heap.peek()
                && f64::from_bits(d) < self.reach
            {
                self.heap.pop();
                return Some(j);
            }
            if !self.expand() {
                return self.heap.pop().map(|std::cmp::Reverse((_, j))| j);
            }
        }
    }
}

/// Asks for the cache line holding `x` (a hint: no effect on results).
#[inline(always)]
pub(crate) fn prefetch<T>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: prefetching is a hint that never faults, here on a valid reference. One of
    // the workspace's two unsafe blocks (the other calls the AVX2 walk once the CPU is
    // known to have it); `unsafe_code = "deny"` everywhere else.
    #[allow(
        unsafe_code,
        unused_unsafe,
        reason = "a prefetch hint; the intrinsic is safe on newer compilers"
    )]
    unsafe {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        _mm_prefetch::<_MM_HINT_T0>((x as *const T).cast());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;
    use monoculus_core::rng::Stream;

    fn brute(points: &[DVec2], i: usize, j: usize, v: &VisionParams) -> bool {
        (0..points.len()).any(|k| k != i && k != j && blocks(points[i], points[k], points[j], v))
    }

    /// Blockers at the edge of the blocking cone, on lines of every slope through a
    /// corner of the cells they are walked in (so a blocker sits across a band edge and
    /// a cell edge from where the line enters the band): the walk must find them all.
    #[test]
    fn blockers_at_the_cone_edge_next_to_cell_corners() {
        let v = VisionParams::default();
        let mut rng = Stream::new(7, 0, 0, 0);
        // Robots 0..4 pin the bounds, so moving robots 4, 5 and 6 keeps the grid's cells.
        let mut pts = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(20.0, 0.0),
            DVec2::new(0.0, 20.0),
            DVec2::new(20.0, 20.0),
        ];
        pts.extend((0..400).map(|_| DVec2::new(rng.uniform() * 20.0, rng.uniform() * 20.0)));
        let (i, j, k) = (4, 5, 6);
        let (mut checked, mut blocked) = (0, 0);
        while checked < 3000 {
            let grid = SegmentGrid::new(&pts);
            let g = if rng.coin() {
                &grid.rows
            } else {
                &grid.columns
            };
            let (a, b) = (g.run, 1 - g.run);
            let mut corner = DVec2::ZERO;
            corner[a] = g.origin[0] + (1 + rng.below(g.cells - 2)) as f64 / g.inv_width;
            corner[b] = g.origin[1] + (1 + rng.below(g.bands - 2)) as f64 * g.height;
            let p = DVec2::new(rng.uniform() * 20.0, rng.uniform() * 20.0);
            // Through the corner, or just beside it (by about the cone's width).
            corner[a] += rng.uniform_in(-2.0, 2.0) * v.eps_ang * (corner - p).length();
            let q = p + (corner - p) * rng.uniform_in(1.2, 2.5);
            let d = q - p;
            let inside = (0..2).all(|x| (0.5..19.5).contains(&q[x]));
            // Walked in `g` only if its run axis is the major axis.
            if !inside || (d[a].abs() < d[b].abs()) || (g.run == 1 && d[a].abs() == d[b].abs()) {
                continue;
            }
            let normal = DVec2::new(-d.y, d.x).normalize();
            pts[i] = p;
            pts[j] = q;
            for side in [-1.0, 1.0] {
                for frac in [0.5, 0.999, 1.001] {
                    pts[k] = corner + normal * (side * frac * v.eps_ang * (corner - p).length());
                    let expect = brute(&pts, i, j, &v);
                    assert_eq!(
                        SegmentGrid::new(&pts).blocked(&pts, i, j, &v),
                        expect,
                        "{p} -> {q}, blocker {} ({frac})",
                        pts[k]
                    );
                    checked += 1;
                    blocked += usize::from(expect);
                }
            }
        }
        assert!(
            blocked > 1000,
            "only {blocked} of {checked} placements block"
        );
    }
    /// Robots with company within the radius (pairs at and around the radius, some
    /// across cell edges and corners, far from the origin) are never marked isolated;
    /// lone robots are.
    #[test]
    fn isolated_robots_have_nobody_within_the_radius() {
        let mut rng = Stream::new(5, 0, 0, 0);
        let offset = DVec2::new(-4.0e4, 7.0e3);
        let radius = 1e-6;
        // The first two robots pin the box, so adding robots inside keeps the cells.
        let mut pts = vec![offset, offset + DVec2::splat(40.0)];
        pts.extend((0..2000).map(|_| offset + DVec2::new(rng.uniform(), rng.uniform()) * 40.0));
        let first = SegmentGrid::new(&pts);
        let g = &first.rows;
        for k in 0..600 {
            let angle = rng.uniform() * std::f64::consts::TAU;
            let at = [0.0, 0.5, 0.999_999, 1.0, 1.000_001, 3.0][k % 6] * radius;
            let dir = DVec2::new(angle.cos(), angle.sin()) * at;
            if k % 3 == 2 {
                // Beside a robot.
                pts.push(pts[2 + rng.below(2000)] + dir);
            } else {
                // Either side of a cell corner.
                let (x, y) = g.corner(1 + rng.below(g.cells - 2), 1 + rng.below(g.bands - 2));
                let corner = DVec2::new(x, y);
                pts.extend([corner + dir * 0.5, corner - dir * 0.5]);
            }
        }
        // The same cells as `first`.
        let grid = SegmentGrid::with_spacing(&pts, first.spacing, first.lo, first.hi);
        let (mut lone, mut missed) = (0, 0);
        for (k, &p) in pts.iter().enumerate() {
            let alone = pts
                .iter()
                .enumerate()
                .all(|(t, &q)| t == k || (q - p).length() > radius);
            let marked = grid.isolated(k, radius);
            assert!(!marked || alone, "robot {k} at {p} has company");
            // Beyond the room left for rounding (about 1e-5 here), robots are marked.
            let remote = pts
                .iter()
                .enumerate()
                .all(|(t, &q)| t == k || (q - p).length() > 1e-4);
            lone += usize::from(remote);
            missed += usize::from(remote && !marked);
        }
        assert!(
            lone > 1700 && missed == 0,
            "{missed} of {lone} lone robots not marked"
        );
        assert!(!grid.isolated(0, grid.cell_size()));
    }

    /// Blockers inside the cone, a few hundred units from the swarm's corner and far
    /// from the origin: the cone is a million times thinner than the rounding of the
    /// stored single-precision coordinates, which the line filter must allow for.
    #[test]
    fn the_single_precision_filter_keeps_blockers_it_cannot_resolve() {
        let v = VisionParams::default();
        let mut rng = Stream::new(11, 0, 0, 0);
        let offset = DVec2::new(1.0e5, -3.0e4);
        let mut pts: Vec<DVec2> = (0..3000)
            .map(|_| offset + DVec2::new(rng.uniform() * 1000.0, rng.uniform() * 1000.0))
            .collect();
        let (i, j, k) = (0, 1, 2);
        let mut blocked = 0;
        for _ in 0..400 {
            let (p, q) = (pts[i], pts[j]);
            let (d, t) = (q - p, rng.uniform_in(0.05, 0.95));
            let normal = DVec2::new(-d.y, d.x).normalize();
            // Within the cone, or just outside it.
            let frac = rng.uniform_in(-1.2, 1.2);
            pts[k] = p + d * t + normal * (frac * v.eps_ang * t * d.length());
            let expect = brute(&pts, i, j, &v);
            assert_eq!(
                SegmentGrid::new(&pts).blocked(&pts, i, j, &v),
                expect,
                "{p} -> {q}, blocker {} ({frac})",
                pts[k]
            );
            blocked += usize::from(expect);
            pts[i] = offset + DVec2::new(rng.uniform() * 1000.0, rng.uniform() * 1000.0);
            pts[j] = offset + DVec2::new(rng.uniform() * 1000.0, rng.uniform() * 1000.0);
        }
        assert!(blocked > 200, "only {blocked} of 400 placements block");
    }
}
