//! Faulty robots (SPEC 9.1): crashed robots stop from their round, Byzantine robots follow
//! their rule, everybody sees them, and the metrics are the correct robots'.

mod common;

use glam::DVec2;
use monoculus_core::metrics;
use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;
use monoculus_engine::{ByzantineRule, CrashAt, FaultCount, FaultKind, FaultPlan, FaultSpec, Role};

fn with_faults(
    kind: AlgorithmKind,
    scheduler: SchedulerSpec,
    seed: u64,
    f: FaultSpec,
) -> SimConfig {
    SimConfig {
        faults: Some(f),
        ..common::config(kind, scheduler, seed)
    }
}

fn crash(count: usize, at: CrashAt) -> FaultSpec {
    FaultSpec {
        count: FaultCount::Robots(count),
        kind: FaultKind::Crash(at),
    }
}

fn byzantine(count: usize, rule: ByzantineRule) -> FaultSpec {
    FaultSpec {
        count: FaultCount::Robots(count),
        kind: FaultKind::Byzantine(rule),
    }
}

/// Steps `sim` round by round (at most `rounds`), giving the positions before each round.
fn rounds_of(sim: &mut Simulation<DVec2>, rounds: usize) -> Vec<Vec<DVec2>> {
    let mut states = vec![sim.positions().to_vec()];
    for _ in 0..rounds {
        sim.step();
        states.push(sim.positions().to_vec());
    }
    states
}

#[test]
fn no_faulty_robots_is_the_run_without_faults() {
    for kind in [
        AlgorithmKind::ConvergeLocality,
        AlgorithmKind::ConvergeQuadrant,
        AlgorithmKind::ConvergeQuadrantTermination,
    ] {
        for scheduler in [
            SchedulerSpec::Fsync,
            SchedulerSpec::Ssync {
                p: 0.5,
                fairness: None,
            },
        ] {
            let start = common::square(40, 12.0, 2);
            let plain = Simulation::new(common::config(kind, scheduler.clone(), 2), start.clone())
                .unwrap()
                .run();
            let zero = with_faults(kind, scheduler.clone(), 2, crash(0, CrashAt::Round(0)));
            assert_eq!(Simulation::new(zero, start).unwrap().run(), plain);
        }
    }
}

#[test]
fn crashed_robots_stop_from_their_round_and_the_others_keep_going() {
    for at in [0u64, 3] {
        let spec = crash(5, CrashAt::Round(at));
        let cfg = with_faults(
            AlgorithmKind::ConvergeLocality,
            SchedulerSpec::Fsync,
            7,
            spec,
        );
        let start = common::square(30, 15.0, 7);
        let plan = FaultPlan::draw(&spec, start.len(), 7);
        let mut sim = Simulation::new(cfg, start).unwrap();
        let states = rounds_of(&mut sim, 12);
        let crashed: Vec<usize> = (0..30).filter(|&i| !plan.is_correct(i)).collect();
        assert_eq!(crashed.len(), 5);
        for (k, pair) in states.windows(2).enumerate() {
            for &i in &crashed {
                if k as u64 >= at {
                    assert_eq!(pair[0][i], pair[1][i], "robot {i} moved in round {k}");
                }
            }
        }
        // Before its crash round a crashed robot runs the algorithm: with at = 3 some of
        // them move in the first rounds (the start is spread out, everybody sees far).
        if at == 3 {
            assert!(crashed.iter().any(|&i| states[0][i] != states[3][i]));
        }
        assert!((0..30).any(|i| plan.is_correct(i) && states[0][i] != states[12][i]));
    }
}

#[test]
fn random_crash_rounds_are_drawn_within_until() {
    let spec = crash(6, CrashAt::Random { until: 4 });
    let plan = FaultPlan::draw(&spec, 20, 11);
    let cfg = with_faults(
        AlgorithmKind::ConvergeLocality,
        SchedulerSpec::Fsync,
        11,
        spec,
    );
    let mut sim = Simulation::new(cfg, common::square(20, 12.0, 11)).unwrap();
    let states = rounds_of(&mut sim, 8);
    for i in 0..20 {
        if let Role::Crashed { from } = plan.role(i) {
            assert!(from <= 4);
            for pair in states[from as usize..].windows(2) {
                assert_eq!(pair[0][i], pair[1][i]);
            }
        }
    }
}

