//! [`PlaneIndex`]: the band grid, for d = 2, kept across snapshots in which few robots
//! moved (those are [`Stale`]: skipped in its cells and tested one by one), or, under
//! ASYNC, [followed](SpatialIndex::follow) as robots move a little at every tick.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU8, Ordering};

use glam::DVec2;
use monoculus_core::vision::{VisionParams, blocks, visible_points_sweep_2d};

use super::{SegmentGrid, SpatialIndex, Stale, Tube, prefetch};

/// The band grid over a snapshot in the plane.
pub struct PlaneIndex {
    /// The grid (built on first use, or inherited).
    grid: OnceLock<Box<SegmentGrid>>,
    /// The robots whose positions differ from those `grid` was built over.
    stale: Stale,
    /// Per robot, whether no other robot was within `eps_pos` of it where `grid` was
    /// built: 0 not asked yet, 1 yes, 2 no or unsure. Filled in as asked, by any thread
    /// (the answer does not depend on who asks). Within `eps_pos` plus twice the
    /// drift limit of a followed index.
    isolated: OnceLock<Box<[AtomicU8]>>,
    /// Set for an index that follows moving robots.
    follow: Option<Follow>,
}

/// What a followed index knows of how far robots are from the points of its grid.
///
/// Every robot not stale is within `drift` of the point `base` holds for it, the
/// point the grid was built over, and `drift` never exceeds [`DRIFT_LIMIT`] cells: a
/// robot that moves farther becomes stale. Each query widens by `drift` what it
/// takes from the cells (the walk's tube, a radius, the reach of the rings of cells)
/// and ends in the same exact test on the current positions, so its answer is that of
/// a grid built afresh (tested with robots in mid-move).
#[derive(Debug)]
struct Follow {
    /// The positions the grid was built over (set when it is).
    base: OnceLock<Vec<DVec2>>,
    /// The largest squared distance of a robot not stale from its point in `base`, as
    /// computed.
    drift2: f64,
    /// Its root, rounded up: within it of the true distance.
    drift: f64,
}

/// The farthest a followed robot may be from its grid point before it is stale, in
/// cells (a tenth: measured a little faster than a quarter, see docs/performance.md).
const DRIFT_LIMIT: f64 = 0.1;

impl PlaneIndex {
    fn grid(&self, pos: &[DVec2]) -> &SegmentGrid {
        self.grid.get_or_init(|| Box::new(self.make(pos, false)))
    }

    fn make(&self, pos: &[DVec2], parallel: bool) -> SegmentGrid {
        if let Some(f) = &self.follow {
            // A new grid is built only where nothing moved since the index was made.
            let _ = f.base.set(pos.to_vec());
        }
        if parallel {
            SegmentGrid::new_parallel(pos)
        } else {
            SegmentGrid::new(pos)
        }
    }

    /// How far a robot not stale may be from its grid point.
    fn drift(&self) -> f64 {
        self.follow.as_ref().map_or(0.0, |f| f.drift)
    }

    /// The radius within which `isolated` tells other robots apart.
    fn isolation_radius(&self, grid: &SegmentGrid, v: &VisionParams) -> f64 {
        match self.follow {
            Some(_) => v.eps_pos + 2.0 * DRIFT_LIMIT * grid.cell_size(),
            None => v.eps_pos,
        }
    }

    /// Whether no robot other than `k` was within `eps_pos` of it where the grid was
    /// built.
    fn was_isolated(&self, pos: &[DVec2], v: &VisionParams, k: usize) -> bool {
        let known = self.isolated.get_or_init(|| {
            std::iter::repeat_with(|| AtomicU8::new(0))
                .take(pos.len())
                .collect()
        });
        match known[k].load(Ordering::Relaxed) {
            0 => {
                let grid = self.grid(pos);
                let yes = grid.isolated(k, self.isolation_radius(grid, v));
                known[k].store(if yes { 1 } else { 2 }, Ordering::Relaxed);
                yes
            }
            state => state == 1,
        }
    }
}

