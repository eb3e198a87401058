//! The recorder against plain runs: frames, metrics and Looks.
use super::*;
use crate::Experiment;
use monoculus_core::geometry::Point;
use monoculus_core::vision::{ExactSight, Sight};
use std::path::Path;

fn cell(text: &str) -> Cell {
    let exp = Experiment::parse(
        text,
        "test.toml",
        Path::new("."),
        &[],
        &crate::Registry::builtin(),
    )
    .unwrap();
    assert_eq!(exp.cells.len(), 1);
    exp.cells[0].clone()
}

fn config(algorithm: &str, scheduler: &str, n: usize, dim: usize) -> String {
    format!(
        "name = \"t\"\nseeds = 1\n[swarm]\nn = {n}\ndim = {dim}\ninit = \"square\"\nside = 8.0\n\
         [algorithm]\nname = \"{algorithm}\"\nstep = 1.0\nlocality = 2.0\n\
         [scheduler]\n{scheduler}\n[stop]\nmax_rounds = 200\n"
    )
}

const ASYNC: &str = "kind = \"async\"\nidle = { kind = \"uniform\", min = 1, max = 30 }\n\
    compute = { kind = \"uniform\", min = 1, max = 20 }\nmove = { kind = \"uniform\", min = 5, max = 30 }";

fn point<P: Point>(c: &[f32]) -> Vec<f32> {
    c[..P::DIM].to_vec()
}

/// The frames, metrics and Looks of a round scheduler against a plain run: frame k is
/// the configuration after round k, its Looks see what an exact sight over it shows,
/// and each decision is where the robot is in frame k + 1.
fn rounds_match_a_plain_run<P: IndexPoint>(text: &str) {
    let cell = cell(text);
    let replay = record(&cell, 3, "t".into(), Limits::default()).unwrap();
    let mut sim = Simulation::<P>::new(cell.sim_config(3), cell.initial_positions(3)).unwrap();
    let mut plain: Vec<(Vec<P>, f64, f64, u64)> = Vec::new();
    let outcome = sim.run_with(|r| {
        plain.push((r.positions.to_vec(), r.hull, r.diameter, r.moving));
    });
    assert!(outcome.rounds >= 2, "the test needs a few rounds");
    assert_eq!(replay.stride, 1);
    assert_eq!(replay.frames.len(), plain.len());
    assert_eq!(replay.metrics.time.len(), plain.len());
    for (k, (pos, hull, diameter, _)) in plain.iter().enumerate() {
        let f = &replay.frames[k];
        assert_eq!(f.step, k);
        let mut expect = Vec::new();
        for p in pos {
            coords(p, &mut expect);
        }
        assert_eq!(f.positions, expect, "frame {k}");
        assert_eq!(replay.metrics.time[k], k as u64);
        assert_eq!(
            replay.metrics.hull[k].to_bits(),
            hull.to_bits(),
            "round {k}"
        );
        assert_eq!(replay.metrics.diameter[k].to_bits(), diameter.to_bits());
        // The moving count of frame k is the next round's.
        let next = plain.get(k + 1).map_or(0, |p| p.3);
        assert_eq!(replay.metrics.moving[k], next, "round {k}");
        let moving = f
            .states
            .iter()
            .filter(|&&s| s == State::Moving as u8)
            .count();
        assert_eq!(moving as u64, next);
    }
    assert!(!replay.looks.is_empty());
    for look in &replay.looks {
        let (pos, ..) = &plain[look.frame];
        let i = look.robot as usize;
        let exact = ExactSight::new(pos.clone(), cell.sim_config(3).vision);
        let mut oracle = exact.visible_points(i);
        oracle.sort_unstable();
        let mut seen: Vec<usize> = look.seen.iter().map(|&j| j as usize).collect();
        seen.sort_unstable();
        assert_eq!(seen, oracle, "robot {i} at frame {}", look.frame);
        let (after, ..) = &plain[look.frame + 1];
        let mut there = Vec::new();
        coords(&after[i], &mut there);
        match &look.destination {
            Some(d) => assert_eq!(point::<P>(d), there, "robot {i} goes where it decided"),
            None => assert_eq!(after[i], pos[i], "robot {i} stays"),
        }
    }
    assert!(replay.outcome.starts_with(if outcome.converged {
        "converged"
    } else {
        "not converged"
    }));
}

