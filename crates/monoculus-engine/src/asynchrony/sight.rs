//! [`LookSight`]: what ASYNC Looks see, kept from one tick to the next, and
//! [`TickSight`], the sight of one tick's Looks.

use std::collections::VecDeque;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, Ordering};

use bevy_ecs::prelude::*;
use monoculus_core::metrics::bounds;
use monoculus_core::vision::{Near, Sight, VisionParams, distinct, in_range};
use rayon::prelude::*;

use super::components::on_move;
use super::roster::Roster;
use super::{AheadShape, KeptShape, Timing};
use crate::IndexPoint;
use crate::index::{Locate, SpatialIndex, prefetch};
use crate::resources::{Params, SightBackend, SnapshotSight};
use crate::systems::build_sight;

/// The sight of ASYNC's Looks, kept across ticks. In the plane it is a band grid over
/// the positions of the tick it was made at ([`SpatialIndex::moving`]), which robots
/// leave as they move: each robot in mid-move is given, when its move starts, the disc
/// its segment sweeps until the grid's last tick (the segment is known from the Look
/// that decided it), so nothing is done for it at the ticks in between, and a Look's
/// queries place it on its segment only where they ask for it ([`TickSight`]). A robot
/// whose disc would reach farther than the grid's limit (two bins, or 1.25 after a
/// grid that served long) from where the grid holds it is stale: tested one by one.
/// The grid is made again at the first tick with Looks after its last tick, or when
/// too many robots are stale. So a tick costs its events and its Looks, whatever the
/// time resolution. Every answer is that of a sight taken afresh over the tick's
/// positions (tested, with robots in mid-move).
///
/// Elsewhere (space, the brute-force and R-tree backends, fat robots) a sight is taken
/// afresh at every tick with Looks.
#[derive(Resource)]
pub struct LookSight<P: IndexPoint> {
    /// Robots in mid-move.
    movers: Roster<Mover<P>>,
    /// The moving index, once made.
    moving: Option<Moving<P>>,
    /// The sight taken afresh, where no moving index is kept.
    snapshot: Option<SnapshotSight<P>>,
    /// Looks since the moving index was made.
    looks: usize,
    /// Decisions taken ahead of their Looks' ticks ([`LookSight::ahead_at`]): (tick,
    /// robot, displacement), in tick order, robots ascending within a tick.
    ahead: VecDeque<(u64, u32, Option<P>)>,
    /// The last tick whose Looks were decided ahead, if any.
    ahead_until: Option<u64>,
}

/// A robot in mid-move, as [`Timing::position_at`] reads it (where it started is its
/// settled position).
#[derive(Clone, Copy, Debug)]
struct Mover<P> {
    to: P,
    since: u64,
    until: u64,
}

impl<P: IndexPoint> Mover<P> {
    /// Where the robot is at `tick` ([`on_move`]: also before its move starts, for a
    /// move filed ahead, see [`LookSight::depart`]).
    #[inline]
    fn at(&self, from: P, tick: u64) -> P {
        on_move(from, self.to, self.since, self.until, tick)
    }

    /// A disc the robot, leaving `from`, stays in at every tick from `first` (at or
    /// after its start) to `last`: around the stretch of its segment between its
    /// positions at those ticks (once arrived, the robot is at `to` itself), with room
    /// for the rounding of the positions between.
    fn disc(&self, from: P, first: u64, last: u64) -> (P, f64) {
        let start = self.at(from, first);
        let end = if last >= self.until {
            self.to
        } else {
            self.at(from, last)
        };
        let scale = (0..P::DIM)
            .map(|a| from.axis(a).abs().max(self.to.axis(a).abs()))
            .fold(0.0, f64::max);
        let centre = (start + end) * 0.5;
        let reach = 0.5 * (end - start).length() * (1.0 + 1e-12) + 16.0 * f64::EPSILON * scale;
        (centre, reach)
    }
}

/// The moving index and what it was made over.
struct Moving<P: IndexPoint> {
    /// Over the positions at the tick it was made.
    index: P::Index,
    /// The tick it was made at.
    made: u64,
    /// The last tick at which the robots are within their discs.
    last: u64,
    /// Stale robots beyond which the index is made again.
    stale_limit: usize,
}

