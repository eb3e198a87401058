//! Resources: state shared by all robots of one simulation.

use bevy_ecs::prelude::*;
use monoculus_core::algorithms::ModelParams;
use monoculus_core::errors::MovementErrors;
use monoculus_core::vision::{ExactSight, VisionParams};

use crate::index::SpaceIndex;
use crate::{IndexPoint, IndexedSight, SchedulerSpec};

/// How visibility questions are answered (`vision.backend = "index" | "exact" | "rtree"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SightBackend {
    /// The spatial index: the band grid in the plane, the R-tree in space (the default).
    #[default]
    Index,
    /// Brute force from the definition: slow, for cross-checking.
    Exact,
    /// An rstar R-tree in every dimension (in space the same as `Index`): the plane's
    /// alternative to the band grid, for comparison.
    Rtree,
}

/// The fixed parameters of a run.
#[derive(Resource, Clone, Debug)]
pub struct Params {
    /// b, c, observation errors, target policy.
    pub model: ModelParams,
    /// Visibility tolerances.
    pub vision: VisionParams,
    /// Visibility backend.
    pub backend: SightBackend,
    /// Scheduler.
    pub scheduler: SchedulerSpec,
    /// The run's seed.
    pub seed: u64,
    /// Movement errors.
    pub movement: MovementErrors,
    /// Every robot's role, when some are faulty.
    pub faults: Option<std::sync::Arc<crate::FaultPlan>>,
    /// The first bad decision of the run, if its algorithm made one.
    pub failure: Failure,
}

/// Where a run's algorithm failed (a step along a direction that is not a unit vector, a
/// panic): the robot, the round (ASYNC: the robot's cycle) and what happened. The run
/// stops after the step in which it happened.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunFailure {
    /// The round, or under ASYNC the robot's cycle (1-based).
    pub round: u64,
    /// The robot.
    pub robot: usize,
    /// What the algorithm did.
    pub message: String,
}

impl std::fmt::Display for RunFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} (robot {}, round {})",
            self.message, self.robot, self.round
        )
    }
}

/// The first [`RunFailure`] of a run, shared by the threads that decide: of failures in
/// one step, the one of the lowest (round, robot), whatever the thread count.
#[derive(Clone, Debug, Default)]
pub struct Failure(std::sync::Arc<std::sync::Mutex<Option<RunFailure>>>);

impl Failure {
    /// Records a failure.
    pub fn record(&self, failure: RunFailure) {
        let mut f = self.0.lock().unwrap_or_else(|p| p.into_inner());
        if f.as_ref()
            .is_none_or(|old| (failure.round, failure.robot) < (old.round, old.robot))
        {
            *f = Some(failure);
        }
    }

    /// The failure, if any.
    pub fn get(&self) -> Option<RunFailure> {
        self.0.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }
}

impl Params {
    /// Whether robot `i` runs the algorithm (is not faulty).
    pub fn is_correct(&self, i: usize) -> bool {
        self.faults.as_ref().is_none_or(|f| f.is_correct(i))
    }

    /// The positions of the correct robots (all of them without faults).
    pub fn correct<'a, P: Copy>(&self, points: &'a [P]) -> std::borrow::Cow<'a, [P]> {
        match &self.faults {
            Some(f) => std::borrow::Cow::Owned(f.correct(points)),
            None => std::borrow::Cow::Borrowed(points),
        }
    }
}

/// The current round number (rounds completed so far).
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct Clock {
    /// Rounds completed.
    pub round: u64,
}

/// Positions of all robots by index, gathered after every Move; `generation` counts
/// the rounds in which something moved.
#[derive(Resource, Clone, Debug)]
pub struct Positions<P: IndexPoint> {
    /// Positions by robot index.
    pub points: Vec<P>,
    /// Incremented whenever a robot moves.
    pub generation: u64,
}

/// What all robots Look at: one immutable snapshot of the configuration.
pub enum SnapshotSight<P: IndexPoint> {
    /// Through the spatial index.
    Index(IndexedSight<P>),
    /// Brute force.
    Exact(ExactSight<P>),
    /// Through an R-tree.
    Rtree(IndexedSight<P, SpaceIndex<P>>),
}

/// The Look snapshot and the position generation it was taken at.
#[derive(Resource)]
pub struct Snapshot<P: IndexPoint> {
    /// The sight, if one has been taken.
    pub sight: Option<SnapshotSight<P>>,
    /// The generation of [`Positions`] it reflects.
    pub generation: u64,
}

/// The SSYNC and sequential schedulers' bookkeeping.
#[derive(Resource, Clone, Debug, Default)]
pub struct ScheduleState {
    /// Sequential random order: the cycle whose permutation is cached.
    pub cycle: Option<u64>,
    /// That permutation.
    pub order: Vec<usize>,
}

/// Counters over the run and of the last round.
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct Tally {
    /// Activations so far.
    pub activations: u64,
    /// Activations that moved so far.
    pub moves: u64,
    /// Total distance travelled.
    pub distance: f64,
    /// Activations in the last round.
    pub round_activations: u64,
    /// Robots that moved in the last round.
    pub round_moves: u64,
    /// Rounds (ASYNC: ticks) in which the area of the hull of the positions grew.
    pub hull_growth_rounds: u64,
    /// The largest relative growth of the hull in one round (tick): area / previous - 1.
    pub hull_growth_max: f64,
    /// ASYNC: ticks in which the hull of the positions and of the destinations of
    /// decided moves grew (the form in which Lemma 2 holds under ASYNC).
    pub committed_hull_growth: u64,
}

/// The vertices of the current hull of the correct robots' positions (plane only; see
/// [`HullGeometry::hull_vertices`](monoculus_core::geometry::HullGeometry)).
#[derive(Resource, Clone, Debug)]
pub struct HullVertices<P: IndexPoint> {
    /// The vertices (empty in space).
    pub vertices: Vec<P>,
    /// The [`Positions::generation`] they were taken at.
    pub generation: u64,
}

/// The shape of the configuration, measured after every round.
#[derive(Resource, Clone, Debug, Default)]
pub struct Shape {
    /// Area (d = 2) or volume (d = 3) of the convex hull.
    pub hull: f64,
    /// The largest hull measured so far in the run.
    pub hull_max: f64,
    /// Largest pairwise distance.
    pub diameter: f64,
    /// Bounding-box extent per axis.
    pub extents: Vec<f64>,
}
