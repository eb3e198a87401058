use bevy_ecs::prelude::*;
use monoculus_core::algorithms::{RobotMemory, activate};
use monoculus_core::rng::{Purpose, Stream};
use monoculus_core::vision::Sight;
use rayon::prelude::*;

use crate::IndexPoint;
use crate::components::{Activated, Intent, Memory, Robot};
use crate::resources::{Clock, Params, Snapshot, SnapshotSight};

/// One robot's decision in `round`: its global displacement or `None`.
pub fn decide_one<P: IndexPoint, S: Sight<P> + ?Sized>(
    params: &Params,
    sight: &S,
    robot: usize,
    round: u64,
    memory: Option<&mut RobotMemory>,
) -> Option<P> {
    let mut stream = Stream::keyed(params.seed, Purpose::Decide, robot as u64, round);
    activate(&params.algorithm, sight, robot, memory, &mut stream)
}

/// The displacement a robot actually makes for the decided displacement `d` in its
/// activation `round` (movement errors; identity when they are off).
pub fn realise<P: IndexPoint>(params: &Params, robot: usize, round: u64, d: P) -> P {
    if !params.movement.any() {
        return d;
    }
    params.movement.apply(
        d,
        &mut Stream::keyed(params.seed, Purpose::Error, robot as u64, round),
    )
}

type RobotItem<'a, P> = (
    &'a Robot,
    &'a Activated,
    Mut<'a, Intent<P>>,
    Option<Mut<'a, Memory>>,
);

fn compute_all<P: IndexPoint, S: Sight<P>>(
    params: &Params,
    round: u64,
    sight: &S,
    items: &mut [RobotItem<'_, P>],
) {
    items
        .par_iter_mut()
        .with_min_len(32)
        .for_each(|(robot, active, intent, memory)| {
            intent.0 = if active.0 {
                let i = robot.index as usize;
                decide_one(params, sight, i, round, memory.as_mut().map(|m| &mut m.0))
                    .map(|d| realise(params, i, round, d))
            } else {
                None
            };
        });
}

/// Compute: every activated robot decides against the Look snapshot, in parallel
/// (rayon); the result does not depend on the number of threads.
pub fn compute_intents<P: IndexPoint>(
    params: Res<Params>,
    clock: Res<Clock>,
    snapshot: Res<Snapshot<P>>,
    mut robots: Query<(&Robot, &Activated, &mut Intent<P>, Option<&mut Memory>)>,
) {
    let sight = snapshot.sight.as_ref().expect("Look runs before Compute");
    // Query items are gathered a batch at a time for rayon: a list of all of them would
    // cost about 100 bytes per robot at the memory peak.
    const BATCH: usize = 1 << 16;
    let mut robots = robots.iter_mut();
    loop {
        let mut items: Vec<RobotItem<'_, P>> = robots.by_ref().take(BATCH).collect();
        if items.is_empty() {
            break;
        }
        match sight {
            SnapshotSight::Index(s) => compute_all(&params, clock.round, s, &mut items),
            SnapshotSight::Exact(s) => compute_all(&params, clock.round, s, &mut items),
        }
    }
}
