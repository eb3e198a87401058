use bevy_ecs::prelude::*;
use monoculus_core::algorithms::{RobotMemory, activate, certainly_stays};
use monoculus_core::rng::{Purpose, Stream};
use monoculus_core::vision::Sight;
use rayon::prelude::*;

use crate::components::{Activated, Intent, Memory, Robot};
use crate::faults::{Role, byzantine_move};
use crate::resources::{Clock, Params, Snapshot, SnapshotSight};
use crate::{IndexPoint, SchedulerSpec};

/// One robot's decision in `round`: its global displacement or `None`. A crashed robot
/// stays from its crash round on; a Byzantine robot follows its rule (SPEC 9.1).
pub fn decide_one<P: IndexPoint, S: Sight<P> + ?Sized>(
    params: &Params,
    sight: &S,
    robot: usize,
    round: u64,
    memory: Option<&mut RobotMemory>,
) -> Option<P> {
    let role = params
        .faults
        .as_ref()
        .map_or(Role::Correct, |f| f.role(robot));
    let stream = || Stream::keyed(params.seed, Purpose::Decide, robot as u64, round);
    match role {
        // Under ASYNC `round` is the robot's cycle: the Look checks the crash by epoch.
        Role::Crashed { from }
            if round >= from && !matches!(params.scheduler, SchedulerSpec::Async(_)) =>
        {
            None
        }
        Role::Byzantine(rule) => byzantine_move(
            rule,
            sight.positions(),
            robot,
            params.algorithm.step,
            &mut stream(),
        ),
        _ if certainly_stays(&params.algorithm, sight, robot) => None,
        _ => activate(&params.algorithm, sight, robot, memory, &mut stream()),
    }
}

/// Whether robot `robot` may move if activated: Byzantine robots always may; for the
/// others, unless [`certainly_stays`] vouches that it stays.
fn may_move<P: IndexPoint, S: Sight<P>>(params: &Params, sight: &S, robot: usize) -> bool {
    matches!(
        params.faults.as_ref().map(|f| f.role(robot)),
        Some(Role::Byzantine(_))
    ) || !certainly_stays(&params.algorithm, sight, robot)
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

fn decide_item<P: IndexPoint, S: Sight<P>>(
    params: &Params,
    round: u64,
    sight: &S,
    (robot, _, intent, memory): &mut RobotItem<'_, P>,
) {
    let i = robot.index as usize;
    intent.0 = decide_one(params, sight, i, round, memory.as_mut().map(|m| &mut m.0))
        .map(|d| realise(params, i, round, d));
}

/// Decides for every activated robot: those [`certainly_stays`] vouches for at once,
/// the others gathered a batch at a time (a list of all query items would cost about
/// 100 bytes per robot at the memory peak) and decided in parallel, or on this thread
/// when there are only a few (ConvergeQuadrant: the robots on the bounding box).
fn compute_all<P: IndexPoint, S: Sight<P>>(
    params: &Params,
    round: u64,
    sight: &S,
    robots: &mut Query<(&Robot, &Activated, &mut Intent<P>, Option<&mut Memory>)>,
) {
    const BATCH: usize = 1 << 16;
    const FEW: usize = 64;
    let mut robots = robots.iter_mut();
    let mut items: Vec<RobotItem<'_, P>> = Vec::new();
    loop {
        items.clear();
        for (robot, active, mut intent, memory) in robots.by_ref() {
            if active.0 && may_move(params, sight, robot.index as usize) {
                items.push((robot, active, intent, memory));
                if items.len() == BATCH {
                    break;
                }
            } else if intent.0.is_some() {
                intent.0 = None;
            }
        }
        if items.is_empty() {
            break;
        }
        if items.len() < FEW {
            for item in &mut items {
                decide_item(params, round, sight, item);
            }
        } else {
            items
                .par_iter_mut()
                .with_min_len(32)
                .for_each(|item| decide_item(params, round, sight, item));
        }
    }
}

/// Compute: every activated robot decides against the Look snapshot, in parallel
/// (rayon); the result does not depend on the number of threads.
pub fn compute_intents<P: IndexPoint>(
    params: Res<Params>,
    clock: Res<Clock>,
    snapshot: Res<Snapshot<P>>,
    mut robots: Query<(&Robot, &Activated, &mut Intent<P>, Option<&mut Memory>)>,
) {
    match snapshot.sight.as_ref().expect("Look runs before Compute") {
        SnapshotSight::Index(s) => compute_all(&params, clock.round, s, &mut robots),
        SnapshotSight::Exact(s) => compute_all(&params, clock.round, s, &mut robots),
        SnapshotSight::Rtree(s) => compute_all(&params, clock.round, s, &mut robots),
    }
}
