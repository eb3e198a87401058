//! The systems of one ASYNC event tick, in the order of [`AsyncSet`].

use bevy_ecs::prelude::*;
use monoculus_core::algorithms::Algorithm;
use monoculus_core::vision::Sight;
use rayon::prelude::*;

use super::parallel::{MANY_EVENTS, join_if, map_events, update_robots};
use super::sight::Looking;
use super::{
    AsyncClock, AsyncSpec, Clocks, CommittedHull, KeptShape, Lights, LookSight, Phase,
    RobotEntities, TickDist, Timing,
};
use crate::algorithm::Rule;
use crate::faults::Role;
use crate::resources::{Params, Positions, Shape, SnapshotSight, Tally};
use crate::systems::{Item, KeptBy, MemoryOf, decide_items, decide_one, light, realise};
use crate::{IndexPoint, SchedulerSpec};

/// The phases of one event tick, run in this order.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AsyncSet {
    /// Jump to the next tick at which some phase ends.
    Advance,
    /// Moves that end now: the robots arrive and go idle.
    FinishMoves,
    /// Computes that end now: the robots start moving (or go idle).
    FinishComputes,
    /// Idle phases that end now: these robots Look, all against one snapshot of this
    /// tick (robots in mid-move seen on their segments), and decide in parallel.
    Look,
    /// Epoch accounting and shape measurement.
    Account,
}

const TIMING: u64 = 0x7131_0000;
/// Stream tags of the duration draws.
pub(crate) const IDLE: u64 = 1;
pub(crate) const COMPUTE: u64 = 2;
pub(crate) const MOVE: u64 = 3;
/// The draw of a random start.
pub(crate) const START: u64 = 4;

/// A duration for robot `robot` at its stream's cycle `cycle`: the one given for that
/// phase ([`AsyncSpec::durations`]), else a draw from its own stream. The streams count
/// cycles from the Look (a cycle's Move and the Idle after it draw at the next count);
/// given durations count them as users do, from the Idle before the Look.
pub(crate) fn duration(params: &Params, robot: u32, cycle: u64, tag: u64, dist: TickDist) -> u64 {
    if let SchedulerSpec::Async(AsyncSpec {
        durations: Some(given),
        ..
    }) = &params.scheduler
    {
        let (user_cycle, phase) = match tag {
            START => (0, Phase::Idle),
            IDLE => (cycle, Phase::Idle),
            COMPUTE => (cycle, Phase::Compute),
            _ => (cycle.saturating_sub(1), Phase::Move),
        };
        if let Some(ticks) = given.get(robot, user_cycle, phase) {
            return ticks;
        }
    }
    dist.sample(&mut monoculus_core::rng::Stream::new(
        params.seed,
        TIMING + tag,
        robot as u64,
        cycle,
    ))
}

pub(super) fn spec(params: &Params) -> &AsyncSpec {
    match &params.scheduler {
        SchedulerSpec::Async(s) => s,
        _ => unreachable!("async systems run only under the async scheduler"),
    }
}

/// A run condition: whether some robot's `phase` ends at this tick. At fine durations a
/// tick has an event or two, and a phase's system run for none still fetched every
/// resource it names.
pub(crate) fn phase_ends(phase: Phase) -> impl Fn(Res<AsyncClock>) -> bool + Clone {
    move |clock: Res<AsyncClock>| clock.ends(phase)
}

/// A run condition: whether this tick has anything to account for (a cycle completed,
/// a move ended or decided); [`account`] changes nothing otherwise.
pub(crate) fn to_account(clock: Res<AsyncClock>) -> bool {
    !clock.completed.is_empty() || clock.move_ended || clock.move_decided
}

/// Advance: the next tick with phase ends, its robots sorted by the phase that ends.
pub fn advance<P: IndexPoint>(mut clock: ResMut<AsyncClock>, clocks: Res<Clocks<P>>) {
    if !clock.advance() {
        return;
    }
    let t = clock.tick;
    clock.sort_due(MANY_EVENTS, |r| {
        let timing = &clocks.0[r as usize];
        (timing.until == t).then_some(timing.phase)
    });
}

