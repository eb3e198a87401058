//! [`Algorithm`]: what one activation of a robot decides, the trait every algorithm
//! implements, the paper's and a user's alike.

use std::fmt;

use serde::Serialize;
use serde::de::DeserializeOwned;

use super::{Decision, Goal, Observation, Sensing};
use crate::geometry::Point;
use crate::rng::Stream;

/// When a run ends (SPEC section 6; config `stop.criterion`). Whether the swarm it ends
/// with has converged is the algorithm's [`Goal`]'s to say.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StopCriterion {
    /// No robot would move if activated.
    Quiescent,
    /// Every pair of robots is within the locality constant c.
    Diameter,
    /// Either of the two above (ConvergeLocality's default: on a line the two end robots
    /// keep stepping forever while staying within c).
    QuiescentOrDiameter,
    /// The bounding box extends at most 2b on every axis.
    Box,
}

impl StopCriterion {
    /// The config name.
    pub fn name(self) -> &'static str {
        match self {
            StopCriterion::Quiescent => "quiescent",
            StopCriterion::Diameter => "diameter",
            StopCriterion::QuiescentOrDiameter => "quiescent_or_diameter",
            StopCriterion::Box => "box",
        }
    }

    /// Whether quiescence is part of the criterion.
    pub fn checks_quiescence(self) -> bool {
        matches!(
            self,
            StopCriterion::Quiescent | StopCriterion::QuiescentOrDiameter
        )
    }
}

/// The most colours an algorithm's robots may show ([`Algorithm::LIGHTS`]): a robot's
/// light is kept in a byte.
///
/// ```
/// assert_eq!(monoculus_core::algorithms::MAX_LIGHTS, 256);
/// ```
pub const MAX_LIGHTS: usize = 256;

/// The parameters of an algorithm that has none: `[algorithm.params]` must be empty.
///
/// ```
/// use monoculus_core::algorithms::NoParams;
///
/// let none: NoParams = serde::Deserialize::deserialize(
///     serde::de::value::MapDeserializer::<_, serde::de::value::Error>::new(
///         std::iter::empty::<(&str, &str)>(),
///     ),
/// )
/// .unwrap();
/// assert_eq!(none, NoParams {});
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoParams {}

