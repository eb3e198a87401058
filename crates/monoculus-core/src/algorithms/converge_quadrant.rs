//! ConvergeQuadrant (SPEC 4.2) and the set E it shares with the termination variant.

use super::{Algorithm, Decision, Goal, NoParams, Observation, Ola, StopCriterion};
use crate::geometry::Point;
use crate::observe::Side;
use crate::rng::Stream;

/// E: the (local axis, side) pairs whose side is empty while the opposite side is not.
pub fn empty_sides<V: Point>(obs: &Observation<'_, Ola, V>) -> Vec<(usize, Side)> {
    let mut e = Vec::with_capacity(V::DIM);
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
pub(crate) fn all_sides_empty<V: Point>(obs: &Observation<'_, Ola, V>) -> bool {
    (0..obs.dim()).all(|k| Side::BOTH.iter().all(|&s| !obs.side_occupied(k, s)))
}

/// The unit local vector along `axis` toward `side`.
pub fn along<V: Point>(axis: usize, side: Side) -> V {
    V::unit_axis(axis) * side.sign()
}

/// ConvergeQuadrant (OLA, SPEC 4.2). The rules, in order:
/// 1. exactly one point visible: move toward it;
/// 2. |E| = 0: stay;
/// 3. |E| = 1: move b along that axis toward the non-empty side;
/// 4. |E| >= 2: move toward a random visible point in the closed orthant of the
///    non-empty sides of E.
#[derive(Clone, Copy, Debug, Default)]
pub struct ConvergeQuadrant;

impl Algorithm for ConvergeQuadrant {
    const NAME: &'static str = "converge_quadrant";
    type Sensing = Ola;
    type Params = NoParams;
    type State = ();
    const STOP: StopCriterion = StopCriterion::Box;
    const GOAL: Goal = Goal::Box;
    const ASSUMES_C_AT_LEAST_2B: bool = true;
    // An inner robot: E is empty and it sees at least two points.
    const STAYS_WHEN_SURROUNDED: bool = true;

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(ConvergeQuadrant)
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Ola, V>,
        _: &mut (),
        rng: &mut Stream,
    ) -> Decision<V> {
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
                let orthant: Vec<(usize, Side)> =
                    e.iter().map(|&(k, s)| (k, s.opposite())).collect();
                match obs.random_in_orthant(&orthant, rng) {
                    Some(dir) => Decision::Step(dir),
                    None => Decision::Stay,
                }
            }
        }
    }
}
