//! The paper's guarantees as properties over many seeds and schedulers.

mod common;

use glam::DVec2;
use monoculus_core::init::{InitShape, generate};
use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;

fn schedulers() -> [SchedulerSpec; 4] {
    [
        SchedulerSpec::Fsync,
        SchedulerSpec::Ssync {
            p: 0.5,
            fairness: None,
        },
        SchedulerSpec::Ssync {
            p: 0.3,
            fairness: Some(3),
        },
        SchedulerSpec::Sequential {
            order: SequentialOrder::Random,
        },
    ]
}

#[test]
fn converge_locality_never_grows_the_hull_and_converges() {
    for scheduler in schedulers() {
        for seed in 0..12 {
            let n = [8, 25, 60][seed as usize % 3];
            let cfg = common::config(AlgorithmKind::ConvergeLocality, scheduler.clone(), seed);
            let out = Simulation::new(cfg.clone(), common::square(n, 15.0, seed))
                .unwrap()
                .run();
            assert!(out.converged, "{scheduler:?} seed {seed}: {out:?}");
            assert_eq!(
                out.hull_growth_rounds, 0,
                "Lemma 2: {scheduler:?} seed {seed}"
            );
            assert!(out.hull_final <= out.hull_initial * (1.0 + 1e-9));
            assert!(
                out.final_diameter <= 2.0 * 2.0,
                "{scheduler:?} seed {seed}: {}",
                out.final_diameter
            );
        }
    }
}

#[test]
fn converge_locality_at_quiescence_diameter_is_at_most_2c() {
    for seed in 0..30 {
        let mut cfg = common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, seed);
        cfg.stop.criterion = StopCriterion::Quiescent;
        cfg.stop.max_rounds = 2_000;
        let out = Simulation::new(cfg.clone(), common::square(20 + seed as usize, 12.0, seed))
            .unwrap()
            .run();
        assert!(out.converged, "seed {seed} never quiescent: {out:?}");
        assert!(
            out.final_diameter <= 4.0,
            "seed {seed}: diameter {} > 2c at quiescence",
            out.final_diameter
        );
        assert_eq!(out.hull_growth_rounds, 0);
    }
}

#[test]
fn converge_locality_on_a_line_stops_by_diameter() {
    let line: Vec<DVec2> = generate(&InitShape::Line { side: 12.0 }, 15, 4);
    let cfg = common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, 4);
    let out = Simulation::new(cfg.clone(), line).unwrap().run();
    assert!(out.converged && out.final_diameter <= 2.0, "{out:?}");
}

#[test]
fn converge_quadrant_ends_inside_a_2b_box() {
    for scheduler in schedulers() {
        for seed in 0..10 {
            let n = [5, 30, 80][seed as usize % 3];
            let cfg = common::config(AlgorithmKind::ConvergeQuadrant, scheduler.clone(), seed);
            let out = Simulation::new(cfg.clone(), common::square(n, 12.0, seed))
                .unwrap()
                .run();
            assert!(out.converged, "{scheduler:?} seed {seed}: {out:?}");
            assert!(
                out.final_extents.iter().all(|&e| e <= 2.0),
                "{:?}",
                out.final_extents
            );
        }
    }
    // Also from a lattice and a line, where many robots are collinear.
    for start in [
        generate::<DVec2>(&InitShape::Lattice { side: 10.0 }, 36, 0),
        generate::<DVec2>(&InitShape::Line { side: 10.0 }, 12, 1),
    ] {
        let cfg = common::config(AlgorithmKind::ConvergeQuadrant, SchedulerSpec::Fsync, 2);
        let out = Simulation::new(cfg.clone(), start).unwrap().run();
        assert!(
            out.converged && out.final_extents.iter().all(|&e| e <= 2.0),
            "{out:?}"
        );
    }
}

/// The termination algorithm reaches quiescence: the run says so, and evaluating every
/// robot's decision afresh on the final configuration agrees. Quiescence comes long before
/// robots have seen all 2d sides empty: in these runs at most one robot of a run ends
/// with all bits set, which is what `terminated` reports (at most n).
#[test]
fn converge_quadrant_termination_reaches_quiescence() {
    for scheduler in [
        SchedulerSpec::Fsync,
        SchedulerSpec::Ssync {
            p: 0.5,
            fairness: Some(4),
        },
    ] {
        for seed in 0..10 {
            let n = [4, 20, 50][seed as usize % 3];
            let mut cfg = common::config(
                AlgorithmKind::ConvergeQuadrantTermination,
                scheduler.clone(),
                seed,
            );
            cfg.stop.max_rounds = 50_000;
            let mut sim = Simulation::new(cfg.clone(), common::square(n, 10.0, seed)).unwrap();
            let out = sim.run();
            assert!(
                out.converged,
                "{scheduler:?} seed {seed}: never quiescent {out:?}"
            );
            assert!(
                sim.is_quiescent(),
                "{scheduler:?} seed {seed}: a robot would move"
            );
            let terminated = out.terminated.expect("the termination algorithm counts");
            assert!(terminated <= n as u64);
        }
    }
}

