//! Radius queries: the robots near a point, whether a robot is isolated, and the hints
//! that fetch their bins ahead. Each asks the parts whose boxes meet its square.

use monoculus_core::vision::Near;

use super::SegmentGrid;
use super::bands::Part;
use super::filter::LANES;
use super::prefetch::prefetch;

impl SegmentGrid {
    /// Asks for what [`SegmentGrid::isolated`] reads first about robot `k` (a hint).
    #[inline]
    pub fn prefetch_isolated(&self, k: usize) {
        prefetch(&self.rows.place[k]);
    }

    /// The parts of the rows' layout whose boxes meet the square of half-side `radius`
    /// around `(x, y)` (the first always: its box is every robot's).
    #[inline]
    fn parts_near(&self, x: f64, y: f64, radius: f64) -> impl Iterator<Item = &Part> {
        let (x0, x1, y0, y1) = (x - radius, x + radius, y - radius, y + radius);
        let parts = &self.rows.parts;
        parts
            .iter()
            .enumerate()
            .filter(move |(k, p)| *k == 0 || p.meets(x0, x1, y0, y1))
            .map(|(_, p)| p)
    }

    /// Calls `f` with every robot whose bin meets the square of half-side `radius`
    /// around `(x, y)` (a superset of the robots within `radius`).
    pub fn for_each_near(&self, x: f64, y: f64, radius: f64, f: &mut dyn FnMut(usize)) {
        let g = &self.rows;
        for part in self.parts_near(x, y, radius) {
            // The same bins of every band.
            let (c0, c1) = (part.bin(x - radius), part.bin(x + radius));
            for r in part.band(y - radius)..=part.band(y + radius) {
                for s in g.bins_range(part, r, c0, c1) {
                    f(g.items[s] as usize);
                }
            }
        }
    }

    /// Adds to `out` robots other than `skip` whose bin meets the square around
    /// `(x, y)` of half-side the spacing its part's bins are made for, until it is full:
    /// a few neighbours, however crowded the bins. The innermost part first, and in
    /// each the band through `(x, y)` first.
    pub fn near_few(&self, x: f64, y: f64, skip: usize, out: &mut Near) {
        let g = &self.rows;
        for part in g.parts.iter().rev() {
            let radius = part.spacing;
            if !part.meets(x - radius, x + radius, y - radius, y + radius) {
                continue;
            }
            let (low, mid, high) = (part.band(y - radius), part.band(y), part.band(y + radius));
            let bands = std::iter::once(mid).chain(low..mid).chain(mid + 1..=high);
            let (c0, c1) = (part.bin(x - radius), part.bin(x + radius));
            for r in bands {
                for s in g.bins_range(part, r, c0, c1) {
                    if out.is_full() {
                        return;
                    }
                    let k = g.items[s] as usize;
                    if k != skip {
                        out.push(k);
                    }
                }
            }
        }
    }

    /// Calls `f` with every robot that may lie within `radius` of `(x, y)`, every robot
    /// being within `drift` of the point the grid was built over: of the robots of the
    /// bins meeting the square of half-side `radius + drift`, those whose stored point
    /// is within `radius + drift` (of a [moving](SegmentGrid::moving) grid: whose disc
    /// comes within `radius`), with room for the rounding of stored coordinates. The
    /// test reads the bins' own coordinates, so that a crowded bin costs no read of
    /// the robots' positions beyond the few that pass. `drift` bounds every stored reach
    /// (each rounded up by at most a millionth of it).
    pub fn for_each_reaching(
        &self,
        x: f64,
        y: f64,
        radius: f64,
        drift: f64,
        f: &mut dyn FnMut(usize),
    ) {
        let g = &self.rows;
        let wide = radius + drift;
        if !self.single || !wide.is_finite() {
            return self.for_each_near(x, y, wide, f);
        }
        let extent = self.lo[0].abs() + self.lo[1].abs() + x.abs() + y.abs();
        let room = 4.0 * (self.rounding + drift * 2f64.powi(-23))
            + 16.0 * f64::EPSILON * extent
            + 1e-9 * radius;
        let (rx, ry) = (x - self.lo[0], y - self.lo[1]);
        // Each robot is tested first against a square around the query point in single
        // precision, which holds every stored point that the double-precision test
        // keeps. That test keeps a point u (a stored coordinate, exact in single
        // precision) only if |u - r| <= T (1 + 2^-50), T its radius (`within`, or
        // `radius + reach + room`), r the query's coordinate; the square tests
        // fl(u - fl(r)), off from u - r by at most 2^-24 |r| + 2^-24 |u - fl(r)|, so
        // by at most 2^-23 (T + |r|) for a kept point, against a half-side
        // B >= T + 2^-21 (T + |rx| + |ry|): `box32(w, d)` rounds up
        // w + 2^-20 (w + d + |rx| + |ry|), and a disc's half-side adds its reach
        // (at most `drift` (1 + 2^-19), as stored rounded up) to that of
        // `radius + room` in single precision, losing at most 2^-24 of the sum.
        // Tested at the boundary, also from far outside the swarm's box.
        let r32 = [rx as f32, ry as f32];
        let box32 = |w: f64, reach: f64| {
            let slack = 2f64.powi(-20) * (w + reach + rx.abs() + ry.abs());
            let b = (w + slack) as f32;
            if f64::from(b) < w + slack {
                b.next_up()
            } else {
                b
            }
        };
        #[inline(always)]
        fn near(&[u, v]: &[f32; 2], rx: f64, ry: f64, within: f64) -> bool {
            let (du, dv) = (f64::from(u) - rx, f64::from(v) - ry);
            du * du + dv * dv <= within * within
        }
        for part in self.parts_near(x, y, wide) {
            let (c0, c1) = (part.bin(x - wide), part.bin(x + wide));
            for r in part.band(y - wide)..=part.band(y + wide) {
                let slice = g.bins_range(part, r, c0, c1);
                // A band's robots tested LANES at a time, branch-free, in single
                // precision, into a mask (a radius query in a crowded core reads
                // hundreds, few of which pass); those that pass, in double precision.
                let coords = &g.coords;
                if g.reach.is_empty() {
                    let within = radius + drift + room;
                    let b = box32(within, drift);
                    each_passing(
                        slice,
                        f,
                        &g.items,
                        |s| in_squares(lanes(coords, s), r32, |_| b),
                        |s| near(&coords[s], rx, ry, within),
                    );
                } else {
                    let reach = &g.reach;
                    let b = box32(radius + room, drift);
                    each_passing(
                        slice,
                        f,
                        &g.items,
                        |s| {
                            let room = lanes(reach, s);
                            in_squares(lanes(coords, s), r32, |l| b + room[l])
                        },
                        |s| near(&coords[s], rx, ry, radius + f64::from(reach[s]) + room),
                    );
                }
            }
        }
    }