/// An algorithm for monoculus robots: what one robot decides in one activation from what
/// it senses.
///
/// A type implementing it is the algorithm with its parameters; the engine runs it under
/// every scheduler, error model, fault model, in the plane and in space, and every
/// command (`run`, `trace`, `replay`, `slurm`, ...) takes it by [`Algorithm::NAME`] once a
/// binary registers it. What a robot may sense is fixed by [`Algorithm::Sensing`]: the
/// [`Observation`] `decide` gets has only the queries that model grants, so an
/// algorithm of the `ld` model cannot ask for positions or distances (the compiler
/// refuses):
///
/// ```compile_fail
/// use monoculus_core::algorithms::{Ld, Observation};
/// use monoculus_core::geometry::Point;
///
/// fn peek<V: Point>(obs: &Observation<'_, Ld, V>) -> Vec<V> {
///     obs.relative_positions() // only `Observation<'_, Positions, V>` has it
/// }
/// ```
///
/// `decide` takes the algorithm by shared reference and gets the robot's own state and
/// its own random stream: an oblivious robot (`State = ()`) has nowhere to keep anything
/// between activations, and a run's results do not depend on the number of threads.
///
/// ConvergeLocality (SPEC 4.1), as the crate itself implements it:
///
/// ```
/// use monoculus_core::algorithms::{Algorithm, Decision, Ld, NoParams, Observation};
/// use monoculus_core::geometry::Point;
/// use monoculus_core::rng::Stream;
///
/// struct Locality;
///
/// impl Algorithm for Locality {
///     const NAME: &'static str = "locality";
///     type Sensing = Ld;
///     type Params = NoParams;
///     type State = ();
///
///     fn new(_: NoParams) -> Result<Self, String> {
///         Ok(Locality)
///     }
///
///     fn decide<V: Point>(&self, obs: &Observation<'_, Ld, V>, _: &mut (), rng: &mut Stream) -> Decision<V> {
///         if let Some(toward) = obs.sole_visible() {
///             return Decision::Step(toward);
///         }
///         match obs.random_far(rng) {
///             Some(toward) => Decision::Step(toward),
///             None => Decision::Stay,
///         }
///     }
/// }
/// ```
pub trait Algorithm: Sized + Send + Sync + 'static {
    /// The name a config's `algorithm.name` selects (snake case; one per binary).
    const NAME: &'static str;

    /// What its robots sense: [`Directions`](super::Directions) (unit directions only),
    /// [`Ld`](super::Ld) (directions and far bits), [`Ola`](super::Ola) (directions in
    /// the agreed axes, and the sides occupied) or [`Positions`](super::Positions)
    /// (baselines that see positions).
    type Sensing: Sensing;

    /// Its parameters, read from the config's `[algorithm.params]` (any key of which
    /// may be a list, swept as any other key): a serde struct of the algorithm's own,
    /// whose `Default` gives the values of the keys left out; [`NoParams`] for none.
    /// Unknown keys are refused whatever the struct says.
    type Params: Serialize + DeserializeOwned + Default + Clone + fmt::Debug + Send + Sync + 'static;

    /// What a robot keeps between its activations: `()` (or any zero-sized type) for
    /// oblivious robots, the paper's setting; otherwise a small value every robot starts
    /// with as `Default` and `decide` may change. A robot with a state also keeps its
    /// local frame for the whole run (SPEC section 10), as the termination algorithm's
    /// robots keep their axes.
    type State: Clone + Default + PartialEq + fmt::Debug + Send + Sync + 'static;

    /// The stop criterion a config's `stop.criterion = "default"` means for it.
    const STOP: StopCriterion = StopCriterion::QuiescentOrDiameter;

    /// What convergence means for it (SPEC section 11): a run has converged when its
    /// stop criterion ended it and this holds at the end; a run that fell quiescent
    /// without it is *stuck*. A config's `stop.goal` may set another.
    ///
    /// ```
    /// use monoculus_core::algorithms::{Algorithm, ConvergeLocality, ConvergeQuadrant, Goal, Median};
    ///
    /// assert_eq!(ConvergeLocality::GOAL, Goal::Disc);
    /// assert_eq!(ConvergeQuadrant::GOAL, Goal::Box);
    /// assert_eq!(Median::GOAL, Goal::Diameter); // the default
    /// ```
    const GOAL: Goal = Goal::Diameter;

    /// Whether its guarantees assume the paper's c >= 2b (a config with c < 2b then
    /// gets a warning).
    const ASSUMES_C_AT_LEAST_2B: bool = false;

    /// `Some(reason)` if it is defined in the plane only (a config with `dim = 3` is
    /// refused with the reason).
    const PLANE_ONLY: Option<&'static str> = None;

    /// A promise for [`Ola`](super::Ola) algorithms: a robot that sees robots beyond both
    /// sides of every agreed axis decides [`Decision::Stay`] and leaves its state as it
    /// is. The engine then skips such robots without activating them, read off the
    /// swarm's bounding box (without observation errors, limited range or fat robots,
    /// where the box tells nothing), as it does for ConvergeQuadrant's inner robots.
    /// Ignored for the other models.
    const STAYS_WHEN_SURROUNDED: bool = false;

    /// Its robots' lights (the luminous-robot model, SPEC section 10): the names of the
    /// colours a robot may show, at most [`MAX_LIGHTS`](super::MAX_LIGHTS); empty (the
    /// default) for robots without lights. A robot shows colour [`Algorithm::light`] of
    /// its state (from the start: that of the `Default` state); the others see it with
    /// its direction ([`Observation::lit`](super::Observation::lit),
    /// [`Observation::random_lit`](super::Observation::random_lit)). Robots with lights
    /// keep a state, so they keep their local frame too.
    ///
    /// ```
    /// use monoculus_core::algorithms::{Algorithm, Decision, Directions, NoParams, Observation};
    /// use monoculus_core::geometry::Point;
    /// use monoculus_core::rng::Stream;
    ///
    /// /// Steps toward a robot showing `on` if it sees one, and shows `on` once it has moved.
    /// struct Relay;
    ///
    /// #[derive(Clone, Debug, Default, PartialEq)]
    /// struct Lamp(bool);
    ///
    /// impl Algorithm for Relay {
    ///     const NAME: &'static str = "relay";
    ///     type Sensing = Directions;
    ///     type Params = NoParams;
    ///     type State = Lamp;
    ///     const LIGHTS: &'static [&'static str] = &["off", "on"];
    ///
    ///     fn new(_: NoParams) -> Result<Self, String> {
    ///         Ok(Relay)
    ///     }
    ///
    ///     fn light(lamp: &Lamp) -> usize {
    ///         lamp.0 as usize
    ///     }
    ///
    ///     fn decide<V: Point>(&self, obs: &Observation<'_, Directions, V>, lamp: &mut Lamp, rng: &mut Stream) -> Decision<V> {
    ///         match obs.random_lit(1, rng) {
    ///             Some(toward) => {
    ///                 lamp.0 = true;
    ///                 Decision::Step(toward)
    ///             }
    ///             None => Decision::Stay,
    ///         }
    ///     }
    /// }
    /// assert_eq!(Relay::light(&Lamp::default()), 0);
    /// ```
    const LIGHTS: &'static [&'static str] = &[];

    /// The colour a robot with this state shows: an index into [`Algorithm::LIGHTS`]
    /// (`0` by default). `decide` sets the light by changing the state; under ASYNC
    /// the others see the new colour once the robot's Compute has ended. An index out of
    /// the palette fails the run, naming the algorithm, the robot and the round.
    fn light(_state: &Self::State) -> usize {
        0
    }

    /// The algorithm with these parameters, or why they are not valid (one line; the
    /// config error names `algorithm.params`).
    fn new(params: Self::Params) -> Result<Self, String>;

    /// One activation: the robot's observation in its local frame, its state and its
    /// random stream; the decision, in the same local frame. A step's direction must be
    /// a unit vector (a run whose algorithm returns another, or NaN, stops as failed,
    /// naming the algorithm, the robot and the round).
    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Self::Sensing, V>,
        state: &mut Self::State,
        rng: &mut Stream,
    ) -> Decision<V>;

    /// Whether its robots keep their state (and frame) between activations: by default
    /// when [`Algorithm::State`] is not zero-sized. Bindings whose algorithms declare
    /// memory at run time say here.
    fn keeps_state(&self) -> bool {
        std::mem::size_of::<Self::State>() != 0
    }

    /// Whether the activations of a round (ASYNC: of a tick) are decided together, in
    /// one call of [`Algorithm::decide_together`], instead of one by one with
    /// [`Algorithm::decide`]: for bindings whose call is dear (an algorithm written
    /// with numpy decides a whole round at once). They run on one thread, in robot
    /// order.
    fn decides_together(&self) -> bool {
        false
    }

    /// The activations of a round (ASYNC: a tick) at once, for algorithms that decide
    /// together ([`Algorithm::decides_together`]): one observation, state and stream per activation, in
    /// robot order; one decision each, in the same order. By default, `decide` for each.
    fn decide_together<V: Point>(
        &self,
        obs: &[Observation<'_, Self::Sensing, V>],
        states: &mut [&mut Self::State],
        rngs: &mut [&mut Stream],
    ) -> Vec<Decision<V>> {
        obs.iter()
            .zip(states.iter_mut())
            .zip(rngs.iter_mut())
            .map(|((o, s), r)| self.decide(o, s, r))
            .collect()
    }

    /// The name of this instance: [`Algorithm::NAME`], unless the type serves algorithms
    /// named at run time (bindings to other languages), which give theirs here.
    fn name(&self) -> &str {
        Self::NAME
    }

    /// The default stop criterion of this instance: [`Algorithm::STOP`], unless the type
    /// serves algorithms declared at run time (bindings), which give theirs here.
    fn stop(&self) -> StopCriterion {
        Self::STOP
    }

    /// The goal of this instance: [`Algorithm::GOAL`], unless the type serves
    /// algorithms declared at run time (bindings), which give theirs here.
    fn goal(&self) -> Goal {
        Self::GOAL
    }

    /// The names of this instance's lights: [`Algorithm::LIGHTS`], unless the type
    /// serves algorithms declared at run time (bindings), which give theirs here (at
    /// most [`MAX_LIGHTS`](super::MAX_LIGHTS); the colour of a state is still
    /// [`Algorithm::light`]).
    ///
    /// ```
    /// use monoculus_core::algorithms::{Algorithm, ConvergeLocality};
    ///
    /// assert_eq!(ConvergeLocality.light_names().len(), 0); // no lights
    /// ```
    fn light_names(&self) -> impl ExactSizeIterator<Item = &str> {
        Self::LIGHTS.iter().copied()
    }

    /// Whether a robot with this state has terminated, for algorithms that terminate:
    /// `runs.csv`'s `terminated` counts the robots for which it is `Some(true)` at the
    /// end of a run (empty when it is `None`, the default).
    fn terminated(_state: &Self::State, _dim: usize) -> Option<bool> {
        None
    }

    /// A byte of the state a replay shows for each robot (the termination algorithm:
    /// its bits), if any.
    fn shown_bits(_state: &Self::State) -> Option<u8> {
        None
    }
}
