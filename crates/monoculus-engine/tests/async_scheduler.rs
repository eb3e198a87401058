//! The ASYNC scheduler: FSYNC as a special case, the paper's guarantees, determinism.

mod common;

use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;

fn with_async(mut cfg: SimConfig, spec: AsyncSpec) -> SimConfig {
    cfg.scheduler = SchedulerSpec::Async(spec);
    cfg
}

fn lockstep(i: u64, c: u64, m: u64) -> AsyncSpec {
    AsyncSpec {
        idle: TickDist::Fixed { ticks: i },
        compute: TickDist::Fixed { ticks: c },
        motion: TickDist::Fixed { ticks: m },
        start: AsyncStart::Together,
        durations: None,
    }
}

/// Idle U(shortest, 2 scale), Compute U(shortest, scale), Move Exp(0.8 scale), a
/// random start.
fn scaled_timing(scale: u64, shortest: u64) -> AsyncSpec {
    AsyncSpec {
        idle: TickDist::Uniform {
            min: shortest,
            max: 2 * scale,
        },
        compute: TickDist::Uniform {
            min: shortest,
            max: scale,
        },
        motion: TickDist::Exponential {
            mean: 0.8 * scale as f64,
        },
        start: AsyncStart::Random,
        durations: None,
    }
}

fn random_timing(start: AsyncStart) -> AsyncSpec {
    AsyncSpec {
        idle: TickDist::Uniform { min: 1, max: 10 },
        compute: TickDist::Exponential { mean: 3.0 },
        motion: TickDist::Uniform { min: 1, max: 6 },
        start,
        durations: None,
    }
}

#[test]
fn fixed_durations_starting_together_reproduce_fsync() {
    let criteria = [
        StopCriterion::QuiescentOrDiameter,
        StopCriterion::Quiescent,
        StopCriterion::Box,
        StopCriterion::Diameter,
    ];
    for kind in AlgorithmKind::ALL {
        for seed in 0..4 {
            for (k, &criterion) in criteria.iter().enumerate() {
                let mut cfg = common::config(kind, SchedulerSpec::Fsync, seed);
                cfg.stop.criterion = criterion;
                cfg.stop.max_rounds = 400;
                let start = common::square(8 + 7 * seed as usize, 9.0, seed);
                let mut fsync = Simulation::new(cfg.clone(), start.clone()).unwrap();
                let f = fsync.run();
                let (i, c, m) = [(1, 1, 1), (3, 2, 4), (2, 5, 1), (1, 1, 7)][k];
                let mut asim =
                    Simulation::new(with_async(cfg.clone(), lockstep(i, c, m)), start).unwrap();
                let mut a = asim.run();
                assert!(a.ticks.is_some());
                a.ticks = None;
                assert_eq!(f, a, "{} seed {seed} {criterion:?}", kind.name());
                assert_eq!(fsync.positions(), asim.positions());
            }
        }
    }
}

#[test]
fn epochs_and_ticks_in_lockstep() {
    let cfg = common::config(AlgorithmKind::ConvergeQuadrant, SchedulerSpec::Fsync, 1);
    let start = common::square(30, 12.0, 1);
    let f = Simulation::new(cfg.clone(), start.clone()).unwrap().run();
    let a = Simulation::new(with_async(cfg.clone(), lockstep(2, 3, 4)), start)
        .unwrap()
        .run();
    // Cycle k: Look at 9k, compute until 9k+3, move until 9k+7 = end of epoch k+1.
    assert_eq!(a.rounds, f.rounds, "{f:?} {a:?}");
    assert_eq!(a.ticks, Some(9 * f.rounds - 2), "{f:?} {a:?}");
}

