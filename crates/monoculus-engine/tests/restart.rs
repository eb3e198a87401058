//! A simulation started again ([`Simulation::restart`]) is the run [`Simulation::new`]
//! makes, bit for bit, whatever ran in it before: every scheduler, faults, kept states,
//! the plane and space, and runs whose algorithm or scheduler differ from the last.

mod common;

use glam::{DVec2, DVec3};
use monoculus_core::init::{InitShape, generate};
use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;
use monoculus_engine::{
    ByzantineRule, CrashAt, FaultCount, FaultKind, FaultSpec, IndexPoint, Objective,
};

fn schedulers() -> Vec<SchedulerSpec> {
    vec![
        SchedulerSpec::Fsync,
        SchedulerSpec::Ssync {
            p: 0.4,
            fairness: Some(3),
        },
        SchedulerSpec::Sequential {
            order: SequentialOrder::Random,
        },
        SchedulerSpec::Adversary {
            objective: Objective::Grow,
            fairness: Some(4),
        },
        SchedulerSpec::Async(AsyncSpec {
            idle: TickDist::Uniform { min: 1, max: 10 },
            compute: TickDist::Exponential { mean: 3.0 },
            motion: TickDist::Uniform { min: 1, max: 6 },
            start: AsyncStart::Random,
            durations: None,
        }),
    ]
}

fn configs() -> Vec<SimConfig> {
    let mut out = Vec::new();
    for (k, scheduler) in schedulers().into_iter().enumerate() {
        for kind in [
            AlgorithmKind::ConvergeLocality,
            AlgorithmKind::ConvergeQuadrantTermination,
            AlgorithmKind::Median,
        ] {
            let seed = 7 * k as u64 + kind as u64;
            let mut cfg = common::config(kind, scheduler.clone(), seed);
            cfg.stop.max_rounds = 300;
            out.push(cfg.clone());
            cfg.faults = Some(FaultSpec {
                count: FaultCount::Robots(2),
                kind: if k % 2 == 0 {
                    FaultKind::Crash(CrashAt::Round(2))
                } else {
                    FaultKind::Byzantine(ByzantineRule::Random)
                },
            });
            cfg.stop.criterion = StopCriterion::Diameter;
            out.push(cfg);
        }
    }
    out
}

/// What a run gives: its outcome and where its robots ended.
fn ran<P: IndexPoint>(sim: &mut Simulation<P>) -> (RunOutcome, Vec<P>) {
    let outcome = sim.run();
    (outcome, sim.positions().to_vec())
}

fn same<P: IndexPoint + std::fmt::Debug>(a: &(RunOutcome, Vec<P>), b: &(RunOutcome, Vec<P>)) {
    assert_eq!(a.0, b.0);
    assert_eq!(a.1, b.1);
}

#[test]
fn a_restarted_plane_run_is_the_fresh_run() {
    let configs = configs();
    let start = |k: usize| -> Vec<DVec2> {
        match k % 3 {
            0 => common::square(12, 6.0, k as u64),
            1 => generate(&InitShape::Lattice { side: 4.0 }, 16, k as u64),
            _ => generate(&InitShape::Line { side: 5.0 }, 9, k as u64),
        }
    };
    // One simulation through every config in turn (each after a different one), and
    // through the same configs again in reverse.
    let mut kept: Option<Simulation<DVec2>> = None;
    let order: Vec<usize> = (0..configs.len()).chain((0..configs.len()).rev()).collect();
    for k in order {
        let fresh = ran(&mut Simulation::new(configs[k].clone(), start(k)).unwrap());
        let again = match kept.as_mut() {
            Some(sim) => {
                sim.restart(configs[k].clone(), start(k)).unwrap();
                ran(sim)
            }
            None => {
                kept = Some(Simulation::new(configs[k].clone(), start(k)).unwrap());
                ran(kept.as_mut().unwrap())
            }
        };
        same(&fresh, &again);
    }
}

#[test]
fn a_restarted_space_run_is_the_fresh_run() {
    let mut kept = Simulation::new(
        common::config(AlgorithmKind::ConvergeQuadrant, SchedulerSpec::Fsync, 0),
        generate::<DVec3>(&InitShape::Square { side: 5.0 }, 10, 0),
    )
    .unwrap();
    kept.run();
    for seed in 0..6 {
        for scheduler in [SchedulerSpec::Fsync, schedulers().pop().unwrap()] {
            let cfg = common::config(AlgorithmKind::ConvergeQuadrant, scheduler, seed);
            let start =
                generate::<DVec3>(&InitShape::Square { side: 5.0 }, 8 + seed as usize, seed);
            let fresh = ran(&mut Simulation::new(cfg.clone(), start.clone()).unwrap());
            kept.restart(cfg, start).unwrap();
            same(&fresh, &ran(&mut kept));
        }
    }
}

#[test]
fn a_restart_refuses_a_bad_start_as_new_does() {
    let cfg = common::config(AlgorithmKind::ConvergeLocality, SchedulerSpec::Fsync, 0);
    let mut sim = Simulation::new(cfg.clone(), common::square(5, 3.0, 0)).unwrap();
    let bad = vec![DVec2::new(f64::NAN, 0.0), DVec2::ZERO];
    let expected = Simulation::new(cfg.clone(), bad.clone()).err().unwrap();
    assert_eq!(sim.restart(cfg.clone(), bad).unwrap_err(), expected);
    // And runs as new after that.
    sim.restart(cfg.clone(), common::square(5, 3.0, 1)).unwrap();
    let fresh = ran(&mut Simulation::new(cfg, common::square(5, 3.0, 1)).unwrap());
    same(&fresh, &ran(&mut sim));
}

/// A sweep's runs one after the other: as many robots each time, so that the robots of
/// the run before are set again in place (a run of another size between them, so that
/// they are also despawned and spawned), for every scheduler, with and without kept
/// states, faults included.
#[test]
fn runs_of_as_many_robots_one_after_the_other_are_the_fresh_runs() {
    for cfg in configs() {
        let mut kept: Option<Simulation<DVec2>> = None;
        for (seed, n) in [(1, 11), (2, 11), (3, 11), (4, 7), (5, 11), (6, 11)] {
            let mut cfg = cfg.clone();
            cfg.seed = seed;
            let start = common::square(n, 5.0, seed);
            let fresh = ran(&mut Simulation::new(cfg.clone(), start.clone()).unwrap());
            let sim = match kept.as_mut() {
                Some(sim) => {
                    sim.restart(cfg, start).unwrap();
                    sim
                }
                None => kept.insert(Simulation::new(cfg, start).unwrap()),
            };
            same(&fresh, &ran(sim));
        }
    }
}
