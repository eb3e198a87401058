//! A luminous algorithm of the `ld` model: ConvergeLocality (SPEC 4.1) whose robots show
//! a light. A robot that has just decided to move shows `moving`; a robot that sees a
//! robot showing `moving` stays and shows `resting`; any other robot decides as
//! ConvergeLocality does. The light is the robot's only memory: it says whether its last
//! activation moved it, and the others see it with its direction.

use monoculus::prelude::*;

/// The colours: index 0, the first, is what every robot shows at the start.
const RESTING: usize = 0;
const MOVING: usize = 1;

/// What a robot keeps between its activations: its light.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Light(pub usize);

/// ConvergeLocality that waits while it sees a robot moving.
pub struct WaitForMovers;

impl Algorithm for WaitForMovers {
    const NAME: &'static str = "wait_for_movers";
    type Sensing = Ld;
    type Params = NoParams;
    type State = Light;
    const LIGHTS: &'static [&'static str] = &["resting", "moving"];
    // ConvergeLocality's guarantees assume c >= 2b, and its goal is every robot within
    // a disc of radius c; so are this variant's.
    const ASSUMES_C_AT_LEAST_2B: bool = true;
    const GOAL: Goal = Goal::Disc;

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(WaitForMovers)
    }

    fn light(state: &Light) -> usize {
        state.0
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Ld, V>,
        light: &mut Light,
        rng: &mut Stream,
    ) -> Decision<V> {
        if obs.sees_light(MOVING) {
            *light = Light(RESTING);
            return Decision::Stay;
        }
        let toward = obs.sole_visible().or_else(|| obs.random_far(rng));
        *light = Light(if toward.is_some() { MOVING } else { RESTING });
        toward.map_or(Decision::Stay, Decision::Step)
    }
}
