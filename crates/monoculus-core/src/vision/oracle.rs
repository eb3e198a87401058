//! Exact visibility without an index: the definition (brute force) and the angular
//! sweep. These are the oracles the indexed path is tested against.

use glam::DVec2;

use super::{Sight, VisionParams, blocks, distinct, in_range};
use crate::geometry::Point;

/// Whether `j` is seen from `i`, straight from the definition: O(n).
pub fn sees_brute<P: Point>(positions: &[P], i: usize, j: usize, v: &VisionParams) -> bool {
    let (p, q) = (positions[i], positions[j]);
    if i == j || !distinct(p, q, v) || !in_range(p, q, v) {
        return false;
    }
    !positions
        .iter()
        .enumerate()
        .any(|(k, &r)| k != i && k != j && blocks(p, r, q, v))
}

/// Calls `f` with every robot other than `i` within distance `radius` (inclusive) of
/// robot `i`, ascending: [`Sight::for_each_within`] by its definition, O(n).
///
/// ```
/// use glam::DVec2;
/// let pts = [DVec2::ZERO, DVec2::X, DVec2::new(3.0, 0.0)];
/// let mut near = vec![];
/// monoculus_core::vision::within_brute(&pts, 0, 1.0, &mut |k| near.push(k));
/// assert_eq!(near, [1]);
/// ```
pub fn within_brute<P: Point>(positions: &[P], i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
    let p = positions[i];
    for (k, &q) in positions.iter().enumerate() {
        if k != i && (q - p).length() <= radius {
            f(k);
        }
    }
}

/// Calls `f` with every robot farther than `radius` from robot `i`, ascending:
/// [`Sight::for_each_beyond`] by its definition, O(n).
///
/// ```
/// use glam::DVec2;
/// let pts = [DVec2::ZERO, DVec2::X, DVec2::new(3.0, 0.0)];
/// let mut far = vec![];
/// monoculus_core::vision::beyond_brute(&pts, 0, 1.0, &mut |k| far.push(k));
/// assert_eq!(far, [2]);
/// ```
pub fn beyond_brute<P: Point>(positions: &[P], i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
    let p = positions[i];
    for (k, &q) in positions.iter().enumerate() {
        if (q - p).length() > radius {
            f(k);
        }
    }
}

/// The robots other than `i`, nearest first (ties by index): [`Sight::nearest_first`]
/// by its definition, O(n log n).
///
/// ```
/// use glam::DVec2;
/// let pts = [DVec2::ZERO, DVec2::new(3.0, 0.0), DVec2::X];
/// assert_eq!(monoculus_core::vision::nearest_first_brute(&pts, 0), [2, 1]);
/// ```
pub fn nearest_first_brute<P: Point>(positions: &[P], i: usize) -> Vec<usize> {
    let p = positions[i];
    let mut order = Vec::with_capacity(positions.len());
    order.extend(
        (positions.iter().enumerate())
            .filter(|&(k, _)| k != i)
            .map(|(k, &q)| ((q - p).length(), k)),
    );
    order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    order.into_iter().map(|(_, k)| k).collect()
}

/// Merges seen robots into visible points: keeps `j` unless a seen robot with a
/// smaller index lies within `eps_pos` of it. Input and output ascending.
pub fn representatives<P: Point>(positions: &[P], seen: &[usize], v: &VisionParams) -> Vec<usize> {
    // Sort by the first coordinate and compare only neighbours within eps_pos on it.
    let mut by_x: Vec<usize> = seen.to_vec();
    by_x.sort_by(|&a, &b| {
        positions[a]
            .axis(0)
            .total_cmp(&positions[b].axis(0))
            .then(a.cmp(&b))
    });
    let mut shadowed = vec![false; by_x.len()];
    for a in 0..by_x.len() {
        let qa = positions[by_x[a]];
        for b in a + 1..by_x.len() {
            let qb = positions[by_x[b]];
            if qb.axis(0) - qa.axis(0) > v.eps_pos {
                break;
            }
            if (qb - qa).length() <= v.eps_pos {
                if by_x[a] < by_x[b] {
                    shadowed[b] = true;
                } else {
                    shadowed[a] = true;
                }
            }
        }
    }
    let mut out: Vec<usize> = by_x
        .iter()
        .zip(&shadowed)
        .filter(|(_, s)| !**s)
        .map(|(&j, _)| j)
        .collect();
    out.sort_unstable();
    out
}

