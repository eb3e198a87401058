//! Algorithms that decide a round's activations together (one call per round or tick,
//! as a binding's vectorized algorithm does) give the runs of the same rules decided
//! one by one, under every scheduler, with and without a state.

mod common;

use glam::DVec2;
use monoculus_core::algorithms::{
    Algorithm, ConvergeLocality, ConvergeQuadrantTermination, Decision, Observation,
};
use monoculus_core::geometry::Point;
use monoculus_core::rng::Stream;
use monoculus_engine::prelude::*;

/// `A`, its activations decided together.
struct Together<A>(A);

impl<A: Algorithm> Algorithm for Together<A> {
    const NAME: &'static str = A::NAME;
    type Sensing = A::Sensing;
    type Params = A::Params;
    type State = A::State;
    const STOP: StopCriterion = A::STOP;
    const GOAL: Goal = A::GOAL;
    const STAYS_WHEN_SURROUNDED: bool = A::STAYS_WHEN_SURROUNDED;

    fn new(p: A::Params) -> Result<Self, String> {
        A::new(p).map(Together)
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, A::Sensing, V>,
        state: &mut A::State,
        rng: &mut Stream,
    ) -> Decision<V> {
        self.0.decide(obs, state, rng)
    }

    fn decides_together(&self) -> bool {
        true
    }

    fn terminated(state: &A::State, dim: usize) -> Option<bool> {
        A::terminated(state, dim)
    }
}

fn schedulers() -> Vec<SchedulerSpec> {
    vec![
        SchedulerSpec::Fsync,
        SchedulerSpec::Ssync {
            p: 0.5,
            fairness: Some(3),
        },
        SchedulerSpec::Async(AsyncSpec {
            idle: TickDist::Uniform { min: 1, max: 4 },
            compute: TickDist::Uniform { min: 1, max: 3 },
            motion: TickDist::Exponential { mean: 2.0 },
            start: AsyncStart::Random,
            durations: None,
        }),
        SchedulerSpec::Adversary {
            objective: monoculus_engine::Objective::Grow,
            fairness: Some(4),
        },
    ]
}

fn same<A: Algorithm + Clone>(a: A) {
    for scheduler in schedulers() {
        for seed in 0..3 {
            let start: Vec<DVec2> = common::square(25, 8.0, seed);
            let run = |algorithm: AlgorithmBox| {
                let config = SimConfig {
                    scheduler: scheduler.clone(),
                    ..SimConfig::paper(algorithm, seed, 3000)
                };
                Simulation::new(config, start.clone()).unwrap().run()
            };
            let one_by_one = run(AlgorithmBox::new(a.clone()));
            let together = run(AlgorithmBox::new(Together(a.clone())));
            assert_eq!(
                together,
                one_by_one,
                "{} {scheduler:?} seed {seed}",
                A::NAME
            );
            assert!(one_by_one.moves > 0);
        }
    }
}

#[test]
fn deciding_together_changes_no_run() {
    same(ConvergeLocality);
    same(ConvergeQuadrantTermination);
}