/// FinishMoves.
pub fn finish_moves<P: IndexPoint>(
    params: Res<Params>,
    mut clock: ResMut<AsyncClock>,
    mut clocks: ResMut<Clocks<P>>,
    mut positions: ResMut<Positions<P>>,
    mut committed: ResMut<CommittedHull<P>>,
    (mut kept_shape, mut sight): (ResMut<KeptShape<P>>, ResMut<LookSight<P>>),
) {
    let t = clock.tick;
    let ending = clock.take_ending(Phase::Move);
    // Each robot's next clock (where it arrives, its Idle phase drawn from its own
    // stream), on both threads on a crowded tick; then, in robot order, the agenda.
    let idle = spec(&params).idle;
    let points = &positions.points;
    let mut arrived: Vec<(u32, P)> = Vec::with_capacity(ending.len());
    update_robots(
        &mut clocks.0,
        &ending,
        |_, r, timing| {
            let arrival = timing.pending().map(|_| timing.target(points[r as usize]));
            let looked = timing.looked;
            timing.set_pending(None);
            timing.phase = Phase::Idle;
            timing.since = t;
            timing.until = t + duration(&params, r, timing.cycle, IDLE, idle);
            (timing.until, arrival, looked)
        },
        |r, (until, arrival, looked)| {
            if let Some(target) = arrival {
                arrived.push((r, target));
            }
            clock.completed.push((r, looked));
            clock.schedule(until, r);
        },
    );
    for &(r, target) in &arrived {
        positions.points[r as usize] = target;
    }
    if !arrived.is_empty() {
        clock.move_ended = true;
        clock.in_motion -= arrived.len();
    }
    clock.restore_ending(Phase::Move, ending);
    if clock.move_ended {
        positions.generation += 1;
    }
    // The structures that follow the moves are told of the arrivals in robot order,
    // each on its own thread on a crowded tick.
    let (committed, kept_shape, sight) = (&mut *committed, &mut *kept_shape, &mut *sight);
    join_if(
        arrived.len() >= MANY_EVENTS,
        || {
            for &(r, target) in &arrived {
                if params.is_correct(r as usize) {
                    committed.arrive(r);
                }
                kept_shape.arrive(r, target);
            }
        },
        || {
            for &(r, target) in &arrived {
                sight.arrive(r, target, t);
            }
        },
    );
}

/// FinishComputes.
pub fn finish_computes<P: IndexPoint>(
    params: Res<Params>,
    mut clock: ResMut<AsyncClock>,
    mut clocks: ResMut<Clocks<P>>,
    mut tally: ResMut<Tally>,
    positions: Res<Positions<P>>,
    (mut kept_shape, mut sight): (ResMut<KeptShape<P>>, ResMut<LookSight<P>>),
    mut lights: ResMut<Lights>,
) {
    let t = clock.tick;
    let ending = clock.take_ending(Phase::Compute);
    // The colours set by these Computes are shown from now on.
    if !lights.set.is_empty() {
        let Lights { shown, set } = &mut *lights;
        for &r in &ending {
            shown[r as usize] = set[r as usize];
        }
    }
    // Each robot's Move phase, drawn from its own stream, and where it departs from,
    // on both threads on a crowded tick; then, in robot order, the agenda and tallies.
    let motion = spec(&params).motion;
    let points = &positions.points;
    let mut departed: Vec<(u32, P, Timing<P>)> = Vec::with_capacity(ending.len());
    update_robots(
        &mut clocks.0,
        &ending,
        |_, r, timing| {
            // A robot that decided to stay spends its Move phase in place, so that every
            // cycle is Idle, Look, Compute, Move whatever the decision.
            timing.phase = Phase::Move;
            timing.since = t;
            timing.until = t + duration(&params, r, timing.cycle, MOVE, motion);
            (*timing, points[r as usize])
        },
        |r, (timing, from)| {
            if let Some(d) = timing.pending() {
                departed.push((r, from, timing));
                // Moves count the correct robots only (SPEC 9.1).
                if params.is_correct(r as usize) {
                    tally.moves += 1;
                    tally.distance += d.length();
                }
                clock.epoch_moves += 1;
            }
            clock.schedule(timing.until, r);
        },
    );
    clock.restore_ending(Phase::Compute, ending);
    // As for the arrivals: in robot order, a structure a thread.
    let (kept_shape, sight) = (&mut *kept_shape, &mut *sight);
    join_if(
        departed.len() >= MANY_EVENTS,
        || {
            for &(r, from, timing) in &departed {
                kept_shape.depart(r, from, timing);
            }
        },
        || {
            for &(r, from, timing) in &departed {
                sight.depart(r, from, timing);
            }
        },
    );
}

/// Positions of all robots at the current tick: movers on their segments.
pub(crate) fn positions_now<P: IndexPoint>(
    tick: u64,
    settled: &[P],
    robots: impl Iterator<Item = (u32, P, Timing<P>)>,
) -> Vec<P> {
    let mut pts = settled.to_vec();
    for (r, from, timing) in robots {
        if timing.phase == Phase::Move {
            pts[r as usize] = timing.position_at(from, tick);
        }
    }
    pts
}