/// Visible points from robot `i` by the definition: O(n^2). For tests on small sets.
pub fn visible_points_brute<P: Point>(positions: &[P], i: usize, v: &VisionParams) -> Vec<usize> {
    let seen: Vec<usize> = (0..positions.len())
        .filter(|&j| sees_brute(positions, i, j, v))
        .collect();
    representatives(positions, &seen, v)
}

/// Robots seen from robot `i` in the plane by an angular sweep: sort the others by angle
/// (then distance) and test each only against the robots whose angle lies within the
/// tolerance window. O(n log n) unless many robots share a ray.
pub fn seen_sweep_2d(positions: &[DVec2], i: usize, v: &VisionParams) -> Vec<usize> {
    let p = positions[i];
    let mut others: Vec<(f64, f64, usize)> = positions
        .iter()
        .enumerate()
        // Robots beyond the range are not seen, and block nothing within it (a blocker
        // is nearer than what it hides).
        .filter(|&(j, &q)| j != i && distinct(p, q, v) && in_range(p, q, v))
        .map(|(j, &q)| {
            let d = q - p;
            (d.y.atan2(d.x), d.length(), j)
        })
        .collect();
    others.sort_by(|a, b| {
        a.0.total_cmp(&b.0)
            .then(a.1.total_cmp(&b.1))
            .then(a.2.cmp(&b.2))
    });
    let m = others.len();
    // atan2 differences approximate the true angle to ~1e-15; widen the window by a
    // margin and let `blocks` decide exactly.
    let window = v.eps_ang + 1e-12;
    let circ = |a: f64, b: f64| {
        let d = (a - b).abs();
        d.min(std::f64::consts::TAU - d)
    };
    let mut seen = Vec::with_capacity(m);
    for s in 0..m {
        let (theta, _, j) = others[s];
        let q = positions[j];
        // Backwards first: in a group sharing one angle the nearer robots come first.
        let blocked = [m - 1, 1].into_iter().any(|stride| {
            (1..m)
                .map(|step| &others[(s + stride * step) % m])
                .take_while(|other| circ(other.0, theta) <= window)
                .any(|other| blocks(p, positions[other.2], q, v))
        });
        if !blocked {
            seen.push(j);
        }
    }
    seen.sort_unstable();
    seen
}

/// Visible points from robot `i` in the plane, by the angular sweep: O(n log n).
pub fn visible_points_sweep_2d(positions: &[DVec2], i: usize, v: &VisionParams) -> Vec<usize> {
    representatives(positions, &seen_sweep_2d(positions, i, v), v)
}

/// A [`Sight`] without an index: every question answered from the definition by
/// scanning all robots. Slow (O(n) per question) and obviously right: the reference
/// the engine's spatial index is checked against, also selectable in configs
/// (`vision.backend = "exact"`) to cross-check a run.
#[derive(Clone, Debug)]
pub struct ExactSight<P: Point> {
    positions: Vec<P>,
    vision: VisionParams,
    bounds: (P, P),
}

impl<P: Point> ExactSight<P> {
    /// A sight over `positions`.
    pub fn new(positions: Vec<P>, vision: VisionParams) -> Self {
        let bounds = crate::metrics::bounds(&positions);
        ExactSight {
            positions,
            vision,
            bounds,
        }
    }
}

impl<P: Point> Sight<P> for ExactSight<P> {
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
        sees_brute(&self.positions, i, j, &self.vision)
    }
    fn for_each_within(&self, i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        within_brute(&self.positions, i, radius, f);
    }
    fn nearest_first(&self, i: usize) -> Box<dyn Iterator<Item = usize> + '_> {
        Box::new(nearest_first_brute(&self.positions, i).into_iter())
    }
    fn visible_points(&self, i: usize) -> Vec<usize> {
        visible_points_brute(&self.positions, i, &self.vision)
    }
}
