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

/// The title of a replay of `cell` (of the experiment `name`) with `seed`: `vs-n,
/// swarm.n=10, algorithm.name=converge_locality, seed 3` (the cell's swept values, if
/// any), as `monoculus replay` shows it.
///
/// ```
/// use std::path::Path;
///
/// use monoculus_experiments::replay::title;
/// use monoculus_experiments::{Experiment, Registry};
///
/// let text = "name = \"t\"\n[swarm]\nn = [4, 6]\ninit = \"square\"\n\
///             [algorithm]\nname = \"converge_locality\"\n";
/// let exp = Experiment::parse(text, "t", Path::new("."), &[], &Registry::builtin()).unwrap();
/// assert_eq!(title(&exp.name, &exp.cells[1], 3), "t, swarm.n=6, seed 3");
/// ```
pub fn title(name: &str, cell: &Cell, seed: u64) -> String {
    if cell.key.is_empty() {
        format!("{name}, seed {seed}")
    } else {
        format!("{name}, {}, seed {seed}", cell.key.replace(';', ", "))
    }
}

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
    fn frame(&mut self, step: usize, now: &[P], lights: &[u8]) -> Option<usize> {
        step.is_multiple_of(self.replay.stride)
            .then(|| self.push_frame(step, now, lights))
    }

    fn push_frame(&mut self, step: usize, now: &[P], lights: &[u8]) -> usize {
        let frame = Frame {
            step,
            row: self.replay.metrics.step.len() - 1,
            positions: self.drawn.coords(now),
            states: vec![State::Idle as u8; self.drawn.robots.len()],
            bits: Vec::new(),
            lights: self.drawn.lights(lights),
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
        let frame = self.frame(step, &now, &sim.lights_now());
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
            self.push_frame(last, &sim.positions_now(), &sim.lights_now());
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
    let initial: Vec<P> = cell.initial_positions(seed);
    let mut recording = Recording::new(cell, seed, &initial, title, limits);
    let mut sim = Simulation::<P>::new(cell.sim_config(seed), initial)?;
    let outcome = sim.run_observed(|sim| recording.observe(sim));
    Ok(recording.finish(&mut sim, Some(&outcome)))
}

/// A run recorded while something else drives it: [`observe`](Self::observe) after
/// every step the simulation takes (and once at its start), then
/// [`finish`](Self::finish). [`record`] is this over a whole run; the Python package's
/// `Simulation.replay()` drives it step by step as the simulation was.
///
/// ```
/// use std::path::Path;
///
/// use glam::DVec2;
/// use monoculus_engine::Simulation;
/// use monoculus_experiments::replay::{Limits, Recording};
/// use monoculus_experiments::{Experiment, Registry};
///
/// let text = "name = \"doc\"\nseeds = [3]\n[swarm]\nn = 6\nside = 4.0\n\
///             init = \"square\"\n[algorithm]\nname = \"converge_locality\"\n";
/// let exp = Experiment::parse(text, "doc", Path::new("."), &[], &Registry::builtin()).unwrap();
/// let cell = &exp.cells[0];
/// let start: Vec<DVec2> = cell.initial_positions(3);
/// let mut recording = Recording::new(cell, 3, &start, "doc".into(), Limits::default());
/// let mut sim = Simulation::new(cell.sim_config(3), start).unwrap();
/// recording.observe(&sim);
/// for _ in 0..2 {
///     sim.step();
///     recording.observe(&sim);
/// }
/// let replay = recording.finish(&mut sim, None);
/// assert_eq!(replay.frames.len(), 3);
/// assert!(replay.outcome.starts_with("stepped 2 rounds"));
/// ```
pub struct Recording<P: IndexPoint> {
    rec: Recorder<P>,
}

impl<P: IndexPoint> Recording<P> {
    /// Begins the replay of a run of `cell` with `seed` from `initial` (the positions
    /// the simulation starts from: the cell's, or any others).
    pub fn new(cell: &Cell, seed: u64, initial: &[P], title: String, limits: Limits) -> Self {
        let config = cell.sim_config(seed);
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
            lights: kind.lights().to_vec(),
            looks_note: (!record_looks).then(|| {
                format!(
                    "Looks are recorded for runs of at most {} robots, all drawn",
                    limits.max_look_robots
                )
            }),
            notes,
            ..Replay::begin(title, subtitle, initial, &drawn)
        };
        let rec = Recorder {
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
        Recording { rec }
    }

    /// Records `sim` as it is now: call it once before the first step and after every
    /// step ([`Simulation::run_observed`] calls its observer so).
    pub fn observe(&mut self, sim: &Simulation<P>) {
        self.rec.after_step(sim);
    }

    /// The replay. `outcome` is the run's, if it ran to its end; `None` for a run only
    /// stepped so far, whose verdict is then what a run ending now would get
    /// (`stepped 12 rounds; converged now; ...`).
    pub fn finish(mut self, sim: &mut Simulation<P>, outcome: Option<&RunOutcome>) -> Replay {
        self.rec.finish(sim);
        let mut replay = self.rec.replay;
        let ticks = replay.ticks;
        match outcome {
            Some(o) => {
                replay.outcome = outcome_line(o, ticks);
                replay.verdict = verdict(o);
            }
            None => {
                let (v, line) = stepped_line(sim);
                replay.verdict = v;
                replay.outcome = line;
            }
        }
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
        replay
    }
}

/// The verdict and outcome line of a run stepped so far, not run to its end: what a run
/// ending now would get (`converged`, `stuck` or `not converged`) and `stepped 12
/// rounds; converged now; 30 moves; diameter 0.8000`.
///
/// ```
/// use glam::DVec2;
/// use monoculus_core::algorithms::ConvergeLocality;
/// use monoculus_engine::prelude::*;
/// use monoculus_experiments::replay::stepped_line;
///
/// let config = SimConfig::paper(AlgorithmBox::new(ConvergeLocality), 1, 100);
/// let mut sim = Simulation::new(config, vec![DVec2::ZERO, DVec2::new(5.0, 0.0)]).unwrap();
/// sim.step();
/// let (verdict, line) = stepped_line(&mut sim);
/// assert_eq!(verdict, "not converged");
/// assert!(line.starts_with("stepped 1 rounds; the run goes on; 2 moves"));
/// ```
pub fn stepped_line<P: IndexPoint>(sim: &mut Simulation<P>) -> (&'static str, String) {
    let ticks = sim.async_progress().is_some();
    let stop = sim.criterion_met_now();
    let goal = sim.goal_holds_now();
    let (v, now) = match stop {
        Some(_) if goal => ("converged", "converged now"),
        Some(monoculus_engine::StoppedBy::Quiescent) => {
            ("stuck", "stuck now: quiescent short of its goal")
        }
        _ => ("not converged", "the run goes on"),
    };
    let (_, diameter) = sim.shape();
    let line = format!(
        "stepped {} {}; {now}; {} moves; diameter {diameter:.4}",
        sim.rounds_done(),
        if ticks { "epochs" } else { "rounds" },
        sim.world()
            .resource::<monoculus_engine::resources::Tally>()
            .moves,
    );
    (v, line)
}

/// The run's verdict and outcome, one line: `converged after 12 rounds; ...`, `stuck
/// after 2 epochs: quiescent short of its goal (every robot within a disc of radius c);
/// ...`, `not converged: max_rounds after 500 rounds; ...`.
pub fn outcome_line(o: &RunOutcome, ticks: bool) -> String {
    let verdict = match verdict(o) {
        "not converged" => format!("not converged ({})", stopped_by_words(o.stopped_by)),
        v => v.to_string(),
    };
    let why = if o.stuck() {
        format!(": quiescent short of its goal ({})", o.goal.describe())
    } else {
        String::new()
    };
    format!(
        "{verdict} after {} {}{}{why}; {} moves; final diameter {:.4}",
        o.rounds,
        if ticks { "epochs" } else { "rounds" },
        o.ticks.map_or(String::new(), |t| format!(" ({t} ticks)")),
        o.moves,
        o.final_diameter
    )
}

/// The verdict of a run: `converged`, `stuck` or `not converged`.
pub fn verdict(o: &RunOutcome) -> &'static str {
    if o.converged {
        "converged"
    } else if o.stuck() {
        "stuck"
    } else {
        "not converged"
    }
}

/// What ended a run that did not converge, in words.
fn stopped_by_words(s: monoculus_engine::StoppedBy) -> &'static str {
    use monoculus_engine::StoppedBy;
    match s {
        StoppedBy::MaxRounds => "stopped at stop.max_rounds",
        StoppedBy::ScheduleEnd => "the schedule file ended",
        StoppedBy::Failure => "the algorithm failed",
        StoppedBy::Interrupted => "interrupted",
        // Stopped by its criterion without its goal, not quiescent (a criterion set
        // by stop.criterion that the goal does not follow from).
        StoppedBy::Quiescent | StoppedBy::Diameter | StoppedBy::Box => {
            "its stop criterion held, its goal did not"
        }
    }
}

#[cfg(test)]
mod tests;