#[test]
fn converge_locality_under_async_never_grows_the_committed_hull() {
    for seed in 0..16 {
        let start = if seed % 2 == 0 {
            AsyncStart::Together
        } else {
            AsyncStart::Random
        };
        let cfg = with_async(
            common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, seed),
            random_timing(start),
        );
        let n = [10, 30, 60][seed as usize % 3];
        let out = Simulation::new(cfg.clone(), common::square(n, 14.0, seed))
            .unwrap()
            .run();
        assert!(out.converged, "seed {seed}: {out:?}");
        assert_eq!(
            out.committed_hull_growth, 0,
            "Lemma 2 under ASYNC, seed {seed}: {out:?}"
        );
        assert!(out.final_diameter <= 4.0);
        assert!(out.rounds > 0 && out.ticks.unwrap() > out.rounds);
    }
}

#[test]
fn converge_quadrant_under_async_reaches_its_box() {
    for seed in 0..10 {
        let cfg = with_async(
            common::config(AlgorithmKind::ConvergeQuadrant, SchedulerSpec::Fsync, seed),
            random_timing(AsyncStart::Random),
        );
        let out = Simulation::new(
            cfg,
            common::square([5, 25, 50][seed as usize % 3], 10.0, seed),
        )
        .unwrap()
        .run();
        assert!(out.converged, "seed {seed}: {out:?}");
        assert!(out.final_extents.iter().all(|&e| e <= 2.0));
    }
}

#[test]
fn termination_stops_under_async() {
    for seed in 0..6 {
        let mut cfg = common::config(
            AlgorithmKind::ConvergeQuadrantTermination,
            SchedulerSpec::Fsync,
            seed,
        );
        cfg.stop.max_rounds = 20_000;
        let mut sim = Simulation::new(
            with_async(cfg.clone(), random_timing(AsyncStart::Together)),
            common::square(20, 8.0, seed),
        )
        .unwrap();
        let out = sim.run();
        assert!(out.converged, "seed {seed}: {out:?}");
        // Stopped means: nobody in mid-move, and nobody would move if it looked now.
        assert!(sim.is_quiescent(), "seed {seed}: a robot would move");
        assert!(out.terminated.is_some_and(|t| t <= 20));
    }
}

#[test]
fn async_results_do_not_depend_on_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let cfg = with_async(
                common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, 5),
                random_timing(AsyncStart::Random),
            );
            let mut sim = Simulation::new(cfg.clone(), common::square(300, 30.0, 5)).unwrap();
            let out = sim.run();
            (out, sim.positions().to_vec())
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn the_exact_backend_agrees_under_async() {
    for kind in [
        AlgorithmKind::ConvergeLocality,
        AlgorithmKind::ConvergeQuadrant,
    ] {
        let mut cfg = with_async(
            common::config(kind, SchedulerSpec::Fsync, 2),
            random_timing(AsyncStart::Random),
        );
        let start = common::square(25, 8.0, 2);
        let a = Simulation::new(cfg.clone(), start.clone()).unwrap().run();
        cfg.backend = SightBackend::Exact;
        assert_eq!(
            a,
            Simulation::new(cfg.clone(), start).unwrap().run(),
            "{}",
            kind.name()
        );
    }
}

/// A robot in its Move phase is where its segment says at each tick (the position every
/// Look of that tick sees it at); idle robots are where they settled.
#[test]
fn a_move_is_interpolated_along_its_segment() {
    use monoculus_engine::asynchrony::{Phase, Timing};
    let t = Timing::<glam::DVec2>::new(Phase::Move, 10, 14, 0, 9, Some(glam::DVec2::new(4.0, 0.0)));
    assert_eq!(
        t.position_at(glam::DVec2::ZERO, 11),
        glam::DVec2::new(1.0, 0.0)
    );
    assert_eq!(
        t.position_at(glam::DVec2::ZERO, 14),
        glam::DVec2::new(4.0, 0.0)
    );
    let mut idle = t;
    idle.phase = Phase::Idle;
    assert_eq!(idle.position_at(glam::DVec2::ZERO, 11), glam::DVec2::ZERO);
}

