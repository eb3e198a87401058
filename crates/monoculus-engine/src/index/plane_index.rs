//! [`PlaneIndex`]: the band grid, for d = 2, kept across snapshots in which few robots
//! moved (those are [`Stale`]: skipped in its cells and tested one by one).

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU8, Ordering};

use glam::DVec2;
use monoculus_core::vision::{VisionParams, blocks, visible_points_sweep_2d};

use super::{SegmentGrid, SpatialIndex, Stale, prefetch};

/// The band grid over a snapshot in the plane.
pub struct PlaneIndex {
    /// The grid (built on first use, or inherited).
    grid: OnceLock<Box<SegmentGrid>>,
    /// The robots whose positions differ from those `grid` was built over.
    stale: Stale,
    /// Per robot, whether no other robot was within `eps_pos` of it where `grid` was
    /// built: 0 not asked yet, 1 yes, 2 no or unsure. Filled in as asked, by any thread
    /// (the answer does not depend on who asks).
    isolated: OnceLock<Box<[AtomicU8]>>,
}

impl PlaneIndex {
    fn grid(&self, pos: &[DVec2]) -> &SegmentGrid {
        self.grid.get_or_init(|| Box::new(SegmentGrid::new(pos)))
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
                let yes = self.grid(pos).isolated(k, v.eps_pos);
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
        }
    }

    /// Keeps `previous`'s grid if it was built and since then at most n / 64 robots moved
    /// (at least 8), all within the grid's box.
    fn after(previous: Self, before: &[DVec2], now: &[DVec2], same_vision: bool) -> Self {
        let fresh = || Self::new(now);
        let n = now.len();
        if before.len() != n {
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
        }
    }

    /// Builds the grid, both layouts at once (ASYNC builds a grid at every tick with
    /// Looks, between parallel decisions).
    fn build(&self, pos: &[DVec2]) {
        self.grid
            .get_or_init(|| Box::new(SegmentGrid::new_parallel(pos)));
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
        !grid.blocked(pos, i, j, v) && !self.stale.iter().any(blocker)
    }

    fn for_each_within(&self, pos: &[DVec2], i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        let p = pos[i];
        // The same exact test as the oracle, on the grid's candidates.
        let mut test = |k: usize| {
            if k != i && (pos[k] - p).length() <= radius {
                f(k);
            }
        };
        if self.stale.is_empty() {
            self.grid(pos).for_each_near(p.x, p.y, radius, &mut test);
        } else {
            self.grid(pos).for_each_near(p.x, p.y, radius, &mut |k| {
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
        Box::new(self.grid(pos).nearest_first(pos, i, &self.stale))
    }

    fn for_each_beyond(&self, pos: &[DVec2], i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        let grid = self.grid(pos);
        if self.stale.is_empty() {
            return grid.for_each_beyond(pos, i, radius, f);
        }
        grid.for_each_beyond(pos, i, radius, &mut |k| {
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
