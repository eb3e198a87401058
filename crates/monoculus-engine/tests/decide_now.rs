//! `Simulation::decide_now`: under FSYNC without movement errors it is the move the next
//! round makes, for every algorithm (states and lights included) on every configuration
//! of the zoo; and asking it, under any scheduler, changes nothing of the run.

mod common;

use common::{config, square, zoo};
use glam::DVec2;
use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;

const KINDS: [AlgorithmKind; 6] = AlgorithmKind::ALL;

#[test]
fn under_fsync_it_is_the_next_round_s_move() {
    for kind in KINDS {
        for (name, start) in zoo(5) {
            let mut sim = Simulation::new(config(kind, SchedulerSpec::Fsync, 3), start).unwrap();
            for round in 0..3 {
                let before = sim.positions().to_vec();
                let decided: Vec<Option<DVec2>> = (0..before.len())
                    .map(|i| sim.decide_now(i).unwrap())
                    .collect();
                sim.step();
                for (i, d) in decided.iter().enumerate() {
                    let moved = sim.positions()[i] - before[i];
                    let want = d.unwrap_or(DVec2::ZERO);
                    assert!(
                        (moved - want).length() <= 1e-12 * (1.0 + want.length()),
                        "{kind:?} on {name}, round {round}, robot {i}: decided {d:?}, moved {moved:?}"
                    );
                }
            }
        }
    }
}

/// Positions after `steps` steps of `scheduler`, asking every robot's decision before
/// each step or not.
fn run(kind: AlgorithmKind, scheduler: &SchedulerSpec, ask: bool) -> Vec<DVec2> {
    let mut sim = Simulation::new(config(kind, scheduler.clone(), 8), square(25, 5.0, 8)).unwrap();
    for _ in 0..40 {
        if ask {
            for i in 0..25 {
                let _ = sim.decide_now(i).unwrap();
            }
        }
        sim.step();
    }
    sim.positions_now()
}

#[test]
fn asking_changes_nothing() {
    let asynchronous = SchedulerSpec::Async(AsyncSpec {
        idle: TickDist::Uniform { min: 1, max: 6 },
        compute: TickDist::Uniform { min: 1, max: 4 },
        motion: TickDist::Uniform { min: 1, max: 5 },
        ..AsyncSpec::default()
    });
    for scheduler in [
        SchedulerSpec::Fsync,
        SchedulerSpec::Ssync {
            p: 0.5,
            fairness: None,
        },
        asynchronous,
    ] {
        for kind in KINDS {
            assert_eq!(
                run(kind, &scheduler, true),
                run(kind, &scheduler, false),
                "{kind:?} under {scheduler:?}"
            );
        }
    }
}
