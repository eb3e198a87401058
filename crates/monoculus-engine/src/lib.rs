//! The monoculus engine: robots are `bevy_ecs` entities; a round is a `Schedule` of
//! systems in [`RoundSet`] order (Activate, Look, Compute, Move, Measure); the Look is
//! an immutable snapshot with a spatial index ([`IndexedSight`]: a band grid in the
//! plane, an rstar R-tree in space) that answers the
//! visibility questions of the algorithms; Compute runs over robots in parallel with
//! rayon. Results do not depend on the number of threads: every random draw comes from
//! a stream keyed by (seed, robot, round).
//!
//! ```
//! use glam::DVec2;
//! use monoculus_core::prelude::*;
//! use monoculus_core::errors::MovementErrors;
//! use monoculus_core::init::{InitShape, generate};
//! use monoculus_core::algorithms::ConvergeLocality;
//! use monoculus_engine::prelude::*;
//!
//! let algorithm = AlgorithmBox::new(ConvergeLocality);
//! let config = SimConfig {
//!     stop: StopSpec {
//!         criterion: algorithm.default_stop(),
//!         goal: algorithm.goal(),
//!         max_rounds: 10_000,
//!     },
//!     algorithm,
//!     model: ModelParams::new(1.0, 2.0),
//!     vision: VisionParams::for_step(1.0),
//!     backend: SightBackend::Index,
//!     scheduler: SchedulerSpec::Fsync,
//!     seed: 7,
//!     movement: MovementErrors::NONE,
//!     faults: None,
//! };
//! let start: Vec<DVec2> = generate(&InitShape::Square { side: 20.0 }, 50, 7);
//! let outcome = Simulation::new(config, start).unwrap().run();
//! assert!(outcome.converged);
//! assert_eq!(outcome.hull_growth_rounds, 0); // Lemma 2
//! ```

pub mod algorithm;
pub mod asynchrony;
pub mod components;
mod error;
pub mod faults;
pub mod index;
pub mod resources;
mod scheduler;
mod simulation;
mod stop;
pub mod systems;

pub use algorithm::AlgorithmBox;
pub use asynchrony::{AsyncSpec, AsyncStart, TickDist};
pub use error::{EngineError, MAX_MAGNITUDE, MAX_ROBOTS};
pub use faults::{ByzantineRule, CrashAt, FaultCount, FaultKind, FaultPlan, FaultSpec, Role};
pub use index::{IndexPoint, IndexedSight, SegmentGrid, SpaceIndex, SpatialIndex, Tube};
pub use resources::{RunFailure, SightBackend};
pub use scheduler::{ActivationError, ActivationList, Objective, SchedulerSpec, SequentialOrder};
pub use simulation::{Activity, RobotView, RoundReport, RunOutcome, SimConfig, Simulation};
pub use stop::{Goal, StopCriterion, StopSpec, StoppedBy};
pub use systems::RoundSet;

/// The most used items.
pub mod prelude {
    pub use crate::{
        AlgorithmBox, AsyncSpec, AsyncStart, Goal, IndexedSight, RunOutcome, SchedulerSpec,
        SequentialOrder, SightBackend, SimConfig, Simulation, StopCriterion, StopSpec, StoppedBy,
        TickDist,
    };
}
