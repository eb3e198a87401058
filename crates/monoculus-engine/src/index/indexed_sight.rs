//! [`IndexedSight`]: the engine's [`Sight`], answered through the spatial index of the
//! points' dimension ([`IndexPoint::Index`]: the band grid in the plane, an rstar R-tree
//! in space).

use std::sync::OnceLock;

use monoculus_core::metrics::bounds;
use monoculus_core::vision::{Sight, VisionParams, distinct, in_range};

use super::{IndexPoint, SpatialIndex, SpatialOrder};

/// One snapshot of the swarm with a spatial index over it, built on first use.
///
/// - `sees(i, j)`: in the plane, a walk along the segment i -> j through the band grid;
///   in space, one R-tree tube query. Then the exact predicate on the few robots found.
/// - `for_each_within`, `nearest_first`, `for_each_beyond`: the grid's bins in the
///   plane (rings of bins, bins outside the disc), the tree's queries in space.
/// - `visible_points(i)` (a full look): the angular sweep in the plane (O(n log n)),
///   one tube query per robot in space.
///
/// A sight taken [after](IndexedSight::after) another in which few robots moved keeps
/// the other's grid: the robots that moved since it was built are stale, skipped in
/// its bins and tested one by one (late ConvergeQuadrant rounds move a handful of
/// robots out of thousands). ASYNC's Looks see through a moving index instead
/// ([`crate::asynchrony::TickSight`]).
///
/// The index is the dimension's own ([`IndexPoint::Index`]) unless chosen: `I =
/// SpaceIndex<DVec2>` puts the plane in an R-tree (`vision.backend = "rtree"`).
pub struct IndexedSight<P: IndexPoint, I: SpatialIndex<P> = <P as IndexPoint>::Index> {
    positions: Vec<P>,
    index: I,
    /// Hull vertices (plane), for farthest-robot questions (built on first use).
    hull: OnceLock<Vec<P>>,
    vision: VisionParams,
    /// The bounding box (computed on first use).
    bounds: OnceLock<(P, P)>,
}

impl<P: IndexPoint> IndexedSight<P> {
    /// A sight over `positions` with the dimension's index, built when first needed.
    pub fn new(positions: Vec<P>, vision: VisionParams) -> Self {
        Self::with_index(positions, vision)
    }
}

impl<P: IndexPoint, I: SpatialIndex<P>> IndexedSight<P, I> {
    /// A sight over `positions` with the index `I`, built when first needed.
    pub fn with_index(positions: Vec<P>, vision: VisionParams) -> Self {
        IndexedSight {
            bounds: OnceLock::new(),
            index: I::new(&positions),
            positions,
            hull: OnceLock::new(),
            vision,
        }
    }

    /// A sight over `positions`, a later configuration of the swarm `previous` saw. In
    /// the plane, if `previous` built its grid and since then at most n / 64 robots moved,
    /// all within the grid's box, the grid is kept and those robots are marked stale;
    /// otherwise as [`IndexedSight::new`]. Every answer is the same either way (tested).
    pub fn after(previous: Self, positions: Vec<P>, vision: VisionParams) -> Self {
        let index = I::after(
            previous.index,
            &previous.positions,
            &positions,
            previous.vision == vision,
        );
        IndexedSight {
            bounds: OnceLock::new(),
            index,
            positions,
            hull: OnceLock::new(),
            vision,
        }
    }

    /// Builds the index now (else it is built by the first query that needs it).
    pub fn build_index(&self) {
        self.index.build(&self.positions);
    }

    /// The robots in an order that keeps neighbours in space together, once the index
    /// is [built](IndexedSight::build_index) (in the plane; `None` in space).
    pub fn order(&self) -> Option<SpatialOrder<'_>> {
        self.index.order()
    }

    /// How many robots moved since the grid in use was built (0 for a fresh one).
    pub fn stale_robots(&self) -> usize {
        self.index.stale_robots()
    }

    /// Gives the positions back (to reuse the allocation).
    pub fn into_positions(self) -> Vec<P> {
        self.positions
    }
}

impl<P: IndexPoint, I: SpatialIndex<P>> Sight<P> for IndexedSight<P, I> {
    fn positions(&self) -> &[P] {
        &self.positions
    }

    fn vision(&self) -> &VisionParams {
        &self.vision
    }

    fn bounds(&self) -> (P, P) {
        *self.bounds.get_or_init(|| bounds(&self.positions))
    }

    fn sees(&self, i: usize, j: usize) -> bool {
        let (p, q) = (self.positions[i], self.positions[j]);
        if i == j || !distinct(p, q, &self.vision) || !in_range(p, q, &self.vision) {
            return false;
        }
        self.index
            .clear(self.positions.as_slice(), &self.vision, i, j)
    }

    fn for_each_within(&self, i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        self.index
            .for_each_within(self.positions.as_slice(), i, radius, f);
    }

    fn nearest_first(&self, i: usize) -> Box<dyn Iterator<Item = usize> + '_> {
        self.index.nearest_first(self.positions.as_slice(), i)
    }

    /// The farthest robot is a hull vertex: O(h) after the hull (O(n log n), once).
    fn farthest(&self, i: usize) -> f64 {
        let p = self.positions[i];
        let hull = self.hull.get_or_init(|| P::hull_vertices(&self.positions));
        let set: &[P] = if hull.is_empty() {
            &self.positions
        } else {
            hull
        };
        set.iter().map(|&q| (q - p).length()).fold(0.0, f64::max)
    }

    fn for_each_beyond(&self, i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        self.index
            .for_each_beyond(self.positions.as_slice(), i, radius, f);
    }

    fn alone(&self, j: usize) -> bool {
        self.index.alone(self.positions.as_slice(), &self.vision, j)
    }

    fn neighbours(&self, i: usize) -> Vec<usize> {
        self.index.neighbours(self.positions.as_slice(), i)
    }

    fn visible_points(&self, i: usize) -> Vec<usize> {
        self.index
            .visible_points(&self.positions, &self.vision, i, &|j| self.sees(i, j))
    }
}
