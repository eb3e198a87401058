//! Recording a run as it goes: a frame every `stride`-th step, metrics at every step,
//! and, for runs of few robots, what each robot saw at its Looks.

use glam::{DVec2, DVec3};
use monoculus_core::observe::inspect;
use monoculus_engine::resources::Shape;
use monoculus_engine::{Activity, EngineError, IndexPoint, IndexedSight, RunOutcome, Simulation};

use super::{
    Drawn, Frame, Limits, Look, Replay, State, coords, frame_bytes, hull_of, look_bytes, ordinal,
};
use crate::Cell;

/// Records one run of `cell` with `seed`.
pub fn record(
    cell: &Cell,
    seed: u64,
    title: String,
    limits: Limits,
) -> Result<Replay, EngineError> {
    match cell.dim() {
        3 => record_in::<DVec3>(cell, seed, title, limits),
        _ => record_in::<DVec2>(cell, seed, title, limits),
    }
}

struct Recorder<P> {
    replay: Replay,
    drawn: Drawn,
    record_looks: bool,
    vision: monoculus_core::vision::VisionParams,
    /// Round schedulers: the previous step's full positions and whether it got a frame.
    previous: Option<(Vec<P>, Option<usize>)>,
    /// [`Limits::max_bytes`].
    budget: usize,
    /// [`Replay::bytes`], kept as frames and Looks are added.
    bytes: usize,
    /// Steps seen.
    steps: usize,
    /// Per metrics row: whether the step ended an epoch (round schedulers: always).
    pinned: Vec<bool>,
    /// Epochs completed at the last step.
    epochs: u64,
    /// [`Limits::max_metric_rows`].
    max_rows: usize,
    /// The rows at which the metrics are thinned next.
    row_cap: usize,
}

impl<P: IndexPoint> Recorder<P> {
    fn frame(&mut self, step: usize, now: &[P]) -> Option<usize> {
        step.is_multiple_of(self.replay.stride)
            .then(|| self.push_frame(step, now))
    }

    fn push_frame(&mut self, step: usize, now: &[P]) -> usize {
        let frame = Frame {
            step,
            row: self.replay.metrics.step.len() - 1,
            positions: self.drawn.coords(now),
            states: vec![State::Idle as u8; self.drawn.robots.len()],
            bits: Vec::new(),
            hull: hull_of(now),
        };
        self.bytes += frame_bytes(&frame);
        self.replay.frames.push(frame);
        self.replay.frames.len() - 1
    }

    /// Adds the row of `step`, first dropping the previous step's row if neither an
    /// epoch's end, a frame, nor the stride keeps it (ASYNC).
    fn metrics(&mut self, step: usize, sim: &Simulation<P>, now: &[P]) {
        let stride = self.replay.metrics.stride;
        let framed = |row: usize, frames: &[Frame]| frames.last().is_some_and(|f| f.row == row);
        if let Some(row) = self.replay.metrics.step.len().checked_sub(1)
            && !self.pinned[row]
            && !self.replay.metrics.step[row].is_multiple_of(stride)
            && !framed(row, &self.replay.frames)
        {
            self.replay.metrics.pop();
            self.pinned.pop();
        }
        let shape = Shape::of(now);
        let m = &mut self.replay.metrics;
        m.step.push(step);
        m.time.push(sim.time());
        let pinned = match sim.async_progress() {
            Some((_, epochs)) => {
                m.epoch.push(epochs);
                let ended = epochs != self.epochs;
                self.epochs = epochs;
                ended || step == 0
            }
            None => true,
        };
        self.pinned.push(pinned);
        m.hull.push(shape.hull);
        m.diameter.push(shape.diameter);
        m.moving.push(0);
    }

