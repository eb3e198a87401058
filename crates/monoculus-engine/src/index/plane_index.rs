//! [`PlaneIndex`]: the band grid, for d = 2, kept across snapshots in which few robots
//! moved (those are [`Stale`]: skipped in its bins and tested one by one), or, under
//! ASYNC, [moving](SpatialIndex::moving): robots carry their own reach as they move.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU8, Ordering};

use glam::DVec2;
use monoculus_core::vision::{Near, VisionParams, blocks, visible_points_sweep_2d};

use super::{Locate, SegmentGrid, SpatialIndex, SpatialOrder, Stale, Tube, prefetch};

/// The band grid over a snapshot in the plane.
pub struct PlaneIndex {
    /// The grid (built on first use, or inherited).
    grid: OnceLock<Box<SegmentGrid>>,
    /// The robots whose positions differ from those `grid` was built over (of a moving
    /// index: those beyond its limit).
    stale: Stale,
    /// Per robot, whether no other robot was within `eps_pos` of it where `grid` was
    /// built: 0 not asked yet, 1 yes, 2 no or unsure. Filled in as asked, by any thread
    /// (the answer does not depend on who asks). Of a moving index: within `eps_pos`
    /// plus twice its limit.
    isolated: OnceLock<Box<[AtomicU8]>>,
    /// Set for an index over moving robots.
    moving: Option<Moving>,
}

/// What a moving index knows of where robots are.
///
/// Every robot not stale stays within a disc, stored in the grid in place of its point
/// (the line filter tests the disc), that lies within `drift` of the point the grid was
/// built over, its `base`; `drift` is at most `limit`. Each query widens by `drift` the
/// bins it takes (the walk's bands and bins, a radius, the reach of the rings of
/// bins) and ends in the same exact test on the current positions, so its answer is
/// that of a grid built afresh (tested with robots in mid-move).
///
/// A stale robot too stays within a disc (beyond the limit), kept in `discs` in the
/// order of the stale list: queries test it there before placing the robot.
#[derive(Debug)]
struct Moving {
    base: Vec<DVec2>,
    limit: f64,
    drift: f64,
    discs: Vec<(DVec2, f64)>,
}

/// Whether a robot within `reach` of `centre` may be within `radius` of `p` (with room
/// for rounding).
fn disc_may_reach(centre: DVec2, reach: f64, p: DVec2, radius: f64) -> bool {
    let d = (centre - p).length();
    d <= radius + reach * (1.0 + 1e-9) + 1e-12 * d
}

impl PlaneIndex {
    /// The grid, built over the positions of the first query if not yet (an index over
    /// moving robots is built when made).
    fn grid<L: Locate<DVec2> + ?Sized>(&self, pos: &L) -> &SegmentGrid {
        self.grid.get_or_init(|| {
            Box::new(SegmentGrid::new(
                pos.as_slice()
                    .expect("a grid is built over a snapshot's positions"),
            ))
        })
    }