/// How far from its point a robot of the moving index may go, in bins...
const LIMIT: f64 = 2.0;
/// ...or after a grid that served [`LONG_LIFE`] ticks or more: a move at density 1 is
/// about a bin long, so that a robot's first move since the grid was made fits and a
/// second soon makes it stale, and the walks are widened by little more than a move.
/// Where grids serve a few ticks (a late swarm packed in a core whose bins are far
/// smaller than a move), the longer limit makes them less often (measured in
/// docs/performance.md).
const SHORT_LIMIT: f64 = 1.25;
/// The ticks a grid served beyond which the next has the shorter limit.
const LONG_LIFE: u64 = 128;
/// What a bin of drift adds to a Look (its walks visit that much more of the grid on
/// either side, and robots in mid-move are candidates more often), in robots' worth of
/// making the index (measured: about 3,000 instructions a Look against 280 a robot).
const DRIFT_COST: f64 = 11.0;

/// Robots in mid-move from which a new grid's work on them is shared between threads.
const PARALLEL_MOVERS: usize = 4096;

/// Stale robots beyond which the moving index is made again (they are tested one by
/// one in every query): n / 64, between 8 and 64.
fn stale_limit(n: usize) -> usize {
    (n / 64).clamp(8, 64)
}

impl<P: IndexPoint> LookSight<P> {
    /// For a swarm of `n` robots, all at rest.
    pub fn new(n: usize) -> Self {
        LookSight {
            movers: Roster::new(n),
            moving: None,
            snapshot: None,
            looks: 0,
            ahead: VecDeque::new(),
            ahead_until: None,
        }
    }

    /// The last tick up to which the Looks after `tick` may be decided now, at `tick`:
    /// none of them sees a decision taken at `tick` or later, since a Compute lasts at
    /// least `lead` ticks, and the moving index, [readied](LookSight::ready) at `tick`,
    /// serves them all. `None` where no tick after `tick` qualifies, where the Looks
    /// after `tick` were decided already, or where no moving index is kept.
    pub(crate) fn ahead_window(&self, params: &Params, tick: u64, lead: u64) -> Option<u64> {
        if !Self::moves(params) || self.ahead_until.is_some_and(|u| tick <= u) {
            return None;
        }
        let m = self.moving.as_ref().filter(|m| m.made <= tick)?;
        let last = m.last.min(tick.saturating_add(lead.saturating_sub(1)));
        (last > tick).then_some(last)
    }

    /// The sight at `tick`, after the current one and at most the last of its
    /// [window](LookSight::ahead_window), for a Look decided ahead: robots at rest at
    /// their points in `settled` (the current tick's), movers on their segments (those
    /// that arrive before `tick` at their targets, those whose Compute ends by then
    /// [departed](LookSight::depart) ahead). The swarm's hull and box, which `shape`
    /// gives for the current tick only, set `outlined`: a decision that asked for them
    /// is taken again at its own tick; but for the farthest robot where `ahead` tells
    /// it.
    pub(crate) fn ahead_at<'a>(
        &'a self,
        params: &Params,
        tick: u64,
        (settled, shape, ahead): (&'a [P], &'a KeptShape<P>, &'a AheadShape<P>),
        outlined: &'a AtomicBool,
    ) -> TickSight<'a, P, Located<'a, P>> {
        let m = self.moving.as_ref().expect("a window has a moving index");
        debug_assert!(m.made < tick && tick <= m.last);
        let at = Located {
            settled,
            movers: &self.movers,
            tick,
        };
        let mut sight = TickSight::new(at, settled.len(), &m.index, params.vision);
        sight.outlined = Some(outlined);
        sight.ahead = Some((ahead, tick));
        sight.with_shape(shape, tick)
    }

    /// Keeps the decisions taken ahead for the Looks up to tick `until` (`decided`:
    /// (tick, robot, displacement) in tick order, robots ascending within a tick; the
    /// Looks not listed are decided at their ticks), `looks` Looks in all; how many
    /// it keeps.
    pub(crate) fn keep_ahead(
        &mut self,
        until: u64,
        decided: impl IntoIterator<Item = (u64, u32, Option<P>)>,
        looks: usize,
    ) -> usize {
        let before = self.ahead.len();
        self.ahead.extend(decided);
        self.ahead_until = Some(until);
        self.looks += looks;
        self.ahead.len() - before
    }

    /// The decisions taken ahead for the Looks of `tick`, (robot, displacement) with the
    /// robots ascending, into `into`.
    pub(crate) fn take_ahead(&mut self, tick: u64, into: &mut Vec<(u32, Option<P>)>) {
        into.clear();
        while let Some(&(t, r, d)) = self.ahead.front() {
            if t > tick {
                break;
            }
            debug_assert_eq!(t, tick, "a Look decided ahead happens at its tick");
            into.push((r, d));
            self.ahead.pop_front();
        }
    }

