//! The same config and seed give bitwise-identical results for any rayon pool size.

mod common;

use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;

fn run_in_pool(
    threads: usize,
    kind: AlgorithmKind,
    scheduler: SchedulerSpec,
) -> (RunOutcome, Vec<glam::DVec2>) {
    run_sized(threads, kind, scheduler, 300, 20_000)
}

fn run_sized(
    threads: usize,
    kind: AlgorithmKind,
    scheduler: SchedulerSpec,
    n: usize,
    max_rounds: u64,
) -> (RunOutcome, Vec<glam::DVec2>) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut cfg = common::config(kind, scheduler.clone(), 42);
        cfg.stop.max_rounds = max_rounds;
        let side = (n as f64).sqrt() * 1.7;
        let mut sim = Simulation::new(cfg.clone(), common::square(n, side, 42)).unwrap();
        let out = sim.run();
        (out, sim.positions().to_vec())
    })
}

#[test]
fn results_do_not_depend_on_thread_count() {
    for kind in [
        AlgorithmKind::ConvergeLocality,
        AlgorithmKind::ConvergeQuadrant,
    ] {
        for scheduler in [
            SchedulerSpec::Fsync,
            SchedulerSpec::Ssync {
                p: 0.5,
                fairness: None,
            },
        ] {
            let (a, pa) = run_in_pool(1, kind, scheduler.clone());
            let (b, pb) = run_in_pool(2, kind, scheduler.clone());
            let (c, pc) = run_in_pool(5, kind, scheduler.clone());
            assert_eq!(a, b, "{} {scheduler:?}", kind.name());
            assert_eq!(a, c);
            assert_eq!(pa, pb);
            assert_eq!(pa, pc);
        }
    }
}

/// ConvergeLocality under ASYNC with `spec`, `n` robots for `epochs` epochs, on 1, 2
/// and 5 threads: the same outcome and every position.
fn async_is_the_same_on_any_thread_count(spec: AsyncSpec, n: usize, epochs: u64) {
    let kind = AlgorithmKind::ConvergeLocality;
    let scheduler = SchedulerSpec::Async(spec);
    let (a, pa) = run_sized(1, kind, scheduler.clone(), n, epochs);
    assert!(a.activations >= epochs * n as u64, "{a:?}");
    for threads in [2, 5] {
        let (b, pb) = run_sized(threads, kind, scheduler.clone(), n, epochs);
        assert_eq!(a, b, "{threads} threads");
        assert_eq!(pa, pb, "{threads} threads");
    }
}

#[test]
fn async_results_do_not_depend_on_thread_count() {
    // 1,500 robots Looking together, then cycles of a few ticks: ticks of hundreds of
    // events, whose work (sorting the tick's robots, the structures told of moves that
    // start and end, the Looks) is shared between threads. Three epochs.
    let spec = AsyncSpec {
        idle: TickDist::Uniform { min: 1, max: 3 },
        compute: TickDist::Uniform { min: 1, max: 2 },
        motion: TickDist::Exponential { mean: 2.0 },
        start: AsyncStart::Together,
        durations: None,
    };
    async_is_the_same_on_any_thread_count(spec, 1500, 3);
}

#[test]
fn async_results_at_fine_durations_do_not_depend_on_thread_count() {
    // Durations of tens of ticks: a tick has a few Looks, shared between threads from
    // two on, each against a moving index kept for stretches of ticks. Two epochs.
    let spec = AsyncSpec {
        idle: TickDist::Uniform { min: 1, max: 100 },
        compute: TickDist::Uniform { min: 1, max: 50 },
        motion: TickDist::Exponential { mean: 40.0 },
        start: AsyncStart::Random,
        durations: None,
    };
    async_is_the_same_on_any_thread_count(spec, 600, 2);
}

#[test]
fn async_looks_decided_ahead_do_not_depend_on_thread_count() {
    // Computes of at least 100 ticks: the Looks of the ticks to come are decided with
    // a tick's own, hundreds at once, shared between threads. Three epochs.
    let spec = AsyncSpec {
        idle: TickDist::Uniform {
            min: 100,
            max: 1000,
        },
        compute: TickDist::Uniform { min: 100, max: 500 },
        motion: TickDist::Exponential { mean: 400.0 },
        start: AsyncStart::Random,
        durations: None,
    };
    async_is_the_same_on_any_thread_count(spec, 2000, 3);
}