/// The lookers' decisions, shared between threads if `shared` (the Looks of a tick
/// differ in cost, so that they are split as finely as rayon will; whether they are
/// shared is [`LookCost::share`](super::parallel::LookCost::share)'s choice); a robot
/// crashed by `epoch` (SPEC 9.1: at its first Look at or after its crash epoch) stays,
/// its memory as it was.
type Decided<P, A> = (Option<P>, Option<KeptBy<P, A>>);

/// A looker: its index, its cycle and what it keeps.
type Looker<P, A> = (u32, u64, Option<KeptBy<P, A>>);

fn decide_all<P: IndexPoint, S: Sight<P>, A: Algorithm>(
    (params, algorithm): (&Params, &A),
    view: (&S, &[u8]),
    (epoch, shared): (u64, bool),
    inputs: &[Looker<P, A>],
) -> Vec<Decided<P, A>> {
    let crashed = |r: u32| {
        matches!(
            params.faults.as_ref().map(|f| f.role(r as usize)),
            Some(Role::Crashed { from }) if epoch >= from
        )
    };
    if algorithm.decides_together() {
        // The lookers that are not crashed, decided in one call in robot order.
        let mut items: Vec<Item<P, A>> = inputs
            .iter()
            .filter(|(r, ..)| !crashed(*r))
            .map(|(r, cycle, m)| (*r as usize, *cycle, m.clone()))
            .collect();
        let mut decided = decide_items(params, algorithm, view, &mut items)
            .into_iter()
            .zip(items);
        return inputs
            .iter()
            .map(|(r, cycle, memory)| {
                if crashed(*r) {
                    return (None, memory.clone());
                }
                let (d, (_, _, m)) = decided.next().expect("one decision a looker");
                (d.map(|d| realise(params, *r as usize, *cycle, d)), m)
            })
            .collect();
    }
    let decide = |(r, cycle, memory): &Looker<P, A>| {
        let (r, cycle) = (*r, *cycle);
        let mut memory = memory.clone();
        if crashed(r) {
            return (None, memory);
        }
        let d = decide_one(params, algorithm, view, r as usize, cycle, memory.as_mut())
            .map(|d| realise(params, r as usize, cycle, d));
        (d, memory)
    };
    if shared {
        inputs.par_iter().map(decide).collect()
    } else {
        inputs.iter().map(decide).collect()
    }
}

/// The largest swarm whose kept shape is refreshed while the Looks' index is readied.
/// Together they hold both passes' scratch memory at once: at 10^6 robots that raised
/// the late state's peak by 2.5 MB, which the whole run's 300 MB cannot spare, for a
/// gain lost in the noise there (the refresh is 1% of a coarse tick at 10^5, 4% at
/// 10^4).
const TOGETHER_UP_TO: usize = 1 << 17;

/// What the Look system keeps across ticks: the committed hull (destinations), the
/// sight, and the kept shape (the swarm's hull and box for the Looks).
type LookState<'w, P> = (
    ResMut<'w, CommittedHull<P>>,
    ResMut<'w, LookSight<P>>,
    ResMut<'w, KeptShape<P>>,
);

