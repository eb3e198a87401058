//! Centre of gravity (Cohen and Peleg), a baseline that sees positions (SPEC 4.4).

use super::{Algorithm, Decision, NoParams, Observation, Positions, StopCriterion};
use crate::geometry::Point;
use crate::rng::Stream;

/// Centre of gravity (Cohen and Peleg; SPEC 4.4), a baseline that sees positions: move
/// toward the centroid of the visible points by min(b, distance to it).
#[derive(Clone, Copy, Debug, Default)]
pub struct CenterOfGravity;

impl Algorithm for CenterOfGravity {
    const NAME: &'static str = "center_of_gravity";
    type Sensing = Positions;
    type Params = NoParams;
    type State = ();
    const STOP: StopCriterion = StopCriterion::Diameter;

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(CenterOfGravity)
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Positions, V>,
        _: &mut (),
        _: &mut Stream,
    ) -> Decision<V> {
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
}
