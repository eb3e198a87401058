//! An oblivious algorithm of the `directions` model: a robot moves b toward a uniformly
//! random visible robot. Robots that see only directions cannot tell a near robot from a
//! far one, and the paper's impossibility result says no algorithm of that model
//! converges from every start: a rigid step toward a near robot overshoots it, out of
//! the hull.

use monoculus::prelude::*;

/// Move b toward a uniformly random visible robot; stay if none is visible.
pub struct TowardAnyone;

impl Algorithm for TowardAnyone {
    const NAME: &'static str = "toward_anyone";
    type Sensing = Directions;
    type Params = NoParams;
    type State = ();
    // Rigid steps never let it be quiescent: a run converges when the diameter is c.
    const STOP: StopCriterion = StopCriterion::Diameter;

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(TowardAnyone)
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Directions, V>,
        _: &mut (),
        rng: &mut Stream,
    ) -> Decision<V> {
        obs.random_visible(rng)
            .map_or(Decision::Stay, Decision::Step)
    }
}
