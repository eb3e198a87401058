//! Components: what each robot entity carries.

use bevy_ecs::prelude::*;
use monoculus_core::algorithms::Kept;

use crate::IndexPoint;

/// A robot's index: its row in the initial configuration and the key of its random
/// streams. Robots are anonymous to each other; the index is the engine's bookkeeping.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct Robot {
    /// 0-based index.
    pub index: u32,
}

/// Whether the scheduler activates the robot this round.
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Activated(pub bool);

/// Rounds since the robot was last activated (SSYNC k-fairness).
#[derive(Component, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Waiting(pub u32);

/// The displacement computed this round (`None`: stay or not activated).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Intent<P: IndexPoint>(pub Option<P>);

/// What a robot keeps between activations when its algorithm has a state (only the robots
/// of such an algorithm carry it): its frame, fixed for the run, and the state.
#[derive(Component, Clone, Debug, PartialEq)]
pub struct Memory<P: IndexPoint, T: Clone + PartialEq + Send + Sync + 'static>(pub Kept<P, T>);
