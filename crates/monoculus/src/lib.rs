//! monoculus for your own algorithms.
//!
//! Implement [`Algorithm`](prelude::Algorithm) for a type of your crate, register it with
//! [`App`], and your binary has the whole `monoculus` command line (`run`, `check`,
//! `trace`, `look`, `replay`, `plot`, `table`, `merge`, `slurm`, `stress`,
//! `impossibility`) with your algorithm beside the paper's: every scheduler, error and
//! fault model, the plane and space, replays and Slurm arrays (whose scripts call your
//! binary).
//!
//! ```no_run
//! use monoculus::prelude::*;
//!
//! /// Move toward a uniformly random visible robot.
//! struct TowardAnyone;
//!
//! impl Algorithm for TowardAnyone {
//!     const NAME: &'static str = "toward_anyone";
//!     type Sensing = Directions;
//!     type Params = NoParams;
//!     type State = ();
//!
//!     fn new(_: NoParams) -> Result<Self, String> {
//!         Ok(TowardAnyone)
//!     }
//!
//!     fn decide<V: Point>(
//!         &self,
//!         obs: &Observation<'_, Directions, V>,
//!         _: &mut (),
//!         rng: &mut Stream,
//!     ) -> Decision<V> {
//!         obs.random_visible(rng).map_or(Decision::Stay, Decision::Step)
//!     }
//! }
//!
//! fn main() -> std::process::ExitCode {
//!     App::new().algorithm::<TowardAnyone>().run()
//! }
//! ```
//!
//! The guide, from an empty crate to a sweep and a replay: `docs/algorithms.md` in the
//! repository.

use std::process::ExitCode;

pub use glam::{DVec2, DVec3};
pub use monoculus_core::algorithms::{Algorithm, BadDecision};
pub use monoculus_engine::{AlgorithmBox, RunOutcome, SimConfig, Simulation, StoppedBy};
pub use monoculus_experiments::{Experiment, Registry, RunOptions, SweepReport, run_experiment};

/// The guide: writing an algorithm, from an empty crate to a sweep and a replay
/// (`docs/algorithms.md`; its code is compiled and run with the crate's tests).
#[doc = include_str!("../../../docs/algorithms.md")]
pub mod guide {}

/// The guide's page on robots with state and lights (`docs/state-and-lights.md`; its code
/// is compiled and run with the crate's tests).
#[doc = include_str!("../../../docs/state-and-lights.md")]
pub mod state_and_lights {}

/// The paper's algorithms and the baselines, the same types the built-in names select:
/// to compare with, wrap or call from an algorithm of your own.
///
/// ```
/// use monoculus::DVec2;
/// use monoculus::algorithms::ConvergeLocality;
///
/// let start = vec![DVec2::ZERO, DVec2::new(5.0, 0.0), DVec2::new(0.0, 5.0)];
/// let config = monoculus::SimConfig::paper(monoculus::AlgorithmBox::new(ConvergeLocality), 0, 1000);
/// assert!(monoculus::Simulation::new(config, start).unwrap().run().converged);
/// ```
pub mod algorithms {
    pub use monoculus_core::algorithms::{
        AngleBisector, CenterOfGravity, ConvergeLocality, ConvergeQuadrant,
        ConvergeQuadrantTermination, Median,
    };
}