impl SpatialIndex<DVec2> for PlaneIndex {
    fn new(positions: &[DVec2]) -> Self {
        PlaneIndex {
            grid: OnceLock::new(),
            stale: Stale::none(positions.len()),
            isolated: OnceLock::new(),
            follow: None,
        }
    }

    fn following(positions: &[DVec2]) -> Self {
        PlaneIndex {
            follow: Some(Follow {
                base: OnceLock::new(),
                drift2: 0.0,
                drift: 0.0,
            }),
            ..Self::new(positions)
        }
    }

    /// Keeps `previous`'s grid if it was built and since then at most n / 64 robots moved
    /// (at least 8), all within the grid's box.
    fn after(previous: Self, before: &[DVec2], now: &[DVec2], same_vision: bool) -> Self {
        let fresh = || Self::new(now);
        let n = now.len();
        if before.len() != n || previous.follow.is_some() {
            return fresh();
        }
        let Some(grid) = previous.grid.into_inner() else {
            return fresh();
        };
        let limit = (n / 64).max(8);
        let mut stale = previous.stale;
        for (k, (was, is)) in before.iter().zip(now).enumerate() {
            if was != is {
                if !grid.covers(is.x, is.y) {
                    return fresh();
                }
                stale.insert(k);
            }
        }
        if stale.len() > limit {
            return fresh();
        }
        PlaneIndex {
            grid: OnceLock::from(grid),
            stale,
            // Still true of the robots that did not move, among themselves.
            isolated: if same_vision {
                previous.isolated
            } else {
                OnceLock::new()
            },
            follow: None,
        }
    }

    /// A robot that stays within a tenth of a cell of its grid point widens the drift
    /// every query allows for; one that goes farther is stale. `false` (make a new
    /// index) where more than n / 64 robots (at least 8) are stale or one left the grid's
    /// box.
    fn follow(&mut self, pos: &mut [DVec2], changes: impl Iterator<Item = (u32, DVec2)>) -> bool {
        let (Some(f), Some(grid)) = (self.follow.as_mut(), self.grid.get()) else {
            for (k, p) in changes {
                pos[k as usize] = p;
            }
            // A followed grid not built yet will be, over the positions of its first
            // query.
            return self.follow.is_some();
        };
        let base = f.base.get().expect("a followed grid records its points");
        let limit = DRIFT_LIMIT * grid.cell_size();
        let (limit2, mut drift2) = (limit * limit, f.drift2);
        let mut inside = true;
        for (k, p) in changes {
            let k = k as usize;
            if pos[k] == p {
                continue;
            }
            pos[k] = p;
            inside &= grid.covers(p.x, p.y);
            let d2 = (p - base[k]).length_squared();
            if d2 <= limit2 {
                drift2 = drift2.max(d2);
            } else {
                self.stale.insert(k);
            }
        }
        // Rounded up: the distance computed is within a few ulps of the true one.
        f.drift2 = drift2;
        f.drift = drift2.sqrt() * (1.0 + 1e-12) + f64::MIN_POSITIVE;
        inside && self.stale.len() <= (pos.len() / 64).max(8)
    }

    /// Builds the grid, both layouts at once (ASYNC builds a grid at every tick with
    /// Looks, between parallel decisions).
    fn build(&self, pos: &[DVec2]) {
        self.grid.get_or_init(|| Box::new(self.make(pos, true)));
    }

    fn stale_robots(&self) -> usize {
        self.stale.len()
    }

