//! [`SegmentGrid`]: a uniform grid for line-of-sight queries in the plane.
//!
//! Measured (`monoculus stress`, n = 10^5, density 1): three quarters of a
//! ConvergeLocality round went to R-tree traversals of the thin tubes along lines of
//! sight across the swarm, whose overlapping boxes make a long thin query visit many
//! nodes. The grid visits only the cells the tube crosses, column by column along the
//! segment's major axis, and tests their robots with a cheap perpendicular-distance
//! filter before the exact predicate. Candidates are a superset of the blockers, and
//! the decision is the shared [`blocks`](monoculus_core::vision::blocks), so answers
//! are those of the R-tree and of the brute-force oracle (tested).

use monoculus_core::geometry::Point;
use monoculus_core::vision::{VisionParams, blocks};

use super::{IndexPoint, Tube};

/// Robots bucketed by grid cell (compressed rows: cell `c` holds
/// `items[start[c]..start[c + 1]]`, ascending robot indices).
pub struct SegmentGrid {
    origin: [f64; 2],
    cell: f64,
    inv_cell: f64,
    nx: usize,
    ny: usize,
    start: Vec<u32>,
    items: Vec<u32>,
    /// The coordinates of `items`, in the same order: a cell's robots are contiguous.
    coords: Vec<[f64; 2]>,
}

impl SegmentGrid {
    /// A grid over the first two coordinates of `points`, about two robots per cell.
    pub fn new<P: Point>(points: &[P]) -> Self {
        let n = points.len().max(1);
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in points {
            for a in 0..2 {
                lo[a] = lo[a].min(p.axis(a));
                hi[a] = hi[a].max(p.axis(a));
            }
        }
        let ext = [(hi[0] - lo[0]).max(0.0), (hi[1] - lo[1]).max(0.0)];
        let longest = ext[0].max(ext[1]);
        // About two robots per cell, but never more cells than 4n (thin swarms).
        let by_area = (2.0 * ext[0] * ext[1] / n as f64).sqrt();
        let cell = by_area
            .max(longest / (2.0 * n as f64).sqrt())
            .max(longest * 1e-9)
            .max(1e-300);
        let nx = (ext[0] / cell) as usize + 1;
        let ny = (ext[1] / cell) as usize + 1;
        let mut grid = SegmentGrid {
            origin: lo,
            cell,
            inv_cell: 1.0 / cell,
            nx,
            ny,
            start: vec![0; nx * ny + 1],
            items: vec![0; points.len()],
            coords: vec![[0.0; 2]; points.len()],
        };
        let cells: Vec<usize> = points
            .iter()
            .map(|p| grid.cell_of(p.axis(0), p.axis(1)))
            .collect();
        for &c in &cells {
            grid.start[c + 1] += 1;
        }
        for c in 0..nx * ny {
            grid.start[c + 1] += grid.start[c];
        }
        let mut fill = grid.start.clone();
        for (i, &c) in cells.iter().enumerate() {
            grid.items[fill[c] as usize] = i as u32;
            grid.coords[fill[c] as usize] = [points[i].axis(0), points[i].axis(1)];
            fill[c] += 1;
        }
        grid
    }

    /// The cell index along `axis` of coordinate `v`, clamped to the grid (truncation
    /// equals floor here: negative values clamp to 0).
    #[inline]
    fn clamp(&self, v: f64, axis: usize) -> usize {
        let k = (v - self.origin[axis]) * self.inv_cell;
        let max = if axis == 0 { self.nx - 1 } else { self.ny - 1 };
        if k <= 0.0 { 0 } else { (k as usize).min(max) }
    }

    /// The side of a cell.
    pub fn cell_size(&self) -> f64 {
        self.cell
    }

    /// Calls `f` with every robot whose cell meets the square of half-side `radius`
    /// around `(x, y)` (a superset of the robots within `radius`).
    pub fn for_each_near(&self, x: f64, y: f64, radius: f64, f: &mut dyn FnMut(usize, [f64; 2])) {
        let (c0, c1) = (self.clamp(x - radius, 0), self.clamp(x + radius, 0));
        let (r0, r1) = (self.clamp(y - radius, 1), self.clamp(y + radius, 1));
        for row in r0..=r1 {
            let (a, b) = (
                self.start[row * self.nx + c0] as usize,
                self.start[row * self.nx + c1 + 1] as usize,
            );
            for k in a..b {
                f(self.items[k] as usize, self.coords[k]);
            }
        }
    }

    fn cell_of(&self, x: f64, y: f64) -> usize {
        self.clamp(y, 1) * self.nx + self.clamp(x, 0)
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
        let (p, q) = (positions[i], positions[j]);
        let tol = Tube::new(p, q, v.eps_ang).tolerance();
        let d = q - p;
        let len = d.length();
        let (px, py, dx, dy) = (p.axis(0), p.axis(1), d.axis(0), d.axis(1));
        let (len2, band) = (len * len, 2.0 * tol * len);
        // Walk along the major axis `a`, one column of cells at a time; in each column
        // visit the rows the tube can touch.
        let (a, b) = if d.axis(0).abs() >= d.axis(1).abs() {
            (0, 1)
        } else {
            (1, 0)
        };
        let (pa, pb, da, db) = (p.axis(a), p.axis(b), d.axis(a), d.axis(b));
        let (a_lo, a_hi) = (pa.min(pa + da) - tol, pa.max(pa + da) + tol);
        let (c0, c1) = (self.clamp(a_lo, a), self.clamp(a_hi, a));
        let slope = if da != 0.0 { db / da } else { 0.0 };
        for col in c0..=c1 {
            let x0 = (self.origin[a] + col as f64 * self.cell).max(a_lo);
            let x1 = (self.origin[a] + (col + 1) as f64 * self.cell).min(a_hi);
            let (y0, y1) = (pb + slope * (x0 - pa), pb + slope * (x1 - pa));
            let (r0, r1) = (
                self.clamp(y0.min(y1) - tol, b),
                self.clamp(y0.max(y1) + tol, b),
            );
            for row in r0..=r1 {
                let c = if a == 0 {
                    row * self.nx + col
                } else {
                    col * self.nx + row
                };
                for s in self.start[c] as usize..self.start[c + 1] as usize {
                    // Cheap filter on the cell's contiguous coordinates: within twice the
                    // tube's radius of the line, strictly between p and q.
                    let [x, y] = self.coords[s];
                    let (rx, ry) = (x - px, y - py);
                    let along = rx * dx + ry * dy;
                    if along <= 0.0 || along >= len2 || (rx * dy - ry * dx).abs() > band {
                        continue;
                    }
                    let k = self.items[s] as usize;
                    if k != i && k != j && blocks(p, positions[k], q, v) {
                        return true;
                    }
                }
            }
        }
        false
    }
}
