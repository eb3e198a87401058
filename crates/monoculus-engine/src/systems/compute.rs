use bevy_ecs::prelude::*;
use monoculus_core::algorithms::{
    Algorithm, BadDecision, Kept, activate_lit, activate_together, certainly_stays,
};
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

/// What a robot looks at: the sight of the swarm and the colour each robot shows (empty
/// when the algorithm has no lights).
pub type View<'a, S> = (&'a S, &'a [u8]);

/// The colour each of `n` robots shows, from the states of those that keep one (the
/// others show the light of the default state); empty when `algorithm` declares no
/// lights ([`Algorithm::light_names`]).
pub fn lights_of<'a, A: Algorithm>(
    algorithm: &A,
    n: usize,
    states: impl Iterator<Item = (usize, &'a A::State)>,
) -> Vec<u8> {
    if algorithm.light_names().len() == 0 {
        return Vec::new();
    }
    let mut lights = vec![light::<A>(&A::State::default()); n];
    for (k, state) in states {
        lights[k] = light::<A>(state);
    }
    lights
}

/// The colour a robot with `state` shows, as kept (a light out of the palette fails the
/// run at the robot's activation; it is shown as 0 until then).
pub fn light<A: Algorithm>(state: &A::State) -> u8 {
    u8::try_from(A::light(state)).unwrap_or(0)
}

/// What happens to robot `robot` in `round` before its algorithm is asked: `Some` when
/// that is decided already (a crashed robot stays from its crash round on; a Byzantine
/// robot follows its rule, SPEC 9.1; a robot [`certainly_stays`] vouches for stays),
/// `None` when it is activated.
fn settled<P: IndexPoint, S: Sight<P> + ?Sized, A: Algorithm>(
    params: &Params,
    sight: &S,
    robot: usize,
    round: u64,
) -> Option<Option<P>> {
    let role = params
        .faults
        .as_ref()
        .map_or(Role::Correct, |f| f.role(robot));
    match role {
        // Under ASYNC `round` is the robot's cycle: the Look checks the crash by epoch.
        Role::Crashed { from }
            if round >= from && !matches!(params.scheduler, SchedulerSpec::Async(_)) =>
        {
            Some(None)
        }
        Role::Byzantine(rule) => Some(byzantine_move(
            rule,
            sight.positions(),
            robot,
            params.model.step,
            &mut decide_stream(params, robot, round),
        )),
        _ if certainly_stays::<A, P, S>(&params.model, sight, robot) => Some(None),
        _ => None,
    }
}

fn decide_stream(params: &Params, robot: usize, round: u64) -> Stream {
    Stream::keyed(params.seed, Purpose::Decide, robot as u64, round)
}

fn record(params: &Params, robot: usize, round: u64, bad: BadDecision) {
    params.failure.record(RunFailure {
        round: round.saturating_add(1),
        robot,
        message: bad.to_string(),
    });
}

/// One robot's decision in `round`: its global displacement or `None` (see [`settled`]
/// for the robots that are not activated). A bad decision of the algorithm (or its
/// panic) is recorded as the run's failure, and the robot stays.
pub fn decide_one<P: IndexPoint, S: Sight<P> + ?Sized, A: Algorithm>(
    params: &Params,
    algorithm: &A,
    (sight, lights): View<'_, S>,
    robot: usize,
    round: u64,
    memory: Option<&mut KeptBy<P, A>>,
) -> Option<P> {
    if let Some(d) = settled::<P, S, A>(params, sight, robot, round) {
        return d;
    }
    let mut stream = decide_stream(params, robot, round);
    match activate_lit(
        algorithm,
        &params.model,
        (sight, lights),
        robot,
        memory,
        &mut stream,
    ) {
        Ok(d) => d,
        Err(bad) => {
            record(params, robot, round, bad);
            None
        }
    }
}

/// A robot's decided displacement (after movement errors) and what it keeps.
type Decided<P, A> = (Option<P>, Option<KeptBy<P, A>>);

/// One activation: the robot, its round (ASYNC: its cycle) and what it keeps.
pub type Item<P, A> = (usize, u64, Option<KeptBy<P, A>>);

