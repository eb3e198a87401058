//! A schedule given in full (SPEC 9.4): replaying the activations of an SSYNC run gives
//! that run exactly; unlisted rounds activate nobody; the run ends after the last round.

mod common;

use std::sync::Arc;

use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;
use monoculus_engine::{ActivationList, EngineError};

fn file(rounds: Vec<(u64, Vec<u32>)>) -> SchedulerSpec {
    SchedulerSpec::File(Arc::new(ActivationList::new(rounds).unwrap()))
}

/// The robots that looked in the last round.
fn looked(sim: &Simulation<glam::DVec2>) -> Vec<u32> {
    let views = sim.robot_views();
    (0..views.len() as u32)
        .filter(|&i| views[i as usize].looked)
        .collect()
}

/// The robots each round of `sim`'s run activated, and the run's outcome.
fn record(sim: &mut Simulation<glam::DVec2>) -> (Vec<(u64, Vec<u32>)>, RunOutcome) {
    let mut rounds = Vec::new();
    let outcome = sim.run_observed(|s| {
        if s.time() > 0 {
            rounds.push((s.time(), looked(s)));
        }
    });
    (rounds, outcome)
}

#[test]
fn replaying_an_ssync_run_gives_that_run() {
    for kind in [
        AlgorithmKind::ConvergeLocality,
        AlgorithmKind::ConvergeQuadrant,
        AlgorithmKind::ConvergeQuadrantTermination,
    ] {
        for seed in 0..3 {
            let ssync = SchedulerSpec::Ssync {
                p: 0.4,
                fairness: Some(6),
            };
            let start = common::square(25, 8.0, seed);
            let mut sim =
                Simulation::new(common::config(kind, ssync, seed), start.clone()).unwrap();
            let (rounds, expected) = record(&mut sim);
            assert!(expected.converged, "{} seed {seed}", kind.name());
            assert_eq!(rounds.len() as u64, expected.rounds);
            let mut replay =
                Simulation::new(common::config(kind, file(rounds), seed), start).unwrap();
            let got = replay.run();
            assert_eq!(got, expected, "{} seed {seed}", kind.name());
            assert_eq!(replay.positions(), sim.positions());
        }
    }
}

#[test]
fn unlisted_rounds_activate_nobody_and_the_run_ends_after_the_last() {
    let start = common::square(20, 10.0, 4);
    // Round 2 activates robots 3 and 7; rounds 1, 3 and 4 nobody; 5 is the last.
    let cfg = common::config(
        AlgorithmKind::ConvergeLocality,
        file(vec![(2, vec![7, 3]), (5, vec![])]),
        4,
    );
    let mut sim = Simulation::new(cfg, start.clone()).unwrap();
    let mut moved_in = Vec::new();
    let outcome = sim.run_observed(|s| {
        if s.time() > 0 {
            moved_in.push((s.time(), looked(s)));
        }
    });
    assert_eq!(outcome.rounds, 5);
    assert!(!outcome.converged);
    assert_eq!(outcome.activations, 2);
    assert_eq!(
        moved_in,
        vec![
            (1, vec![]),
            (2, vec![3, 7]),
            (3, vec![]),
            (4, vec![]),
            (5, vec![])
        ]
    );
    let moved: Vec<u32> = (0..start.len() as u32)
        .filter(|&i| sim.positions()[i as usize] != start[i as usize])
        .collect();
    assert!(moved.iter().all(|i| [3, 7].contains(i)), "{moved:?}");
}

#[test]
fn a_schedule_for_more_robots_than_the_swarm_is_refused() {
    let cfg = common::config(
        AlgorithmKind::ConvergeLocality,
        file(vec![(1, vec![0, 20])]),
        1,
    );
    let err = Simulation::new(cfg, common::square(20, 10.0, 1)).err();
    assert_eq!(
        err,
        Some(EngineError::Invalid(
            "the schedule activates robot 20 of 20 (robots are numbered from 0)".into()
        ))
    );
}

#[test]
fn lists_are_checked() {
    use monoculus_engine::ActivationError;
    assert_eq!(
        ActivationList::new(vec![(2, vec![]), (2, vec![1])]),
        Err(ActivationError::NotIncreasing {
            round: 2,
            previous: 2
        })
    );
    assert_eq!(
        ActivationList::new(vec![(1, vec![4, 1, 4])]),
        Err(ActivationError::Twice { round: 1, robot: 4 })
    );
    assert_eq!(
        ActivationList::new(vec![(0, vec![])]),
        Err(ActivationError::RoundZero)
    );
}
