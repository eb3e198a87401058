use bevy_ecs::prelude::*;
use monoculus_core::algorithms::{Algorithm, Kept, activate, certainly_stays};
use monoculus_core::rng::{Purpose, Stream};
use monoculus_core::vision::Sight;
use rayon::prelude::*;

use crate::algorithm::Rule;
use crate::components::{Activated, Intent, Memory, Robot};
use crate::faults::{Role, byzantine_move};
use crate::index::SpatialOrder;
use crate::resources::{Clock, Params, RunFailure, Snapshot, SnapshotSight};
use crate::{IndexPoint, SchedulerSpec};

/// What a robot keeps, if its algorithm has a state.
pub type KeptBy<P, A> = Kept<P, <A as Algorithm>::State>;

/// One robot's decision in `round`: its global displacement or `None`. A crashed robot
/// stays from its crash round on; a Byzantine robot follows its rule (SPEC 9.1). A bad
/// decision of the algorithm (or its panic) is recorded as the run's failure, and the
/// robot stays.
pub fn decide_one<P: IndexPoint, S: Sight<P> + ?Sized, A: Algorithm>(
    params: &Params,
    algorithm: &A,
    sight: &S,
    robot: usize,
    round: u64,
    memory: Option<&mut KeptBy<P, A>>,
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
            params.model.step,
            &mut stream(),
        ),
        _ if certainly_stays::<A, P, S>(&params.model, sight, robot) => None,
        _ => match activate(
            algorithm,
            &params.model,
            sight,
            robot,
            memory,
            &mut stream(),
        ) {
            Ok(d) => d,
            Err(bad) => {
                params.failure.record(RunFailure {
                    round: round.saturating_add(1),
                    robot,
                    message: bad.to_string(),
                });
                None
            }
        },
    }
}

/// Whether robot `robot` may move if activated: Byzantine robots always may; for the
/// others, unless [`certainly_stays`] vouches that it stays.
fn may_move<P: IndexPoint, S: Sight<P>, A: Algorithm>(
    params: &Params,
    sight: &S,
    robot: usize,
) -> bool {
    matches!(
        params.faults.as_ref().map(|f| f.role(robot)),
        Some(Role::Byzantine(_))
    ) || !certainly_stays::<A, P, S>(&params.model, sight, robot)
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

/// The component a robot of `A` keeps its state in.
pub type MemoryOf<P, A> = Memory<P, <A as Algorithm>::State>;

type RobotItem<'a, P, A> = (
    &'a Robot,
    &'a Activated,
    Mut<'a, Intent<P>>,
    Option<Mut<'a, MemoryOf<P, A>>>,
);

type Robots<'w, 's, P, A> = Query<
    'w,
    's,
    (
        &'static Robot,
        &'static Activated,
        &'static mut Intent<P>,
        Option<&'static mut MemoryOf<P, A>>,
    ),
>;

/// Deciding robots from which they decide in parallel (fewer: on this thread).
const FEW: usize = 64;

/// The robots that decide this round, a bit each, and how many they are; the intents of
/// the others are cleared. Whether any of them has a memory.
fn deciding<P: IndexPoint, S: Sight<P>, A: Algorithm>(
    params: &Params,
    sight: &S,
    robots: &mut Robots<'_, '_, P, A>,
) -> (Vec<u64>, usize, bool) {
    let mut bits = vec![0u64; sight.len().div_ceil(64)];
    let (mut count, mut with_memory) = (0, false);
    for (robot, active, mut intent, memory) in robots.iter_mut() {
        let k = robot.index as usize;
        if active.0 && may_move::<P, S, A>(params, sight, k) {
            bits[k / 64] |= 1 << (k % 64);
            count += 1;
            with_memory |= memory.is_some();
        } else if intent.0.is_some() {
            intent.0 = None;
        }
    }
    (bits, count, with_memory)
}

/// Whether robot `k` is among `bits`.
#[inline]
fn holds(bits: &[u64], k: usize) -> bool {
    bits[k / 64] & (1 << (k % 64)) != 0
}

fn decide_item<P: IndexPoint, S: Sight<P>, A: Algorithm>(
    (params, algorithm): (&Params, &A),
    round: u64,
    sight: &S,
    (robot, _, intent, memory): &mut RobotItem<'_, P, A>,
) {
    let i = robot.index as usize;
    intent.0 = decide_one(
        params,
        algorithm,
        sight,
        i,
        round,
        memory.as_mut().map(|m| &mut m.0),
    )
    .map(|d| realise(params, i, round, d));
}

