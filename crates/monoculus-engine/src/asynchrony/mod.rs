//! The ASYNC scheduler (SPEC section 5): continuous time in whole ticks. Every robot
//! repeats Idle -> Look -> Compute -> Move with durations drawn from its own streams;
//! all Looks of one tick see one snapshot, robots in mid-move at their interpolated
//! positions. Time is counted in epochs: the shortest spans in which every robot
//! completes at least one full cycle.

mod agenda;
mod ahead;
mod boxes;
mod committed;
mod components;
mod durations;
mod kept_hull;
mod parallel;
mod roster;
mod shape;
mod sight;
mod spec;
mod systems;

pub use committed::CommittedHull;
pub use components::{AsyncClock, Clocks, Lights, Phase, RobotEntities, Timing};
pub use durations::{Durations, DurationsError, GivenDuration, phase_name};
pub(crate) use shape::AheadShape;
pub use shape::KeptShape;
pub use sight::{Located, LookSight, Looking, TickSight};
pub use spec::{AsyncSpec, AsyncStart, MAX_PHASE_TICKS, TickDist};
pub use systems::{AsyncSet, account, advance, finish_computes, finish_moves, look};
pub(crate) use systems::{COMPUTE, IDLE, MOVE, START, duration, positions_now};
pub(crate) use systems::{phase_ends, to_account};