    /// Whether certainly no other robot lies within `radius` of robot `k`, where the
    /// grid was built: the robots of the bins near its stored point, tested on stored
    /// coordinates with room for their rounding. `false` when unsure (a radius not
    /// below the smallest bins' size, coordinates not finite in single precision).
    pub fn isolated(&self, k: usize, radius: f64) -> bool {
        let g = &self.rows;
        // Two stored coordinates are each off by at most `rounding` plus the double
        // rounding of the shift to the swarm's corner, and so is the point rebuilt
        // from them; twice that leaves room.
        let extent = self.lo[0].abs() + self.lo[1].abs() + self.hi[0].abs() + self.hi[1].abs();
        let reach = radius + 4.0 * self.rounding + 16.0 * f64::EPSILON * extent;
        if !self.single || reach.is_nan() || reach >= self.bin_size() {
            return false;
        }
        let s = g.place[k] as usize;
        let [x, y] = g.coords[s].map(f64::from);
        let (ax, ay) = (x + self.lo[0], y + self.lo[1]);
        self.parts_near(ax, ay, reach).all(|part| {
            let (c0, c1) = (part.bin(ax - reach), part.bin(ax + reach));
            (part.band(ay - reach)..=part.band(ay + reach)).all(|r| {
                g.bins_range(part, r, c0, c1).all(|t| {
                    let [u, v] = g.coords[t].map(f64::from);
                    t == s || (u - x).abs() > reach || (v - y).abs() > reach
                })
            })
        })
    }
}

/// The [`LANES`] entries of `v` from `s` on (a layout's arrays are padded so that a
/// chunk may run past the robots: those lanes are masked out).
#[inline(always)]
fn lanes<T>(v: &[T], s: usize) -> &[T; LANES] {
    <&[T; LANES]>::try_from(&v[s..s + LANES]).expect("LANES entries")
}

/// Whether each of the [`LANES`] stored points `chunk` lies in the square of half-side
/// `b(lane)` around `q`, each coordinate of the chunk tested on its own, branch-free.
#[inline(always)]
fn in_squares(chunk: &[[f32; 2]; LANES], q: [f32; 2], b: impl Fn(usize) -> f32) -> [bool; LANES] {
    let flat = chunk.as_flattened();
    let within: [bool; 2 * LANES] =
        std::array::from_fn(|i| (flat[i] - q[i & 1]).abs() <= b(i >> 1));
    std::array::from_fn(|l| within[2 * l] & within[2 * l + 1])
}

/// Calls `f(items[s])` for each place `s` of `places` (ascending) that passes both
/// tests: `chunk(s)`, which tests the [`LANES`] places from `s` at once, branch-free,
/// so that a chunk costs no branch unless one of its robots passes, then `exact(s)`.
#[inline(always)]
fn each_passing(
    places: std::ops::Range<usize>,
    f: &mut dyn FnMut(usize),
    items: &[u32],
    chunk: impl Fn(usize) -> [bool; LANES],
    exact: impl Fn(usize) -> bool,
) {
    let mut s = places.start;
    while s < places.end {
        let mut mask = 0u32;
        for (l, pass) in chunk(s).into_iter().enumerate() {
            mask |= u32::from(pass) << l;
        }
        mask &= (1 << LANES.min(places.end - s)) - 1;
        while mask != 0 {
            let at = s + mask.trailing_zeros() as usize;
            if exact(at) {
                f(items[at] as usize);
            }
            mask &= mask - 1;
        }
        s += LANES;
    }
}
