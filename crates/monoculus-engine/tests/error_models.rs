//! Observation and movement errors: off by default, seeded, and with visible effects.

mod common;

use monoculus_core::errors::{FactorDist, MovementErrors, ObservationErrors};
use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;

fn run(cfg: SimConfig, seed: u64) -> RunOutcome {
    Simulation::new(cfg.clone(), common::square(40, 12.0, seed))
        .unwrap()
        .run()
}

#[test]
fn zero_errors_change_nothing() {
    for kind in AlgorithmKind::ALL {
        let cfg = common::config(kind, SchedulerSpec::Fsync, 1);
        let mut with = cfg.clone();
        with.model.errors = ObservationErrors {
            flip_p: 0.0,
            flip_window: 0.3,
            angle_sigma: 0.0,
        };
        with.movement = MovementErrors {
            step_factor: FactorDist::Fixed { value: 1.0 },
            non_rigid: None,
        };
        assert_eq!(run(cfg.clone(), 1), run(with, 1), "{}", kind.name());
    }
}

#[test]
fn angular_noise_changes_runs_but_converge_locality_still_converges() {
    for seed in 0..6 {
        let mut cfg = common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, seed);
        let exact = run(cfg.clone(), seed);
        cfg.model.errors.angle_sigma = 0.05;
        let noisy = run(cfg.clone(), seed);
        assert_ne!(exact, noisy);
        assert!(noisy.converged, "{noisy:?}");
        assert_eq!(noisy, run(cfg.clone(), seed), "seeded");
    }
}

#[test]
fn noisy_quadrant_robots_still_gather() {
    for seed in 0..6 {
        let mut cfg = common::config(AlgorithmKind::ConvergeQuadrant, SchedulerSpec::Fsync, seed);
        cfg.model.errors.angle_sigma = 0.02;
        let out = run(cfg.clone(), seed);
        assert!(out.converged, "{out:?}");
        assert_ne!(
            out,
            run(
                common::config(AlgorithmKind::ConvergeQuadrant, SchedulerSpec::Fsync, seed),
                seed
            )
        );
    }
}

#[test]
fn far_bit_flips_change_choices() {
    let mut cfg = common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, 2);
    let exact = run(cfg.clone(), 2);
    cfg.model.errors = ObservationErrors {
        flip_p: 0.5,
        flip_window: 0.5,
        angle_sigma: 0.0,
    };
    let flipped = run(cfg.clone(), 2);
    assert_ne!(exact, flipped);
    assert_eq!(flipped, run(cfg.clone(), 2));
    // The indexed and exact backends perceive the same errors.
    cfg.backend = SightBackend::Exact;
    assert_eq!(flipped, run(cfg.clone(), 2));
}

#[test]
fn movement_errors_scale_the_distance() {
    let mut cfg = common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, 3);
    cfg.movement.step_factor = FactorDist::Fixed { value: 0.5 };
    let half = run(cfg.clone(), 3);
    assert!(half.converged);
    assert!(
        (half.distance - 0.5 * half.moves as f64).abs() < 1e-9,
        "{half:?}"
    );
    cfg.movement = MovementErrors {
        step_factor: FactorDist::Fixed { value: 1.0 },
        non_rigid: Some(0.25),
    };
    let cut = run(cfg.clone(), 3);
    assert!(cut.converged);
    assert!(cut.distance < cut.moves as f64 && cut.distance >= 0.25 * cut.moves as f64);
    cfg.movement = MovementErrors {
        step_factor: FactorDist::Uniform { min: 0.8, max: 1.2 },
        non_rigid: None,
    };
    let varied = run(cfg.clone(), 3);
    let mean = varied.distance / varied.moves as f64;
    assert!((mean - 1.0).abs() < 0.05, "{mean}");
}

#[test]
fn errors_under_async_are_deterministic_across_threads() {
    let go = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let mut cfg =
                    common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, 8);
                cfg.scheduler = SchedulerSpec::Async(AsyncSpec {
                    idle: TickDist::Uniform { min: 1, max: 5 },
                    compute: TickDist::Fixed { ticks: 2 },
                    motion: TickDist::Exponential { mean: 3.0 },
                    start: AsyncStart::Random,
                    durations: None,
                });
                cfg.model.errors = ObservationErrors {
                    flip_p: 0.2,
                    flip_window: 0.2,
                    angle_sigma: 0.03,
                };
                cfg.movement = MovementErrors {
                    step_factor: FactorDist::Normal { mean: 1.0, sd: 0.1 },
                    non_rigid: Some(0.5),
                };
                Simulation::new(cfg.clone(), common::square(200, 25.0, 8))
                    .unwrap()
                    .run()
            })
    };
    let a = go(1);
    assert!(a.converged, "{a:?}");
    assert_eq!(a, go(2));
}