    /// Robot `robot` starts a move from `from` (its clock says where to and when). The
    /// clock may be one still to come, for Looks decided ahead (docs/architecture.md):
    /// the robot is at `from` until the move starts, and told again then.
    pub fn depart(&mut self, robot: u32, from: P, timing: Timing<P>) {
        debug_assert!(timing.pending().is_some() && timing.phase == super::Phase::Move);
        let mover = Mover {
            to: timing.target(from),
            since: timing.since,
            until: timing.until,
        };
        self.movers.set(robot, mover);
        if let Some(m) = &mut self.moving
            && timing.since <= m.last
        {
            let (centre, reach) = mover.disc(from, timing.since, m.last);
            m.index.follow(robot as usize, centre, reach);
        }
    }

    /// Robot `robot` ended its move at tick `tick`, and is at rest at its target `at`.
    pub fn arrive(&mut self, robot: u32, at: P, tick: u64) {
        self.movers.remove(robot);
        if let Some(m) = &mut self.moving
            && tick <= m.last
        {
            m.index.follow(robot as usize, at, 0.0);
        }
    }

    /// Whether Looks use the moving index (else a snapshot of each tick).
    fn moves(params: &Params) -> bool {
        P::Index::can_move()
            && matches!(params.backend, SightBackend::Index)
            && !params.vision.fat()
    }

    /// Readies the moving index for `looks` Looks at `tick` (made again if it no
    /// longer serves), before [`LookSight::at`] gives the sight: apart, so that the
    /// index may be made while another thread refreshes the kept shape.
    pub fn ready(&mut self, params: &Params, tick: u64, settled: &[P], looks: usize) {
        if !Self::moves(params) {
            return;
        }
        let current = self
            .moving
            .as_ref()
            .is_some_and(|m| tick <= m.last && m.index.stale_robots() <= m.stale_limit);
        if !current {
            self.moving = self.remake(tick, settled);
            self.looks = 0;
        }
        self.looks += looks;
    }