#[test]
fn fsync_frames_metrics_and_looks_match_a_plain_run() {
    rounds_match_a_plain_run::<DVec2>(&config("converge_locality", "kind = \"fsync\"", 40, 2));
    rounds_match_a_plain_run::<DVec2>(&config("converge_quadrant", "kind = \"fsync\"", 30, 2));
    rounds_match_a_plain_run::<DVec3>(&config("converge_locality", "kind = \"fsync\"", 30, 3));
}

#[test]
fn ssync_looks_are_those_of_the_activated_robots() {
    let text = config(
        "converge_quadrant_termination",
        "kind = \"ssync\"\np = 0.5",
        20,
        2,
    );
    rounds_match_a_plain_run::<DVec2>(&text);
    let replay = record(&cell(&text), 3, "t".into(), Limits::default()).unwrap();
    // Not every robot looks every round, and the bits are recorded and only grow.
    assert!(replay.looks.len() < 20 * (replay.frames.len() - 1));
    assert!(replay.termination);
    for pair in replay.frames.windows(2) {
        for (a, b) in pair[0].bits.iter().zip(&pair[1].bits) {
            assert_eq!(a & b, *a, "memory bits are never cleared");
        }
    }
    assert!(replay.frames.iter().any(|f| f.bits.iter().any(|&b| b != 0)));
}

#[test]
fn async_frames_are_ticks_with_movers_on_their_segments() {
    let cell = cell(&config("converge_locality", ASYNC, 25, 2));
    let replay = record(&cell, 1, "t".into(), Limits::default()).unwrap();
    // Observing does not change the run.
    let mut sim = Simulation::<DVec2>::new(cell.sim_config(1), cell.initial_positions(1)).unwrap();
    let outcome = sim.run();
    assert_eq!(replay.outcome, outcome_line(&outcome, true));
    assert!(replay.ticks);
    assert_eq!(*replay.metrics.time.last().unwrap(), outcome.ticks.unwrap());
    // The start, then every event tick (the first may be tick 0 too).
    assert!(replay.metrics.time[1..].windows(2).all(|t| t[0] < t[1]));
    assert_eq!(replay.metrics.epoch.len(), replay.metrics.time.len());
    // Some frame shows a robot strictly between two of its positions at rest, and
    // every decided move ends at its destination.
    let mut mid_move = false;
    for look in &replay.looks {
        let i = look.robot as usize;
        let at = |f: &Frame| point::<DVec2>(&f.positions[2 * i..2 * i + 2]);
        let later = &replay.frames[look.frame + 1..];
        // The robot computes, then moves, then is idle again (or the run ends).
        let end = later
            .iter()
            .position(|f| f.states[i] == State::Idle as u8)
            .map(|k| &later[k]);
        if let (Some(d), Some(end)) = (&look.destination, end) {
            assert_eq!(at(end), *d, "robot {i} ends its move at its destination");
            let from = at(&replay.frames[look.frame]);
            mid_move |= later
                .iter()
                .take_while(|f| f.states[i] != State::Idle as u8)
                .any(|f| at(f) != from && at(f) != *d);
        }
    }
    assert!(mid_move, "some frame shows a robot in mid-move");
    // Looks see the configuration of their tick: what an exact sight over every
    // robot's position at that tick (movers on their segments) shows.
    let mut sim = Simulation::<DVec2>::new(cell.sim_config(1), cell.initial_positions(1)).unwrap();
    let mut at_step: Vec<Vec<DVec2>> = Vec::new();
    sim.run_observed(|sim| at_step.push(sim.positions_now()));
    assert_eq!(at_step.len(), replay.metrics.time.len());
    assert!(replay.looks.len() > 50);
    for look in &replay.looks {
        let now = &at_step[replay.frames[look.frame].step];
        let exact = ExactSight::new(now.clone(), cell.sim_config(1).vision);
        let mut oracle = exact.visible_points(look.robot as usize);
        oracle.sort_unstable();
        let mut seen: Vec<usize> = look.seen.iter().map(|&j| j as usize).collect();
        seen.sort_unstable();
        assert_eq!(seen, oracle);
    }
}

