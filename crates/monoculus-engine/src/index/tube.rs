//! [`Tube`]: the R-tree selection of robots that may block one line of sight.

use rstar::{AABB, SelectionFunction, primitives::GeomWithData};

use super::IndexPoint;

/// Selects the leaves whose envelope meets the segment from `p` to `q` widened by
/// `tol`: every robot that could lie in the blocking cone of half-angle eps_ang (the
/// exact test is done afterwards by `blocks`). Conservative by construction.
pub struct Tube<P: IndexPoint> {
    p: P,
    q: P,
    tol: f64,
}

impl<P: IndexPoint> Tube<P> {
    /// The tube for the view from `p` to `q` with angular tolerance `eps_ang`, around
    /// robots of radius `radius` (0: points).
    pub fn new(p: P, q: P, eps_ang: f64, radius: f64) -> Self {
        let len = (q - p).length();
        let scale = (0..P::DIM)
            .map(|a| p.axis(a).abs().max(q.axis(a).abs()))
            .fold(len, f64::max);
        // The cone's widest point is len * sin(eps_ang) from the segment; add room for
        // rounding in the exact test.
        let tol = len * eps_ang * 1.001 + radius * (1.0 + 1e-9) + 16.0 * f64::EPSILON * scale;
        Tube { p, q, tol }
    }

    /// The radius around the segment within which a blocker can lie.
    pub fn tolerance(&self) -> f64 {
        self.tol
    }

    /// Whether the segment, widened by `tol`, meets the box [lo, hi] (slab test).
    pub fn meets(&self, lo: &[f64], hi: &[f64]) -> bool {
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for a in 0..P::DIM {
            let (pa, da) = (self.p.axis(a), self.q.axis(a) - self.p.axis(a));
            let (l, h) = (lo[a] - self.tol, hi[a] + self.tol);
            if da.abs() < 1e-300 {
                if pa < l || pa > h {
                    return false;
                }
            } else {
                let (ta, tb) = ((l - pa) / da, (h - pa) / da);
                t0 = t0.max(ta.min(tb));
                t1 = t1.min(ta.max(tb));
                if t0 > t1 {
                    return false;
                }
            }
        }
        true
    }
}

fn corners<A: rstar::Point<Scalar = f64>>(env: &AABB<A>) -> ([f64; 3], [f64; 3]) {
    let (l, u) = (env.lower(), env.upper());
    let mut lo = [0.0; 3];
    let mut hi = [0.0; 3];
    for a in 0..A::DIMENSIONS {
        lo[a] = l.nth(a);
        hi[a] = u.nth(a);
    }
    (lo, hi)
}

impl<P: IndexPoint> SelectionFunction<GeomWithData<P::Array, u32>> for Tube<P> {
    fn should_unpack_parent(&self, envelope: &AABB<P::Array>) -> bool {
        let (lo, hi) = corners(envelope);
        self.meets(&lo, &hi)
    }

    fn should_unpack_leaf(&self, leaf: &GeomWithData<P::Array, u32>) -> bool {
        let env = rstar::RTreeObject::envelope(leaf);
        let (lo, hi) = corners(&env);
        self.meets(&lo, &hi)
    }
}
