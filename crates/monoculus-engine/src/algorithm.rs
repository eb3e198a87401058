//! [`AlgorithmBox`]: an [`Algorithm`] with its parameters, ready for a [`SimConfig`].
//!
//! The engine's systems are generic over the algorithm: a run's Look, Compute and
//! quiescence checks are compiled for its algorithm's type, the paper's and a user's
//! alike, with no dispatch per robot. What a [`SimConfig`] holds is the algorithm
//! erased: it installs those systems (and the robots' states) into a run's world, once,
//! when the run is built.
//!
//! [`SimConfig`]: crate::SimConfig

use std::any::Any;
use std::fmt;
use std::sync::Arc;

use bevy_ecs::prelude::*;
use glam::{DVec2, DVec3};
use monoculus_core::algorithms::{
    Algorithm, AlgorithmKind, AngleBisector, CenterOfGravity, ConvergeLocality, ConvergeQuadrant,
    ConvergeQuadrantTermination, Goal, Median, Model, Sensing, StopCriterion,
};

use crate::IndexPoint;
use crate::resources::Params;
use crate::simulation::{Hooks, SimConfig};

/// The algorithm of a run, as a resource of its world.
#[derive(Resource)]
pub struct Rule<A: Algorithm>(pub Arc<A>);

/// What installing an algorithm into a run needs.
pub(crate) struct Setup<'a, P: IndexPoint> {
    pub(crate) world: &'a mut World,
    pub(crate) schedule: &'a mut Schedule,
    pub(crate) config: &'a SimConfig,
    pub(crate) params: &'a Params,
    pub(crate) initial: &'a [P],
}