/// Looks that see robots in mid-move change the runs: long moves against one-tick moves
/// (the engine's own check that Looks use the movers' interpolated positions is the unit
/// test `looks_see_movers_on_their_segments`).
#[test]
fn runs_with_long_moves_differ_from_runs_with_one_tick_moves() {
    let slow = AsyncSpec {
        motion: TickDist::Fixed { ticks: 9 },
        ..random_timing(AsyncStart::Random)
    };
    let quick = AsyncSpec {
        motion: TickDist::Fixed { ticks: 1 },
        ..random_timing(AsyncStart::Random)
    };
    let cfg = common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, 3);
    let start = common::square(40, 12.0, 3);
    let a = Simulation::new(with_async(cfg.clone(), slow), start.clone())
        .unwrap()
        .run();
    let b = Simulation::new(with_async(cfg.clone(), quick), start)
        .unwrap()
        .run();
    assert_ne!(a.moves, b.moves);
}

#[test]
fn under_async_the_hull_of_positions_alone_can_grow() {
    // A robot finishing a move decided earlier can end outside the current hull, which
    // shrank meanwhile: observed, and reported in hull_growth_rounds.
    let grew = (0..12).any(|seed| {
        let cfg = with_async(
            common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, seed),
            random_timing(AsyncStart::Together),
        );
        Simulation::new(cfg.clone(), common::square(60, 14.0, seed))
            .unwrap()
            .run()
            .hull_growth_rounds
            > 0
    });
    assert!(grew);
}

#[test]
fn watching_a_run_tick_by_tick_does_not_change_it() {
    let schedulers = [
        SchedulerSpec::Fsync,
        SchedulerSpec::Ssync {
            p: 0.5,
            fairness: None,
        },
        SchedulerSpec::Async(random_timing(AsyncStart::Random)),
    ];
    for scheduler in schedulers {
        for kind in [
            AlgorithmKind::ConvergeLocality,
            AlgorithmKind::ConvergeQuadrantTermination,
        ] {
            let cfg = common::config(kind, scheduler.clone(), 5);
            let start = common::square(30, 8.0, 5);
            let plain = Simulation::new(cfg.clone(), start.clone()).unwrap().run();
            let mut sim = Simulation::new(cfg.clone(), start).unwrap();
            let mut steps = 0u64;
            let mut times = Vec::new();
            let watched = sim.run_observed(|s| {
                steps += 1;
                times.push(s.time());
                let views = s.robot_views();
                assert_eq!(views.len(), 30);
                assert_eq!(s.positions_now().len(), 30);
                let has_bits = kind == AlgorithmKind::ConvergeQuadrantTermination;
                assert!(views.iter().all(|v| v.bits.is_some() == has_bits));
            });
            assert_eq!(watched, plain, "{scheduler:?} {kind:?}");
            match scheduler {
                // The start and every counted round.
                SchedulerSpec::Async(_) => {
                    assert!(steps > watched.rounds, "a step per event tick");
                    assert_eq!(times.last().copied(), watched.ticks);
                }
                _ => {
                    assert_eq!(steps, watched.rounds + 1);
                    assert!(times.windows(2).all(|t| t[1] == t[0] + 1));
                }
            }
        }
    }
}

/// Durations from a few ticks a cycle to hundreds: the moving index is made at every
/// tick with Looks where Looks are many, and serves long stretches of ticks where they
/// are few, robots in mid-move placed on their segments when asked. The runs are those
/// of the brute-force sight, from random, lattice and collinear starts.
#[test]
fn the_moving_index_agrees_with_the_exact_backend_at_every_time_resolution() {
    use monoculus_core::init::{InitShape, generate};
    let timing = |scale: u64| scaled_timing(scale, 1);
    let starts = [
        ("random", common::square(150, 12.0, 5)),
        (
            "lattice",
            generate(&InitShape::Lattice { side: 10.0 }, 144, 5),
        ),
        ("line", generate(&InitShape::Line { side: 12.0 }, 60, 5)),
    ];
    for scale in [5, 20, 100] {
        for kind in [
            AlgorithmKind::ConvergeLocality,
            AlgorithmKind::ConvergeQuadrant,
        ] {
            for (name, start) in &starts {
                let cfg = common::config(kind, SchedulerSpec::Fsync, 5);
                let mut cfg = with_async(cfg, timing(scale));
                cfg.stop.max_rounds = 6;
                let a = Simulation::new(cfg.clone(), start.clone()).unwrap().run();
                cfg.backend = SightBackend::Exact;
                let b = Simulation::new(cfg, start.clone()).unwrap().run();
                assert_eq!(a, b, "{} from {name}, durations x{scale}", kind.name());
            }
        }
    }
}

