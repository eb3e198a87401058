//! Shrinking a counterexample: fewer robots, coordinates on a coarse grid (whole numbers,
//! then halves, then quarters) near the origin, seed 0, a schedule of the rounds up to
//! the violation with fewer activations, and fewer given ASYNC durations, for as long as
//! the property still breaks.

use monoculus_core::rng::Stream;

use super::search::State;
use super::*;

/// The random stream shrinking draws from (robots to activate in an emptied round).
const SHRINK_STREAM: u64 = 0x5348_524b;

/// Grids tried, coarsest first.
const GRIDS: [f64; 4] = [1.0, 0.5, 0.25, 0.125];

/// Seeds tried for a swarm with one robot fewer (besides its own).
const RESEEDS: u64 = 4;

/// Most passes over all the reductions.
const MAX_PASSES: usize = 12;

pub(super) fn shrink(state: &mut State<'_>, found: Found) -> Found {
    let hunt = state.hunt;
    let dim = hunt.cell.dim();
    let mut rng = Stream::new(hunt.spec.seed, SHRINK_STREAM, 0, 0);
    let mut cur = found;
    // The run stops at the violation: the schedule past it plays no part.
    if hunt.property() != Property::NoConvergence
        && let Some(s) = cur.candidate.schedule.as_mut()
    {
        s.truncate(cur.evaluation.round.max(1) as usize);
    }
    for _ in 0..MAX_PASSES {
        let before = cur.candidate.clone();
        // Fewer robots: each one left out in turn, the last first.
        while cur.candidate.len() > hunt.n_min {
            // With its seed, else with one of a few others (the frames and random
            // choices of a smaller swarm are other draws).
            let mut variants: Vec<Candidate> = (0..cur.candidate.len())
                .rev()
                .map(|i| hunt.without_robot(&cur.candidate, i, &mut rng))
                .collect();
            let reseeded: Vec<Candidate> = variants
                .iter()
                .flat_map(|v| {
                    (0..RESEEDS).map(move |s| Candidate {
                        seed: s,
                        ..v.clone()
                    })
                })
                .collect();
            variants.extend(reseeded);
            if !take_first(state, &mut cur, variants) {
                break;
            }
        }
        // Near the origin, then the whole configuration on a grid, then robot by robot.
        let shift = translated(&cur.candidate, dim);
        take_first(state, &mut cur, vec![shift]);
        let whole: Vec<Candidate> = GRIDS
            .iter()
            .map(|&g| snapped(&cur.candidate, None, g, dim))
            .collect();
        take_first(state, &mut cur, whole);
        for i in 0..cur.candidate.len() {
            let one: Vec<Candidate> = GRIDS
                .iter()
                .map(|&g| snapped(&cur.candidate, Some(i), g, dim))
                .collect();
            take_first(state, &mut cur, one);
        }
        // The smallest seed that still breaks it.
        if cur.candidate.seed > 0 {
            let seeds: Vec<Candidate> = (0..RESEEDS.min(cur.candidate.seed))
                .map(|s| Candidate {
                    seed: s,
                    ..cur.candidate.clone()
                })
                .collect();
            take_first(state, &mut cur, seeds);
        }
        // Fewer activations: in each round, each robot left out in turn (at least one
        // robot stays activated).
        if hunt.subsets && hunt.property() != Property::NoConvergence {
            let rounds = cur.candidate.schedule.as_ref().map_or(0, Vec::len);
            for k in 0..rounds {
                loop {
                    let mask = cur.candidate.schedule.as_ref().expect("subsets")[k];
                    if mask.count_ones() <= 1 {
                        break;
                    }
                    let variants: Vec<Candidate> = robots_of(mask)
                        .into_iter()
                        .map(|r| {
                            let mut c = cur.candidate.clone();
                            c.schedule.as_mut().expect("subsets")[k] &= !(1u64 << r);
                            c
                        })
                        .collect();
                    if !take_first(state, &mut cur, variants) {
                        break;
                    }
                }
            }
        }
        // Fewer given durations: all of them taken back, else each in turn.
        if !cur.candidate.durations.is_empty() {
            let none = Candidate {
                durations: Vec::new(),
                ..cur.candidate.clone()
            };
            if !take_first(state, &mut cur, vec![none]) {
                loop {
                    let variants: Vec<Candidate> = (0..cur.candidate.durations.len())
                        .map(|k| {
                            let mut c = cur.candidate.clone();
                            c.durations.remove(k);
                            c
                        })
                        .collect();
                    if !take_first(state, &mut cur, variants) {
                        break;
                    }
                }
            }
        }
        if state.stopped() || cur.candidate == before {
            break;
        }
    }
    // The schedule ends with the violation's round.
    if hunt.property() != Property::NoConvergence
        && let Some(s) = cur.candidate.schedule.as_mut()
    {
        s.truncate(cur.evaluation.round.max(1) as usize);
    }
    cur
}

/// Evaluates `variants` (in parallel) and moves `cur` to the first that still breaks the
/// property; whether one did.
fn take_first(state: &mut State<'_>, cur: &mut Found, variants: Vec<Candidate>) -> bool {
    let variants: Vec<Candidate> = variants
        .into_iter()
        .filter(|v| *v != cur.candidate)
        .collect();
    if variants.is_empty() || state.stopped() {
        return false;
    }
    let before = state.evaluations;
    let evaluations = state.evaluate_all(&variants);
    state.shrink_evaluations += state.evaluations - before;
    let hit = variants
        .into_iter()
        .zip(evaluations)
        .find(|(_, e)| e.violated && e.failure.is_none());
    let Some((candidate, evaluation)) = hit else {
        state.progress("shrink");
        return false;
    };
    *cur = Found {
        candidate,
        evaluation,
    };
    state.best = Some(cur.clone());
    state.progress("shrink");
    state.notify_best();
    true
}

/// `c` moved by whole numbers so that its smallest coordinate on each axis lies in [0, 1).
fn translated(c: &Candidate, dim: usize) -> Candidate {
    let mut c = c.clone();
    for a in 0..dim {
        let lo = c.points.iter().map(|p| p[a]).fold(f64::INFINITY, f64::min);
        let shift = lo.floor();
        for p in &mut c.points {
            p[a] -= shift;
        }
    }
    c
}

/// `c` with robot `i` (or every robot) on the grid of spacing `g`.
fn snapped(c: &Candidate, i: Option<usize>, g: f64, dim: usize) -> Candidate {
    let mut c = c.clone();
    for (k, p) in c.points.iter_mut().enumerate() {
        if i.is_none_or(|i| i == k) {
            for x in p.iter_mut().take(dim) {
                *x = (*x / g).round() * g + 0.0;
            }
        }
    }
    c
}
