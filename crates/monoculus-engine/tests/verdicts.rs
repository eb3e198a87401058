//! Verdicts (SPEC section 11): a run has converged when its stop criterion ended it and
//! its goal holds at the end; a run that fell quiescent short of its goal is stuck; what
//! ended a run is named, whatever it was.

use std::sync::Arc;

use glam::DVec2;
use monoculus_core::algorithms::{
    Algorithm, ConvergeLocality, Decision, Ld, NoParams, Observation,
};
use monoculus_core::geometry::Point;
use monoculus_core::init::{InitShape, generate};
use monoculus_core::rng::Stream;
use monoculus_engine::prelude::*;
use monoculus_engine::{ActivationList, StoppedBy};

/// An LD rule whose robots stop for good after three moves, with a light: `fresh`
/// until then, `tired` after (the new user's algorithm).
struct Tired;

#[derive(Clone, Debug, Default, PartialEq)]
struct Moves(u8);

impl Algorithm for Tired {
    const NAME: &'static str = "tired";
    type Sensing = Ld;
    type Params = NoParams;
    type State = Moves;
    const LIGHTS: &'static [&'static str] = &["fresh", "tired"];

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(Tired)
    }

    fn light(m: &Moves) -> usize {
        usize::from(m.0 >= 3)
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Ld, V>,
        m: &mut Moves,
        rng: &mut Stream,
    ) -> Decision<V> {
        if m.0 >= 3 {
            return Decision::Stay;
        }
        match obs.sole_visible().or_else(|| obs.random_far(rng)) {
            Some(toward) => {
                m.0 += 1;
                Decision::Step(toward)
            }
            None => Decision::Stay,
        }
    }
}

fn square(n: usize, side: f64, seed: u64) -> Vec<DVec2> {
    generate(&InitShape::Square { side }, n, seed)
}

/// Two clusters of `per` robots, `apart` from each other, each within a disc of radius
/// `spread`.
fn two_clusters(per: usize, apart: f64, spread: f64, seed: u64) -> Vec<DVec2> {
    let mut rng = Stream::new(seed, 9, 0, 0);
    (0..2 * per)
        .map(|i| {
            let centre = DVec2::new(if i < per { 0.0 } else { apart }, 0.0);
            let (r, a) = (
                spread * rng.uniform().sqrt(),
                rng.uniform() * std::f64::consts::TAU,
            );
            centre + DVec2::new(r * a.cos(), r * a.sin())
        })
        .collect()
}

#[test]
fn a_user_rule_that_stops_far_apart_is_stuck_under_every_scheduler() {
    for scheduler in [
        SchedulerSpec::Fsync,
        SchedulerSpec::Ssync {
            p: 0.5,
            fairness: None,
        },
        SchedulerSpec::Async(AsyncSpec::default()),
    ] {
        for seed in 0..5 {
            let config = SimConfig {
                scheduler: scheduler.clone(),
                ..SimConfig::paper(AlgorithmBox::new(Tired), seed, 10_000)
            };
            let o = Simulation::new(config, square(20, 20.0, seed))
                .unwrap()
                .run();
            assert_eq!(o.stopped_by, StoppedBy::Quiescent, "{scheduler:?} {seed}");
            assert!(o.final_diameter > 2.0, "{scheduler:?} {seed}: {o:?}");
            assert_eq!(o.goal, Goal::Diameter);
            assert!(
                !o.goal_met && !o.converged && o.stuck(),
                "{scheduler:?} {seed}"
            );
        }
    }
}

#[test]
fn converge_locality_with_limited_vision_from_two_far_clusters_is_stuck() {
    for seed in 0..5 {
        let mut config = SimConfig::paper(AlgorithmBox::new(ConvergeLocality), seed, 10_000);
        config.vision.range = 4.0;
        let o = Simulation::new(config, two_clusters(10, 40.0, 2.0, seed))
            .unwrap()
            .run();
        assert_eq!(o.stopped_by, StoppedBy::Quiescent);
        assert!(o.stuck() && !o.converged, "{o:?}");
        assert!(o.final_radius > 2.0 && o.final_diameter > 30.0);
    }
}

/// A 3 x 3 lattice of spacing 0.8 is quiescent for ConvergeLocality (every visible
/// robot near) at diameter 2.26 > c: inside a disc of radius 1.13, its goal.
#[test]
fn the_quiescent_lattice_meets_converge_locality_s_goal_not_the_diameter() {
    let lattice: Vec<DVec2> = (0..9)
        .map(|k| DVec2::new((k % 3) as f64 * 0.8, (k / 3) as f64 * 0.8))
        .collect();
    let config = SimConfig::paper(AlgorithmBox::new(ConvergeLocality), 0, 100);
    // Asked before the run, under FSYNC too: quiescent, and the goal holds.
    let mut sim = Simulation::new(config.clone(), lattice.clone()).unwrap();
    assert_eq!(sim.criterion_met_now(), Some(StoppedBy::Quiescent));
    assert!(sim.goal_holds_now());
    let o = sim.run();
    assert_eq!((o.stopped_by, o.rounds), (StoppedBy::Quiescent, 0));
    assert!(o.final_diameter > 2.0);
    assert!((o.final_radius - 0.8 * 2f64.sqrt()).abs() < 1e-12);
    assert!(o.converged && !o.stuck());
    // Judged by the diameter (`stop.goal = "diameter"`), the same run is stuck.
    let mut by_diameter = config;
    by_diameter.stop.goal = Goal::Diameter;
    let o = Simulation::new(by_diameter, lattice).unwrap().run();
    assert!(o.stuck() && !o.converged);
}

