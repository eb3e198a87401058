//! The paper's Figure 1: the naive strategies grow the hull; ConvergeLocality does not.

mod common;

use glam::DVec2;
use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;

fn diamond() -> Vec<DVec2> {
    vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(10.0, 0.0),
        DVec2::new(5.0, 0.3),
        DVec2::new(5.0, -0.5),
    ]
}

#[test]
fn median_and_bisector_grow_the_hull_of_the_thin_diamond() {
    for kind in [AlgorithmKind::Median, AlgorithmKind::AngleBisector] {
        for seed in 0..10 {
            let out = Simulation::new(common::config(kind, SchedulerSpec::Fsync, seed), diamond())
                .unwrap()
                .run();
            assert!(
                out.hull_growth_rounds > 0,
                "{} seed {seed}: {out:?}",
                kind.name()
            );
            assert!(
                (out.hull_growth_max - 0.2).abs() < 1e-3,
                "the side robots overshoot by 0.2 each: {}",
                out.hull_growth_max
            );
            assert!(
                out.committed_hull_growth > 0,
                "destinations outside the hull"
            );
            assert!(out.converged);
        }
    }
    let out = Simulation::new(
        common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, 0),
        diamond(),
    )
    .unwrap()
    .run();
    assert_eq!(
        (
            out.hull_growth_rounds,
            out.committed_hull_growth,
            out.hull_growth_max
        ),
        (0, 0, 0.0)
    );
}

#[test]
fn on_random_starts_the_naive_strategies_sometimes_grow_the_hull_but_converge() {
    let mut grew = 0;
    for seed in 0..20 {
        let out = Simulation::new(
            common::config(AlgorithmKind::AngleBisector, SchedulerSpec::Fsync, seed),
            common::square(10, 20.0, seed),
        )
        .unwrap()
        .run();
        assert!(out.converged);
        grew += usize::from(out.hull_growth_rounds > 0);
    }
    assert!(grew > 0, "the bisector grows the hull in some runs");
}