/// An algorithm erased for one dimension.
pub(crate) trait Install<P: IndexPoint>: Send + Sync {
    /// Spawns the robots, inserts the algorithm and wires its systems.
    fn install(&self, setup: Setup<'_, P>) -> Hooks<P>;
    /// Spawns the robots and inserts the algorithm into a world whose schedule is wired
    /// for this algorithm's type already (a run started again: [`Simulation::restart`](crate::Simulation::restart)).
    fn reinstall(&self, setup: Setup<'_, P>);
    /// The algorithm's type, for which a schedule is wired.
    fn algorithm_type(&self) -> std::any::TypeId;
}

struct Held<A>(Arc<A>);

impl<P: IndexPoint, A: Algorithm> Install<P> for Held<A> {
    fn install(&self, setup: Setup<'_, P>) -> Hooks<P> {
        crate::simulation::install::<P, A>(self.0.clone(), setup)
    }

    fn reinstall(&self, setup: Setup<'_, P>) {
        crate::simulation::populate::<P, A>(self.0.clone(), setup);
    }

    fn algorithm_type(&self) -> std::any::TypeId {
        std::any::TypeId::of::<A>()
    }
}

/// An algorithm with its parameters, erased, for a [`SimConfig`]: made from any
/// [`Algorithm`] value with [`AlgorithmBox::new`] (or from the name of one of the paper's
/// algorithms, [`AlgorithmKind`]). Cloning it is cheap.
///
/// ```
/// use monoculus_core::algorithms::{AlgorithmKind, ConvergeLocality, Goal, Model, StopCriterion};
/// use monoculus_engine::AlgorithmBox;
///
/// let a = AlgorithmBox::new(ConvergeLocality);
/// assert_eq!((a.name(), a.model()), ("converge_locality", Model::Ld));
/// assert_eq!(a.default_stop(), StopCriterion::QuiescentOrDiameter);
/// assert_eq!(a.goal(), Goal::Disc);
/// assert_eq!(AlgorithmBox::from(AlgorithmKind::ConvergeLocality).name(), a.name());
/// ```
///
/// [`SimConfig`]: crate::SimConfig
#[derive(Clone)]
pub struct AlgorithmBox {
    plane: Arc<dyn Install<DVec2>>,
    space: Arc<dyn Install<DVec3>>,
    name: Arc<str>,
    model: Model,
    stop: StopCriterion,
    goal: Goal,
    assumes_c_at_least_2b: bool,
    plane_only: Option<&'static str>,
    keeps_state: bool,
    shows_bits: bool,
    lights: Arc<[String]>,
}

impl AlgorithmBox {
    /// `algorithm`, ready for a run.
    pub fn new<A: Algorithm>(algorithm: A) -> Self {
        let name: Arc<str> = algorithm.name().into();
        let keeps_state = algorithm.keeps_state();
        let (stop, goal) = (algorithm.stop(), algorithm.goal());
        let lights: Arc<[String]> = algorithm.light_names().map(String::from).collect();
        let held = Arc::new(Held(Arc::new(algorithm)));
        AlgorithmBox {
            plane: held.clone(),
            space: held,
            name,
            model: <A::Sensing as Sensing>::MODEL,
            stop,
            goal,
            assumes_c_at_least_2b: A::ASSUMES_C_AT_LEAST_2B,
            plane_only: A::PLANE_ONLY,
            keeps_state,
            shows_bits: A::shown_bits(&A::State::default()).is_some(),
            lights,
        }
    }

    /// Its name ([`Algorithm::name`]).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Its sensing model.
    pub fn model(&self) -> Model {
        self.model
    }

    /// Its default stop criterion ([`Algorithm::stop`]).
    pub fn default_stop(&self) -> StopCriterion {
        self.stop
    }

    /// Its goal ([`Algorithm::goal`]): what its convergence means.
    pub fn goal(&self) -> Goal {
        self.goal
    }

    /// Whether its guarantees assume c >= 2b ([`Algorithm::ASSUMES_C_AT_LEAST_2B`]).
    pub fn assumes_c_at_least_2b(&self) -> bool {
        self.assumes_c_at_least_2b
    }

    /// Why it runs in the plane only, if it does ([`Algorithm::PLANE_ONLY`]).
    pub fn plane_only(&self) -> Option<&'static str> {
        self.plane_only
    }

    /// Whether its robots keep a state (and their frame) between activations.
    pub fn keeps_state(&self) -> bool {
        self.keeps_state
    }

    /// The names of its robots' lights ([`Algorithm::light_names`]; empty: none), in
    /// the order of their indices.
    pub fn lights(&self) -> &[String] {
        &self.lights
    }

    /// Whether a replay shows a byte of its robots' states ([`Algorithm::shown_bits`]).
    pub fn shows_bits(&self) -> bool {
        self.shows_bits
    }

    /// The algorithm for points `P`.
    pub(crate) fn for_points<P: IndexPoint>(&self) -> &dyn Install<P> {
        let any: &dyn Any = if P::DIM == 2 {
            &self.plane
        } else {
            &self.space
        };
        any.downcast_ref::<Arc<dyn Install<P>>>()
            .expect("the engine's points are DVec2 and DVec3")
            .as_ref()
    }
}

impl fmt::Debug for AlgorithmBox {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "AlgorithmBox({})", self.name)
    }
}

impl From<AlgorithmKind> for AlgorithmBox {
    fn from(kind: AlgorithmKind) -> Self {
        match kind {
            AlgorithmKind::ConvergeLocality => AlgorithmBox::new(ConvergeLocality),
            AlgorithmKind::ConvergeQuadrant => AlgorithmBox::new(ConvergeQuadrant),
            AlgorithmKind::ConvergeQuadrantTermination => {
                AlgorithmBox::new(ConvergeQuadrantTermination)
            }
            AlgorithmKind::CenterOfGravity => AlgorithmBox::new(CenterOfGravity),
            AlgorithmKind::Median => AlgorithmBox::new(Median),
            AlgorithmKind::AngleBisector => AlgorithmBox::new(AngleBisector),
        }
    }
}
