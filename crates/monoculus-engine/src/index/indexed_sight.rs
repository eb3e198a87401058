//! [`IndexedSight`]: the engine's [`Sight`], answered through a spatial index: the
//! [`SegmentGrid`] in the plane, an rstar R-tree in space.

use std::any::Any;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU8, Ordering};

use glam::DVec2;
use monoculus_core::metrics::bounds;
use monoculus_core::vision::{
    Sight, VisionParams, blocks, distinct, representatives, visible_points_sweep_2d,
};
use rstar::{RTree, primitives::GeomWithData};

use super::{IndexPoint, SegmentGrid, Stale, Tube, prefetch};

/// One snapshot of the swarm with a spatial index over it, built on first use.
///
/// - `sees(i, j)`: in the plane, a walk along the segment i -> j through the band grid;
///   in space, one R-tree tube query. Then the exact predicate on the few robots found.
/// - `for_each_within`, `nearest_first`, `for_each_beyond`: the grid's cells in the
///   plane (rings of cells, cells outside the disc), the tree's queries in space.
/// - `visible_points(i)` (a full look): the angular sweep in the plane (O(n log n)),
///   one tube query per robot otherwise.
///
/// A sight taken [after](IndexedSight::after) another in which few robots moved keeps
/// the other's grid: the robots that moved since it was built are [`Stale`], skipped in
/// its cells and tested one by one (late ConvergeQuadrant rounds move a handful of
/// robots out of thousands, and rebuilding the grid was a fifth of such a round).
pub struct IndexedSight<P: IndexPoint> {
    positions: Vec<P>,
    /// In space, built on the first visibility question: many activations (OLA inner
    /// robots) need only the bounding box. Never built in the plane.
    tree: OnceLock<RTree<GeomWithData<P::Array, u32>>>,
    /// In the plane, the index (built on first use, or inherited).
    grid: OnceLock<Box<SegmentGrid>>,
    /// The robots whose positions differ from those `grid` was built over.
    stale: Stale,
    /// In the plane, per robot, whether no other robot was within `eps_pos` of it
    /// where `grid` was built: 0 not asked yet, 1 yes, 2 no or unsure. Filled in as
    /// asked, by any thread (the answer does not depend on who asks).
    isolated: OnceLock<Box<[AtomicU8]>>,
    /// Hull vertices (plane), for farthest-robot questions (built on first use).
    hull: OnceLock<Vec<P>>,
    vision: VisionParams,
    bounds: (P, P),
}

impl<P: IndexPoint> IndexedSight<P> {
    /// A sight over `positions`; the index is bulk-loaded (O(n log n)) when first needed.
    pub fn new(positions: Vec<P>, vision: VisionParams) -> Self {
        let bounds = bounds(&positions);
        IndexedSight {
            stale: Stale::none(positions.len()),
            positions,
            tree: OnceLock::new(),
            grid: OnceLock::new(),
            isolated: OnceLock::new(),
            hull: OnceLock::new(),
            vision,
            bounds,
        }
    }

    /// A sight over `positions`, a later configuration of the swarm `previous` saw. If
    /// `previous` built its grid and since then at most n / 64 robots moved, all within
    /// the grid's box, the grid is kept and those robots are marked stale; otherwise as
    /// [`IndexedSight::new`]. Every answer is the same either way (tested).
    pub fn after(previous: Self, positions: Vec<P>, vision: VisionParams) -> Self {
        let mut next = Self::new(positions, vision);
        let n = next.positions.len();
        if P::DIM != 2 || previous.positions.len() != n {
            return next;
        }
        let Some(grid) = previous.grid.into_inner() else {
            return next;
        };
        let limit = (n / 64).max(8);
        let mut stale = previous.stale;
        for (k, (was, now)) in previous.positions.iter().zip(&next.positions).enumerate() {
            if was != now {
                if !grid.covers(now.axis(0), now.axis(1)) {
                    return next;
                }
                stale.insert(k);
            }
        }
        if stale.len() > limit {
            return next;
        }
        next.stale = stale;
        next.grid = OnceLock::from(grid);
        // Still true of the robots that did not move, among themselves.
        if previous.vision == vision {
            next.isolated = previous.isolated;
        }
        next
    }

