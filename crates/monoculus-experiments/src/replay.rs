//! Recording one run for watching: frames of positions and robot states, exact metrics
//! at every step, and what robots saw at their Looks. `monoculus replay` renders a
//! [`Replay`] as a self-contained HTML player or an animated GIF (`monoculus-plot`).
//!
//! A step is a round (ASYNC: an event tick). Frame `k` of a round scheduler is the
//! configuration after round `k`, and its robot states, Looks and moving count are those
//! of round `k + 1`, which looks at it: clicking a robot shows rays to the robots drawn
//! in the same frame. Under ASYNC a frame is the configuration at a tick, movers where
//! they are on their segments, and the Looks are those taken at that tick.
//!
//! Large runs are thinned to fit [`Limits`]: every `sample`-th robot is drawn, and every
//! `stride`-th frame kept (the stride doubles whenever the frames outgrow the budget);
//! the metrics stay exact for every step, over all robots.

use glam::{DVec2, DVec3};
use monoculus_core::algorithms::{AlgorithmKind, Model};
use monoculus_core::geometry::{Point, convex_hull_2d};
use monoculus_core::observe::inspect;
use monoculus_engine::resources::Shape;
use monoculus_engine::{Activity, EngineError, IndexPoint, IndexedSight, RunOutcome, Simulation};

use crate::Cell;
use crate::positions::TracePositions;

/// What a replay may hold.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Robots drawn at most (above it, every k-th robot is drawn).
    pub max_drawn: usize,
    /// Bytes of frames and Looks at most (the stride of kept frames doubles beyond it).
    pub max_bytes: usize,
    /// Looks are recorded only for runs of at most this many robots.
    pub max_look_robots: usize,
    /// ASYNC: rows of metrics at most beyond the ticks that end an epoch or show a
    /// frame (the other ticks' rows are thinned like frames beyond it).
    pub max_metric_rows: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_drawn: 20_000,
            max_bytes: 30 << 20,
            max_look_robots: 2_000,
            max_metric_rows: 200_000,
        }
    }
}

/// A robot's state in a frame, as drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum State {
    /// Not activated, or waiting (ASYNC), or the run has ended.
    Idle = 0,
    /// Looked and stays.
    Staying = 1,
    /// ASYNC: looked, computing.
    Computing = 2,
    /// Moving.
    Moving = 3,
}

impl From<Activity> for State {
    fn from(a: Activity) -> Self {
        match a {
            Activity::Idle => State::Idle,
            Activity::Staying => State::Staying,
            Activity::Computing => State::Computing,
            Activity::Moving => State::Moving,
        }
    }
}

/// One kept frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// The step it shows (0: the start).
    pub step: usize,
    /// Its row of [`Metrics`].
    pub row: usize,
    /// Drawn robots' coordinates, `dim` per robot.
    pub positions: Vec<f32>,
    /// Drawn robots' [`State`]s.
    pub states: Vec<u8>,
    /// Termination algorithm: each drawn robot's memory bits (bit `2 * axis + high`).
    pub bits: Vec<u8>,
    /// The plane: the convex hull of all robots (not only the drawn ones), x, y per
    /// vertex, counter-clockwise. Empty in space.
    pub hull: Vec<f32>,
}

/// The metrics of every step (round, or ASYNC event tick), over all robots; a row per
/// step, unless an ASYNC run has more than [`Limits::max_metric_rows`] ticks: then every
/// tick that ends an epoch or shows a frame keeps its row, and every `stride`-th other.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Metrics {
    /// The step of each row.
    pub step: Vec<usize>,
    /// ASYNC: rows kept of other ticks are those whose step is a multiple of it.
    pub stride: usize,
    /// Round (ASYNC: tick).
    pub time: Vec<u64>,
    /// ASYNC: epochs completed; empty otherwise.
    pub epoch: Vec<u64>,
    /// Hull area (volume in space).
    pub hull: Vec<f64>,
    /// Diameter.
    pub diameter: Vec<f64>,
    /// Robots moving from this configuration (round schedulers: robots that move in the
    /// next round; ASYNC: robots in a Move phase with a displacement).
    pub moving: Vec<u64>,
}

impl Metrics {
    fn pop(&mut self) {
        self.step.pop();
        self.time.pop();
        self.epoch.pop();
        self.hull.pop();
        self.diameter.pop();
        self.moving.pop();
    }