#[test]
fn the_cap_a_schedule_s_end_and_an_interruption_never_converge() {
    // Two robots 3 apart: one FSYNC round ends them 1 apart (diameter <= c).
    let pair = vec![DVec2::ZERO, DVec2::new(3.0, 0.0)];
    let run = |config: SimConfig| Simulation::new(config, pair.clone()).unwrap().run();
    let o = run(SimConfig::paper(
        AlgorithmBox::new(ConvergeLocality),
        0,
        100,
    ));
    assert_eq!(
        (o.stopped_by, o.rounds, o.converged),
        (StoppedBy::Diameter, 1, true)
    );
    // Capped at 0 rounds: the goal (a disc of radius 1.5 <= c) holds, but the cap ended
    // the run.
    let o = run(SimConfig::paper(AlgorithmBox::new(ConvergeLocality), 0, 0));
    assert_eq!(o.stopped_by, StoppedBy::MaxRounds);
    assert!(o.goal_met && !o.converged && !o.stuck());
    // A schedule that activates robot 0 once: 2 apart after it, then the file ends.
    let list = ActivationList::new(vec![(1, vec![0])]).unwrap();
    let o = run(SimConfig {
        scheduler: SchedulerSpec::File(Arc::new(list)),
        ..SimConfig::paper(AlgorithmBox::new(ConvergeLocality), 0, 100)
    });
    assert_eq!(o.stopped_by, StoppedBy::Diameter, "2 apart is within c");
    let list = ActivationList::new(vec![(1, vec![0]), (2, vec![])]).unwrap();
    let far = vec![DVec2::ZERO, DVec2::new(5.0, 0.0)];
    let o = Simulation::new(
        SimConfig {
            scheduler: SchedulerSpec::File(Arc::new(list)),
            ..SimConfig::paper(AlgorithmBox::new(ConvergeLocality), 0, 100)
        },
        far,
    )
    .unwrap()
    .run();
    assert_eq!((o.stopped_by, o.converged), (StoppedBy::ScheduleEnd, false));
    // An interrupted run.
    let mut sim = Simulation::new(
        SimConfig::paper(AlgorithmBox::new(ConvergeLocality), 0, 100),
        pair.clone(),
    )
    .unwrap();
    sim.set_interrupt(Arc::new(std::sync::atomic::AtomicBool::new(true)));
    let o = sim.run();
    assert!(o.interrupted() && !o.converged);
    assert_eq!(o.stopped_by, StoppedBy::Interrupted);
}

/// The goal and the final radius are the correct robots' (SPEC 9.1): crashed robots
/// count in no measure.
#[test]
fn the_goal_is_judged_over_the_correct_robots() {
    use monoculus_engine::resources::Params;
    use monoculus_engine::{CrashAt, FaultCount, FaultKind, FaultSpec};
    for seed in 0..4 {
        let mut config = SimConfig::paper(AlgorithmBox::new(ConvergeLocality), seed, 10_000);
        config.faults = Some(FaultSpec {
            count: FaultCount::Robots(3),
            kind: FaultKind::Crash(CrashAt::Round(0)),
        });
        let mut sim = Simulation::new(config, square(12, 10.0, seed)).unwrap();
        let o = sim.run();
        let params = sim.world().resource::<Params>();
        let correct = params.correct(sim.positions()).into_owned();
        assert_eq!(correct.len(), 9);
        let radius = monoculus_core::geometry::enclosing_radius(&correct);
        assert_eq!(o.final_radius, radius);
        assert_eq!(o.goal_met, radius <= 2.0);
        let all = monoculus_core::geometry::enclosing_radius(sim.positions());
        assert!(all >= radius);
    }
}

/// The stop and goal a binding declares at run time are the ones its box carries.
#[test]
fn bindings_declare_their_stop_and_goal_at_run_time() {
    struct Declared;
    impl Algorithm for Declared {
        const NAME: &'static str = "declared";
        type Sensing = Ld;
        type Params = NoParams;
        type State = ();
        fn new(_: NoParams) -> Result<Self, String> {
            Ok(Declared)
        }
        fn decide<V: Point>(
            &self,
            _: &Observation<'_, Ld, V>,
            _: &mut (),
            _: &mut Stream,
        ) -> Decision<V> {
            Decision::Stay
        }
        fn stop(&self) -> StopCriterion {
            StopCriterion::Box
        }
        fn goal(&self) -> Goal {
            Goal::Box
        }
    }
    let b = AlgorithmBox::new(Declared);
    assert_eq!(
        (b.default_stop(), b.goal()),
        (StopCriterion::Box, Goal::Box)
    );
    let config = SimConfig::paper(b, 0, 5);
    assert_eq!(
        (config.stop.criterion, config.stop.goal),
        (StopCriterion::Box, Goal::Box)
    );
}