    /// ASYNC: doubles the metrics stride, keeping the pinned rows, the frames' rows and
    /// the last; the next thinning comes when half the budget is added again (the
    /// rows that must stay can outnumber it).
    fn thin_metrics(&mut self) {
        let m = &mut self.replay.metrics;
        m.stride = (m.stride * 2).min(1 << 32);
        let last = m.step.len() - 1;
        let mut framed = vec![false; m.step.len()];
        for f in &self.replay.frames {
            framed[f.row] = true;
        }
        let keep: Vec<bool> = (0..m.step.len())
            .map(|r| self.pinned[r] || framed[r] || r == last || m.step[r].is_multiple_of(m.stride))
            .collect();
        let mut renumber = vec![0; keep.len()];
        let mut kept = 0;
        for (r, &k) in keep.iter().enumerate() {
            renumber[r] = kept;
            kept += usize::from(k);
        }
        m.retain(&keep);
        let mut k = keep.iter();
        self.pinned.retain(|_| *k.next().unwrap());
        for f in &mut self.replay.frames {
            f.row = renumber[f.row];
        }
        self.row_cap = self.max_rows.max(kept + self.max_rows / 2);
    }

    /// The states, bits, moving count and Looks of the step at `frame` (positions
    /// `seen_at`) from the views after the step that decided them.
    fn decisions(
        &mut self,
        row: usize,
        frame: Option<usize>,
        seen_at: &[P],
        views: &[monoculus_engine::RobotView<P>],
    ) {
        self.replay.metrics.moving[row] = views
            .iter()
            .filter(|v| v.activity == Activity::Moving)
            .count() as u64;
        let Some(f) = frame else { return };
        let frame = &mut self.replay.frames[f];
        for (k, &i) in self.drawn.robots.iter().enumerate() {
            frame.states[k] = State::from(views[i].activity) as u8;
        }
        if self.replay.termination {
            frame.bits = self
                .drawn
                .robots
                .iter()
                .map(|&i| views[i].bits.unwrap_or(0))
                .collect();
        }
        if !self.record_looks || !views.iter().any(|v| v.looked) {
            return;
        }
        let sight = IndexedSight::new(seen_at.to_vec(), self.vision);
        let model = self.replay.model;
        let locality = self.replay.locality;
        for (i, v) in views.iter().enumerate().filter(|(_, v)| v.looked) {
            let seen = inspect(&sight, i, locality);
            let destination = v.decision.map(|d| {
                let mut c = Vec::with_capacity(P::DIM);
                coords(&(seen_at[i] + d), &mut c);
                c
            });
            let flags = seen
                .iter()
                .map(|s| match model {
                    "ld" => u8::from(s.far),
                    "ola" => s
                        .sides
                        .iter()
                        .rev()
                        .fold(0u8, |acc, &side| acc * 3 + (side + 1) as u8),
                    _ => 0,
                })
                .collect();
            let look = Look {
                frame: f,
                robot: i as u32,
                destination,
                seen: seen.iter().map(|s| s.index as u32).collect(),
                flags,
            };
            self.bytes += look_bytes(&look);
            self.replay.looks.push(look);
        }
    }

    fn after_step(&mut self, sim: &Simulation<P>) {
        let step = self.steps;
        self.steps += 1;
        let now = sim.positions_now();
        self.metrics(step, sim, &now);
        let frame = self.frame(step, &now);
        let views = sim.robot_views();
        let row = self.replay.metrics.step.len() - 1;
        if self.replay.ticks {
            self.decisions(row, frame, &now, &views);
            if row >= self.row_cap {
                self.thin_metrics();
            }
        } else {
            // Every round keeps its row: the previous round's is the one before.
            if let Some((before, before_frame)) = self.previous.take()
                && step > 0
            {
                self.decisions(row - 1, before_frame, &before, &views);
            }
            self.previous = Some((now, frame));
        }
        if self.bytes > self.budget {
            self.replay.thin();
            self.bytes = self.replay.bytes();
            if let Some((_, f)) = self.previous.as_mut() {
                *f = self.replay.frames.iter().position(|fr| fr.step == step);
            }
        }
    }

