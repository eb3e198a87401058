//! ConvergeQuadrant (SPEC 4.2) and the set E it shares with the termination variant.

use super::Decision;
use crate::geometry::Point;
use crate::observe::{OlaObservation, Side};
use crate::rng::Stream;
use crate::vision::Sight;

/// E: the (local axis, side) pairs whose side is empty while the opposite side is not.
pub fn empty_sides<P: Point, S: Sight<P> + ?Sized>(
    obs: &OlaObservation<'_, P, S>,
) -> Vec<(usize, Side)> {
    let mut e = Vec::with_capacity(P::DIM);
    for k in 0..obs.dim() {
        let low = obs.side_occupied(k, Side::Low);
        let high = obs.side_occupied(k, Side::High);
        match (low, high) {
            (false, true) => e.push((k, Side::Low)),
            (true, false) => e.push((k, Side::High)),
            _ => {}
        }
    }
    e
}

/// Whether every axis has both sides empty: all robots lie within `eps_axis` of the
/// robot on every axis.
pub(crate) fn all_sides_empty<P: Point, S: Sight<P> + ?Sized>(
    obs: &OlaObservation<'_, P, S>,
) -> bool {
    (0..obs.dim()).all(|k| Side::BOTH.iter().all(|&s| !obs.side_occupied(k, s)))
}

/// The unit local vector along `axis` toward `side`.
pub(crate) fn along<P: Point>(axis: usize, side: Side) -> P {
    P::unit_axis(axis) * side.sign()
}

/// The rules, in order:
/// 1. exactly one point visible: move toward it;
/// 2. |E| = 0: stay;
/// 3. |E| = 1: move b along that axis toward the non-empty side;
/// 4. |E| >= 2: move toward a random visible point in the closed orthant of the
///    non-empty sides of E.
pub fn decide<P: Point, S: Sight<P> + ?Sized>(
    obs: &OlaObservation<'_, P, S>,
    stream: &mut Stream,
) -> Decision<P> {
    let e = empty_sides(obs);
    // With |E| = 0 some axis has robots on both sides, so at least two points are
    // visible and rule 1 cannot apply; only then may the look be skipped.
    if (!e.is_empty() || all_sides_empty(obs))
        && let Some(dir) = obs.sole_visible()
    {
        return Decision::Step(dir);
    }
    match e.len() {
        0 => Decision::Stay,
        1 => {
            let (axis, empty) = e[0];
            Decision::Step(along(axis, empty.opposite()))
        }
        _ => {
            let orthant: Vec<(usize, Side)> = e.iter().map(|&(k, s)| (k, s.opposite())).collect();
            match obs.random_in_orthant(&orthant, stream) {
                Some(dir) => Decision::Step(dir),
                None => Decision::Stay,
            }
        }
    }
}
