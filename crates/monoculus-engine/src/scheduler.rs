//! Schedulers (SPEC section 5) as data; the activation system in `systems` reads it.

/// Order of the sequential scheduler (`scheduler.order = "round_robin" | "random"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SequentialOrder {
    /// Robot `round mod n`.
    #[default]
    RoundRobin,
    /// A fresh random permutation of the robots for every n rounds (each robot once per
    /// cycle, in random order).
    Random,
}

/// Which robots act in a round.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SchedulerSpec {
    /// Every robot, every round.
    Fsync,
    /// Each robot with probability `p` (at least one per round); with `fairness = Some(k)`
    /// no robot waits more than k rounds.
    Ssync {
        /// Activation probability.
        p: f64,
        /// Largest number of rounds a robot may wait, if any.
        fairness: Option<u32>,
    },
    /// One robot per round.
    Sequential {
        /// Which one.
        order: SequentialOrder,
    },
    /// Continuous time in whole ticks: every robot cycles Idle -> Look -> Compute ->
    /// Move with random durations; time is reported in epochs.
    Async(crate::AsyncSpec),
}

impl SchedulerSpec {
    /// The config name.
    pub fn name(&self) -> &'static str {
        match self {
            SchedulerSpec::Fsync => "fsync",
            SchedulerSpec::Ssync { .. } => "ssync",
            SchedulerSpec::Sequential { .. } => "sequential",
            SchedulerSpec::Async(_) => "async",
        }
    }
}