    fn clear(&self, pos: &[DVec2], v: &VisionParams, i: usize, j: usize) -> bool {
        // A visible robot is asked next whether it is alone (`Sight::alone`): what that
        // reads arrives during the walk (hints, no effect on results).
        let grid = self.grid(pos);
        if let Some(known) = self.isolated.get() {
            prefetch(&known[j]);
        }
        grid.prefetch_isolated(j);
        let (p, q) = (pos[i], pos[j]);
        let blocker = |k: usize| k != i && k != j && blocks(p, pos[k], q, v);
        if v.fat() {
            // The grid's walk follows a line, not a fat robot's disc: every robot is
            // asked (the engine sees fat robots through the R-tree instead).
            return !(0..pos.len()).any(blocker);
        }
        if grid.blocked(pos, i, j, v, self.drift()) {
            return false;
        }
        // A blocker lies within the tube's tolerance of the segment: a stale robot
        // farther from its line (with twice the room, for rounding) is not asked.
        let (d, tol) = (q - p, Tube::new(p, q, v.eps_ang, 0.0).tolerance());
        let reach = 2.0 * tol * d.length();
        !self
            .stale
            .iter()
            .any(|k| (pos[k] - p).perp_dot(d).abs() <= reach && blocker(k))
    }

    fn for_each_within(&self, pos: &[DVec2], i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        let p = pos[i];
        // The same exact test as the oracle, on the grid's candidates.
        let mut test = |k: usize| {
            if k != i && (pos[k] - p).length() <= radius {
                f(k);
            }
        };
        let radius_cells = radius + self.drift();
        if self.stale.is_empty() {
            self.grid(pos)
                .for_each_near(p.x, p.y, radius_cells, &mut test);
        } else {
            self.grid(pos)
                .for_each_near(p.x, p.y, radius_cells, &mut |k| {
                    if !self.stale.contains(k) {
                        test(k)
                    }
                });
            self.stale.iter().for_each(test);
        }
    }

    fn nearest_first<'a>(
        &'a self,
        pos: &'a [DVec2],
        i: usize,
    ) -> Box<dyn Iterator<Item = usize> + 'a> {
        Box::new(
            self.grid(pos)
                .nearest_first(pos, i, &self.stale, self.drift()),
        )
    }

    fn for_each_beyond(&self, pos: &[DVec2], i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        let grid = self.grid(pos);
        let drift = self.drift();
        if self.stale.is_empty() {
            return grid.for_each_beyond(pos, i, radius, drift, f);
        }
        grid.for_each_beyond(pos, i, radius, drift, &mut |k| {
            if !self.stale.contains(k) {
                f(k)
            }
        });
        let p = pos[i];
        for k in self.stale.iter() {
            if (pos[k] - p).length() > radius {
                f(k);
            }
        }
    }

    fn alone(&self, pos: &[DVec2], v: &VisionParams, j: usize) -> bool {
        if self.stale.contains(j) || !self.was_isolated(pos, v, j) {
            return false;
        }
        // Robots that did not move are where they were; the others are tested here.
        let p = pos[j];
        self.stale
            .iter()
            .all(|k| k == j || (pos[k] - p).length() > v.eps_pos)
    }

    fn neighbours(&self, pos: &[DVec2], i: usize) -> Vec<usize> {
        let p = pos[i];
        // About a dozen robots in the 2 x 3 cells around (pre-sized: grown one by one,
        // the vector cost a tenth of a round).
        let mut out = Vec::with_capacity(32);
        let grid = self.grid(pos);
        grid.for_each_near(p.x, p.y, grid.cell_size(), &mut |k| {
            if k != i {
                out.push(k);
            }
        });
        // Robots are mostly decided in index order, each thread a run of them: the next
        // one's cells are asked for now (a hint, no effect on results).
        if let Some(next) = pos.get(i + 1) {
            grid.prefetch_near(next.x, next.y, grid.cell_size());
        }
        // The first few are asked about at once (`count_visible_up_to`): their positions,
        // for the lines of sight (a hint, no effect on results).
        for &k in out.iter().take(4) {
            prefetch(&pos[k]);
        }
        out
    }

    /// The angular sweep, O(n log n); for fat robots one line of sight per robot.
    fn visible_points(
        &self,
        pos: &[DVec2],
        v: &VisionParams,
        i: usize,
        sees: &dyn Fn(usize) -> bool,
    ) -> Vec<usize> {
        if v.fat() {
            let seen: Vec<usize> = (0..pos.len()).filter(|&j| sees(j)).collect();
            return monoculus_core::vision::representatives(pos, &seen, v);
        }
        visible_points_sweep_2d(pos, i, v)
    }
}
