//! Lights under each scheduler: a robot sees the colour the others set in their last
//! activation, from the end of its Compute on (under ASYNC, not while it computes);
//! a run whose robots would only change their lights is not quiescent.

use glam::DVec2;
use monoculus_core::algorithms::{Algorithm, Decision, Directions, NoParams, Observation};
use monoculus_core::geometry::Point;
use monoculus_core::rng::Stream;
use monoculus_engine::prelude::*;

/// What a robot saw of the other's light at each of its first two Looks.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Looks {
    count: u8,
    saw_on: [bool; 2],
}

/// Turns its light on at its first Look and records whether it saw a robot showing on
/// at its first two Looks; never moves.
#[derive(Clone)]
struct Witness {
    together: bool,
}

impl Algorithm for Witness {
    const NAME: &'static str = "witness";
    type Sensing = Directions;
    type Params = NoParams;
    type State = Looks;
    const LIGHTS: &'static [&'static str] = &["off", "on"];
    const STOP: StopCriterion = StopCriterion::Diameter;

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(Witness { together: false })
    }

    fn light(looks: &Looks) -> usize {
        usize::from(looks.count > 0)
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Directions, V>,
        looks: &mut Looks,
        _: &mut Stream,
    ) -> Decision<V> {
        if let Some(seen) = looks.saw_on.get_mut(looks.count as usize) {
            *seen = obs.sees_light(1);
        }
        looks.count = looks.count.saturating_add(1);
        Decision::Stay
    }

    fn decides_together(&self) -> bool {
        self.together
    }

    fn shown_bits(looks: &Looks) -> Option<u8> {
        Some(looks.count.min(2) << 2 | looks.saw_on[0] as u8 | (looks.saw_on[1] as u8) << 1)
    }
}

/// Runs two robots of `Witness` until each has looked twice: what each saw at its two
/// Looks (bit 0: on at the first, bit 1: on at the second), and the times of its Looks
/// (rounds completed, or ASYNC ticks).
fn run_until_two_looks(
    scheduler: SchedulerSpec,
    seed: u64,
    together: bool,
) -> (Vec<u8>, [[u64; 2]; 2]) {
    let config = SimConfig {
        scheduler,
        ..SimConfig::paper(AlgorithmBox::new(Witness { together }), seed, 100)
    };
    let start = vec![DVec2::ZERO, DVec2::new(5.0, 0.0)];
    let mut sim = Simulation::new(config, start).unwrap();
    let mut times = [[u64::MAX; 2]; 2];
    for _ in 0..10_000 {
        sim.step();
        let bits: Vec<u8> = sim.robot_views().iter().map(|v| v.bits.unwrap()).collect();
        for (r, b) in bits.iter().enumerate() {
            for (k, at) in times[r].iter_mut().enumerate() {
                if (b >> 2) as usize > k && *at == u64::MAX {
                    *at = sim.time();
                }
            }
        }
        if bits.iter().all(|b| b >> 2 >= 2) {
            return (bits.iter().map(|b| b & 3).collect(), times);
        }
    }
    panic!("two Looks each within 10,000 steps");
}

/// What each robot should have seen: the other on at a Look iff the other's light was
/// shown by then, `shown_after` its first Look.
fn expected(times: [[u64; 2]; 2], shown_after: u64) -> Vec<u8> {
    (0..2)
        .map(|r| {
            let shown = times[1 - r][0] + shown_after;
            (0..2).map(|k| u8::from(shown <= times[r][k]) << k).sum()
        })
        .collect()
}

#[test]
fn under_async_a_light_shows_once_the_compute_ends() {
    // Compute phases of 1,000 ticks, first Looks within 10 ticks of each other, Move
    // phases of 20: a first Look in the other's Compute sees it off; every second Look
    // comes after both Computes and sees it on.
    let scheduler = SchedulerSpec::Async(AsyncSpec {
        idle: TickDist::Uniform { min: 1, max: 10 },
        compute: TickDist::Fixed { ticks: 1000 },
        motion: TickDist::Fixed { ticks: 20 },
        start: AsyncStart::Random,
        durations: None,
    });
    let mut apart = 0;
    for together in [false, true] {
        for seed in 0..20 {
            let (saw, times) = run_until_two_looks(scheduler.clone(), seed, together);
            apart += usize::from(times[0][0] != times[1][0]);
            assert_eq!(
                saw,
                expected(times, 1000),
                "seed {seed}, Looks at {times:?}"
            );
            assert_eq!(saw, vec![0b10, 0b10], "seed {seed}, Looks at {times:?}");
        }
    }
    assert!(
        apart >= 20,
        "the first Looks were apart in {apart} runs of 40"
    );
}

#[test]
fn under_round_schedulers_a_light_shows_from_the_next_round() {
    let mut later = 0;
    for scheduler in [
        SchedulerSpec::Fsync,
        SchedulerSpec::Ssync {
            p: 0.5,
            fairness: Some(2),
        },
    ] {
        for together in [false, true] {
            for seed in 0..10 {
                let (saw, times) = run_until_two_looks(scheduler.clone(), seed, together);
                // A Look in a later round than the other's first sees it on.
                assert_eq!(
                    saw,
                    expected(times, 1),
                    "{scheduler:?} seed {seed} {times:?}"
                );
                later += usize::from(saw.iter().any(|s| s & 1 != 0));
            }
        }
    }
    assert!(later > 0, "some first Look came after the other's");
}

/// Each robot turns its light on, then off, and stays: nobody ever moves.
#[derive(Clone)]
struct Blink;

impl Algorithm for Blink {
    const NAME: &'static str = "blink";
    type Sensing = Directions;
    type Params = NoParams;
    type State = u8;
    const LIGHTS: &'static [&'static str] = &["off", "on"];
    const STOP: StopCriterion = StopCriterion::Quiescent;

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(Blink)
    }

    fn light(state: &u8) -> usize {
        usize::from(*state == 1)
    }

    fn decide<V: Point>(
        &self,
        _: &Observation<'_, Directions, V>,
        state: &mut u8,
        _: &mut Stream,
    ) -> Decision<V> {
        *state = state.saturating_add(1);
        Decision::Stay
    }
}

#[test]
fn robots_that_only_change_their_lights_are_not_quiescent() {
    let asynchronous = SchedulerSpec::Async(AsyncSpec {
        idle: TickDist::Fixed { ticks: 3 },
        compute: TickDist::Fixed { ticks: 2 },
        motion: TickDist::Fixed { ticks: 1 },
        start: AsyncStart::Together,
        durations: None,
    });
    for scheduler in [SchedulerSpec::Fsync, asynchronous] {
        let config = SimConfig {
            scheduler: scheduler.clone(),
            ..SimConfig::paper(AlgorithmBox::new(Blink), 0, 100)
        };
        let start = vec![DVec2::ZERO, DVec2::new(5.0, 0.0), DVec2::new(0.0, 5.0)];
        let outcome = Simulation::new(config, start).unwrap().run();
        // Quiescent far apart: stuck, not converged.
        assert_eq!(outcome.stopped_by, StoppedBy::Quiescent, "{scheduler:?}");
        assert!(outcome.stuck() && !outcome.converged, "{scheduler:?}");
        // On, then off: quiescent once every robot's light is off again (the round or
        // epoch that would change nothing is not counted).
        assert_eq!(outcome.rounds, 2, "{scheduler:?}");
        assert_eq!(outcome.moves, 0);
    }
}
