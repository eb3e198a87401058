use bevy_ecs::prelude::*;

use crate::IndexPoint;
use crate::components::{Activated, Intent, Robot};
use crate::resources::{Positions, Tally};

/// Move: activated robots apply their displacement.
pub fn apply_moves<P: IndexPoint>(
    robots: Query<(&Robot, &Activated, &Intent<P>)>,
    mut positions: ResMut<Positions<P>>,
    mut tally: ResMut<Tally>,
) {
    let (mut activated, mut moved) = (0u64, 0u64);
    for (robot, active, intent) in &robots {
        if !active.0 {
            continue;
        }
        activated += 1;
        if let Some(d) = intent.0 {
            positions.points[robot.index as usize] += d;
            moved += 1;
            // Summed robot by robot, in index order, as the async scheduler does.
            tally.distance += d.length();
        }
    }
    tally.round_activations = activated;
    tally.round_moves = moved;
    tally.activations += activated;
    tally.moves += moved;
    if moved > 0 {
        positions.generation += 1;
    }
}