#[test]
fn large_runs_are_thinned_and_sampled_but_metrics_stay_whole() {
    let text =
        config("converge_locality", "kind = \"fsync\"", 60, 2).replace("side = 8.0", "side = 30.0");
    let cell = cell(&text);
    let whole = record(&cell, 2, "t".into(), Limits::default()).unwrap();
    let limits = Limits {
        max_drawn: 25,
        max_bytes: 2_000,
        ..Limits::default()
    };
    let thin = record(&cell, 2, "t".into(), limits).unwrap();
    assert_eq!(
        thin.metrics, whole.metrics,
        "metrics are exact for every round"
    );
    assert_eq!(thin.sample, 3);
    assert_eq!(thin.start.len(), 2 * 20);
    assert!(thin.stride > 1, "{} frames", whole.frames.len());
    let last = whole.metrics.time.len() - 1;
    for f in &thin.frames {
        assert!(f.step.is_multiple_of(thin.stride) || f.step == last);
        assert_eq!(f.positions.len(), 2 * 20);
        let w = &whole.frames[f.step];
        let sampled: Vec<f32> = w
            .positions
            .chunks(2)
            .step_by(3)
            .flatten()
            .copied()
            .collect();
        assert_eq!(f.positions, sampled);
        assert_eq!(f.hull, w.hull, "the hull is over all robots");
    }
    assert_eq!(thin.frames.last().unwrap().step, last);
    assert!(thin.looks.is_empty() && thin.looks_note.is_some());
    assert!(
        thin.notes
            .iter()
            .any(|n| n.contains("20 of 60 robots drawn (every 3rd)"))
    );
    assert_eq!(
        [1, 2, 3, 4, 11, 12, 13, 21, 22, 102].map(ordinal),
        [
            "1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "22nd", "102nd"
        ]
    );
    // Thinning alone keeps the Looks of the kept frames.
    let kept = record(
        &cell,
        2,
        "t".into(),
        Limits {
            max_bytes: 40_000,
            ..Limits::default()
        },
    )
    .unwrap();
    assert!(kept.stride > 1 && !kept.looks.is_empty());
    for look in &kept.looks {
        let step = kept.frames[look.frame].step;
        let same = whole
            .looks
            .iter()
            .find(|l| l.robot == look.robot && whole.frames[l.frame].step == step)
            .expect("the same Look in the whole replay");
        assert_eq!(same.seen, look.seen);
        assert_eq!(same.destination, look.destination);
    }
}

#[test]
fn long_async_runs_keep_the_metrics_of_every_epoch_and_frame() {
    let cell = cell(&config("converge_locality", ASYNC, 25, 2));
    let whole = record(&cell, 1, "t".into(), Limits::default()).unwrap();
    assert_eq!(whole.metrics.stride, 1);
    assert_eq!(
        whole.metrics.step,
        (0..whole.metrics.time.len()).collect::<Vec<_>>()
    );
    let limits = Limits {
        max_metric_rows: 40,
        max_bytes: 20_000,
        ..Limits::default()
    };
    let thin = record(&cell, 1, "t".into(), limits).unwrap();
    let m = &thin.metrics;
    assert!(m.stride > 1 && thin.stride > 1);
    assert!(m.step.len() < whole.metrics.step.len());
    // Every kept row is the whole run's row of its step.
    for (r, &step) in m.step.iter().enumerate() {
        let w = &whole.metrics;
        assert_eq!(
            (
                m.time[r],
                m.epoch[r],
                m.hull[r].to_bits(),
                m.diameter[r].to_bits(),
                m.moving[r]
            ),
            (
                w.time[step],
                w.epoch[step],
                w.hull[step].to_bits(),
                w.diameter[step].to_bits(),
                w.moving[step]
            ),
            "row {r} (step {step})"
        );
    }
    // Each epoch's end keeps its row, and each frame its own.
    for s in 1..whole.metrics.epoch.len() {
        if whole.metrics.epoch[s] != whole.metrics.epoch[s - 1] {
            assert!(
                m.step.contains(&s),
                "the end of epoch {}",
                whole.metrics.epoch[s]
            );
        }
    }
    for f in &thin.frames {
        assert_eq!(m.step[f.row], f.step);
    }
    assert_eq!(m.step.last(), whole.metrics.step.last());
    assert!(
        thin.notes
            .iter()
            .any(|n| n.contains("metrics kept for every tick that ends an epoch"))
    );
}
