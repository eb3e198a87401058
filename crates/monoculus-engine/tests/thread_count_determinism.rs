//! The same config and seed give bitwise-identical results for any rayon pool size.

mod common;

use monoculus_core::prelude::*;
use monoculus_engine::prelude::*;

fn run_in_pool(
    threads: usize,
    kind: AlgorithmKind,
    scheduler: SchedulerSpec,
) -> (RunOutcome, Vec<glam::DVec2>) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let cfg = common::config(kind, scheduler.clone(), 42);
        let mut sim = Simulation::new(cfg.clone(), common::square(300, 30.0, 42)).unwrap();
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
