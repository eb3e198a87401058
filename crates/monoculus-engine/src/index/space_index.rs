//! [`SpaceIndex`]: an rstar R-tree, for d = 3: lines of sight as tube queries, radius,
//! nearest-first and beyond-a-radius queries through the tree.

use std::sync::OnceLock;

use monoculus_core::vision::{Near, VisionParams, blocks, representatives};
use rstar::{RTree, primitives::GeomWithData};

use super::{IndexPoint, Locate, SpatialIndex, Tube};

/// The R-tree over a snapshot in space, built on the first visibility question (many
/// activations, OLA inner robots, need only the bounding box).
pub struct SpaceIndex<P: IndexPoint> {
    tree: OnceLock<RTree<GeomWithData<P::Array, u32>>>,
}

impl<P: IndexPoint> SpaceIndex<P> {
    fn tree<L: Locate<P> + ?Sized>(&self, pos: &L) -> &RTree<GeomWithData<P::Array, u32>> {
        self.tree.get_or_init(|| {
            let pos = pos
                .as_slice()
                .expect("a tree is built over a snapshot's positions");
            let items: Vec<GeomWithData<P::Array, u32>> = pos
                .iter()
                .enumerate()
                .map(|(i, p)| GeomWithData::new(p.to_array(), i as u32))
                .collect();
            RTree::bulk_load(items)
        })
    }
}

impl<P: IndexPoint> SpatialIndex<P> for SpaceIndex<P> {
    fn new(_positions: &[P]) -> Self {
        SpaceIndex {
            tree: OnceLock::new(),
        }
    }

    /// A fresh tree: bulk loading is cheap next to a round in space.
    fn after(_previous: Self, _before: &[P], now: &[P], _same_vision: bool) -> Self {
        Self::new(now)
    }

    fn stale_robots(&self) -> usize {
        0
    }

    fn clear<L: Locate<P> + ?Sized>(&self, pos: &L, v: &VisionParams, i: usize, j: usize) -> bool {
        let (p, q) = (pos.at(i), pos.at(j));
        let tube = Tube::new(p, q, v.eps_ang, v.robot_radius);
        !self
            .tree(pos)
            .locate_with_selection_function(tube)
            .any(|leaf| {
                let k = leaf.data as usize;
                k != i && k != j && blocks(p, pos.at(k), q, v)
            })
    }

    fn for_each_within<L: Locate<P> + ?Sized>(
        &self,
        pos: &L,
        i: usize,
        radius: f64,
        f: &mut dyn FnMut(usize),
    ) {
        let p = pos.at(i);
        // Ask the tree for a slightly larger radius, then decide with the same test as
        // the oracle, so both agree on points at the boundary.
        let r2 = radius * radius * (1.0 + 1e-12) + f64::MIN_POSITIVE;
        for leaf in self.tree(pos).locate_within_distance(p.to_array(), r2) {
            let k = leaf.data as usize;
            if k != i && (pos.at(k) - p).length() <= radius {
                f(k);
            }
        }
    }

    fn nearest_first<'a, L: Locate<P> + ?Sized>(
        &'a self,
        pos: &'a L,
        i: usize,
    ) -> Box<dyn Iterator<Item = usize> + 'a> {
        let p = pos.at(i).to_array();
        Box::new(
            self.tree(pos)
                .nearest_neighbor_iter(p)
                .map(|leaf| leaf.data as usize)
                .filter(move |&k| k != i),
        )
    }

    /// Tree nodes entirely within `radius` are skipped: O(robots beyond + boundary).
    fn for_each_beyond<L: Locate<P> + ?Sized>(
        &self,
        pos: &L,
        i: usize,
        radius: f64,
        f: &mut dyn FnMut(usize),
    ) {
        let p = pos.at(i);
        let selection = Beyond::<P> {
            centre: p.to_array(),
            radius2: radius * radius * (1.0 - 1e-12),
        };
        for leaf in self.tree(pos).locate_with_selection_function(selection) {
            let k = leaf.data as usize;
            if (pos.at(k) - p).length() > radius {
                f(k);
            }
        }
    }

    fn alone<L: Locate<P> + ?Sized>(&self, _pos: &L, _v: &VisionParams, _j: usize) -> bool {
        false
    }

    fn neighbours<L: Locate<P> + ?Sized>(&self, _pos: &L, _i: usize, _near: &mut Near) {}

    /// One line of sight per robot.
    fn visible_points(
        &self,
        pos: &[P],
        v: &VisionParams,
        _i: usize,
        sees: &dyn Fn(usize) -> bool,
    ) -> Vec<usize> {
        let seen: Vec<usize> = (0..pos.len()).filter(|&j| sees(j)).collect();
        representatives(pos, &seen, v)
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