/// The decisions of several activations, before movement errors: one by one, in
/// parallel; or, for an algorithm that decides together ([`Algorithm::decides_together`]), in
/// one call, in the order given.
pub fn decide_items<P: IndexPoint, S: Sight<P>, A: Algorithm>(
    params: &Params,
    algorithm: &A,
    (sight, lights): View<'_, S>,
    items: &mut [Item<P, A>],
) -> Vec<Option<P>> {
    if !algorithm.decides_together() {
        return items
            .par_iter_mut()
            .with_min_len(32)
            .map(|(r, round, m)| {
                decide_one(params, algorithm, (sight, lights), *r, *round, m.as_mut())
            })
            .collect();
    }
    let mut out = vec![None; items.len()];
    let mut batch = Vec::new();
    let mut at = Vec::new();
    for (k, (robot, round, kept)) in items.iter_mut().enumerate() {
        match settled::<P, S, A>(params, sight, *robot, *round) {
            Some(d) => out[k] = d,
            None => {
                batch.push((*robot, kept.as_mut(), decide_stream(params, *robot, *round)));
                at.push((k, *robot, *round));
            }
        }
    }
    let decided = activate_together(algorithm, &params.model, (sight, lights), &mut batch);
    for ((k, robot, round), d) in at.into_iter().zip(decided) {
        match d {
            Ok(d) => out[k] = d,
            Err(bad) => record(params, robot, round, bad),
        }
    }
    out
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
    view: View<'_, S>,
    (robot, _, intent, memory): &mut RobotItem<'_, P, A>,
) {
    let i = robot.index as usize;
    intent.0 = decide_one(
        params,
        algorithm,
        view,
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
    view: View<'_, S>,
    (bits, count): (&[u64], usize),
    robots: &mut Robots<'_, '_, P, A>,
) {
    const BATCH: usize = 1 << 16;
    let mut robots = robots
        .iter_mut()
        .filter(|(robot, ..)| holds(bits, robot.index as usize));
    if count < FEW {
        for mut item in robots {
            decide_item(params, round, view, &mut item);
        }
        return;
    }
    let mut items: Vec<RobotItem<'_, P, A>> = Vec::with_capacity(count.min(BATCH));
    loop {
        items.clear();
        items.extend(robots.by_ref().take(BATCH));
        if items.is_empty() {
            break;
        }
        items
            .par_iter_mut()
            .with_min_len(32)
            .for_each(|item| decide_item(params, round, view, item));
    }
}

/// Decides for the robots of `bits` in parallel, taken in `order`, so that the robots
/// one thread decides one after the other are neighbours whose queries read the same
/// bins of the index (at 10^6 robots and more, most of what a decision reads comes
/// from memory otherwise). The decisions (and memories) are kept by rank, then handed
/// to the robots in the order of their entities. The same decisions as
/// [`decide_batched`]: each depends only on the robot, the round and the sight.
fn decide_in_order<P: IndexPoint, S: Sight<P>, A: Algorithm>(
    (params, algorithm): (&Params, &A),
    round: u64,
    view: View<'_, S>,
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
        decide_one(params, algorithm, view, k, round, memory).map(|d| realise(params, k, round, d))
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

/// Decides for the robots of `bits` together, in robot order ([`decide_items`]).
fn decide_together<P: IndexPoint, S: Sight<P>, A: Algorithm>(
    (params, algorithm): (&Params, &A),
    round: u64,
    view: View<'_, S>,
    bits: &[u64],
    robots: &mut Robots<'_, '_, P, A>,
) {
    let mut items: Vec<Item<P, A>> = robots
        .iter()
        .filter(|(r, ..)| holds(bits, r.index as usize))
        .map(|(r, _, _, m)| (r.index as usize, round, m.map(|m| m.0.clone())))
        .collect();
    items.sort_unstable_by_key(|(r, ..)| *r);
    let decided = decide_items(params, algorithm, view, &mut items);
    let mut by_robot: std::collections::HashMap<usize, Decided<P, A>> = items
        .into_iter()
        .zip(decided)
        .map(|((r, _, m), d)| (r, (d.map(|d| realise(params, r, round, d)), m)))
        .collect();
    for (robot, _, mut intent, memory) in robots.iter_mut() {
        let Some((d, m)) = by_robot.remove(&(robot.index as usize)) else {
            continue;
        };
        intent.0 = d;
        if let (Some(mut stored), Some(m)) = (memory, m)
            && stored.0 != m
        {
            stored.0 = m;
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
    // The colours shown are those of the states before this Compute.
    let lights = lights_of::<A>(
        params.1,
        Sight::len(sight),
        robots
            .iter()
            .filter_map(|(r, _, _, m)| Some((r.index as usize, &m?.0.state))),
    );
    let view = (sight, &lights[..]);
    if params.1.decides_together() {
        return decide_together(params, round, view, &bits, robots);
    }
    if count >= FEW
        && let Some(order) = order().filter(|o| o.robots.len() == Sight::len(sight))
    {
        return decide_in_order(params, round, view, order, (&bits, with_memory), robots);
    }
    decide_batched(params, round, view, (&bits, count), robots);
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