    /// The stale robots, each with the disc it stays in (of a moving index).
    fn stale_robots_and_discs(&self) -> impl Iterator<Item = (usize, Option<(DVec2, f64)>)> + '_ {
        let discs = self.moving.as_ref().map(|m| m.discs.as_slice());
        self.stale
            .iter()
            .enumerate()
            .map(move |(x, k)| (k, discs.map(|d| d[x])))
    }

    /// How far a robot not stale may be from its grid point.
    fn drift(&self) -> f64 {
        self.moving.as_ref().map_or(0.0, |m| m.drift)
    }

    /// The radius within which `isolated` tells other robots apart.
    fn isolation_radius(&self, v: &VisionParams) -> f64 {
        match &self.moving {
            Some(m) => v.eps_pos + 2.0 * m.limit,
            None => v.eps_pos,
        }
    }

    /// Whether no robot other than `k` was within `eps_pos` of it where the grid was
    /// built.
    fn was_isolated<L: Locate<DVec2> + ?Sized>(&self, pos: &L, v: &VisionParams, k: usize) -> bool {
        let grid = self.grid(pos);
        let known = self.isolated.get_or_init(|| {
            std::iter::repeat_with(|| AtomicU8::new(0))
                .take(grid.len())
                .collect()
        });
        match known[k].load(Ordering::Relaxed) {
            0 => {
                let yes = grid.isolated(k, self.isolation_radius(v));
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
            moving: None,
        }
    }

    /// Keeps `previous`'s grid if it was built and since then at most n / 64 robots moved
    /// (at least 8), all within the grid's box.
    fn after(previous: Self, before: &[DVec2], now: &[DVec2], same_vision: bool) -> Self {
        let fresh = || Self::new(now);
        let n = now.len();
        if before.len() != n || previous.moving.is_some() {
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
            moving: None,
        }
    }

    fn can_move() -> bool {
        true
    }

    /// The grid, its two layouts built at once, with room for a disc per robot; nested
    /// parts over a crowded core only for one tick.
    fn moving(positions: Vec<DVec2>, one_tick: bool) -> Option<Self> {
        let grid = SegmentGrid::moving(&positions, one_tick);
        Some(PlaneIndex {
            grid: OnceLock::from(Box::new(grid)),
            stale: Stale::none(positions.len()),
            isolated: OnceLock::new(),
            moving: Some(Moving {
                base: positions,
                limit: 0.0,
                drift: 0.0,
                discs: Vec::new(),
            }),
        })
    }

    fn moving_again(self, fill: impl FnOnce(&mut Vec<DVec2>), one_tick: bool) -> Option<Self> {
        let (Some(moving), Some(grid)) = (self.moving, self.grid.into_inner()) else {
            return Self::moving_filled(fill, one_tick);
        };
        let mut base = moving.base;
        base.clear();
        fill(&mut base);
        let n = base.len();
        let grid = (*grid).moving_again(&base, one_tick, true);
        let mut stale = self.stale;
        stale.empty(n);
        let mut discs = moving.discs;
        discs.clear();
        // Not asked yet, of any robot.
        let isolated = self
            .isolated
            .into_inner()
            .filter(|known| known.len() == n)
            .map_or_else(OnceLock::new, |known| {
                for k in known.iter() {
                    k.store(0, Ordering::Relaxed);
                }
                OnceLock::from(known)
            });
        Some(PlaneIndex {
            grid: OnceLock::from(Box::new(grid)),
            stale,
            isolated,
            moving: Some(Moving {
                base,
                limit: 0.0,
                drift: 0.0,
                discs,
            }),
        })
    }

    fn points(&self) -> &[DVec2] {
        &self.moving.as_ref().expect("a moving index").base
    }

    fn bin_size(&self) -> f64 {
        self.grid
            .get()
            .expect("a moving index is built when made")
            .bin_size()
    }

    fn allow(&mut self, limit: f64) {
        self.moving.as_mut().expect("a moving index").limit = limit;
    }

    fn follow(&mut self, k: usize, centre: DVec2, reach: f64) {
        let m = self.moving.as_mut().expect("a moving index");
        if self.stale.contains(k) {
            let x = self.stale.iter().position(|s| s == k).expect("listed");
            m.discs[x] = (centre, reach);
            return;
        }
        // How far from its point the disc reaches, rounded up; a NaN makes the robot
        // stale.
        let excursion = ((centre - m.base[k]).length() + reach) * (1.0 + 1e-12);
        let within = matches!(
            excursion.partial_cmp(&m.limit),
            Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
        );
        if !within {
            self.stale.insert(k);
            m.discs.push((centre, reach));
            return;
        }
        m.drift = m.drift.max(excursion);
        self.grid
            .get_mut()
            .expect("a moving index is built when made")
            .set_disc(k, [centre.x, centre.y], reach);
    }

    /// Builds the grid, both layouts at once.
    fn build(&self, pos: &[DVec2]) {
        self.grid
            .get_or_init(|| Box::new(SegmentGrid::new_parallel(pos)));
    }

    /// The robots as the grid's horizontal bands hold them: band by band, bin by bin.
    fn order(&self) -> Option<SpatialOrder<'_>> {
        self.grid.get().map(|g| g.order())
    }

    fn stale_robots(&self) -> usize {
        self.stale.len()
    }

    fn clear<L: Locate<DVec2> + ?Sized>(
        &self,
        pos: &L,
        v: &VisionParams,
        i: usize,
        j: usize,
    ) -> bool {
        // A visible robot is asked next whether it is alone (`Sight::alone`): what that
        // reads arrives during the walk (hints, no effect on results).
        let grid = self.grid(pos);
        if let Some(known) = self.isolated.get() {
            prefetch(&known[j]);
        }
        grid.prefetch_isolated(j);
        let (p, q) = (pos.at(i), pos.at(j));
        let blocker = |k: usize| k != i && k != j && blocks(p, pos.at(k), q, v);
        if v.fat() {
            // The grid's walk follows a line, not a fat robot's disc: every robot is
            // asked (the engine sees fat robots through the R-tree instead).
            return !(0..grid.len()).any(blocker);
        }
        if grid.blocked(pos, i, j, v, self.drift()) {
            return false;
        }
        // A blocker lies within the tube's tolerance of the segment: a stale robot
        // farther from its line (with twice the room, for rounding) is not asked.
        let (d, tol) = (q - p, Tube::new(p, q, v.eps_ang, 0.0).tolerance());
        let len = d.length();
        let reach = 2.0 * tol * len;
        !self.stale_robots_and_discs().any(|(k, disc)| {
            if let Some((c, r)) = disc {
                let off = (c - p).perp_dot(d).abs();
                if off > reach + (r * (1.0 + 1e-9) + 1e-12 * (c - p).length()) * len {
                    return false;
                }
            }
            let r = pos.at(k);
            (r - p).perp_dot(d).abs() <= reach && k != i && k != j && blocks(p, r, q, v)
        })
    }

    fn for_each_within<L: Locate<DVec2> + ?Sized>(
        &self,
        pos: &L,
        i: usize,
        radius: f64,
        f: &mut dyn FnMut(usize),
    ) {
        let p = pos.at(i);
        // The same exact test as the oracle, on the grid's candidates.
        let mut test = |k: usize| {
            if k != i && (pos.at(k) - p).length() <= radius {
                f(k);
            }
        };
        let drift = self.drift();
        if self.stale.is_empty() {
            self.grid(pos)
                .for_each_reaching(p.x, p.y, radius, drift, &mut test);
        } else {
            self.grid(pos)
                .for_each_reaching(p.x, p.y, radius, drift, &mut |k| {
                    if !self.stale.contains(k) {
                        test(k)
                    }
                });
            for (k, disc) in self.stale_robots_and_discs() {
                if disc.is_none_or(|(c, r)| disc_may_reach(c, r, p, radius)) {
                    test(k);
                }
            }
        }
    }

    fn nearest_first<'a, L: Locate<DVec2> + ?Sized>(
        &'a self,
        pos: &'a L,
        i: usize,
    ) -> Box<dyn Iterator<Item = usize> + 'a> {
        Box::new(
            self.grid(pos)
                .nearest_first(pos, i, &self.stale, self.drift()),
        )
    }

    fn for_each_beyond<L: Locate<DVec2> + ?Sized>(
        &self,
        pos: &L,
        i: usize,
        radius: f64,
        f: &mut dyn FnMut(usize),
    ) {
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
        let p = pos.at(i);
        for k in self.stale.iter() {
            if (pos.at(k) - p).length() > radius {
                f(k);
            }
        }
    }

    fn alone<L: Locate<DVec2> + ?Sized>(&self, pos: &L, v: &VisionParams, j: usize) -> bool {
        if self.stale.contains(j) || !self.was_isolated(pos, v, j) {
            return false;
        }
        // Robots that did not move are where they were; the others are tested here.
        let p = pos.at(j);
        self.stale_robots_and_discs().all(|(k, disc)| {
            k == j
                || disc.is_some_and(|(c, r)| !disc_may_reach(c, r, p, v.eps_pos))
                || (pos.at(k) - p).length() > v.eps_pos
        })
    }

    fn neighbours<L: Locate<DVec2> + ?Sized>(&self, pos: &L, i: usize, near: &mut Near) {
        let p = pos.at(i);
        // About a dozen robots in the 2 x 3 bins around, at most 32 where a dense core
        // crowds them.
        let grid = self.grid(pos);
        grid.near_few(p.x, p.y, i, near);
        // The first few are asked about at once (`count_visible_up_to`): their positions,
        // for the lines of sight (a hint, no effect on results).
        for &k in near.as_slice().iter().take(4) {
            pos.prefetch(k);
        }
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
