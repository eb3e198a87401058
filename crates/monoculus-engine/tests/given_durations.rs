//! ASYNC durations given per robot and cycle (`AsyncSpec::durations`): each lasts
//! exactly as given, in the user's numbering of cycles, and nothing else changes.

mod common;

use std::sync::Arc;

use monoculus_core::prelude::*;
use monoculus_engine::asynchrony::{Durations, GivenDuration, Phase};
use monoculus_engine::prelude::*;

fn given(list: &[(u32, u64, Phase, u64)]) -> Option<Arc<Durations>> {
    let d = Durations::new(
        list.iter()
            .map(|&(robot, cycle, phase, ticks)| GivenDuration {
                robot,
                cycle,
                phase,
                ticks,
            }),
    )
    .unwrap();
    Some(Arc::new(d))
}

fn lockstep(start: AsyncStart, durations: Option<Arc<Durations>>) -> AsyncSpec {
    AsyncSpec {
        idle: TickDist::ONE,
        compute: TickDist::ONE,
        motion: TickDist::ONE,
        start,
        durations,
    }
}

fn config(spec: AsyncSpec, seed: u64) -> SimConfig {
    let mut cfg = common::config(
        AlgorithmKind::ConvergeLocality,
        SchedulerSpec::Async(spec),
        seed,
    );
    cfg.stop.max_rounds = 40;
    cfg
}

/// The ticks at which robot `robot` Looks, over the first `until` ticks.
fn looks(spec: AsyncSpec, robot: usize, until: u64) -> Vec<u64> {
    let mut sim = Simulation::new(config(spec, 3), common::square(12, 60.0, 3)).unwrap();
    let mut at = Vec::new();
    while sim.time() <= until {
        sim.step();
        if sim.time() <= until && sim.robot_views()[robot].looked {
            at.push(sim.time());
        }
    }
    at
}

#[test]
fn a_given_phase_lasts_exactly_as_given() {
    // One tick a phase: Look at 0, Compute ends at 1, Move at 2, the next Look at 3.
    let plain = looks(lockstep(AsyncStart::Together, None), 0, 30);
    assert_eq!(plain, (0..=10).map(|k| 3 * k).collect::<Vec<_>>());
    // Cycle 0 computes for 10 ticks (Look at 0, Move ends 12); cycle 1 moves for 5 (Look
    // at 12, Move ends 18); cycle 2's Idle lasts 7 (Look at 25).
    let spec = lockstep(
        AsyncStart::Together,
        given(&[
            (0, 0, Phase::Compute, 10),
            (0, 1, Phase::Move, 5),
            (0, 2, Phase::Idle, 7),
        ]),
    );
    assert_eq!(looks(spec, 0, 30), [0, 12, 25, 28]);
    // Robots start Idle for cycle 0's Idle phase when they start at random.
    let spec = lockstep(AsyncStart::Random, given(&[(0, 0, Phase::Idle, 4)]));
    assert_eq!(looks(spec, 0, 12), [4, 7, 10]);
    // A robot not given anything keeps its times... until what it sees changes.
    let spec = lockstep(AsyncStart::Together, given(&[(0, 0, Phase::Compute, 10)]));
    assert_eq!(looks(spec, 1, 9), [0, 3, 6, 9]);
}

#[test]
fn durations_given_where_the_run_never_goes_change_nothing() {
    for seed in 0..6 {
        let random = AsyncSpec {
            idle: TickDist::Uniform { min: 1, max: 10 },
            compute: TickDist::Exponential { mean: 3.0 },
            motion: TickDist::Uniform { min: 1, max: 6 },
            start: AsyncStart::Random,
            durations: None,
        };
        let far = AsyncSpec {
            durations: given(&[
                (1, 1_000_000, Phase::Move, 99),
                (2, 1 << 40, Phase::Idle, 3),
            ]),
            ..random.clone()
        };
        let near = AsyncSpec {
            durations: given(&[(1, 1, Phase::Move, 99)]),
            ..random.clone()
        };
        let start = common::square(20, 8.0, seed);
        let mut a = Simulation::new(config(random, seed), start.clone()).unwrap();
        let mut b = Simulation::new(config(far, seed), start.clone()).unwrap();
        let mut c = Simulation::new(config(near, seed), start).unwrap();
        let (ra, rb, rc) = (a.run(), b.run(), c.run());
        assert_eq!(ra, rb, "seed {seed}");
        assert_eq!(a.positions(), b.positions(), "seed {seed}");
        assert_ne!(
            (ra.ticks, a.positions()),
            (rc.ticks, c.positions()),
            "seed {seed}: a Move of 99 ticks changed nothing"
        );
    }
}

#[test]
fn durations_the_run_cannot_have_are_refused() {
    let start = common::square(5, 3.0, 0);
    let beyond = lockstep(AsyncStart::Together, given(&[(5, 0, Phase::Move, 2)]));
    let e = Simulation::new(config(beyond, 0), start.clone())
        .err()
        .unwrap();
    assert!(e.to_string().contains("robot 5 of 5"), "{e}");
    let no_idle = lockstep(AsyncStart::Together, given(&[(1, 0, Phase::Idle, 2)]));
    let e = Simulation::new(config(no_idle, 0), start).err().unwrap();
    assert!(
        e.to_string().contains("cycle 0 is given an idle phase"),
        "{e}"
    );
}