    fn retain(&mut self, keep: &[bool]) {
        fn by<T>(v: &mut Vec<T>, keep: &[bool]) {
            if v.is_empty() {
                return;
            }
            let mut k = keep.iter();
            v.retain(|_| *k.next().unwrap());
        }
        by(&mut self.step, keep);
        by(&mut self.time, keep);
        by(&mut self.epoch, keep);
        by(&mut self.hull, keep);
        by(&mut self.diameter, keep);
        by(&mut self.moving, keep);
    }
}

/// What one robot saw at one Look.
#[derive(Clone, Debug, PartialEq)]
pub struct Look {
    /// The kept frame whose positions it looked at.
    pub frame: usize,
    /// The observer (robot index; Looks are recorded only when every robot is drawn).
    pub robot: u32,
    /// Where it decided to go (`None`: it stays).
    pub destination: Option<Vec<f32>>,
    /// The visible points (the lowest index of the robots at each).
    pub seen: Vec<u32>,
    /// Per visible point: LD, 1 if far; OLA, the sides `sum_k (side_k + 1) * 3^k`;
    /// positions model, 0.
    pub flags: Vec<u8>,
}

/// A recorded run.
#[derive(Clone, Debug, PartialEq)]
pub struct Replay {
    /// What is shown: experiment, cell, seed.
    pub title: String,
    /// Algorithm, scheduler, robots: one line.
    pub subtitle: String,
    /// The run's outcome, one line.
    pub outcome: String,
    /// 2 or 3.
    pub dim: usize,
    /// Robots in the run.
    pub n: usize,
    /// Every `sample`-th robot is drawn (1: all).
    pub sample: usize,
    /// Every `stride`-th step has a frame (and the last).
    pub stride: usize,
    /// Whether steps are ASYNC ticks.
    pub ticks: bool,
    /// The sensing model: "ld", "ola" or "positions".
    pub model: &'static str,
    /// Locality constant c.
    pub locality: f64,
    /// Whether robots carry the termination algorithm's bits.
    pub termination: bool,
    /// Drawn robots' start positions, `dim` per robot.
    pub start: Vec<f32>,
    /// Kept frames, in step order.
    pub frames: Vec<Frame>,
    /// Every step's metrics.
    pub metrics: Metrics,
    /// Recorded Looks, in frame order.
    pub looks: Vec<Look>,
    /// Why no Looks were recorded, if none were.
    pub looks_note: Option<String>,
    /// Notes shown on the page (observation errors, thinning).
    pub notes: Vec<String>,
}

impl Replay {
    /// Bytes the frames and Looks hold (what [`Limits::max_bytes`] bounds).
    fn bytes(&self) -> usize {
        let frames: usize = self.frames.iter().map(frame_bytes).sum();
        let looks: usize = self.looks.iter().map(look_bytes).sum();
        frames + looks
    }

    /// Doubles the stride and drops the frames (and their Looks) it no longer keeps.
    fn thin(&mut self) {
        self.stride *= 2;
        let stride = self.stride;
        let mut renumber = vec![usize::MAX; self.frames.len()];
        let mut kept = 0;
        for (k, f) in self.frames.iter().enumerate() {
            if f.step.is_multiple_of(stride) {
                renumber[k] = kept;
                kept += 1;
            }
        }
        self.frames.retain(|f| f.step.is_multiple_of(stride));
        self.looks.retain_mut(|l| {
            l.frame = renumber[l.frame];
            l.frame != usize::MAX
        });
    }
}

fn frame_bytes(f: &Frame) -> usize {
    4 * f.positions.len() + f.states.len() + f.bits.len() + 4 * f.hull.len()
}

fn look_bytes(l: &Look) -> usize {
    24 + 5 * l.seen.len()
}

fn coords<P: Point>(p: &P, out: &mut Vec<f32>) {
    out.extend((0..P::DIM).map(|k| p.axis(k) as f32));
}

fn hull_of<P: IndexPoint>(points: &[P]) -> Vec<f32> {
    if P::DIM != 2 {
        return Vec::new();
    }
    let plane: Vec<DVec2> = points
        .iter()
        .map(|p| DVec2::new(p.axis(0), p.axis(1)))
        .collect();
    convex_hull_2d(&plane)
        .iter()
        .flat_map(|v| [v.x as f32, v.y as f32])
        .collect()
}

