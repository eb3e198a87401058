//! The adversarial scheduler (SPEC 9.5): its choice against a brute-force oracle, its
//! k-fairness, and Lemma 2 under it.

mod common;

use glam::DVec2;
use monoculus_core::geometry::HullGeometry;
use monoculus_core::prelude::*;
use monoculus_engine::Objective;
use monoculus_engine::prelude::*;
use monoculus_engine::systems::preferred;

fn adversary(objective: Objective, fairness: Option<u32>) -> SchedulerSpec {
    SchedulerSpec::Adversary {
        objective,
        fairness,
    }
}

/// The choice straight from SPEC 9.5: every mover's move alone, its hull recomputed.
fn oracle(objective: Objective, points: &[DVec2], moves: &[Option<DVec2>]) -> Vec<usize> {
    let movers: Vec<usize> = (0..points.len()).filter(|&i| moves[i].is_some()).collect();
    if movers.is_empty() {
        return vec![];
    }
    let (area, perimeter) = (
        DVec2::hull_measure(points),
        DVec2::hull_perimeter(points).unwrap(),
    );
    let alone = |i: usize| {
        let mut p = points.to_vec();
        p[i] += moves[i].unwrap();
        (DVec2::hull_measure(&p), DVec2::hull_perimeter(&p).unwrap())
    };
    if objective == Objective::Grow {
        let grow: Vec<usize> = movers
            .iter()
            .copied()
            .filter(|&i| alone(i).0 > area * (1.0 + 1e-9) + 1e-12)
            .collect();
        if !grow.is_empty() {
            return grow;
        }
    }
    let mut best = movers[0];
    for &i in &movers[1..] {
        if perimeter - alone(i).1 < perimeter - alone(best).1 {
            best = i;
        }
    }
    vec![best]
}

#[test]
fn the_choice_is_the_definitions() {
    for seed in 0..6 {
        for (name, points) in common::zoo(seed) {
            let mut s = Stream::new(seed, 7, 0, 0);
            // Moves of length 1 in random directions for about half the robots, some
            // leaving the hull, some staying inside.
            let moves: Vec<Option<DVec2>> = (0..points.len())
                .map(|_| {
                    s.coin().then(|| {
                        let a = s.uniform() * std::f64::consts::TAU;
                        DVec2::new(a.cos(), a.sin()) * s.uniform_in(0.1, 1.0)
                    })
                })
                .collect();
            for objective in [Objective::Slow, Objective::Grow] {
                assert_eq!(
                    preferred(objective, &points, &moves),
                    oracle(objective, &points, &moves),
                    "{name} seed {seed} {objective:?}"
                );
            }
        }
    }
}

/// The robots activated in each round of a run, and its outcome.
fn activations(cfg: SimConfig, start: Vec<DVec2>) -> (Vec<Vec<usize>>, RunOutcome) {
    let mut sim = Simulation::new(cfg, start).unwrap();
    let mut rounds = Vec::new();
    let out = sim.run_observed(|s| {
        if s.time() > 0 {
            let views = s.robot_views();
            rounds.push((0..views.len()).filter(|&i| views[i].looked).collect());
        }
    });
    (rounds, out)
}

#[test]
fn every_robot_is_activated_once_every_k_rounds_and_the_hull_never_grows() {
    for objective in [Objective::Slow, Objective::Grow] {
        for (k, seed) in [(3u32, 1u64), (8, 2), (25, 3)] {
            let n = 25;
            let cfg = common::config(
                AlgorithmKind::ConvergeLocality,
                adversary(objective, Some(k)),
                seed,
            );
            let (rounds, out) = activations(cfg, common::square(n, 10.0, seed));
            assert!(out.converged, "{objective:?} k = {k}: {out:?}");
            // Lemma 2 holds under any schedule: ConvergeLocality never grows the hull.
            assert_eq!(out.hull_growth_rounds, 0);
            assert_eq!(out.committed_hull_growth, 0);
            let mut last = vec![0usize; n];
            for (r, active) in rounds.iter().enumerate() {
                for &i in active {
                    last[i] = r + 1;
                }
                for (i, &l) in last.iter().enumerate() {
                    assert!(r + 1 - l < k as usize, "robot {i} waited {k} rounds at {r}");
                }
            }
        }
    }
}

#[test]
fn between_forced_rounds_it_activates_its_choice_alone() {
    // k = 200: only every 200th round is forced (everybody); in the others the slow
    // adversary activates one robot that would move, and ConvergeLocality's robots inside
    // the hull move without changing the perimeter: the adversary keeps picking them.
    let start = common::square(20, 10.0, 4);
    let cfg = common::config(
        AlgorithmKind::ConvergeLocality,
        adversary(Objective::Slow, Some(200)),
        4,
    );
    let (rounds, out) = activations(cfg, start);
    assert!(out.converged);
    assert!(out.rounds > 200, "{out:?}");
    for (r, active) in rounds.iter().enumerate() {
        if (r + 1) % 200 == 0 {
            assert_eq!(active.len(), 20, "round {}", r + 1);
        } else {
            assert_eq!(active.len(), 1, "round {}", r + 1);
        }
    }
    // Each chosen robot would move: at least one move in every round that is not forced.
    let forced = out.rounds / 200;
    assert!(out.moves >= out.rounds - forced, "{out:?}");
}

#[test]
fn the_adversary_is_slower_than_fsync_on_average() {
    let (mut fsync, mut slow) = (0u64, 0u64);
    for seed in 0..5 {
        let start = common::square(20, 10.0, seed);
        let run = |s: SchedulerSpec| {
            Simulation::new(
                common::config(AlgorithmKind::ConvergeLocality, s, seed),
                start.clone(),
            )
            .unwrap()
            .run()
        };
        fsync += run(SchedulerSpec::Fsync).rounds;
        slow += run(adversary(Objective::Slow, None)).rounds;
    }
    assert!(slow > fsync, "adversary {slow} rounds, FSYNC {fsync}");
}

#[test]
fn the_adversary_does_not_depend_on_the_thread_count() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let cfg = common::config(
                AlgorithmKind::ConvergeQuadrant,
                adversary(Objective::Grow, Some(6)),
                8,
            );
            let mut sim = Simulation::new(cfg, common::square(200, 20.0, 8)).unwrap();
            (sim.run(), sim.positions().to_vec())
        })
    };
    assert_eq!(run(1), run(2));
    assert_eq!(run(1), run(3));
}

#[test]
fn the_adversary_is_for_the_plane() {
    let cfg = common::config(
        AlgorithmKind::ConvergeLocality,
        adversary(Objective::Slow, None),
        1,
    );
    let start: Vec<glam::DVec3> = monoculus_core::init::generate(
        &monoculus_core::init::InitShape::Square { side: 5.0 },
        10,
        1,
    );
    assert!(Simulation::new(cfg, start).is_err());
}
