//! ConvergeQuadrantTermination (SPEC 4.3).

use super::converge_quadrant::{along, empty_sides};
use super::{Decision, RobotMemory};
use crate::geometry::Point;
use crate::observe::{OlaObservation, Side};
use crate::rng::Stream;
use crate::vision::Sight;

/// Sets the bit of every (axis, side) in E; with A the axes of E whose two bits are not
/// both set: a boundary robot with A non-empty moves as in ConvergeQuadrant; a corner
/// robot stays if A is empty, moves along the axis if |A| = 1, and toward a random
/// visible point in the orthant of A's non-empty sides if |A| >= 2; all else stays.
pub fn decide<P: Point, S: Sight<P> + ?Sized>(
    obs: &OlaObservation<'_, P, S>,
    memory: &mut RobotMemory,
    stream: &mut Stream,
) -> Decision<P> {
    if memory.terminated() {
        return Decision::Stay;
    }
    let e = empty_sides(obs);
    for &(k, side) in &e {
        memory.set(k, side);
    }
    let a: Vec<(usize, Side)> = e
        .iter()
        .copied()
        .filter(|&(k, _)| !memory.axis_done(k))
        .collect();
    match (e.len(), a.len()) {
        (1, 1) => Decision::Step(along(a[0].0, a[0].1.opposite())),
        (2.., 1) => Decision::Step(along(a[0].0, a[0].1.opposite())),
        (2.., 2..) => {
            let orthant: Vec<(usize, Side)> = a.iter().map(|&(k, s)| (k, s.opposite())).collect();
            match obs.random_in_orthant(&orthant, stream) {
                Some(dir) => Decision::Step(dir),
                None => Decision::Stay,
            }
        }
        _ => Decision::Stay,
    }
}
