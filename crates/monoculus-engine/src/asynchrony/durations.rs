//! [`Durations`]: phase durations given for single cycles of single robots
//! (`scheduler.durations`), in place of draws from the distributions.

use super::components::Phase;
use super::spec::MAX_PHASE_TICKS;

/// One given duration: phase `phase` of cycle `cycle` of robot `robot` lasts `ticks`.
///
/// A robot's cycles are counted from 0, and cycle k is its Idle phase (for cycle 0:
/// the start offset, which exists only with [`AsyncStart::Random`](super::AsyncStart)),
/// its Look, its Compute phase and its Move phase.
///
/// ```
/// use monoculus_engine::asynchrony::{GivenDuration, Phase};
///
/// // Robot 2 computes for 40 ticks in its first cycle.
/// let slow = GivenDuration { robot: 2, cycle: 0, phase: Phase::Compute, ticks: 40 };
/// assert_eq!(slow.ticks, 40);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GivenDuration {
    /// The robot (0-based).
    pub robot: u32,
    /// Its cycle (0-based).
    pub cycle: u64,
    /// The phase: [`Phase::Idle`], [`Phase::Compute`] or [`Phase::Move`].
    pub phase: Phase,
    /// Its length, from 1 to [`MAX_PHASE_TICKS`].
    pub ticks: u64,
}

impl GivenDuration {
    /// Which phase it gives, `(robot, cycle, phase)`: what [`Durations`] sorts and finds
    /// given durations by.
    ///
    /// ```
    /// use monoculus_engine::asynchrony::{GivenDuration, Phase};
    ///
    /// let g = GivenDuration { robot: 1, cycle: 4, phase: Phase::Idle, ticks: 3 };
    /// assert_eq!(g.key(), (1, 4, Phase::Idle));
    /// assert!(Phase::Idle < Phase::Compute && Phase::Compute < Phase::Move);
    /// ```
    pub fn key(&self) -> (u32, u64, Phase) {
        (self.robot, self.cycle, self.phase)
    }
}

/// Why given durations do not make a [`Durations`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DurationsError {
    /// A phase is given twice.
    Twice {
        /// The robot.
        robot: u32,
        /// Its cycle.
        cycle: u64,
        /// The phase.
        phase: Phase,
    },
    /// A length of 0 ticks or of more than [`MAX_PHASE_TICKS`].
    Ticks(u64),
}

impl std::fmt::Display for DurationsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            DurationsError::Twice {
                robot,
                cycle,
                phase,
            } => write!(
                f,
                "the {} phase of robot {robot}'s cycle {cycle} is given twice",
                phase_name(phase)
            ),
            DurationsError::Ticks(t) => write!(
                f,
                "{t} ticks: a phase lasts from 1 to 2^40 = {MAX_PHASE_TICKS} ticks"
            ),
        }
    }
}

impl std::error::Error for DurationsError {}

/// The config name of a phase (`idle`, `compute`, `move`).
///
/// ```
/// use monoculus_engine::asynchrony::{Phase, phase_name};
///
/// assert_eq!(phase_name(Phase::Move), "move");
/// ```
pub fn phase_name(phase: Phase) -> &'static str {
    match phase {
        Phase::Idle => "idle",
        Phase::Compute => "compute",
        Phase::Move => "move",
    }
}

/// Phase durations given per robot and cycle; every phase not given is drawn from its
/// distribution as usual, from the same stream, so a run with a few durations given
/// differs from the plain run only where they are.
///
/// ```
/// use std::sync::Arc;
/// use monoculus_engine::asynchrony::{Durations, GivenDuration, Phase};
/// use monoculus_engine::{AsyncSpec, SchedulerSpec};
///
/// let given = Durations::new([GivenDuration { robot: 0, cycle: 1, phase: Phase::Move, ticks: 9 }])?;
/// assert_eq!(given.get(0, 1, Phase::Move), Some(9));
/// assert_eq!(given.get(0, 0, Phase::Move), None);
/// let scheduler = SchedulerSpec::Async(AsyncSpec {
///     durations: Some(Arc::new(given)),
///     ..AsyncSpec::default()
/// });
/// # let _ = scheduler;
/// # Ok::<(), monoculus_engine::asynchrony::DurationsError>(())
/// ```
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Durations {
    /// Sorted by [`GivenDuration::key`], each key once.
    given: Vec<GivenDuration>,
}