    /// How many robots moved since the grid in use was built (0 for a fresh one).
    pub fn stale_robots(&self) -> usize {
        self.stale.len()
    }

    fn grid(&self) -> &SegmentGrid {
        self.grid
            .get_or_init(|| Box::new(SegmentGrid::new(&self.positions)))
    }

    /// Whether no robot other than `k` was within `eps_pos` of it where the grid was
    /// built.
    fn was_isolated(&self, k: usize) -> bool {
        let known = self.isolated.get_or_init(|| {
            std::iter::repeat_with(|| AtomicU8::new(0))
                .take(self.positions.len())
                .collect()
        });
        match known[k].load(Ordering::Relaxed) {
            0 => {
                let yes = self.grid().isolated(k, self.vision.eps_pos);
                known[k].store(if yes { 1 } else { 2 }, Ordering::Relaxed);
                yes
            }
            state => state == 1,
        }
    }

    fn tree(&self) -> &RTree<GeomWithData<P::Array, u32>> {
        self.tree.get_or_init(|| {
            let items: Vec<GeomWithData<P::Array, u32>> = self
                .positions
                .iter()
                .enumerate()
                .map(|(i, p)| GeomWithData::new(p.to_array(), i as u32))
                .collect();
            RTree::bulk_load(items)
        })
    }

    /// Gives the positions back (to reuse the allocation).
    pub fn into_positions(self) -> Vec<P> {
        self.positions
    }
}

impl<P: IndexPoint> Sight<P> for IndexedSight<P> {
    fn positions(&self) -> &[P] {
        &self.positions
    }

    fn vision(&self) -> &VisionParams {
        &self.vision
    }

    fn bounds(&self) -> (P, P) {
        self.bounds
    }

    fn sees(&self, i: usize, j: usize) -> bool {
        let (p, q) = (self.positions[i], self.positions[j]);
        if i == j || !distinct(p, q, &self.vision) {
            return false;
        }
        if P::DIM == 2 {
            // A visible robot is asked next whether it is alone (`Sight::alone`): what
            // that reads arrives during the walk (hints, no effect on results).
            let grid = self.grid();
            if let Some(known) = self.isolated.get() {
                prefetch(&known[j]);
            }
            grid.prefetch_isolated(j);
            let blocker =
                |k: usize| k != i && k != j && blocks(p, self.positions[k], q, &self.vision);
            return !grid.blocked(&self.positions, i, j, &self.vision)
                && !self.stale.iter().any(blocker);
        }
        let tube = Tube::new(p, q, self.vision.eps_ang);
        !self
            .tree()
            .locate_with_selection_function(tube)
            .any(|leaf| {
                let k = leaf.data as usize;
                k != i && k != j && blocks(p, self.positions[k], q, &self.vision)
            })
    }

    fn for_each_within(&self, i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        let p = self.positions[i];
        if P::DIM == 2 {
            // The same exact test as the oracle, on the grid's candidates.
            let mut test = |k: usize| {
                if k != i && (self.positions[k] - p).length() <= radius {
                    f(k);
                }
            };
            if self.stale.is_empty() {
                self.grid()
                    .for_each_near(p.axis(0), p.axis(1), radius, &mut test);
            } else {
                self.grid()
                    .for_each_near(p.axis(0), p.axis(1), radius, &mut |k| {
                        if !self.stale.contains(k) {
                            test(k)
                        }
                    });
                self.stale.iter().for_each(test);
            }
            return;
        }
        // Ask the tree for a slightly larger radius, then decide with the same test as
        // the oracle, so both agree on points at the boundary.
        let r2 = radius * radius * (1.0 + 1e-12) + f64::MIN_POSITIVE;
        for leaf in self.tree().locate_within_distance(p.to_array(), r2) {
            let k = leaf.data as usize;
            if k != i && (self.positions[k] - p).length() <= radius {
                f(k);
            }
        }
    }

