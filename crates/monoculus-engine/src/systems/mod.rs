//! The systems of one round, in the order of [`RoundSet`]:
//! Activate (scheduler) -> Look (snapshot) -> Compute (algorithms, in parallel) ->
//! Move -> Measure.

mod activate;
mod adversary;
mod compute;
mod look;
mod measure;
mod movement;

use bevy_ecs::prelude::*;

pub use activate::activate_robots;
pub use adversary::{choose_adversarially, preferred};
pub use compute::{
    Item, KeptBy, MemoryOf, View, compute_intents, decide_items, decide_one, light, lights_of,
    realise,
};
pub use look::{build_sight, refresh_snapshot, take_snapshot};
pub use measure::{
    HULL_GROWTH_TOLERANCE, advance_clock, hull_grew, measure_committed, measure_shape, record_hull,
};
pub(crate) use measure::{measure_round, move_round};
pub use movement::apply_moves;

/// The phases of a round, run in this order.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RoundSet {
    /// The scheduler marks the robots that act this round.
    Activate,
    /// The Look: one immutable snapshot of the configuration (and its spatial index).
    Look,
    /// Every activated robot computes its move against the snapshot, in parallel.
    Compute,
    /// Activated robots move.
    Move,
    /// Hull, diameter and extents are measured; the clock advances.
    Measure,
}
