//! ConvergeQuadrantTermination (SPEC 4.3).

use super::converge_quadrant::{along, empty_sides};
use super::{
    Algorithm, Decision, Goal, NoParams, Observation, Ola, StopCriterion, TerminationBits,
};
use crate::geometry::Point;
use crate::observe::Side;
use crate::rng::Stream;

/// ConvergeQuadrantTermination (OLA with 2 bits per axis, SPEC 4.3): sets the bit of
/// every (axis, side) in E; with A the axes of E whose two bits are not both set: a
/// boundary robot with A non-empty moves as in ConvergeQuadrant; a corner robot stays
/// if A is empty, moves along the axis if |A| = 1, and toward a random visible point in
/// the orthant of A's non-empty sides if |A| >= 2; all else stays. A robot with every
/// bit set has terminated. Its robots keep their axes for the whole run.
#[derive(Clone, Copy, Debug, Default)]
pub struct ConvergeQuadrantTermination;

impl Algorithm for ConvergeQuadrantTermination {
    const NAME: &'static str = "converge_quadrant_termination";
    type Sensing = Ola;
    type Params = NoParams;
    type State = TerminationBits;
    const STOP: StopCriterion = StopCriterion::Quiescent;
    const GOAL: Goal = Goal::Box;
    const ASSUMES_C_AT_LEAST_2B: bool = true;
    // An inner robot: E is empty, so no bit is set, and it stays.
    const STAYS_WHEN_SURROUNDED: bool = true;

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(ConvergeQuadrantTermination)
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Ola, V>,
        bits: &mut TerminationBits,
        rng: &mut Stream,
    ) -> Decision<V> {
        if bits.terminated(V::DIM) {
            return Decision::Stay;
        }
        let e = empty_sides(obs);
        for &(k, side) in &e {
            bits.set(k, side);
        }
        let a: Vec<(usize, Side)> = e
            .iter()
            .copied()
            .filter(|&(k, _)| !bits.axis_done(k))
            .collect();
        match (e.len(), a.len()) {
            (1, 1) => Decision::Step(along(a[0].0, a[0].1.opposite())),
            (2.., 1) => Decision::Step(along(a[0].0, a[0].1.opposite())),
            (2.., 2..) => {
                let orthant: Vec<(usize, Side)> =
                    a.iter().map(|&(k, s)| (k, s.opposite())).collect();
                match obs.random_in_orthant(&orthant, rng) {
                    Some(dir) => Decision::Step(dir),
                    None => Decision::Stay,
                }
            }
            _ => Decision::Stay,
        }
    }

    fn terminated(bits: &TerminationBits, dim: usize) -> Option<bool> {
        Some(bits.terminated(dim))
    }

    fn shown_bits(bits: &TerminationBits) -> Option<u8> {
        Some(bits.0)
    }
}