fn model_name(kind: AlgorithmKind) -> &'static str {
    match kind.model() {
        Model::Ld => "ld",
        Model::Ola => "ola",
        Model::Positions => "positions",
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
    drawn: Vec<usize>,
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
        let mut positions = Vec::with_capacity(self.drawn.len() * P::DIM);
        for &i in &self.drawn {
            coords(&now[i], &mut positions);
        }
        let frame = Frame {
            step,
            row: self.replay.metrics.step.len() - 1,
            positions,
            states: vec![State::Idle as u8; self.drawn.len()],
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
        for (k, &i) in self.drawn.iter().enumerate() {
            frame.states[k] = State::from(views[i].activity) as u8;
        }
        if self.replay.termination {
            frame.bits = self
                .drawn
                .iter()
                .map(|&i| views[i].memory.map_or(0, |m| m.bits))
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
    let sample = n.div_ceil(limits.max_drawn.max(1)).max(1);
    let drawn: Vec<usize> = (0..n).step_by(sample).collect();
    let kind = cell.algorithm();
    let record_looks = sample == 1 && n <= limits.max_look_robots;
    let mut notes = Vec::new();
    if config.algorithm.errors.any() {
        notes.push(
            "Looks are shown as the robots' exact senses; the run's observation errors are not drawn"
                .to_string(),
        );
    }
    if sample > 1 {
        notes.push(format!(
            "{} of {n} robots drawn (every {}); metrics and hull over all robots",
            drawn.len(),
            ordinal(sample)
        ));
    }
    let mut start = Vec::with_capacity(drawn.len() * P::DIM);
    for &i in &drawn {
        coords(&initial[i], &mut start);
    }
    let ticks = matches!(config.scheduler, monoculus_engine::SchedulerSpec::Async(_));
    let replay = Replay {
        title,
        subtitle: format!(
            "{}, {} scheduler, {n} robots in {}D, b = {}, c = {}",
            kind.name(),
            scheduler_name(cell),
            P::DIM,
            config.algorithm.step,
            config.algorithm.locality
        ),
        outcome: String::new(),
        dim: P::DIM,
        n,
        sample,
        stride: 1,
        ticks,
        model: model_name(kind),
        locality: config.algorithm.locality,
        termination: kind.has_memory(),
        start,
        frames: Vec::new(),
        metrics: Metrics {
            stride: 1,
            ..Metrics::default()
        },
        looks: Vec::new(),
        looks_note: (!record_looks).then(|| {
            format!(
                "Looks are recorded for runs of at most {} robots, all drawn",
                limits.max_look_robots
            )
        }),
        notes,
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

/// `2nd`, `3rd`, `4th`, `11th`, `21st`...
fn ordinal(k: usize) -> String {
    let suffix = match (k % 10, k % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{k}{suffix}")
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

/// A replay of a `monoculus trace --positions` file: a frame per round, robots that move
/// in the next round coloured moving; no Looks (a trace holds positions only).
pub fn from_trace(trace: &TracePositions, title: String, limits: Limits) -> Replay {
    if trace.has_z {
        from_trace_in::<DVec3>(trace, title, limits)
    } else {
        from_trace_in::<DVec2>(trace, title, limits)
    }
}

fn from_trace_in<P: IndexPoint>(trace: &TracePositions, title: String, limits: Limits) -> Replay {
    let rounds: Vec<Vec<P>> = trace
        .rounds
        .iter()
        .map(|r| r.iter().map(|c| P::from_slice(c)).collect())
        .collect();
    let n = rounds[0].len();
    let sample = n.div_ceil(limits.max_drawn.max(1)).max(1);
    let drawn: Vec<usize> = (0..n).step_by(sample).collect();
    let mut start = Vec::new();
    for &i in &drawn {
        coords(&rounds[0][i], &mut start);
    }
    let mut replay = Replay {
        title,
        subtitle: format!("{n} robots in {}D, from a trace", P::DIM),
        outcome: format!("{} rounds traced", rounds.len() - 1),
        dim: P::DIM,
        n,
        sample,
        stride: 1,
        ticks: false,
        model: "positions",
        locality: f64::NAN,
        termination: false,
        start,
        frames: Vec::new(),
        metrics: Metrics {
            stride: 1,
            ..Metrics::default()
        },
        looks: Vec::new(),
        looks_note: Some("a trace holds positions only: no Looks to show".to_string()),
        notes: Vec::new(),
    };
    let mut bytes = 0;
    for (k, now) in rounds.iter().enumerate() {
        let next = rounds.get(k + 1);
        let moves = |i: usize| next.is_some_and(|next| next[i] != now[i]);
        let shape = Shape::of(now);
        let m = &mut replay.metrics;
        m.step.push(k);
        m.time.push(k as u64);
        m.hull.push(shape.hull);
        m.diameter.push(shape.diameter);
        m.moving.push((0..n).filter(|&i| moves(i)).count() as u64);
        if k.is_multiple_of(replay.stride) || k + 1 == rounds.len() {
            let mut positions = Vec::with_capacity(drawn.len() * P::DIM);
            for &i in &drawn {
                coords(&now[i], &mut positions);
            }
            let frame = Frame {
                step: k,
                row: k,
                positions,
                states: drawn
                    .iter()
                    .map(|&i| {
                        if moves(i) {
                            State::Moving as u8
                        } else {
                            State::Idle as u8
                        }
                    })
                    .collect(),
                bits: Vec::new(),
                hull: hull_of(now),
            };
            bytes += frame_bytes(&frame);
            replay.frames.push(frame);
            if bytes > limits.max_bytes && k + 1 < rounds.len() {
                replay.thin();
                bytes = replay.bytes();
            }
        }
    }
    if sample > 1 {
        replay.notes.push(format!(
            "{} of {n} robots drawn (every {}); metrics and hull over all robots",
            drawn.len(),
            ordinal(sample)
        ));
    }
    if replay.stride > 1 {
        replay.notes.push(format!(
            "every {} round kept as a frame (and the last); metrics for every one",
            ordinal(replay.stride)
        ));
    }
    replay
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Experiment;
    use crate::positions::parse_trace_positions;
    use monoculus_core::vision::{ExactSight, Sight};
    use std::path::Path;

    fn cell(text: &str) -> Cell {
        let exp = Experiment::parse(text, "test.toml", Path::new("."), &[]).unwrap();
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

    #[test]
    fn a_trace_file_replays_its_rounds() {
        let text = "round,robot,x,y\n0,0,0,0\n0,1,4,0\n0,2,0,3\n1,0,1,0\n1,1,4,0\n1,2,0,3\n";
        let trace = parse_trace_positions(text, "t.positions.csv").unwrap();
        let r = from_trace(&trace, "t".into(), Limits::default());
        assert_eq!(r.frames.len(), 2);
        assert_eq!(r.metrics.moving, vec![1, 0]);
        assert_eq!(r.frames[0].states, vec![State::Moving as u8, 0, 0]);
        assert_eq!(r.metrics.hull[0], 6.0);
        assert_eq!(r.metrics.diameter[0], 5.0);
        assert_eq!(r.frames[1].positions, vec![1.0, 0.0, 4.0, 0.0, 0.0, 3.0]);
        assert!(r.looks.is_empty() && r.looks_note.is_some());
    }

    #[test]
    fn bad_trace_files_name_the_line() {
        let bad = [
            ("x,y\n1,2\n", "column round"),
            (
                "round,robot,x,y\n1,0,0,0\n",
                ":2: column round: 1 out of order",
            ),
            (
                "round,robot,x,y\n0,0,0,0\n0,2,0,0\n",
                ":3: column robot: 2 out of order",
            ),
            (
                "round,robot,x,y\n0,0,0,0\n0,1,1,1\n1,0,0,0\n2,0,0,0\n",
                ":5: round 1 lists 1 robots",
            ),
            (
                "round,robot,x,y\n0,0,0,0\n0,1,1,1\n1,0,0,0\n",
                ":4: round 1 lists 1 robots",
            ),
            ("round,robot,x,y\n0,-1,0,0\n", ":2: column robot: `-1`"),
            ("round,robot,x,y\n0,0,0,nan\n", ":2: column y"),
        ];
        for (text, want) in bad {
            let e = parse_trace_positions(text, "t.csv")
                .unwrap_err()
                .to_string();
            assert!(e.contains(want), "{text:?}: {e}");
            assert!(e.starts_with("t.csv:"), "{e}");
        }
    }
}