impl Durations {
    /// The given durations (in any order), or why they are not valid: a phase given
    /// twice, or a length outside 1 to [`MAX_PHASE_TICKS`] ticks.
    pub fn new(
        given: impl IntoIterator<Item = GivenDuration>,
    ) -> Result<Durations, DurationsError> {
        let mut v: Vec<GivenDuration> = given.into_iter().collect();
        if let Some(g) = v.iter().find(|g| g.ticks == 0 || g.ticks > MAX_PHASE_TICKS) {
            return Err(DurationsError::Ticks(g.ticks));
        }
        v.sort_unstable_by_key(GivenDuration::key);
        if let Some(w) = v.windows(2).find(|w| w[0].key() == w[1].key()) {
            let (robot, cycle, phase) = w[0].key();
            return Err(DurationsError::Twice {
                robot,
                cycle,
                phase,
            });
        }
        Ok(Durations { given: v })
    }

    /// The length given to phase `phase` of robot `robot`'s cycle `cycle`, if any.
    pub fn get(&self, robot: u32, cycle: u64, phase: Phase) -> Option<u64> {
        self.given
            .binary_search_by_key(&(robot, cycle, phase), GivenDuration::key)
            .ok()
            .map(|i| self.given[i].ticks)
    }

    /// Every given duration, by robot, cycle and phase.
    pub fn iter(&self) -> impl Iterator<Item = GivenDuration> + '_ {
        self.given.iter().copied()
    }

    /// How many durations are given.
    pub fn len(&self) -> usize {
        self.given.len()
    }

    /// Whether none is.
    pub fn is_empty(&self) -> bool {
        self.given.is_empty()
    }

    /// The largest robot index given, if any.
    pub fn max_robot(&self) -> Option<u32> {
        self.given.last().map(|g| g.robot)
    }

    /// The longest duration given for `phase`, ticks (0 when none is).
    pub fn longest(&self, phase: Phase) -> u64 {
        self.given
            .iter()
            .filter(|g| g.phase == phase)
            .map(|g| g.ticks)
            .max()
            .unwrap_or(0)
    }

    /// The first robot with an Idle phase given for its cycle 0 (which exists only
    /// when the robots start at random), if any.
    pub fn first_start(&self) -> Option<u32> {
        self.given
            .iter()
            .find(|g| g.cycle == 0 && g.phase == Phase::Idle)
            .map(|g| g.robot)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn g(robot: u32, cycle: u64, phase: Phase, ticks: u64) -> GivenDuration {
        GivenDuration {
            robot,
            cycle,
            phase,
            ticks,
        }
    }

    #[test]
    fn looks_up_what_was_given_and_nothing_else() {
        let d = Durations::new([
            g(3, 0, Phase::Move, 7),
            g(0, 2, Phase::Idle, 4),
            g(0, 2, Phase::Compute, 5),
        ])
        .unwrap();
        assert_eq!(d.get(0, 2, Phase::Idle), Some(4));
        assert_eq!(d.get(0, 2, Phase::Compute), Some(5));
        assert_eq!(d.get(0, 2, Phase::Move), None);
        assert_eq!(d.get(3, 0, Phase::Move), Some(7));
        assert_eq!(d.max_robot(), Some(3));
        assert_eq!(d.longest(Phase::Move), 7);
        assert_eq!(d.longest(Phase::Idle), 4);
        assert_eq!(d.first_start(), None);
        let order: Vec<_> = d.iter().map(|x| (x.robot, x.cycle)).collect();
        assert_eq!(order, [(0, 2), (0, 2), (3, 0)]);
    }

    #[test]
    fn refuses_twice_and_lengths_out_of_range() {
        assert_eq!(
            Durations::new([g(1, 1, Phase::Idle, 2), g(1, 1, Phase::Idle, 3)]).unwrap_err(),
            DurationsError::Twice {
                robot: 1,
                cycle: 1,
                phase: Phase::Idle
            }
        );
        assert_eq!(
            Durations::new([g(1, 1, Phase::Idle, 0)]).unwrap_err(),
            DurationsError::Ticks(0)
        );
        assert!(Durations::new([g(1, 1, Phase::Idle, MAX_PHASE_TICKS + 1)]).is_err());
        assert!(
            Durations::new([g(1, 0, Phase::Idle, 1)])
                .unwrap()
                .first_start()
                == Some(1)
        );
    }
}