/// One activation of `algorithm` by robot `robot` of the swarm at `positions`, for unit
/// tests of an algorithm's rules: the paper's b = 1 and c = 2, exact lines of sight, no
/// errors, the robot's frame and stream drawn from `seed` (a fresh state, if the
/// algorithm keeps one). The global displacement, or `None` to stay.
///
/// ```
/// use monoculus::DVec2;
/// use monoculus::algorithms::ConvergeLocality;
///
/// // The end robot of three on a line sees one robot: it moves toward it.
/// let line = [DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), DVec2::new(2.0, 0.0)];
/// let step = monoculus::activate_once(&ConvergeLocality, &line, 0, 7).unwrap();
/// assert!((step.unwrap() - DVec2::new(1.0, 0.0)).length() < 1e-12);
/// ```
pub fn activate_once<A: Algorithm, V: monoculus_core::geometry::Point>(
    algorithm: &A,
    positions: &[V],
    robot: usize,
    seed: u64,
) -> Result<Option<V>, BadDecision> {
    use monoculus_core::algorithms::{ModelParams, activate};
    use monoculus_core::rng::{Purpose, Stream};
    use monoculus_core::vision::{ExactSight, VisionParams};
    let sight = ExactSight::new(positions.to_vec(), VisionParams::for_step(1.0));
    let mut stream = Stream::keyed(seed, Purpose::Decide, robot as u64, 0);
    activate(
        algorithm,
        &ModelParams::new(1.0, 2.0),
        &sight,
        robot,
        None,
        &mut stream,
    )
}

/// What an algorithm's author needs: the trait, what its methods take and return, and
/// the vector types of the plane and of space.
pub mod prelude {
    pub use crate::App;
    pub use glam::{DVec2, DVec3};
    pub use monoculus_core::algorithms::{
        Algorithm, Decision, Directions, Goal, Ld, Lit, Model, NoParams, Observation, Ola,
        Positions, StopCriterion, along, empty_sides,
    };
    pub use monoculus_core::geometry::Point;
    pub use monoculus_core::observe::{Seen, Side};
    pub use monoculus_core::rng::Stream;
}

/// A monoculus command line with your algorithms: [`App::new`] holds the paper's six,
/// [`App::algorithm`] adds one of yours, [`App::run`] runs the command line.
///
/// ```
/// use monoculus::App;
/// use monoculus::prelude::*;
///
/// struct Still;
///
/// impl Algorithm for Still {
///     const NAME: &'static str = "still";
///     type Sensing = Ld;
///     type Params = NoParams;
///     type State = ();
///     fn new(_: NoParams) -> Result<Self, String> {
///         Ok(Still)
///     }
///     fn decide<V: Point>(&self, _: &Observation<'_, Ld, V>, _: &mut (), _: &mut Stream) -> Decision<V> {
///         Decision::Stay
///     }
/// }
///
/// let app = App::new().algorithm::<Still>();
/// assert!(app.registry().get("still").is_some());
/// assert!(app.registry().get("converge_locality").is_some());
/// ```
pub struct App {
    registry: Registry,
    name: Option<&'static str>,
}

impl Default for App {
    fn default() -> Self {
        App::new()
    }
}

impl App {
    /// A command line with the paper's algorithms.
    pub fn new() -> Self {
        App {
            registry: Registry::builtin(),
            name: None,
        }
    }

    /// A command line with no algorithm but yours.
    pub fn without_builtins() -> Self {
        App {
            registry: Registry::new(),
            name: None,
        }
    }

    /// Adds `A`, which configs then select by [`Algorithm::NAME`]. A name registered
    /// twice panics when the binary starts, naming it.
    pub fn algorithm<A: Algorithm>(mut self) -> Self {
        self.registry.register::<A>();
        self
    }

    /// The name the command line calls itself in its help (default: the binary's file
    /// name).
    pub fn name(mut self, name: &'static str) -> Self {
        self.name = Some(name);
        self
    }

    /// The algorithms registered so far.
    pub fn registry(&self) -> &Registry {
        &self.registry
    }

    /// Runs the command line on the process's arguments; returns its exit status (0
    /// success, 2 bad input, 1 other failures, 130 interrupted).
    pub fn run(self) -> ExitCode {
        let name = self.name.unwrap_or_else(|| {
            let exe = std::env::current_exe().ok();
            let stem = exe
                .as_deref()
                .and_then(|p| p.file_stem())
                .and_then(|s| s.to_str())
                .unwrap_or("monoculus");
            // clap takes a name for the life of the program.
            Box::leak(stem.to_string().into_boxed_str())
        });
        monoculus_cli::main_with(name, &self.registry)
    }
}