#[test]
fn byzantine_robots_move_b_by_their_rule_every_activation() {
    for rule in [
        ByzantineRule::Away,
        ByzantineRule::Farthest,
        ByzantineRule::Random,
    ] {
        let spec = byzantine(3, rule);
        let start = common::square(25, 10.0, 5);
        let plan = FaultPlan::draw(&spec, 25, 5);
        let cfg = with_faults(
            AlgorithmKind::ConvergeLocality,
            SchedulerSpec::Fsync,
            5,
            spec,
        );
        let mut sim = Simulation::new(cfg, start).unwrap();
        let states = rounds_of(&mut sim, 6);
        for pair in states.windows(2) {
            let centroid = metrics::centroid(&pair[0]);
            for i in (0..25).filter(|&i| !plan.is_correct(i)) {
                let d = pair[1][i] - pair[0][i];
                assert!((d.length() - 1.0).abs() < 1e-12, "{rule:?}: {d}");
                let want = match rule {
                    ByzantineRule::Away => Some(pair[0][i] - centroid),
                    ByzantineRule::Farthest => {
                        let far = (0..25)
                            .max_by(|&a, &b| {
                                let (da, db) = (
                                    pair[0][a].distance(pair[0][i]),
                                    pair[0][b].distance(pair[0][i]),
                                );
                                da.total_cmp(&db).then(b.cmp(&a))
                            })
                            .unwrap();
                        Some(pair[0][far] - pair[0][i])
                    }
                    ByzantineRule::Random => None,
                };
                if let Some(w) = want {
                    assert!((d - w.normalize()).length() < 1e-9, "{rule:?}: {d} vs {w}");
                }
            }
        }
    }
}

#[test]
fn metrics_and_the_stop_are_the_correct_robots() {
    let spec = crash(4, CrashAt::Round(0));
    let start = common::square(30, 12.0, 3);
    let plan = FaultPlan::draw(&spec, 30, 3);
    let correct_start: Vec<DVec2> = plan.correct(&start);
    let cfg = with_faults(
        AlgorithmKind::ConvergeLocality,
        SchedulerSpec::Fsync,
        3,
        spec,
    );
    let mut sim = Simulation::new(cfg, start.clone()).unwrap();
    let out = sim.run();
    assert_eq!(out.faulty, 4);
    assert_eq!(out.d_opt, metrics::d_opt(&correct_start, 2.0));
    assert_eq!(out.d_max, metrics::d_max(&correct_start));
    let correct_end = plan.correct(sim.positions());
    let diameter = correct_end
        .iter()
        .flat_map(|a| correct_end.iter().map(move |b| a.distance(*b)))
        .fold(0.0, f64::max);
    assert!((out.final_diameter - diameter).abs() < 1e-9);
    // The crashed robots never moved, and no move of theirs is counted.
    for i in (0..30).filter(|&i| !plan.is_correct(i)) {
        assert_eq!(sim.positions()[i], start[i]);
    }
    let moved: f64 = (0..30)
        .filter(|&i| plan.is_correct(i))
        .map(|i| (sim.positions()[i] - start[i]).length())
        .sum();
    assert!(moved <= out.distance + 1e-9);
}

#[test]
fn byzantine_moves_are_not_counted() {
    let spec = byzantine(2, ByzantineRule::Random);
    let mut cfg = with_faults(
        AlgorithmKind::ConvergeLocality,
        SchedulerSpec::Fsync,
        9,
        spec,
    );
    cfg.stop.max_rounds = 5;
    let start = common::square(20, 30.0, 9);
    let out = Simulation::new(cfg, start).unwrap().run();
    // FSYNC: every activation of the 18 correct robots is counted, the 2 others' not.
    assert_eq!(out.activations, 18 * out.rounds);
    assert_eq!(out.faulty, 2);
}

#[test]
fn faults_do_not_depend_on_the_thread_count() {
    let run = |threads: usize, spec: FaultSpec| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let cfg = with_faults(
                AlgorithmKind::ConvergeQuadrant,
                SchedulerSpec::Fsync,
                4,
                spec,
            );
            let mut sim = Simulation::new(cfg, common::square(300, 25.0, 4)).unwrap();
            (sim.run(), sim.positions().to_vec())
        })
    };
    for spec in [
        crash(10, CrashAt::Random { until: 20 }),
        byzantine(5, ByzantineRule::Farthest),
    ] {
        assert_eq!(run(1, spec), run(2, spec));
        assert_eq!(run(1, spec), run(4, spec));
    }
}

