use bevy_ecs::prelude::*;

use crate::IndexPoint;
use crate::components::{Activated, Intent, Robot};
use crate::resources::{Params, Positions, Tally};

/// Move: activated robots apply their displacement. Activations, moves and distance
/// count the correct robots only (SPEC 9.1); any move makes a new configuration.
pub fn apply_moves<P: IndexPoint>(
    params: Res<Params>,
    robots: Query<(&Robot, &Activated, &Intent<P>)>,
    mut positions: ResMut<Positions<P>>,
    mut tally: ResMut<Tally>,
) {
    apply(&params, &robots, &mut positions, &mut tally);
}

/// [`apply_moves`]' work, for the systems that run it with others.
pub(super) fn apply<P: IndexPoint>(
    params: &Params,
    robots: &Query<(&Robot, &Activated, &Intent<P>)>,
    positions: &mut Positions<P>,
    tally: &mut Tally,
) {
    let (mut activated, mut moved, mut any) = (0u64, 0u64, false);
    for (robot, active, intent) in robots {
        if !active.0 {
            continue;
        }
        let i = robot.index as usize;
        let correct = params.is_correct(i);
        activated += u64::from(correct);
        if let Some(d) = intent.0 {
            positions.points[i] += d;
            any = true;
            if correct {
                moved += 1;
                // Summed robot by robot, in index order, as the async scheduler does.
                tally.distance += d.length();
            }
        }
    }
    tally.round_activations = activated;
    tally.round_moves = moved;
    tally.activations += activated;
    tally.moves += moved;
    if any {
        positions.generation += 1;
    }
}
