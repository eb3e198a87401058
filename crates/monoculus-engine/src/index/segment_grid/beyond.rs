//! The robots beyond a radius of a point (for ConvergeLocality's far targets).

use monoculus_core::geometry::Point;

use super::super::Locate;
use super::SegmentGrid;

impl SegmentGrid {
    /// Calls `f` with every robot farther than `radius` from robot `i`: per band of each
    /// part, the bins wholly within the disc are skipped. O(bands + robots beyond +
    /// boundary).
    /// Every robot is within `drift` of the point the grid was built over.
    pub fn for_each_beyond<P: Point, L: Locate<P> + ?Sized>(
        &self,
        positions: &L,
        i: usize,
        radius: f64,
        drift: f64,
        f: &mut dyn FnMut(usize),
    ) {
        let p = positions.at(i);
        let (x, y) = (p.axis(0), p.axis(1));
        let g = &self.rows;
        // A robot whose grid point is within `inside` of p is within `radius` of it.
        let inside = radius - drift;
        let mut emit = |range: std::ops::Range<usize>| {
            for s in range {
                let k = g.items[s] as usize;
                if (positions.at(k) - p).length() > radius {
                    f(k);
                }
            }
        };
        for part in &g.parts {
            // Room for the rounding of bin edges and of robots' bins.
            let room = 1e-9 * (x.abs() + y.abs() + part.spacing);
            for r in 0..part.bands {
                let (_, y0) = part.corner(0, r);
                let dy = (y - y0).abs().max((y0 + part.height - y).abs()) + room;
                // The band's robots within `inner` of x on the run axis are within the
                // disc.
                let inner = if dy < inside {
                    (inside * inside - dy * dy).sqrt() * (1.0 - 1e-9) - room
                } else {
                    -1.0
                };
                let last = part.bins - 1;
                if inner <= 0.0 {
                    emit(g.bins_range(part, r, 0, last));
                    continue;
                }
                let (ca, cb) = (part.bin(x - inner), part.bin(x + inner));
                if cb <= ca + 1 {
                    emit(g.bins_range(part, r, 0, last));
                } else {
                    emit(g.bins_range(part, r, 0, ca));
                    emit(g.bins_range(part, r, cb, last));
                }
            }
        }
    }
}