/// Looks decided ahead of their ticks: where every Compute lasts at least a few ticks,
/// the Looks of the ticks after one with Looks are decided with them, each against the
/// sight of its own tick. The runs are those of the brute-force sight, which decides
/// every Look at its tick: for algorithms that ask for the swarm's hull (the farthest
/// robot), its box, every position or a memory, from random, lattice and collinear
/// starts, and Looks are decided ahead where the index is kept (not for the algorithm
/// with a memory, whose Looks are decided at their ticks).
#[test]
fn looks_decided_ahead_are_those_of_their_ticks() {
    use monoculus_core::init::{InitShape, generate};
    let timing = |scale: u64| scaled_timing(scale, scale / 4);
    let starts = [
        ("random", common::square(150, 12.0, 7)),
        ("dense", common::square(120, 3.0, 7)),
        (
            "lattice",
            generate(&InitShape::Lattice { side: 10.0 }, 144, 7),
        ),
        ("line", generate(&InitShape::Line { side: 12.0 }, 60, 7)),
    ];
    let mut ahead = 0;
    for scale in [40, 400] {
        for kind in [
            AlgorithmKind::ConvergeLocality,
            AlgorithmKind::ConvergeQuadrant,
            AlgorithmKind::CenterOfGravity,
            AlgorithmKind::ConvergeQuadrantTermination,
        ] {
            for (name, start) in &starts {
                let cfg = common::config(kind, SchedulerSpec::Fsync, 7);
                let mut cfg = with_async(cfg, timing(scale));
                cfg.stop.max_rounds = 8;
                let mut sim = Simulation::new(cfg.clone(), start.clone()).unwrap();
                let a = sim.run();
                let decided = sim
                    .world()
                    .resource::<monoculus_engine::asynchrony::AsyncClock>()
                    .looks_ahead;
                if kind == AlgorithmKind::ConvergeQuadrantTermination {
                    assert_eq!(decided, 0, "{name}: a memory is read at the Look's tick");
                }
                ahead += decided;
                cfg.backend = SightBackend::Exact;
                let b = Simulation::new(cfg, start.clone()).unwrap().run();
                assert_eq!(a, b, "{} from {name}, durations x{scale}", kind.name());
            }
        }
    }
    assert!(ahead > 10_000, "{ahead} Looks decided ahead");
}

/// The world's resources are entities that come before the robots: a resource spawned
/// after them carries a sparse index over every robot (4 MB each at 10^6 robots, 24 MB
/// of an ASYNC run's peak once). Under both kinds of scheduler, and after the first
/// tick (which is when the schedule's own resource would otherwise appear).
#[test]
fn resources_come_before_the_robots() {
    use bevy_ecs::prelude::*;
    use monoculus_engine::components::Robot;
    let cfg = common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, 3);
    for cfg in [
        cfg.clone(),
        with_async(cfg, random_timing(AsyncStart::Random)),
    ] {
        let mut sim = Simulation::new(cfg, common::square(300, 12.0, 3)).unwrap();
        sim.step();
        let world = sim.world();
        fn index<F: bevy_ecs::query::QueryFilter>(world: &World) -> Vec<u32> {
            world
                .try_query_filtered::<Entity, F>()
                .expect("registered")
                .iter(world)
                .map(|e| e.index_u32())
                .collect()
        }
        let robots = index::<With<Robot>>(world);
        let others = index::<Without<Robot>>(world);
        assert_eq!(robots.len(), 300);
        assert!(!others.is_empty());
        let first_robot = robots.iter().min().unwrap();
        assert!(
            others.iter().all(|i| i < first_robot),
            "entities {others:?} come after the first robot ({first_robot})"
        );
    }
}
