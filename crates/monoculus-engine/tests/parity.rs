//! The indexed engine (band grid in the plane, R-tree in space) against the brute-force engine: same decisions, same runs.

mod common;

use glam::DVec2;
use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;

/// Runs `cfg` on `pts` with its backend and with `other`, and asserts that both give
/// the same outcome and the same final positions.
fn assert_backends_agree(cfg: &SimConfig, other: SightBackend, pts: &[DVec2], what: &str) {
    let mut a = Simulation::new(cfg.clone(), pts.to_vec()).unwrap();
    let mut other_cfg = cfg.clone();
    other_cfg.backend = other;
    let mut b = Simulation::new(other_cfg, pts.to_vec()).unwrap();
    assert_eq!(a.run(), b.run(), "{what}");
    assert_eq!(a.positions(), b.positions(), "{what}");
}

#[test]
fn indexed_and_exact_backends_give_identical_runs() {
    for kind in AlgorithmKind::ALL {
        for (name, pts) in common::zoo(1) {
            let mut cfg = common::config(kind, SchedulerSpec::Fsync, 3);
            cfg.stop.max_rounds = 60;
            let what = format!("{} on {name}", kind.name());
            assert_backends_agree(&cfg, SightBackend::Exact, &pts, &what);
        }
    }
}

/// The same with the reference `target = "random_listing"`, which lists every visible
/// far point when its first draws miss (the default `random` redraws among the far
/// robots, listed through the index's range query on one side and brute force on the
/// other: covered above).
#[test]
fn backends_agree_with_the_listing_reference() {
    for (name, pts) in common::zoo(2) {
        let mut cfg = common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, 5);
        cfg.model.target = TargetPolicy::RandomListing;
        cfg.stop.max_rounds = 60;
        assert_backends_agree(&cfg, SightBackend::Exact, &pts, name);
    }
}

/// With a limited visibility range (SPEC 9.2) the indexed and exact backends still give
/// identical runs (the OLA shortcuts from the bounding box are off: the robots within
/// the range decide).
#[test]
fn backends_agree_with_a_limited_range() {
    for kind in AlgorithmKind::ALL {
        for (name, pts) in common::zoo(4) {
            for range in [2.5, 5.0] {
                let mut cfg = common::config(kind, SchedulerSpec::Fsync, 3);
                cfg.stop.max_rounds = 40;
                cfg.vision.range = range;
                let what = format!("{} on {name}, V = {range}", kind.name());
                assert_backends_agree(&cfg, SightBackend::Exact, &pts, &what);
            }
        }
    }
}

/// The R-tree in the plane (`vision.backend = "rtree"`) gives the runs of the band grid
/// and of the definition, for every algorithm on every configuration of the zoo.
#[test]
fn an_rtree_in_the_plane_gives_the_same_runs() {
    for kind in AlgorithmKind::ALL {
        for (name, pts) in common::zoo(1) {
            let mut cfg = common::config(kind, SchedulerSpec::Fsync, 3);
            cfg.stop.max_rounds = 60;
            let what = format!("{} on {name}", kind.name());
            assert_backends_agree(&cfg, SightBackend::Rtree, &pts, &what);
        }
    }
    // And under ASYNC, where every Look builds its own sight.
    let mut cfg = common::config(
        AlgorithmKind::ConvergeLocality,
        SchedulerSpec::Async(AsyncSpec::default()),
        2,
    );
    cfg.stop.max_rounds = 30;
    let pts = common::square(60, 8.0, 2);
    assert_backends_agree(&cfg, SightBackend::Rtree, &pts, "ASYNC");
}

/// Fat robots (SPEC 9.3): the engine's index (the R-tree) gives the runs of the
/// definition, for the paper's algorithms on every configuration of the zoo.
#[test]
fn backends_agree_with_fat_robots() {
    for kind in [
        AlgorithmKind::ConvergeLocality,
        AlgorithmKind::ConvergeQuadrant,
        AlgorithmKind::ConvergeQuadrantTermination,
    ] {
        for (k, (name, pts)) in common::zoo(2).into_iter().enumerate() {
            // Each configuration with one radius (a thin and a fat one in turn): the
            // exact backend is slow.
            let radius = [0.05, 0.3][k % 2];
            let mut cfg = common::config(kind, SchedulerSpec::Fsync, 3);
            cfg.stop.max_rounds = 15;
            cfg.vision.robot_radius = radius;
            let what = format!("{} on {name}, r = {radius}", kind.name());
            assert_backends_agree(&cfg, SightBackend::Exact, &pts, &what);
        }
    }
}

/// Swarms larger than the zoo's, so that at least 64 robots decide in a round and the
/// indexed engine decides in the order of its grid (neighbours in space one after the
/// other) while the brute-force engine decides in the robots' own order: random,
/// lattice and collinear, every algorithm, with the whole range and a limited one
/// (where every robot decides, those with a memory too), under FSYNC and, with part
/// of the robots active, SSYNC. Same decisions, same runs.
#[test]
fn deciding_in_the_grids_order_changes_no_decision() {
    use monoculus_core::init::{InitShape, generate};
    let swarms = [
        ("random", common::square(150, 12.0, 3)),
        (
            "lattice",
            generate(&InitShape::Lattice { side: 9.0 }, 100, 3),
        ),
        ("line", generate(&InitShape::Line { side: 16.0 }, 80, 3)),
    ];
    let ssync = SchedulerSpec::Ssync {
        p: 0.7,
        fairness: None,
    };
    for kind in AlgorithmKind::ALL {
        for (name, pts) in &swarms {
            for (scheduler, range) in [
                (SchedulerSpec::Fsync, f64::INFINITY),
                (SchedulerSpec::Fsync, 4.0),
                (ssync.clone(), f64::INFINITY),
            ] {
                let what = format!("{} on {name}, {scheduler:?}, V = {range}", kind.name());
                let mut cfg = common::config(kind, scheduler, 7);
                cfg.stop.max_rounds = 15;
                cfg.vision.range = range;
                assert_backends_agree(&cfg, SightBackend::Exact, pts, &what);
            }
        }
    }
}

/// With faulty robots: crashed robots stay where they stopped and are seen, and
/// Byzantine ones go anywhere, so the hull measured after a round (of the correct
/// robots) is not the hull of what robots see.
#[test]
fn backends_agree_with_faults() {
    use monoculus_engine::{ByzantineRule, CrashAt, FaultCount, FaultKind, FaultSpec};
    let kinds = [
        FaultKind::Crash(CrashAt::Round(1)),
        FaultKind::Byzantine(ByzantineRule::Random),
    ];
    for kind in kinds {
        for (name, pts) in common::zoo(2) {
            for scheduler in [
                SchedulerSpec::Fsync,
                SchedulerSpec::Ssync {
                    p: 0.5,
                    fairness: Some(3),
                },
            ] {
                let mut cfg = common::config(AlgorithmKind::ConvergeLocality, scheduler, 4);
                cfg.stop.max_rounds = 40;
                cfg.stop.criterion = StopCriterion::Diameter;
                cfg.faults = Some(FaultSpec {
                    count: FaultCount::Robots(3),
                    kind,
                });
                let what = format!("{kind:?} on {name}");
                assert_backends_agree(&cfg, SightBackend::Exact, &pts, &what);
            }
        }
    }
}
