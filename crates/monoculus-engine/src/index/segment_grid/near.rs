//! Radius queries: the robots near a point, whether a robot is isolated, and the hints
//! that fetch their cells ahead. Each asks the parts whose boxes meet its square.

use super::SegmentGrid;
use super::bands::Part;
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

    /// Calls `f` with every robot whose cell meets the square of half-side `radius`
    /// around `(x, y)` (a superset of the robots within `radius`).
    pub fn for_each_near(&self, x: f64, y: f64, radius: f64, f: &mut dyn FnMut(usize)) {
        let g = &self.rows;
        for part in self.parts_near(x, y, radius) {
            // The same cells of every band.
            let (c0, c1) = (part.cell(x - radius), part.cell(x + radius));
            for r in part.band(y - radius)..=part.band(y + radius) {
                for s in g.cells_range(part, r, c0, c1) {
                    f(g.items[s] as usize);
                }
            }
        }
    }

    /// Appends to `out` up to `most` robots other than `skip` whose cell meets the
    /// square around `(x, y)` of half-side the spacing its part's cells are made for:
    /// a few neighbours, however crowded the cells. The innermost part first, and in
    /// each the band through `(x, y)` first.
    pub fn near_few(&self, x: f64, y: f64, skip: usize, most: usize, out: &mut Vec<usize>) {
        let g = &self.rows;
        for part in g.parts.iter().rev() {
            let radius = part.spacing;
            if !part.meets(x - radius, x + radius, y - radius, y + radius) {
                continue;
            }
            let (low, mid, high) = (part.band(y - radius), part.band(y), part.band(y + radius));
            let bands = std::iter::once(mid).chain(low..mid).chain(mid + 1..=high);
            let (c0, c1) = (part.cell(x - radius), part.cell(x + radius));
            for r in bands {
                for s in g.cells_range(part, r, c0, c1) {
                    if out.len() >= most {
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
    /// cells meeting the square of half-side `radius + drift`, those whose stored point
    /// is within `radius + drift` (of a [moving](SegmentGrid::moving) grid: whose disc
    /// comes within `radius`), with room for the rounding of stored coordinates. The
    /// test reads the cells' own coordinates, so that a crowded cell costs no read of
    /// the robots' positions beyond the few that pass.
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
        let near = |s: usize, reach: f64| {
            let [u, v] = g.coords[s].map(f64::from);
            let within = radius + reach + room;
            let (du, dv) = (u - rx, v - ry);
            du * du + dv * dv <= within * within
        };
        for part in self.parts_near(x, y, wide) {
            let (c0, c1) = (part.cell(x - wide), part.cell(x + wide));
            for r in part.band(y - wide)..=part.band(y + wide) {
                let slice = g.cells_range(part, r, c0, c1);
                if g.reach.is_empty() {
                    for s in slice {
                        if near(s, drift) {
                            f(g.items[s] as usize);
                        }
                    }
                } else {
                    for s in slice {
                        if near(s, f64::from(g.reach[s])) {
                            f(g.items[s] as usize);
                        }
                    }
                }
            }
        }
    }

    /// Whether certainly no other robot lies within `radius` of robot `k`, where the
    /// grid was built: the robots of the cells near its stored point, tested on stored
    /// coordinates with room for their rounding. `false` when unsure (a radius not
    /// below the smallest cells' size, coordinates not finite in single precision).
    pub fn isolated(&self, k: usize, radius: f64) -> bool {
        let g = &self.rows;
        // Two stored coordinates are each off by at most `rounding` plus the double
        // rounding of the shift to the swarm's corner, and so is the point rebuilt
        // from them; twice that leaves room.
        let extent = self.lo[0].abs() + self.lo[1].abs() + self.hi[0].abs() + self.hi[1].abs();
        let reach = radius + 4.0 * self.rounding + 16.0 * f64::EPSILON * extent;
        if !self.single || reach.is_nan() || reach >= self.cell_size() {
            return false;
        }
        let s = g.place[k] as usize;
        let [x, y] = g.coords[s].map(f64::from);
        let (ax, ay) = (x + self.lo[0], y + self.lo[1]);
        self.parts_near(ax, ay, reach).all(|part| {
            let (c0, c1) = (part.cell(ax - reach), part.cell(ax + reach));
            (part.band(ay - reach)..=part.band(ay + reach)).all(|r| {
                g.cells_range(part, r, c0, c1).all(|t| {
                    let [u, v] = g.coords[t].map(f64::from);
                    t == s || (u - x).abs() > reach || (v - y).abs() > reach
                })
            })
        })
    }
}