#[test]
fn impossible_faults_are_refused() {
    let start = common::square(10, 5.0, 1);
    for (spec, scheduler) in [
        (crash(10, CrashAt::Round(0)), SchedulerSpec::Fsync),
        (crash(11, CrashAt::Round(0)), SchedulerSpec::Fsync),
        (
            FaultSpec {
                count: FaultCount::Fraction(1.5),
                kind: FaultKind::Crash(CrashAt::Round(0)),
            },
            SchedulerSpec::Fsync,
        ),
    ] {
        let cfg = with_faults(AlgorithmKind::ConvergeLocality, scheduler, 1, spec);
        assert!(Simulation::new(cfg, start.clone()).is_err(), "{spec:?}");
    }
}

/// Under ASYNC with fixed durations and a common start the robots run in lockstep, and
/// the run is the FSYNC run: with faults too (a crash at epoch k is a crash at round k).
#[test]
fn lockstep_async_with_faults_is_fsync_with_faults() {
    for (k, spec) in [
        crash(4, CrashAt::Round(0)),
        crash(4, CrashAt::Round(3)),
        crash(6, CrashAt::Random { until: 5 }),
        byzantine(2, ByzantineRule::Away),
        byzantine(3, ByzantineRule::Random),
    ]
    .into_iter()
    .enumerate()
    {
        for kind in [
            AlgorithmKind::ConvergeLocality,
            AlgorithmKind::ConvergeQuadrant,
        ] {
            let mut cfg = with_faults(kind, SchedulerSpec::Fsync, k as u64, spec);
            cfg.stop.criterion = if kind == AlgorithmKind::ConvergeLocality {
                StopCriterion::Diameter
            } else {
                StopCriterion::Box
            };
            cfg.stop.max_rounds = 60;
            let start = common::square(25, 9.0, k as u64);
            let mut fsync = Simulation::new(cfg.clone(), start.clone()).unwrap();
            let f = fsync.run();
            cfg.scheduler = SchedulerSpec::Async(AsyncSpec {
                idle: TickDist::Fixed { ticks: 2 },
                compute: TickDist::Fixed { ticks: 1 },
                motion: TickDist::Fixed { ticks: 3 },
                start: AsyncStart::Together,
                durations: None,
            });
            let mut asim = Simulation::new(cfg, start).unwrap();
            let mut a = asim.run();
            a.ticks = None;
            assert_eq!(f, a, "{} {spec:?}", kind.name());
            assert_eq!(fsync.positions(), asim.positions());
        }
    }
}

/// Under ASYNC with random durations crashed robots stop from their epoch and nobody
/// else is held back; the run is seeded.
#[test]
fn crashes_under_async_stop_the_robot_and_the_run_is_seeded() {
    let spec = crash(5, CrashAt::Round(0));
    let plan = FaultPlan::draw(&spec, 30, 12);
    let mut cfg = with_faults(
        AlgorithmKind::ConvergeLocality,
        SchedulerSpec::Fsync,
        12,
        spec,
    );
    cfg.scheduler = SchedulerSpec::Async(AsyncSpec {
        idle: TickDist::Uniform { min: 1, max: 6 },
        compute: TickDist::Uniform { min: 1, max: 3 },
        motion: TickDist::Exponential { mean: 3.0 },
        start: AsyncStart::Random,
        durations: None,
    });
    cfg.stop.max_rounds = 40;
    let start = common::square(30, 12.0, 12);
    let mut sim = Simulation::new(cfg.clone(), start.clone()).unwrap();
    let out = sim.run();
    assert_eq!(out.faulty, 5);
    for i in (0..30).filter(|&i| !plan.is_correct(i)) {
        assert_eq!(sim.positions()[i], start[i]);
    }
    assert!((0..30).any(|i| plan.is_correct(i) && sim.positions()[i] != start[i]));
    assert_eq!(Simulation::new(cfg, start).unwrap().run(), out);
}
