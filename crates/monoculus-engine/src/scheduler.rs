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

/// A schedule given in full (SPEC 9.4): for rounds k = 1, 2, ..., the robots activated
/// in round k. Rounds not listed activate nobody; the run ends after the last listed one.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct ActivationList {
    /// (round, its robots ascending), rounds strictly increasing, all >= 1.
    rounds: Vec<(u64, Vec<u32>)>,
}

/// Why rounds do not make an [`ActivationList`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ActivationError {
    /// Round 0 (rounds are 1-based).
    #[error("round 0: rounds are numbered from 1")]
    RoundZero,
    /// A round after a later one, or listed again.
    #[error("round {round} after round {previous}: rounds must increase")]
    NotIncreasing {
        /// The round.
        round: u64,
        /// The round before it.
        previous: u64,
    },
    /// A robot twice in one round.
    #[error("robot {robot} is listed twice in round {round}")]
    Twice {
        /// The round.
        round: u64,
        /// The robot.
        robot: u32,
    },
}

impl ActivationList {
    /// A schedule from (round, robots) pairs in increasing order of round; the robots of
    /// a round may come in any order but each once.
    pub fn new(mut rounds: Vec<(u64, Vec<u32>)>) -> Result<Self, ActivationError> {
        let mut previous = 0;
        for (round, robots) in &mut rounds {
            if *round == 0 {
                return Err(ActivationError::RoundZero);
            }
            if *round <= previous {
                return Err(ActivationError::NotIncreasing {
                    round: *round,
                    previous,
                });
            }
            previous = *round;
            robots.sort_unstable();
            if let Some(w) = robots.windows(2).find(|w| w[0] == w[1]) {
                return Err(ActivationError::Twice {
                    round: *round,
                    robot: w[0],
                });
            }
        }
        Ok(ActivationList { rounds })
    }

    /// The number of rounds: the last listed one (0 if none).
    pub fn rounds(&self) -> u64 {
        self.rounds.last().map_or(0, |r| r.0)
    }

    /// The robots of round `k` (1-based), ascending; empty if the round is not listed.
    pub fn round(&self, k: u64) -> &[u32] {
        self.rounds
            .binary_search_by_key(&k, |r| r.0)
            .map_or(&[], |i| self.rounds[i].1.as_slice())
    }

    /// The largest robot index listed, if any.
    pub fn max_robot(&self) -> Option<u32> {
        self.rounds.iter().filter_map(|r| r.1.last().copied()).max()
    }
}

/// What the adversarial scheduler prefers (SPEC 9.5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Objective {
    /// The one robot whose move alone shrinks the hull's perimeter least.
    #[default]
    Slow,
    /// Every robot whose move alone grows the hull's area (if none, as `Slow`).
    Grow,
}

/// Which robots act in a round.
#[derive(Clone, Debug, PartialEq)]
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
    /// Each round, among the robots that would move, the ones `objective` prefers, and
    /// every robot not activated in the last `fairness - 1` rounds (plane only).
    Adversary {
        /// What it prefers.
        objective: Objective,
        /// k: every robot is activated at least once every k rounds (`None`: k = n).
        fairness: Option<u32>,
    },
    /// The robots of a given list in each round (SSYNC-style), until the list ends.
    File(std::sync::Arc<ActivationList>),
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
            SchedulerSpec::File(_) => "file",
            SchedulerSpec::Adversary { .. } => "adversary",
        }
    }

    /// The last round the scheduler has, if it has one (a schedule from a file).
    pub fn last_round(&self) -> Option<u64> {
        match self {
            SchedulerSpec::File(list) => Some(list.rounds()),
            _ => None,
        }
    }
}
