#![doc = include_str!("../README.md")]

pub mod algorithms;
pub mod errors;
pub mod geometry;
pub mod impossibility;
pub mod init;
pub mod metrics;
pub mod observe;
pub mod rng;
pub mod vision;

/// The most used items.
pub mod prelude {
    pub use crate::algorithms::{
        Algorithm, AlgorithmKind, Decision, Directions, Goal, Ld, ModelParams, NoParams,
        Observation, Ola, Positions, StopCriterion, TargetPolicy, activate,
    };
    pub use crate::geometry::{AxisFrame, HullGeometry, Point};
    pub use crate::observe::{Seen, Side};
    pub use crate::rng::{Purpose, Stream};
    pub use crate::vision::{ExactSight, Sight, VisionParams};
}
