//! Looks decided ahead of their ticks: what makes a run's cost independent of how
//! finely its time is counted.
//!
//! A Compute lasts at least `lead` ticks, so a decision taken at tick `t` moves no robot
//! before `t + lead`: every Look of the ticks `t + 1 ..= t + lead - 1` sees the robots
//! where the moves decided before `t` put them, and may be decided at `t` already. At a
//! tick with Looks, the Looks of the ticks after it, up to that bound and to the last
//! tick the moving index serves, are decided together (shared between threads where
//! their work pays for it, as a crowded tick's are), each against the sight at its own
//! tick; the robots whose Compute ends in between are [departed](LookSight::depart)
//! ahead, so that the index holds each robot where it will be. At a fine resolution a
//! tick has a Look or two, and the window a thousand ticks: a window holds as many
//! Looks as a coarse tick, whatever the resolution.
//!
//! Every decision is the one its own tick would take (the robot's streams are keyed by
//! robot and cycle, not by tick). Where that cannot be known now, the Look is decided at
//! its tick as before: a decision that asked for the swarm's hull or box (which the kept
//! shape gives for the current tick), any decision of a window in which an algorithm
//! failed, and every Look of an algorithm with lights, memory, faults or decisions taken
//! together (their inputs change with the ticks in between).

use std::sync::atomic::{AtomicBool, Ordering};

use monoculus_core::algorithms::Algorithm;
use rayon::prelude::*;

use super::systems::{MOVE, duration, spec};
use super::{AsyncClock, Clocks, KeptShape, LookSight, Phase};
use crate::IndexPoint;
use crate::resources::{Failure, Params};
use crate::systems::{decide_one, realise};

/// The fewest ticks a Compute lasts (1 where durations are given robot by robot).
pub(super) fn lead(params: &Params) -> u64 {
    let spec = spec(params);
    if spec.durations.is_some() {
        return 1;
    }
    spec.compute.shortest()
}

/// Decides ahead, at the current tick, the Looks of the ticks after it that
/// [`LookSight::ahead_window`] allows, and keeps their decisions in `sight`: called at
/// a tick whose own Looks were decided against the index readied for it. `pos` are the
/// robots' settled points, `shape` the kept shape refreshed at this tick.
pub(super) fn decide_ahead<P: IndexPoint, A: Algorithm>(
    (params, algorithm): (&Params, &A),
    clock: &mut AsyncClock,
    clocks: &Clocks<P>,
    (pos, shape): (&[P], &KeptShape<P>),
    sight: &mut LookSight<P>,
) {
    let Some(last) = sight.ahead_window(params, clock.tick, lead(params)) else {
        return;
    };
    let (mut lookers, mut departing) = (Vec::new(), Vec::new());
    clock.peek(last, |tick, r| {
        let timing = &clocks.0[r as usize];
        if timing.until != tick {
            return;
        }
        match timing.phase {
            Phase::Idle => lookers.push((tick, r)),
            Phase::Compute if timing.pending().is_some() => departing.push((tick, r)),
            _ => {}
        }
    });
    if lookers.is_empty() {
        return;
    }
    lookers.sort_unstable();
    departing.sort_unstable();
    // The moves that start in the window, as FinishComputes will start them.
    let motion = spec(params).motion;
    let moves: Vec<(P, super::Timing<P>)> = departing
        .iter()
        .map(|&(tick, r)| {
            let mut timing = clocks.0[r as usize];
            timing.phase = Phase::Move;
            timing.since = tick;
            timing.until = tick + duration(params, r, timing.cycle, MOVE, motion);
            sight.depart(r, pos[r as usize], timing);
            (pos[r as usize], timing)
        })
        .collect();
    // The farthest robot at each tick of the window, which the kept shape gives for
    // this tick only.
    let far = shape.ahead(moves.into_iter());
    // A failure is the run's only where its Look is taken at its tick.
    let trial = Params {
        failure: Failure::default(),
        ..params.clone()
    };
    let threads = rayon::current_num_threads();
    let shared = clock.look_cost.share(lookers.len(), threads);
    let started = std::time::Instant::now();
    let seen: &LookSight<P> = sight;
    let decide = |&(tick, r): &(u64, u32)| {
        let outlined = AtomicBool::new(false);
        let at = seen.ahead_at(params, tick, (pos, shape, &far), &outlined);
        let cycle = clocks.0[r as usize].cycle;
        let d = decide_one(&trial, algorithm, (&at, &[]), r as usize, cycle, None)
            .map(|d| realise(&trial, r as usize, cycle, d));
        (!outlined.load(Ordering::Relaxed)).then_some((tick, r, d))
    };
    let decided: Vec<Option<(u64, u32, Option<P>)>> = if shared {
        lookers.par_iter().map(decide).collect()
    } else {
        lookers.iter().map(decide).collect()
    };
    let seconds = started.elapsed().as_secs_f64();
    clock
        .look_cost
        .record(lookers.len(), seconds, if shared { threads } else { 1 });
    if trial.failure.get().is_some() {
        return;
    }
    let kept = sight.keep_ahead(last, decided.into_iter().flatten(), lookers.len());
    clock.looks_ahead += kept as u64;
}