/// Look (and the decision, which the Compute phase then delays).
pub fn look<P: IndexPoint, A: Algorithm>(
    (params, algorithm): (Res<Params>, Res<Rule<A>>),
    (mut clock, mut clocks): (ResMut<AsyncClock>, ResMut<Clocks<P>>),
    entities: Res<RobotEntities>,
    positions: Res<Positions<P>>,
    (mut tally, mut lights): (ResMut<Tally>, ResMut<Lights>),
    (mut committed, mut sight, mut kept_shape): LookState<P>,
    mut memories: Query<&mut MemoryOf<P, A>>,
) {
    let t = clock.tick;
    let lookers = clock.take_ending(Phase::Idle);
    if lookers.is_empty() {
        clock.restore_ending(Phase::Idle, lookers);
        return;
    }
    // The robots' memories, where the algorithm gives them one (components of their
    // entities, the same for every scheduler).
    let with_memory = !memories.is_empty();
    let memory = |r: u32| {
        with_memory
            .then(|| {
                memories
                    .get(entities.0[r as usize])
                    .ok()
                    .map(|m| m.0.clone())
            })
            .flatten()
    };
    // The Looks decided ahead at an earlier tick (`ahead::decide_ahead`); the others
    // are decided now.
    let mut ahead = Vec::new();
    sight.take_ahead(t, &mut ahead);
    let fresh: std::borrow::Cow<[u32]> = if ahead.is_empty() {
        (&lookers[..]).into()
    } else {
        let is_ahead = |r: &u32| ahead.binary_search_by_key(r, |&(a, _)| a).is_ok();
        lookers.iter().copied().filter(|r| !is_ahead(r)).collect()
    };
    let pos = &positions.points;
    let mut decided = Vec::new();
    if !fresh.is_empty() {
        let inputs = map_events(&fresh, |r| (r, clocks.0[r as usize].cycle, memory(r)));
        // The hull and box the Looks may ask for come from the kept shape (its work
        // done here rather than in Account, at the same tick), refreshed while the
        // index is readied, each on its own thread on a crowded tick of a swarm of at
        // most `TOGETHER_UP_TO` robots (both are passes of one thread for the most part).
        let clocks_now = &*clocks;
        join_if(
            fresh.len() >= MANY_EVENTS && pos.len() <= TOGETHER_UP_TO,
            || kept_shape.refresh(|| clocks_now.with_points(pos)),
            || sight.ready(&params, t, pos, fresh.len()),
        );
        let rule = (&*params, &*algorithm.0);
        let shown = &lights.shown[..];
        // Shared between threads where the Looks' work pays for it (timed with the
        // making of the sight, which the tick's Looks pay for too).
        let threads = rayon::current_num_threads();
        let shared = clock.look_cost.share(fresh.len(), threads);
        let when = (clock.epochs, shared);
        let started = std::time::Instant::now();
        decided = match sight.at(&params, t, pos, &kept_shape) {
            Looking::Made(s) => decide_all(rule, (&s, shown), when, &inputs),
            Looking::Moving(s) => decide_all(rule, (&s, shown), when, &inputs),
            Looking::Snapshot(SnapshotSight::Index(s)) => {
                // Built here (if it must be), its two layouts in parallel, not by the
                // first decision while the other threads wait.
                s.build_index();
                decide_all(rule, (s, shown), when, &inputs)
            }
            Looking::Snapshot(SnapshotSight::Exact(s)) => {
                decide_all(rule, (s, shown), when, &inputs)
            }
            Looking::Snapshot(SnapshotSight::Rtree(s)) => {
                decide_all(rule, (s, shown), when, &inputs)
            }
        };
        let seconds = started.elapsed().as_secs_f64();
        let timed_on = if shared { threads } else { 1 };
        clock.look_cost.record(fresh.len(), seconds, timed_on);
        // The Looks of the ticks to come that can be decided now: where nothing but
        // the robots' positions goes into a decision.
        if !with_memory
            && lights.set.is_empty()
            && params.faults.is_none()
            && !algorithm.0.decides_together()
        {
            let rule = (&*params, &*algorithm.0);
            super::ahead::decide_ahead(rule, &mut clock, &clocks, (pos, &kept_shape), &mut sight);
        }
    }
    // Every looker's decision, in the lookers' order.
    let outputs: Vec<Decided<P, A>> = if ahead.is_empty() {
        decided
    } else {
        let (mut early, mut now) = (ahead.into_iter().peekable(), decided.into_iter());
        lookers
            .iter()
            .map(|&r| match early.next_if(|&(a, _)| a == r) {
                Some((_, d)) => (d, None),
                None => now.next().expect("a decision a looker"),
            })
            .collect()
    };
    // The colours the decisions set, shown when their Computes end.
    if !lights.set.is_empty() {
        for (&r, (_, memory)) in lookers.iter().zip(&outputs) {
            if let Some(m) = memory {
                lights.set[r as usize] = light::<A>(&m.state);
            }
        }
    }
    // Each robot's clock (its Compute phase drawn from its own stream), on both threads
    // on a crowded tick; then, in robot order, its memory, the agenda and the
    // committed hull.
    let compute = spec(&params).compute;
    update_robots(
        &mut clocks.0,
        &lookers,
        |i, r, timing| {
            let d = outputs[i].0;
            timing.set_pending(d);
            timing.phase = Phase::Compute;
            timing.looked = t;
            timing.since = t;
            timing.until = t + duration(&params, r, timing.cycle, COMPUTE, compute);
            timing.cycle += 1;
            (
                timing.until,
                d.map(|d| pos[r as usize] + d),
                outputs[i].1.clone(),
            )
        },
        |r, (until, destination, memory)| {
            if let Some(m) = memory
                && let Ok(mut stored) = memories.get_mut(entities.0[r as usize])
            {
                stored.0 = m;
            }
            clock.schedule(until, r);
            clock.epoch_looks += 1;
            if let Some(destination) = destination {
                clock.in_motion += 1;
                clock.move_decided = true;
                // As `committed_points` lists it (the correct robots' only).
                if params.is_correct(r as usize) {
                    committed.decide(r, destination);
                }
            }
        },
    );
    tally.activations += lookers
        .iter()
        .filter(|&&r| params.is_correct(r as usize))
        .count() as u64;
    clock.restore_ending(Phase::Idle, lookers);
}

