//! Stop criteria (SPEC section 6), goals and what ended a run (SPEC section 11).

pub use monoculus_core::algorithms::{Goal, StopCriterion};

/// When a run ends, and what it must reach to count as converged.
///
/// ```
/// use monoculus_engine::{Goal, StopCriterion, StopSpec};
///
/// let stop = StopSpec {
///     criterion: StopCriterion::QuiescentOrDiameter,
///     goal: Goal::Disc,
///     max_rounds: 10_000,
/// };
/// assert_eq!(stop.goal.name(), "disc");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopSpec {
    /// The criterion that ends a run.
    pub criterion: StopCriterion,
    /// What convergence means: a run has converged when `criterion` ended it and this
    /// holds for the configuration it ended with.
    pub goal: Goal,
    /// Runs that reach this many rounds (ASYNC: epochs) stop unconverged.
    pub max_rounds: u64,
}

/// What ended a run (`runs.csv`'s column `stopped_by`).
///
/// ```
/// use monoculus_engine::StoppedBy;
///
/// assert_eq!(StoppedBy::MaxRounds.name(), "max_rounds");
/// assert!(StoppedBy::Quiescent.by_criterion() && !StoppedBy::MaxRounds.by_criterion());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StoppedBy {
    /// No correct robot would move (or change its light) if activated.
    Quiescent,
    /// Every pair of correct robots within c.
    Diameter,
    /// The bounding box's extent at most 2b on every axis.
    Box,
    /// The cap on rounds (ASYNC: epochs), `stop.max_rounds`.
    MaxRounds,
    /// The last round of a schedule file (`scheduler.kind = "file"`).
    ScheduleEnd,
    /// The algorithm failed (a bad decision, a panic).
    Failure,
    /// Stopped from outside ([`Simulation::set_interrupt`](crate::Simulation::set_interrupt)).
    Interrupted,
}

impl StoppedBy {
    /// Every value, in the order of their names in documentation.
    pub const ALL: [StoppedBy; 7] = [
        StoppedBy::Quiescent,
        StoppedBy::Diameter,
        StoppedBy::Box,
        StoppedBy::MaxRounds,
        StoppedBy::ScheduleEnd,
        StoppedBy::Failure,
        StoppedBy::Interrupted,
    ];

    /// Its name in `runs.csv`.
    pub fn name(self) -> &'static str {
        match self {
            StoppedBy::Quiescent => "quiescent",
            StoppedBy::Diameter => "diameter",
            StoppedBy::Box => "box",
            StoppedBy::MaxRounds => "max_rounds",
            StoppedBy::ScheduleEnd => "schedule_end",
            StoppedBy::Failure => "failure",
            StoppedBy::Interrupted => "interrupted",
        }
    }

    /// The value named `name`, if one.
    pub fn from_name(name: &str) -> Option<StoppedBy> {
        StoppedBy::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Whether the stop criterion ended the run (not the cap, a schedule's end, a
    /// failure or an interruption).
    pub fn by_criterion(self) -> bool {
        matches!(
            self,
            StoppedBy::Quiescent | StoppedBy::Diameter | StoppedBy::Box
        )
    }
}
