//! [`Sight`]: what the engine must answer about one snapshot of the swarm.

use super::VisionParams;
use crate::geometry::Point;

/// The most robots [`Sight::neighbours`] gives.
pub const NEIGHBOURS: usize = 32;

/// A few robots near one, as [`Sight::neighbours`] gives them: at most [`NEIGHBOURS`],
/// held on the stack (a Look asks for them once, and most Looks need no more).
///
/// ```
/// use monoculus_core::vision::{NEIGHBOURS, Near};
/// let mut near = Near::new();
/// assert!(near.push(3) && near.push(1));
/// assert_eq!(near.as_slice(), &[3, 1]);
/// while near.push(7) {}
/// assert_eq!(near.len(), NEIGHBOURS);
/// ```
#[derive(Clone, Debug)]
pub struct Near {
    len: usize,
    items: [usize; NEIGHBOURS],
}

impl Default for Near {
    fn default() -> Self {
        Self::new()
    }
}

impl Near {
    /// None yet.
    pub fn new() -> Self {
        Near {
            len: 0,
            items: [0; NEIGHBOURS],
        }
    }

    /// Adds robot `k`; `false` (and nothing added) once [`NEIGHBOURS`] are held.
    pub fn push(&mut self, k: usize) -> bool {
        if self.len == NEIGHBOURS {
            return false;
        }
        self.items[self.len] = k;
        self.len += 1;
        true
    }

    /// Whether no more fit.
    pub fn is_full(&self) -> bool {
        self.len == NEIGHBOURS
    }

    /// How many are held.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether none is held.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The robots, in the order they were added.
    pub fn as_slice(&self) -> &[usize] {
        &self.items[..self.len]
    }
}

/// Questions about one immutable configuration, asked on behalf of one observing robot.
///
/// This trait knows positions; robots never get it. Observations
/// ([`crate::observe`]) wrap a `Sight` privately and expose only directions and
/// far/near bits. Implementations: [`super::ExactSight`] (brute force, the
/// definition) and the engine's spatial index. Both must give the same answers; only
/// their cost differs.
pub trait Sight<P: Point>: Sync {
    /// Positions of all robots, indexed by robot. A sight that locates robots one by
    /// one (ASYNC's, where robots in mid-move are placed when asked) gathers them on the
    /// first call: read [`Sight::position`] where one robot's is needed.
    fn positions(&self) -> &[P];

    /// The position of robot `i`.
    fn position(&self, i: usize) -> P {
        self.positions()[i]
    }

    /// The tolerances.
    fn vision(&self) -> &VisionParams;

    /// Smallest and largest coordinate on each axis over all robots.
    fn bounds(&self) -> (P, P);

    /// Whether robot `j` is seen from robot `i` (SPEC section 2, before co-located
    /// robots are merged into one point).
    fn sees(&self, i: usize, j: usize) -> bool;

    /// Calls `f` with every robot other than `i` within distance `radius` (inclusive)
    /// of robot `i`, in unspecified order.
    fn for_each_within(&self, i: usize, radius: f64, f: &mut dyn FnMut(usize));

    /// Robots other than `i`, nearest first (ties in any order).
    fn nearest_first(&self, i: usize) -> Box<dyn Iterator<Item = usize> + '_>;

    /// A few robots near robot `i`, in any order, put in `near` (possibly none):
    /// candidates tried first when counting visible points. Any answer gives the same
    /// results; a good one (the robots of the surrounding bins) spares a nearest-first
    /// scan.
    fn neighbours(&self, _i: usize, _near: &mut Near) {}

    /// Every visible point from robot `i` as its representative robot, ascending.
    fn visible_points(&self, i: usize) -> Vec<usize>;

    /// The largest distance from robot `i` to any robot.
    fn farthest(&self, i: usize) -> f64 {
        let p = self.position(i);
        self.positions()
            .iter()
            .map(|&q| (q - p).length())
            .fold(0.0, f64::max)
    }

    /// Calls `f` with every robot farther than `radius` from robot `i`, in unspecified
    /// order.
    fn for_each_beyond(&self, i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        super::beyond_brute(self.positions(), i, radius, f);
    }

    /// Number of robots.
    fn len(&self) -> usize {
        self.positions().len()
    }

    /// Whether there are no robots.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether certainly no robot other than `j` lies within `eps_pos` of it (`false`
    /// when unsure, the default): spares [`Sight::is_visible_point`] its search for
    /// co-located robots.
    fn alone(&self, _j: usize) -> bool {
        false
    }

    /// Whether robot `j` represents a visible point from `i`: `j` is seen, and no seen
    /// robot with a smaller index lies within `eps_pos` of it (co-located robots are one
    /// point, represented by the lowest index).
    fn is_visible_point(&self, i: usize, j: usize) -> bool {
        if !self.sees(i, j) {
            return false;
        }
        if self.alone(j) {
            return true;
        }
        let mut shadowed = false;
        let eps = self.vision().eps_pos;
        self.for_each_within(j, eps, &mut |k| {
            if !shadowed && k < j && k != i && self.sees(i, k) {
                shadowed = true;
            }
        });
        !shadowed
    }

    /// Number of robots other than `i` within distance `radius` (inclusive).
    fn count_within(&self, i: usize, radius: f64) -> usize {
        let mut count = 0;
        self.for_each_within(i, radius, &mut |_| count += 1);
        count
    }
}