#[test]
fn start_that_already_satisfies_the_criterion_takes_zero_rounds() {
    let pts = vec![DVec2::ZERO, DVec2::new(0.5, 0.0), DVec2::new(0.0, 0.5)];
    for kind in [
        AlgorithmKind::ConvergeLocality,
        AlgorithmKind::ConvergeQuadrant,
        AlgorithmKind::CenterOfGravity,
    ] {
        let out = Simulation::new(common::config(kind, SchedulerSpec::Fsync, 0), pts.clone())
            .unwrap()
            .run();
        assert_eq!(
            (out.rounds, out.moves, out.activations),
            (0, 0, 0),
            "{}",
            kind.name()
        );
        assert!(out.converged);
    }
}

#[test]
fn quiescent_fsync_counts_only_rounds_with_moves() {
    // Three robots far apart in general position: everybody moves until all are near.
    let mut cfg = common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, 1);
    cfg.stop.criterion = StopCriterion::Quiescent;
    let mut sim = Simulation::new(cfg.clone(), common::square(12, 8.0, 1)).unwrap();
    let mut moving_rounds = 0;
    let out = sim.run_with(|r| {
        if r.round > 0 {
            assert!(r.moving > 0, "a counted round without moves");
            moving_rounds += 1;
        }
    });
    assert!(out.converged);
    assert_eq!(out.rounds, moving_rounds);
    assert_eq!(
        out.activations,
        12 * out.rounds,
        "the final check round is not counted"
    );
}

#[test]
fn the_round_cap_reports_not_converged() {
    let mut cfg = common::config(AlgorithmKind::ConvergeQuadrant, SchedulerSpec::Fsync, 0);
    cfg.stop.max_rounds = 3;
    let out = Simulation::new(cfg.clone(), common::square(50, 30.0, 0))
        .unwrap()
        .run();
    assert!(!out.converged);
    assert_eq!(out.rounds, 3);
}

#[test]
fn schedulers_activate_as_specified() {
    let n = 10;
    let run = |scheduler: SchedulerSpec, rounds: u64| {
        let mut cfg = common::config(AlgorithmKind::ConvergeQuadrant, scheduler.clone(), 5);
        cfg.stop.max_rounds = rounds;
        let mut per_round = vec![];
        Simulation::new(cfg.clone(), common::square(n, 200.0, 5))
            .unwrap()
            .run_with(|r| per_round.push(r.activated));
        per_round
    };
    assert!(
        run(SchedulerSpec::Fsync, 5)[1..]
            .iter()
            .all(|&a| a == n as u64)
    );
    assert!(
        run(
            SchedulerSpec::Sequential {
                order: SequentialOrder::RoundRobin
            },
            5
        )[1..]
            .iter()
            .all(|&a| a == 1)
    );
    let ssync = run(
        SchedulerSpec::Ssync {
            p: 0.05,
            fairness: None,
        },
        200,
    );
    assert!(
        ssync[1..].iter().all(|&a| a >= 1),
        "at least one robot per round"
    );
    let mean = ssync[1..].iter().sum::<u64>() as f64 / 200.0;
    assert!(
        mean < 1.5,
        "p = 0.05 activates about one robot per round, got {mean}"
    );
}

#[test]
fn ssync_fairness_bounds_waiting() {
    use monoculus_engine::components::Waiting;
    let mut cfg = common::config(
        AlgorithmKind::ConvergeQuadrant,
        SchedulerSpec::Ssync {
            p: 0.01,
            fairness: Some(2),
        },
        9,
    );
    cfg.stop.max_rounds = 1000;
    let mut sim = Simulation::new(cfg.clone(), common::square(30, 400.0, 9)).unwrap();
    for _ in 0..50 {
        sim.step();
        let world = sim.world();
        let mut max_wait = 0;
        for w in world.try_query::<&Waiting>().unwrap().iter(world) {
            max_wait = max_wait.max(w.0);
        }
        assert!(
            max_wait <= 2,
            "a robot waited {max_wait} rounds under 2-fairness"
        );
    }
}
