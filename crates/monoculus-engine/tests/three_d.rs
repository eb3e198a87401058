//! Three dimensions: visibility against the definition, and the paper's guarantees.

mod common;

use glam::DVec3;
use monoculus_core::init::{InitShape, generate};
use monoculus_core::prelude::*;
use monoculus_core::vision::visible_points_brute;
use monoculus_engine::prelude::*;

fn cube(n: usize, side: f64, seed: u64) -> Vec<DVec3> {
    generate(&InitShape::Square { side }, n, seed)
}

fn zoo3(seed: u64) -> Vec<(&'static str, Vec<DVec3>)> {
    let mut s = Stream::new(seed, 77, 0, 0);
    let diagonal: Vec<DVec3> = (0..30).map(|_| DVec3::splat(s.uniform() * 10.0)).collect();
    let mut stacked = cube(25, 4.0, seed);
    stacked.extend_from_slice(&stacked.clone()[..8]);
    vec![
        ("random", cube(80, 8.0, seed)),
        (
            "lattice",
            generate(&InitShape::Lattice { side: 4.0 }, 64, seed),
        ),
        ("line", generate(&InitShape::Line { side: 10.0 }, 25, seed)),
        ("diagonal", diagonal),
        ("stacked", stacked),
    ]
}

#[test]
fn rtree_matches_the_definition_in_space() {
    let v = VisionParams::default();
    for seed in 0..3 {
        for (name, pts) in zoo3(seed) {
            let indexed = IndexedSight::new(pts.clone(), v);
            for i in 0..pts.len() {
                let brute = visible_points_brute(&pts, i, &v);
                assert_eq!(
                    indexed.visible_points(i),
                    brute,
                    "{name} seed {seed} robot {i}"
                );
                for j in 0..pts.len() {
                    assert_eq!(
                        indexed.is_visible_point(i, j),
                        brute.contains(&j),
                        "{name}: {i} -> {j}"
                    );
                }
            }
        }
    }
    // The lattice hides most robots: a corner sees far fewer than n - 1.
    let lattice: Vec<DVec3> = generate(&InitShape::Lattice { side: 4.0 }, 64, 0);
    let seen = IndexedSight::new(lattice.clone(), v)
        .visible_points(0)
        .len();
    assert!(seen < 63 && seen > 3, "{seen}");
}

fn run3(kind: AlgorithmKind, scheduler: SchedulerSpec, seed: u64, n: usize) -> RunOutcome {
    let mut cfg = common::config(kind, scheduler.clone(), seed);
    cfg.stop.max_rounds = 50_000;
    Simulation::new(cfg.clone(), cube(n, 10.0, seed))
        .unwrap()
        .run()
}

#[test]
fn converge_locality_in_space_never_grows_the_hull() {
    for scheduler in [
        SchedulerSpec::Fsync,
        SchedulerSpec::Ssync {
            p: 0.5,
            fairness: None,
        },
    ] {
        for seed in 0..8 {
            let out = run3(
                AlgorithmKind::ConvergeLocality,
                scheduler.clone(),
                seed,
                [8, 30, 60][seed as usize % 3],
            );
            assert!(out.converged, "{out:?}");
            assert_eq!(
                out.hull_growth_rounds, 0,
                "hull volume grew: {scheduler:?} seed {seed}"
            );
            assert_eq!(out.committed_hull_growth, 0);
            assert!(out.hull_initial > 0.0 && out.hull_final <= out.hull_initial);
        }
    }
}

#[test]
fn converge_quadrant_in_space_ends_in_a_2b_cube_and_termination_stops() {
    for seed in 0..8 {
        let out = run3(
            AlgorithmKind::ConvergeQuadrant,
            SchedulerSpec::Fsync,
            seed,
            [5, 30, 60][seed as usize % 3],
        );
        assert!(out.converged, "{out:?}");
        assert_eq!(out.final_extents.len(), 3);
        assert!(
            out.final_extents.iter().all(|&e| e <= 2.0),
            "{:?}",
            out.final_extents
        );
        let t = run3(
            AlgorithmKind::ConvergeQuadrantTermination,
            SchedulerSpec::Fsync,
            seed,
            [5, 20, 40][seed as usize % 3],
        );
        assert!(t.converged, "{t:?}");
    }
}

#[test]
fn space_runs_under_async_and_match_the_exact_backend() {
    for kind in [
        AlgorithmKind::ConvergeLocality,
        AlgorithmKind::ConvergeQuadrant,
        AlgorithmKind::CenterOfGravity,
    ] {
        let mut cfg = common::config(
            kind,
            SchedulerSpec::Async(AsyncSpec {
                idle: TickDist::Uniform { min: 1, max: 6 },
                compute: TickDist::Uniform { min: 1, max: 3 },
                motion: TickDist::Uniform { min: 1, max: 3 },
                start: AsyncStart::Random,
                durations: None,
            }),
            4,
        );
        let start = cube(20, 6.0, 4);
        let a = Simulation::new(cfg.clone(), start.clone()).unwrap().run();
        assert!(a.converged, "{}: {a:?}", kind.name());
        cfg.backend = SightBackend::Exact;
        assert_eq!(
            a,
            Simulation::new(cfg.clone(), start).unwrap().run(),
            "{}",
            kind.name()
        );
    }
}

#[test]
fn termination_memory_has_six_bits_in_space() {
    use monoculus_core::algorithms::TerminationBits;
    let mut m = TerminationBits::default();
    for k in 0..3 {
        for side in monoculus_core::observe::Side::BOTH {
            assert!(!m.terminated(3));
            m.set(k, side);
        }
    }
    assert!(m.terminated(3));
    assert_eq!(m.0, 0b11_1111);
}
