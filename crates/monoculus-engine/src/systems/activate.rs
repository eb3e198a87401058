use bevy_ecs::prelude::*;
use monoculus_core::rng::{Purpose, Stream};

use crate::components::{Activated, Robot, Waiting};
use crate::resources::{Clock, Params, ScheduleState};
use crate::{SchedulerSpec, SequentialOrder};

/// Marks the robots the scheduler activates this round. Every draw comes from a stream
/// keyed by (seed, robot, round), so the choice is independent of iteration order.
pub fn activate_robots(
    params: Res<Params>,
    clock: Res<Clock>,
    mut state: ResMut<ScheduleState>,
    mut robots: Query<(&Robot, &mut Activated, &mut Waiting)>,
) {
    let seed = params.seed;
    let round = clock.round;
    // Only the schedulers that pick robots by index need n: FSYNC skips the pass.
    let count = |robots: &Query<(&Robot, &mut Activated, &mut Waiting)>| robots.iter().count();
    match &params.scheduler {
        SchedulerSpec::Fsync => {
            for (_, mut active, _) in &mut robots {
                active.0 = true;
            }
        }
        &SchedulerSpec::Ssync { p, fairness } => {
            let mut any = false;
            for (robot, mut active, waiting) in &mut robots {
                let forced = fairness.is_some_and(|k| waiting.0 >= k);
                let drawn =
                    Stream::keyed(seed, Purpose::Activate, robot.index as u64, round).bernoulli(p);
                active.0 = forced || drawn;
                any |= active.0;
            }
            if !any {
                let n = count(&robots);
                let pick = Stream::keyed(seed, Purpose::Activate, u64::MAX, round).below(n) as u32;
                for (robot, mut active, _) in &mut robots {
                    active.0 = robot.index == pick;
                }
            }
            for (_, active, mut waiting) in &mut robots {
                waiting.0 = if active.0 { 0 } else { waiting.0 + 1 };
            }
        }
        SchedulerSpec::File(list) => {
            let listed = list.round(round + 1);
            for (robot, mut active, _) in &mut robots {
                active.0 = listed.binary_search(&robot.index).is_ok();
            }
        }
        // Chosen after the Look, by `choose_adversarially`.
        SchedulerSpec::Adversary { .. } => {}
        SchedulerSpec::Async(_) => {
            unreachable!("round systems do not run under the async scheduler")
        }
        &SchedulerSpec::Sequential { order } => {
            let n = count(&robots);
            if n == 0 {
                return;
            }
            let slot = (round % n as u64) as usize;
            let pick = match order {
                SequentialOrder::RoundRobin => slot,
                SequentialOrder::Random => {
                    let cycle = round / n as u64;
                    if state.cycle != Some(cycle) {
                        state.order = Stream::keyed(seed, Purpose::Activate, u64::MAX - 1, cycle)
                            .permutation(n);
                        state.cycle = Some(cycle);
                    }
                    state.order[slot]
                }
            } as u32;
            for (robot, mut active, _) in &mut robots {
                active.0 = robot.index == pick;
            }
        }
    }
}
