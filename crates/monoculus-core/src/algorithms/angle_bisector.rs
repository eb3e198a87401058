//! The naive "angle bisector" strategy of the paper's Figure 1 (SPEC 4.4).

use super::Decision;
use super::median::boundary_fan;
use crate::geometry::Point;
use crate::observe::LdObservation;
use crate::vision::Sight;

/// A boundary robot moves b along the bisector of the angle spanned by its visible
/// points; others stay. Planar.
pub fn decide<P: Point, S: Sight<P> + ?Sized>(obs: &LdObservation<'_, P, S>) -> Decision<P> {
    let dirs: Vec<P> = obs.all().into_iter().map(|s| s.direction).collect();
    let Some(fan) = boundary_fan(&dirs) else {
        return Decision::Stay;
    };
    let first = fan[0].0;
    let mut span = fan[fan.len() - 1].0 - first;
    if span < 0.0 {
        span += std::f64::consts::TAU;
    }
    let mid = first + span / 2.0;
    let mut c = [0.0; crate::geometry::MAX_DIM];
    c[0] = mid.cos();
    c[1] = mid.sin();
    Decision::Step(P::from_slice(&c))
}