    fn nearest_first(&self, i: usize) -> Box<dyn Iterator<Item = usize> + '_> {
        if P::DIM == 2 {
            return Box::new(self.grid().nearest_first(&self.positions, i, &self.stale));
        }
        let p = self.positions[i].to_array();
        Box::new(
            self.tree()
                .nearest_neighbor_iter(p)
                .map(|leaf| leaf.data as usize)
                .filter(move |&k| k != i),
        )
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

    /// R-tree nodes entirely within `radius` are skipped: O(robots beyond + boundary).
    fn for_each_beyond(&self, i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        if P::DIM == 2 {
            let grid = self.grid();
            if self.stale.is_empty() {
                return grid.for_each_beyond(&self.positions, i, radius, f);
            }
            grid.for_each_beyond(&self.positions, i, radius, &mut |k| {
                if !self.stale.contains(k) {
                    f(k)
                }
            });
            let p = self.positions[i];
            for k in self.stale.iter() {
                if (self.positions[k] - p).length() > radius {
                    f(k);
                }
            }
            return;
        }
        let p = self.positions[i];
        let selection = Beyond::<P> {
            centre: p.to_array(),
            radius2: radius * radius * (1.0 - 1e-12),
        };
        for leaf in self.tree().locate_with_selection_function(selection) {
            let k = leaf.data as usize;
            if (self.positions[k] - p).length() > radius {
                f(k);
            }
        }
    }

    fn alone(&self, j: usize) -> bool {
        if P::DIM != 2 || self.stale.contains(j) || !self.was_isolated(j) {
            return false;
        }
        // Robots that did not move are where they were; the others are tested here.
        let (p, eps) = (self.positions[j], self.vision.eps_pos);
        self.stale
            .iter()
            .all(|k| k == j || (self.positions[k] - p).length() > eps)
    }

    fn neighbours(&self, i: usize) -> Vec<usize> {
        if P::DIM != 2 {
            return Vec::new();
        }
        let p = self.positions[i];
        // About a dozen robots in the 2 x 3 cells around (grown one by one, the vector
        // was a tenth of a ConvergeLocality round).
        let mut out = Vec::with_capacity(32);
        let grid = self.grid();
        grid.for_each_near(p.axis(0), p.axis(1), grid.cell_size(), &mut |k| {
            if k != i {
                out.push(k);
            }
        });
        // Robots are mostly decided in index order, each thread a run of them: the
        // next one's cells are asked for now (a hint, no effect on results).
        if let Some(next) = self.positions.get(i + 1) {
            grid.prefetch_near(next.axis(0), next.axis(1), grid.cell_size());
        }
        // The first few are asked about at once (`count_visible_up_to`): their
        // positions, for the lines of sight (a hint, no effect on results).
        for &k in out.iter().take(4) {
            prefetch(&self.positions[k]);
        }
        out
    }

    fn visible_points(&self, i: usize) -> Vec<usize> {
        if let Some(plane) = (&self.positions as &dyn Any).downcast_ref::<Vec<DVec2>>() {
            return visible_points_sweep_2d(plane, i, &self.vision);
        }
        let seen: Vec<usize> = (0..self.positions.len())
            .filter(|&j| self.sees(i, j))
            .collect();
        representatives(&self.positions, &seen, &self.vision)
    }
}

/// Selects the leaves that may lie farther than a radius from a centre: a node is
/// opened unless its whole box is within the radius (slightly shrunk, so rounding never
/// prunes a robot the exact test would keep).
struct Beyond<P: IndexPoint> {
    centre: P::Array,
    radius2: f64,
}

impl<P: IndexPoint> rstar::SelectionFunction<GeomWithData<P::Array, u32>> for Beyond<P> {
    fn should_unpack_parent(&self, envelope: &rstar::AABB<P::Array>) -> bool {
        use rstar::Point as _;
        let (lo, hi) = (envelope.lower(), envelope.upper());
        let mut far2 = 0.0;
        for a in 0..P::DIM {
            let c = self.centre.nth(a);
            let d = (c - lo.nth(a)).abs().max((hi.nth(a) - c).abs());
            far2 += d * d;
        }
        far2 > self.radius2
    }
}
