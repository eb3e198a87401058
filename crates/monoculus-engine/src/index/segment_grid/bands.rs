//! [`Bands`]: the layout of the grid, robots bucketed in bands across one axis, each band
//! cut into cells along the other.

use monoculus_core::geometry::Point;

use super::filter::LANES;
use super::slots::slot;

/// Band height and cell width, in units of the mean spacing sqrt(area / n): thinner
/// bands test fewer robots per line in more slices (the choice is measured in
/// docs/performance.md).
pub(super) const BAND: f64 = 2.0;
pub(super) const CELL: f64 = 1.0;

/// Robots bucketed in bands across one axis, each band cut into cells along the other
/// (the run axis), in compressed rows: cell `c` of band `r` holds
/// `items[start[k]..start[k + 1]]` with `k = r * cells + c`, ascending robot indices, so
/// consecutive cells of one band are one slice.
pub(super) struct Bands {
    /// The axis a band runs along (0: x, 1: y); bands are stacked along the other.
    pub(super) run: usize,
    /// The smallest coordinate on the run axis and across it.
    pub(super) origin: [f64; 2],
    pub(super) inv_width: f64,
    pub(super) height: f64,
    pub(super) inv_height: f64,
    pub(super) cells: usize,
    pub(super) bands: usize,
    /// The last cell and band, as floats.
    pub(super) last: [f64; 2],
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
    /// [`SegmentGrid::set_reach`]).
    pub(super) reach: Vec<f32>,
}

impl Bands {
    /// `lo` and `hi` in (x, y) order.
    pub(super) fn new<P: Point>(
        points: &[P],
        run: usize,
        lo: [f64; 2],
        hi: [f64; 2],
        spacing: f64,
    ) -> Self {
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
            reach: Vec::new(),
        };
        let slot: Vec<u32> = points
            .iter()
            .map(|p| {
                let (c, r) = (grid.cell(p.axis(run)), grid.band(p.axis(across)));
                (r * cells + c) as u32
            })
            .collect();
        // A counting sort with no second array of cells (a grid can have 16n of them):
        // each cell's end, then its robots placed from the last one down, which leaves
        // its start there and its robots ascending.
        for &k in &slot {
            grid.start[k as usize] += 1;
        }
        let mut end = 0;
        for c in &mut grid.start[..cells * bands] {
            end += *c;
            *c = end;
        }
        grid.start[cells * bands] = end;
        for (i, &k) in slot.iter().enumerate().rev() {
            grid.start[k as usize] -= 1;
            let at = grid.start[k as usize] as usize;
            grid.items[at] = i as u32;
            grid.place[i] = at as u32;
            grid.coords[at] = [
                (points[i].axis(0) - lo[0]) as f32,
                (points[i].axis(1) - lo[1]) as f32,
            ];
        }
        grid
    }

    /// The cell (along the run axis) of coordinate `v`, clamped to the grid.
    #[inline]
    pub(super) fn cell(&self, v: f64) -> usize {
        slot(v, self.origin[0], self.inv_width, self.last[0])
    }

    /// The band of coordinate `v` across the run axis, clamped to the grid.
    #[inline]
    pub(super) fn band(&self, v: f64) -> usize {
        slot(v, self.origin[1], self.inv_height, self.last[1])
    }

    /// The robots of band `r` in cells `c0..=c1`: indices into `items` and `coords`.
    #[inline]
    pub(super) fn cells_range(&self, r: usize, c0: usize, c1: usize) -> std::ops::Range<usize> {
        let row = r * self.cells;
        self.start[row + c0] as usize..self.start[row + c1 + 1] as usize
    }

    /// The lower edge of cell `c` on the run axis and of band `r` across it.
    #[inline]
    pub(super) fn corner(&self, c: usize, r: usize) -> (f64, f64) {
        (
            self.origin[0] + c as f64 / self.inv_width,
            self.origin[1] + r as f64 * self.height,
        )
    }

    /// The robots of band `r` in the cells meeting `[lo, hi]` on the run axis: indices
    /// into `items` and `coords`.
    #[inline]
    pub(super) fn slice(&self, r: usize, lo: f64, hi: f64) -> std::ops::Range<usize> {
        let row = r * self.cells;
        self.start[row + self.cell(lo)] as usize..self.start[row + self.cell(hi) + 1] as usize
    }
}