    /// Gives the last step a frame if the stride skipped it.
    fn finish(&mut self, sim: &Simulation<P>) {
        let last = self.steps - 1;
        if self.replay.frames.last().is_none_or(|f| f.step != last) {
            self.push_frame(last, &sim.positions_now());
        }
    }
}

fn scheduler_name(cell: &Cell) -> String {
    format!("{:?}", cell.spec.scheduler.kind).to_lowercase()
}

fn record_in<P: IndexPoint>(
    cell: &Cell,
    seed: u64,
    title: String,
    limits: Limits,
) -> Result<Replay, EngineError> {
    let config = cell.sim_config(seed);
    let initial: Vec<P> = cell.initial_positions(seed);
    let n = initial.len();
    let drawn = Drawn::of(n, &limits);
    let sample = drawn.sample;
    let kind = cell.algorithm();
    let record_looks = sample == 1 && n <= limits.max_look_robots;
    let mut notes = Vec::new();
    if config.model.errors.any() {
        notes.push(
            "Looks are shown as the robots' exact senses; the run's observation errors are not drawn"
                .to_string(),
        );
    }
    notes.extend(drawn.note(n));
    let ticks = matches!(config.scheduler, monoculus_engine::SchedulerSpec::Async(_));
    let subtitle = format!(
        "{}, {} scheduler, {n} robots in {}D, b = {}, c = {}",
        kind.name(),
        scheduler_name(cell),
        P::DIM,
        config.model.step,
        config.model.locality
    );
    let replay = Replay {
        ticks,
        model: kind.model().name(),
        locality: config.model.locality,
        termination: kind.shows_bits(),
        looks_note: (!record_looks).then(|| {
            format!(
                "Looks are recorded for runs of at most {} robots, all drawn",
                limits.max_look_robots
            )
        }),
        notes,
        ..Replay::begin(title, subtitle, &initial, &drawn)
    };
    let mut rec = Recorder {
        replay,
        drawn,
        record_looks,
        vision: config.vision,
        previous: None,
        budget: limits.max_bytes,
        bytes: 0,
        steps: 0,
        pinned: Vec::new(),
        epochs: 0,
        max_rows: limits.max_metric_rows.max(1),
        row_cap: limits.max_metric_rows.max(1),
    };
    let mut sim = Simulation::<P>::new(config, initial)?;
    let outcome = sim.run_observed(|sim| rec.after_step(sim));
    rec.finish(&sim);
    let mut replay = rec.replay;
    replay.outcome = outcome_line(&outcome, ticks);
    if replay.stride > 1 {
        replay.notes.push(format!(
            "every {} {} kept as a frame (and the last); metrics for every {}",
            ordinal(replay.stride),
            if ticks { "event tick" } else { "round" },
            if replay.metrics.stride > 1 {
                "epoch"
            } else if ticks {
                "event tick"
            } else {
                "round"
            }
        ));
    }
    if replay.metrics.stride > 1 {
        replay.notes.push(format!(
            "metrics kept for every tick that ends an epoch or shows a frame, and every {} other event tick",
            ordinal(replay.metrics.stride)
        ));
    }
    Ok(replay)
}

fn outcome_line(o: &RunOutcome, ticks: bool) -> String {
    format!(
        "{} after {} {}{}; {} moves; final diameter {:.4}",
        if o.converged {
            "converged"
        } else {
            "not converged"
        },
        o.rounds,
        if ticks { "epochs" } else { "rounds" },
        o.ticks.map_or(String::new(), |t| format!(" ({t} ticks)")),
        o.moves,
        o.final_diameter
    )
}

#[cfg(test)]
mod tests {
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
        let mut sim =
            Simulation::<DVec2>::new(cell.sim_config(1), cell.initial_positions(1)).unwrap();
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
        let mut sim =
            Simulation::<DVec2>::new(cell.sim_config(1), cell.initial_positions(1)).unwrap();
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
        let text = config("converge_locality", "kind = \"fsync\"", 60, 2)
            .replace("side = 8.0", "side = 30.0");
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
}