/// The points whose hull Lemma 2 bounds under ASYNC: every robot's position at the
/// start of its current phase and, for decided moves, the destination (a mover's
/// current position lies between the two), with their ids in [`CommittedHull`]:
/// `2 r` and `2 r + 1`.
pub(crate) fn committed_points<P: IndexPoint>(
    robots: impl Iterator<Item = (u32, P, Timing<P>)>,
) -> impl Iterator<Item = (u32, P)> {
    robots.flat_map(|(r, from, timing)| {
        let destination = timing.pending().map(|d| (2 * r + 1, from + d));
        std::iter::once((2 * r, from)).chain(destination)
    })
}

/// Account: epochs; the shape whenever a move ended (hull growth counted per tick);
/// the committed hull whenever a move ended or was decided.
pub fn account<P: IndexPoint>(
    params: Res<Params>,
    mut clock: ResMut<AsyncClock>,
    positions: Res<Positions<P>>,
    mut shape: ResMut<Shape>,
    mut tally: ResMut<Tally>,
    (mut kept, mut kept_shape): (ResMut<CommittedHull<P>>, ResMut<KeptShape<P>>),
    clocks: Res<Clocks<P>>,
) {
    clock.account();
    let tick = clock.tick;
    let pos = &positions.points;
    let clocks = &*clocks;
    let params = &params;
    let all = || {
        committed_points(
            clocks
                .with_points(pos)
                .filter(|&(r, _, _)| params.is_correct(r as usize)),
        )
    };
    let committed_before = kept.last();
    // The two measures are independent: taken at once where a core is free, on ticks
    // with many events (on a tick with a few, waking the other thread costs more than
    // the measures: fine-grained runs were 1.3x faster on one thread than on two).
    let (committed, measured) = join_if(
        clock.due.len() >= MANY_EVENTS,
        || {
            (clock.move_ended || clock.move_decided).then(|| {
                let measure = kept.measure(all);
                debug_assert_eq!(
                    measure.to_bits(),
                    P::hull_measure(&all().map(|(_, p)| p).collect::<Vec<_>>()).to_bits(),
                    "the hull kept across ticks is the hull over all committed points"
                );
                measure
            })
        },
        || {
            clock.move_ended.then(|| {
                let clocks = || clocks.with_points(pos);
                let now = || positions_now(tick, pos, clocks());
                if params.faults.is_some() {
                    // The correct robots' shape, taken afresh (the kept shape follows
                    // every robot).
                    return Shape::of(&params.correct(&now()));
                }
                let shape = kept_shape.shape(tick, clocks);
                debug_assert_eq!(
                    format!("{shape:?}"),
                    format!("{:?}", Shape::of(&now())),
                    "the shape from the robots that can be on the hull is the shape of all"
                );
                shape
            })
        },
    );
    if committed.is_some_and(|now| crate::systems::hull_grew(committed_before, now)) {
        tally.committed_hull_growth += 1;
    }
    if let Some(mut measured) = measured {
        crate::systems::record_hull(&mut tally, &shape, &mut measured);
        *shape = measured;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn looks_see_movers_on_their_segments() {
        let settled = vec![DVec2::ZERO, DVec2::new(5.0, 0.0), DVec2::new(0.0, 5.0)];
        let idle = Timing::new(Phase::Idle, 0, 20, 0, 0, None);
        let moving = Timing::new(Phase::Move, 10, 14, 1, 8, Some(DVec2::new(-4.0, 0.0)));
        let robots = [
            (0, settled[0], idle),
            (1, settled[1], moving),
            (2, settled[2], idle),
        ];
        let now = positions_now(12, &settled, robots.into_iter());
        assert_eq!(now, vec![settled[0], DVec2::new(3.0, 0.0), settled[2]]);
        let at_end = positions_now(14, &settled, robots.into_iter());
        assert_eq!(at_end[1], DVec2::new(1.0, 0.0));
    }
}