    /// The sight at `tick`, [readied](LookSight::ready) for its Looks: robots at rest
    /// at their points in `settled`, movers on their segments. `shape`,
    /// [refreshed](KeptShape::refresh) at this tick, gives the points the swarm's hull
    /// and box are taken from.
    pub fn at<'a>(
        &'a mut self,
        params: &Params,
        tick: u64,
        settled: &'a [P],
        shape: &'a KeptShape<P>,
    ) -> Looking<'a, P> {
        let moving = Self::moves(params);
        let movers = &self.movers;
        let at = Located {
            settled,
            movers,
            tick,
        };
        if let Some(m) = self.moving.as_ref().filter(|_| moving) {
            // At the tick it was made, every robot is at the point the index holds.
            if m.made == tick {
                let base = m.index.points();
                let sight = TickSight::new(base, base.len(), &m.index, params.vision);
                return Looking::Made(sight.with_shape(shape, tick));
            }
            let sight = TickSight::new(at, settled.len(), &m.index, params.vision);
            return Looking::Moving(sight.with_shape(shape, tick));
        }
        let mut now = match self.snapshot.take() {
            Some(SnapshotSight::Index(s)) => s.into_positions(),
            Some(SnapshotSight::Rtree(s)) => s.into_positions(),
            Some(SnapshotSight::Exact(s)) => s.positions().to_vec(),
            None => Vec::new(),
        };
        now.clear();
        now.extend((0..settled.len()).map(|k| at.at(k)));
        Looking::Snapshot(self.snapshot.insert(build_sight(params, now)))
    }

    /// A moving index over the positions at `tick` (`None` where the dimension's index
    /// cannot move). Where Looks are many (at the rate since the last index, the drift
    /// a stretch of ticks would take would cost them more than making an index at
    /// every tick with Looks), it serves this tick only, with every robot at its point.
    /// Otherwise robots may go [`LIMIT`] bins from their points ([`SHORT_LIMIT`] after
    /// a grid that served [`LONG_LIFE`] ticks), and it serves until all but half the
    /// stale limit of the robots in mid-move would have gone farther; every robot in
    /// mid-move is given its disc up to that tick.
    fn remake(&mut self, tick: u64, settled: &[P]) -> Option<Moving<P>> {
        let old = self.moving.take();
        let rate = old.as_ref().map_or(f64::INFINITY, |m| {
            self.looks as f64 / (tick - m.made).max(1) as f64
        });
        // After a grid that served long, the shorter limit.
        let limit = match old.as_ref() {
            Some(m) if tick - m.made >= LONG_LIFE => SHORT_LIMIT,
            _ => LIMIT,
        };
        let n = settled.len();
        let one_tick = rate * DRIFT_COST * LIMIT >= n as f64;
        let movers = &self.movers;
        let fill = |base: &mut Vec<P>| {
            base.extend_from_slice(settled);
            for &(k, m) in movers.iter() {
                base[k as usize] = m.at(settled[k as usize], tick);
            }
        };
        // In the memory of the index it replaces.
        let mut index = match old {
            Some(old) => old.index.moving_again(fill, one_tick)?,
            None => P::Index::moving_filled(fill, one_tick)?,
        };
        let stale_limit = stale_limit(n);
        let limit = limit * index.bin_size();
        let last = if one_tick {
            tick
        } else {
            // The last tick each mover stays within the limit, for those that would
            // pass it (a little short of it: the disc taken then is that of the ends,
            // plus room for rounding). A mover's disc reaches as far from its point now
            // as the way it goes.
            let within = limit * (1.0 - 1e-6);
            let passes = |&(k, m): &(u32, Mover<P>)| {
                let from = settled[k as usize];
                if 2.0 * m.disc(from, tick, m.until).1 <= within {
                    return None;
                }
                let length = (m.to - from).length();
                let ticks = within / length * (m.until - m.since) as f64;
                Some(tick.saturating_add(ticks as u64))
            };
            // On both threads where the robots in mid-move are many (the late epochs of
            // fine-grained runs make a grid every two ticks).
            let movers = self.movers.as_slice();
            let mut passing: Vec<u64> = if movers.len() >= PARALLEL_MOVERS {
                movers
                    .par_iter()
                    .with_min_len(1024)
                    .filter_map(passes)
                    .collect()
            } else {
                movers.iter().filter_map(passes).collect()
            };
            let allowed = stale_limit / 2;
            if passing.len() <= allowed {
                u64::MAX
            } else {
                *passing.select_nth_unstable(allowed).1
            }
        };
        // An index for this tick only holds every robot at its point (none may leave
        // it, so that `alone` tells robots apart within `eps_pos`).
        index.allow(if last > tick { limit } else { 0.0 });
        if last > tick {
            for &(k, m) in self.movers.iter() {
                let (centre, reach) = m.disc(settled[k as usize], tick, last);
                index.follow(k as usize, centre, reach);
            }
        }
        Some(Moving {
            index,
            made: tick,
            last,
            stale_limit,
        })
    }
}

/// What the Looks of one tick see: through the moving index, or through a sight taken
/// afresh.
pub enum Looking<'a, P: IndexPoint> {
    /// Through the moving index, at the tick it was made (every robot at its point).
    Made(TickSight<'a, P, &'a [P]>),
    /// Through the moving index, robots in mid-move placed when asked.
    Moving(TickSight<'a, P, Located<'a, P>>),
    /// Taken afresh.
    Snapshot(&'a SnapshotSight<P>),
}

/// Where each robot is at one tick: at rest at its settled point, or in mid-move on its
/// segment, placed when asked.
#[derive(Clone, Copy)]
pub struct Located<'a, P: IndexPoint> {
    settled: &'a [P],
    movers: &'a Roster<Mover<P>>,
    tick: u64,
}

impl<P: IndexPoint> Locate<P> for Located<'_, P> {
    #[inline]
    fn at(&self, k: usize) -> P {
        match self.movers.get(k as u32) {
            Some(m) => m.at(self.settled[k], self.tick),
            None => self.settled[k],
        }
    }

    #[inline]
    fn prefetch(&self, k: usize) {
        if let Some(p) = self.settled.get(k) {
            prefetch(p);
        }
        self.movers.prefetch_slot(k as u32);
    }

    #[inline]
    fn prefetch_next(&self, k: usize) {
        self.movers.prefetch_item(k as u32);
    }
}

