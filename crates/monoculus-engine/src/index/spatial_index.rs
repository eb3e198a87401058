//! [`SpatialIndex`]: what an index over one snapshot answers. The dimension chooses the
//! index by type ([`IndexPoint::Index`](super::IndexPoint::Index)): the band grid in the
//! plane ([`PlaneIndex`](super::PlaneIndex)), an rstar R-tree in space
//! ([`SpaceIndex`](super::SpaceIndex)).

use monoculus_core::vision::{Near, VisionParams};

use super::Locate;

/// Every robot once, in an order in which robots near one another in space are near
/// one another ([`SpatialIndex::order`]), and each robot's rank in it.
#[derive(Clone, Copy, Debug)]
pub struct SpatialOrder<'a> {
    /// The robots, in order.
    pub robots: &'a [u32],
    /// Robot `k` is `robots[rank[k]]`.
    pub rank: &'a [u32],
}

/// An index over the positions of one snapshot, built on first use. Every query is given
/// where the robots are (`pos`: the positions the index was made for, or, for a
/// [moving](SpatialIndex::moving) index, where they are now); every answer ends in the
/// shared exact predicate, so it is the brute-force oracle's (tested).
pub trait SpatialIndex<P>: Send + Sync + Sized {
    /// An index over `positions` (built when first asked).
    fn new(positions: &[P]) -> Self;

    /// An index for `now`, a later configuration of the swarm `previous` was made for
    /// (`before`): it may keep what `previous` built where few robots moved.
    fn after(previous: Self, before: &[P], now: &[P], same_vision: bool) -> Self;

    /// Whether this index can be [moving](SpatialIndex::moving).
    fn can_move() -> bool {
        false
    }

    /// An index over `positions`, built now, whose robots then move (ASYNC): each may
    /// be given a disc it stays in ([`SpatialIndex::follow`]), and queries are asked
    /// with the robots where they are at the time. How far from its point a disc may
    /// reach is set by [`SpatialIndex::allow`] (until then, not at all). `None` where
    /// this index cannot follow robots (the R-tree: a new one is made at every tick).
    /// `one_tick`: it serves one tick only, every robot at its point (so its bins may
    /// be sized for the robots they hold, finer in a crowded core; an index that
    /// follows robots for longer has bins of one size, the drift widening every query
    /// being counted in them).
    fn moving(_positions: Vec<P>, _one_tick: bool) -> Option<Self> {
        None
    }

    /// The index [`SpatialIndex::moving`] makes over the points `fill` writes into an
    /// empty vector, made in the memory of `self`, a moving index over as many robots
    /// that is done with: its arrays are emptied and filled again rather than freed and
    /// allocated (under ASYNC the index is made again every few ticks). It may size its
    /// bins as `self` did while the swarm stays in the box it was made for (the band
    /// grid does, for up to 16 indexes in a row): the answers are the same.
    fn moving_again(self, fill: impl FnOnce(&mut Vec<P>), one_tick: bool) -> Option<Self> {
        Self::moving_filled(fill, one_tick)
    }

    /// The index [`SpatialIndex::moving`] makes over the points `fill` writes into an
    /// empty vector, made afresh.
    fn moving_filled(fill: impl FnOnce(&mut Vec<P>), one_tick: bool) -> Option<Self> {
        let mut positions = Vec::new();
        fill(&mut positions);
        Self::moving(positions, one_tick)
    }

    /// Of a [moving](SpatialIndex::moving) index: the side of its bins.
    fn bin_size(&self) -> f64 {
        unreachable!("only a moving index has bins to follow robots in")
    }

    /// Of a [moving](SpatialIndex::moving) index, before any robot is followed: how far
    /// from its point a robot's disc may reach.
    fn allow(&mut self, _limit: f64) {
        unreachable!("only a moving index follows robots")
    }

    /// Of a [moving](SpatialIndex::moving) index: the points it was made over.
    fn points(&self) -> &[P] {
        unreachable!("only a moving index keeps its points")
    }

    /// Of a [moving](SpatialIndex::moving) index: robot `k` stays within `reach` of
    /// `centre` from now until the index is made again (a robot given no disc stays at
    /// its point). A disc reaching farther than [allowed](SpatialIndex::allow) from the
    /// robot's point makes it stale: tested one by one, until the index is
    /// made again.
    fn follow(&mut self, _k: usize, _centre: P, _reach: f64) {
        unreachable!("only a moving index follows robots")
    }

    /// Builds what is built on first use (a no-op for an index built at once), outside
    /// any parallel section: queries inside one would wait for whichever thread
    /// builds it.
    fn build(&self, _pos: &[P]) {}

    /// The robots in an order that keeps those near one another in space together, if
    /// the index has one [built](SpatialIndex::build): decisions taken in that order
    /// share the parts of the index their queries read.
    fn order(&self) -> Option<SpatialOrder<'_>> {
        None
    }

    /// Robots that moved since the index in use was built (0 for a fresh one), or, of a
    /// moving index, the stale ones.
    fn stale_robots(&self) -> usize;

    /// Whether no robot blocks the view from `pos[i]` to `pos[j]` (two distinct points).
    fn clear<L: Locate<P> + ?Sized>(&self, pos: &L, v: &VisionParams, i: usize, j: usize) -> bool;

    /// Calls `f` for every robot other than `i` within `radius` of it.
    fn for_each_within<L: Locate<P> + ?Sized>(
        &self,
        pos: &L,
        i: usize,
        radius: f64,
        f: &mut dyn FnMut(usize),
    );

    /// The robots other than `i` in order of distance from it.
    fn nearest_first<'a, L: Locate<P> + ?Sized>(
        &'a self,
        pos: &'a L,
        i: usize,
    ) -> Box<dyn Iterator<Item = usize> + 'a>;

    /// Calls `f` for every robot farther than `radius` from `i`.
    fn for_each_beyond<L: Locate<P> + ?Sized>(
        &self,
        pos: &L,
        i: usize,
        radius: f64,
        f: &mut dyn FnMut(usize),
    );

    /// Whether robot `j` is known to share its point with nobody (`false`: unknown).
    fn alone<L: Locate<P> + ?Sized>(&self, pos: &L, v: &VisionParams, j: usize) -> bool;

    /// Robots in the bins around `i`, put in `near` (none where the index has no bins).
    fn neighbours<L: Locate<P> + ?Sized>(&self, pos: &L, i: usize, near: &mut Near);

    /// Every point `i` sees, each by the lowest index of its robots (a full look); `sees`
    /// is the sight's own line-of-sight test.
    fn visible_points(
        &self,
        pos: &[P],
        v: &VisionParams,
        i: usize,
        sees: &dyn Fn(usize) -> bool,
    ) -> Vec<usize>;
}