/// Decides for the robots of `bits` in the order of the robots' entities, gathered a
/// batch at a time (a list of all query items would cost about 100 bytes per robot at
/// the memory peak) and decided in parallel, or on this thread when there are only a
/// few (ConvergeQuadrant: the robots on the bounding box).
fn decide_batched<P: IndexPoint, S: Sight<P>, A: Algorithm>(
    params: (&Params, &A),
    round: u64,
    sight: &S,
    bits: &[u64],
    robots: &mut Robots<'_, '_, P, A>,
) {
    const BATCH: usize = 1 << 16;
    let mut robots = robots
        .iter_mut()
        .filter(|(robot, ..)| holds(bits, robot.index as usize));
    let mut items: Vec<RobotItem<'_, P, A>> = Vec::new();
    loop {
        items.clear();
        items.extend(robots.by_ref().take(BATCH));
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

/// Decides for the robots of `bits` in parallel, taken in `order`, so that the robots
/// one thread decides one after the other are neighbours whose queries read the same
/// cells of the index (at 10^6 robots and more, most of what a decision reads comes
/// from memory otherwise). The decisions (and memories) are kept by rank, then handed
/// to the robots in the order of their entities. The same decisions as
/// [`decide_batched`]: each depends only on the robot, the round and the sight.
fn decide_in_order<P: IndexPoint, S: Sight<P>, A: Algorithm>(
    (params, algorithm): (&Params, &A),
    round: u64,
    sight: &S,
    order: SpatialOrder<'_>,
    (bits, with_memory): (&[u64], bool),
    robots: &mut Robots<'_, '_, P, A>,
) {
    let n = order.robots.len();
    let mut memories: Vec<Option<KeptBy<P, A>>> = Vec::new();
    if with_memory {
        memories.resize(n, None);
        for (robot, _, _, memory) in robots.iter() {
            let k = robot.index as usize;
            if holds(bits, k) {
                memories[order.rank[k] as usize] = memory.map(|m| m.0.clone());
            }
        }
    }
    let decide = |r: usize, memory: Option<&mut KeptBy<P, A>>| {
        let k = order.robots[r] as usize;
        if !holds(bits, k) {
            return None;
        }
        decide_one(params, algorithm, sight, k, round, memory).map(|d| realise(params, k, round, d))
    };
    // Collected in rank order (each written once, in parallel).
    let decided: Vec<Option<P>> = if with_memory {
        memories
            .par_iter_mut()
            .enumerate()
            .with_min_len(32)
            .map(|(r, m)| decide(r, m.as_mut()))
            .collect()
    } else {
        (0..n)
            .into_par_iter()
            .with_min_len(32)
            .map(|r| decide(r, None))
            .collect()
    };
    for (robot, _, mut intent, memory) in robots.iter_mut() {
        let k = robot.index as usize;
        if !holds(bits, k) {
            continue;
        }
        let r = order.rank[k] as usize;
        intent.0 = decided[r];
        if let (Some(mut stored), Some(Some(m))) = (memory, memories.get(r))
            && stored.0 != *m
        {
            stored.0 = m.clone();
        }
    }
}

/// Decides for every activated robot: those [`certainly_stays`] vouches for at once,
/// the others in parallel, in the `order` of the sight's index if it has one and they
/// are many.
fn compute_all<'a, P: IndexPoint, S: Sight<P>, A: Algorithm>(
    params: (&Params, &A),
    round: u64,
    sight: &'a S,
    order: impl FnOnce() -> Option<SpatialOrder<'a>>,
    robots: &mut Robots<'_, '_, P, A>,
) {
    let (bits, count, with_memory) = deciding::<P, S, A>(params.0, sight, robots);
    if count >= FEW
        && let Some(order) = order().filter(|o| o.robots.len() == Sight::len(sight))
    {
        return decide_in_order(params, round, sight, order, (&bits, with_memory), robots);
    }
    decide_batched(params, round, sight, &bits, robots);
}

/// Compute: every activated robot decides against the Look snapshot, in parallel
/// (rayon); the result does not depend on the number of threads.
pub fn compute_intents<P: IndexPoint, A: Algorithm>(
    params: Res<Params>,
    algorithm: Res<Rule<A>>,
    clock: Res<Clock>,
    snapshot: Res<Snapshot<P>>,
    mut robots: Robots<P, A>,
) {
    let params = (&*params, &*algorithm.0);
    match snapshot.sight.as_ref().expect("Look runs before Compute") {
        SnapshotSight::Index(s) => {
            let order = || {
                // Built here, its two layouts in parallel, not by the first decision
                // while the other threads wait.
                s.build_index();
                s.order()
            };
            compute_all(params, clock.round, s, order, &mut robots);
        }
        SnapshotSight::Exact(s) => compute_all(params, clock.round, s, || None, &mut robots),
        SnapshotSight::Rtree(s) => compute_all(params, clock.round, s, || None, &mut robots),
    }
}