/// The [`Sight`] of one tick's Looks through the moving index: robots in mid-move are
/// placed on their segments when a query asks for them; what needs every position (a
/// full look, the hull for the farthest robot, the bounding box) gathers them once.
pub struct TickSight<'a, P: IndexPoint, L> {
    at: L,
    len: usize,
    index: &'a P::Index,
    vision: VisionParams,
    /// Where the points the swarm's hull and box are taken from come from, if not from
    /// every position.
    shape: Option<(&'a KeptShape<P>, u64)>,
    /// For a Look decided ahead: set when the hull or box is asked for...
    outlined: Option<&'a AtomicBool>,
    /// ...except where the farthest robot is found from these points at this tick.
    ahead: Option<(&'a AheadShape<P>, u64)>,
    all: OnceLock<Vec<P>>,
    hull: OnceLock<Vec<P>>,
    bounds: OnceLock<(P, P)>,
}

impl<'a, P: IndexPoint, L: Locate<P>> TickSight<'a, P, L> {
    fn new(at: L, len: usize, index: &'a P::Index, vision: VisionParams) -> Self {
        TickSight {
            at,
            len,
            index,
            vision,
            shape: None,
            outlined: None,
            ahead: None,
            all: OnceLock::new(),
            hull: OnceLock::new(),
            bounds: OnceLock::new(),
        }
    }
}

impl<'a, P: IndexPoint, L: Locate<P>> TickSight<'a, P, L> {
    /// The same sight, taking the swarm's hull and box from `shape`'s points at `tick`
    /// (in the plane) rather than from every position.
    fn with_shape(mut self, shape: &'a KeptShape<P>, tick: u64) -> Self {
        if P::DIM == 2 {
            self.shape = Some((shape, tick));
        }
        self
    }

    /// Points whose hull and box are the swarm's.
    fn outline(&self) -> std::borrow::Cow<'_, [P]> {
        if let Some(outlined) = self.outlined {
            outlined.store(true, Ordering::Relaxed);
        }
        match self.shape {
            Some((shape, tick)) => std::borrow::Cow::Owned(shape.points(tick)),
            None => std::borrow::Cow::Borrowed(self.positions()),
        }
    }
}

impl<'a, P: IndexPoint> TickSight<'a, P, &'a [P]> {
    /// A sight through the [moving](SpatialIndex::moving) `index` with the robots at
    /// `positions`, each within the disc the index was given for it (or stale): what
    /// ASYNC's Looks see, with the positions given whole (for tests and benchmarks).
    pub fn over(positions: &'a [P], index: &'a P::Index, vision: VisionParams) -> Self {
        TickSight::new(positions, positions.len(), index, vision)
    }
}

impl<P: IndexPoint, L: Locate<P>> Sight<P> for TickSight<'_, P, L> {
    fn positions(&self) -> &[P] {
        if let Some(all) = self.at.as_slice() {
            return all;
        }
        self.all
            .get_or_init(|| (0..self.len).map(|k| self.at.at(k)).collect())
    }

    #[inline]
    fn position(&self, i: usize) -> P {
        self.at.at(i)
    }

    fn len(&self) -> usize {
        self.len
    }

    fn vision(&self) -> &VisionParams {
        &self.vision
    }

    fn bounds(&self) -> (P, P) {
        *self.bounds.get_or_init(|| bounds(&self.outline()))
    }

    fn sees(&self, i: usize, j: usize) -> bool {
        let (p, q) = (self.at.at(i), self.at.at(j));
        if i == j || !distinct(p, q, &self.vision) || !in_range(p, q, &self.vision) {
            return false;
        }
        self.index.clear(&self.at, &self.vision, i, j)
    }

    fn for_each_within(&self, i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        self.index.for_each_within(&self.at, i, radius, f);
    }

    fn nearest_first(&self, i: usize) -> Box<dyn Iterator<Item = usize> + '_> {
        self.index.nearest_first(&self.at, i)
    }

    /// The farthest robot is a hull vertex.
    fn farthest(&self, i: usize) -> f64 {
        let p = self.at.at(i);
        if let Some(far) = self.ahead.and_then(|(shape, tick)| shape.farthest(p, tick)) {
            return far;
        }
        let hull = self.hull.get_or_init(|| {
            let points = self.outline();
            let hull = P::hull_vertices(&points);
            if hull.is_empty() {
                points.into_owned()
            } else {
                hull
            }
        });
        hull.iter().map(|&q| (q - p).length()).fold(0.0, f64::max)
    }

    fn for_each_beyond(&self, i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        self.index.for_each_beyond(&self.at, i, radius, f);
    }

    fn alone(&self, j: usize) -> bool {
        self.index.alone(&self.at, &self.vision, j)
    }

    fn neighbours(&self, i: usize, near: &mut Near) {
        self.index.neighbours(&self.at, i, near);
    }

    fn visible_points(&self, i: usize) -> Vec<usize> {
        self.index
            .visible_points(self.positions(), &self.vision, i, &|j| self.sees(i, j))
    }
}
