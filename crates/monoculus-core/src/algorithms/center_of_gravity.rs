//! Centre of gravity (Cohen and Peleg), a baseline that sees positions (SPEC 4.4).

use super::Decision;
use crate::geometry::Point;
use crate::observe::PositionObservation;
use crate::vision::Sight;

/// Move toward the centroid of the visible points by min(b, distance to it).
pub fn decide<P: Point, S: Sight<P> + ?Sized>(obs: &PositionObservation<'_, P, S>) -> Decision<P> {
    let rel = obs.relative_positions();
    if rel.is_empty() {
        return Decision::Stay;
    }
    let g = crate::metrics::centroid(&rel);
    let d = g.length();
    if d <= 0.0 {
        Decision::Stay
    } else {
        Decision::StepAtMost(g * (1.0 / d), d)
    }
}
