//! [`SpatialIndex`]: what an index over one snapshot answers. The dimension chooses the
//! index by type ([`IndexPoint::Index`](super::IndexPoint::Index)): the band grid in the
//! plane ([`PlaneIndex`](super::PlaneIndex)), an rstar R-tree in space
//! ([`SpaceIndex`](super::SpaceIndex)).

use monoculus_core::vision::VisionParams;

/// An index over the positions of one snapshot, built on first use. Every method is given
/// the positions the index was made for; every answer ends in the shared exact predicate,
/// so it is the brute-force oracle's (tested).
pub trait SpatialIndex<P>: Send + Sync + Sized {
    /// An index over `positions` (built when first asked).
    fn new(positions: &[P]) -> Self;

    /// An index for `now`, a later configuration of the swarm `previous` was made for
    /// (`before`): it may keep what `previous` built where few robots moved.
    fn after(previous: Self, before: &[P], now: &[P], same_vision: bool) -> Self;

    /// An index over `positions` that may [follow](SpatialIndex::follow) them as robots
    /// move (by default, one that cannot).
    fn following(positions: &[P]) -> Self {
        Self::new(positions)
    }

    /// Robots move: each `(k, p)` puts robot k at p in `pos`, the positions the index
    /// was made for. Returns whether the index answers for the new `pos` (else make a
    /// new one); answers after a follow are those of an index made afresh (by
    /// default it cannot follow).
    fn follow(&mut self, pos: &mut [P], changes: impl Iterator<Item = (u32, P)>) -> bool {
        for (k, p) in changes {
            pos[k as usize] = p;
        }
        false
    }

    /// Builds what is built on first use (a no-op for an index built at once), outside
    /// any parallel section: queries inside one would wait for whichever thread
    /// builds it.
    fn build(&self, _pos: &[P]) {}

    /// Robots that moved since the index in use was built (0 for a fresh one).
    fn stale_robots(&self) -> usize;

    /// Whether no robot blocks the view from `pos[i]` to `pos[j]` (two distinct points).
    fn clear(&self, pos: &[P], v: &VisionParams, i: usize, j: usize) -> bool;

    /// Calls `f` for every robot other than `i` within `radius` of it.
    fn for_each_within(&self, pos: &[P], i: usize, radius: f64, f: &mut dyn FnMut(usize));

    /// The robots other than `i` in order of distance from it.
    fn nearest_first<'a>(&'a self, pos: &'a [P], i: usize) -> Box<dyn Iterator<Item = usize> + 'a>;

    /// Calls `f` for every robot farther than `radius` from `i`.
    fn for_each_beyond(&self, pos: &[P], i: usize, radius: f64, f: &mut dyn FnMut(usize));

    /// Whether robot `j` is known to share its point with nobody (`false`: unknown).
    fn alone(&self, pos: &[P], v: &VisionParams, j: usize) -> bool;

    /// Robots in the cells around `i` (empty where the index has no cells).
    fn neighbours(&self, pos: &[P], i: usize) -> Vec<usize>;

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
