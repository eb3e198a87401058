//! ConvergeLocality (SPEC 4.1).

use super::{Algorithm, Decision, Goal, Ld, NoParams, Observation, StopCriterion};
use crate::geometry::Point;
use crate::rng::Stream;

/// ConvergeLocality (LD, SPEC 4.1): 1. exactly one point visible: move toward it; 2. else
/// toward a uniformly random far point; 3. else stay. Never grows the hull (Lemma 2).
#[derive(Clone, Copy, Debug, Default)]
pub struct ConvergeLocality;

impl Algorithm for ConvergeLocality {
    const NAME: &'static str = "converge_locality";
    type Sensing = Ld;
    type Params = NoParams;
    type State = ();
    const STOP: StopCriterion = StopCriterion::QuiescentOrDiameter;
    const GOAL: Goal = Goal::Disc;
    const ASSUMES_C_AT_LEAST_2B: bool = true;

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(ConvergeLocality)
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Ld, V>,
        _: &mut (),
        rng: &mut Stream,
    ) -> Decision<V> {
        if let Some(dir) = obs.sole_visible() {
            return Decision::Step(dir);
        }
        match obs.random_far(rng) {
            Some(dir) => Decision::Step(dir),
            None => Decision::Stay,
        }
    }
}
