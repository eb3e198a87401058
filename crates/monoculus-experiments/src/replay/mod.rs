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

mod advance;
mod record;
mod trace;

pub use advance::{Advance, advance, record_advances};
pub use record::{Recording, outcome_line, record, stepped_line, title, verdict};
pub use trace::from_trace;

use glam::DVec2;
use monoculus_core::geometry::{Point, convex_hull_2d};
use monoculus_engine::{Activity, IndexPoint};

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
    /// Algorithms with lights: the colour each drawn robot shows (an index into
    /// [`Replay::lights`]), as the Looks of this frame see it; empty otherwise.
    pub lights: Vec<u8>,
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
    /// The run's verdict: `converged`, `stuck` or `not converged` (empty for a replay
    /// of a trace, which holds positions only).
    pub verdict: &'static str,
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
    /// The names of the algorithm's lights (empty: it has none).
    pub lights: Vec<String>,
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
    /// A replay of the robots at `initial`, those `drawn` drawn, with no frames, metrics
    /// or Looks yet; a round scheduler's, with positions only (no model, no locality)
    /// until the caller says otherwise.
    fn begin<P: Point>(title: String, subtitle: String, initial: &[P], drawn: &Drawn) -> Self {
        Replay {
            title,
            subtitle,
            outcome: String::new(),
            verdict: "",
            dim: P::DIM,
            n: initial.len(),
            sample: drawn.sample,
            stride: 1,
            ticks: false,
            model: "positions",
            locality: f64::NAN,
            termination: false,
            lights: Vec::new(),
            start: drawn.coords(initial),
            frames: Vec::new(),
            metrics: Metrics {
                stride: 1,
                ..Metrics::default()
            },
            looks: Vec::new(),
            looks_note: None,
            notes: Vec::new(),
        }
    }

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

/// The robots a replay draws: all, or every `sample`-th where they are more than
/// [`Limits::max_drawn`].
struct Drawn {
    sample: usize,
    robots: Vec<usize>,
}

impl Drawn {
    fn of(n: usize, limits: &Limits) -> Self {
        let sample = n.div_ceil(limits.max_drawn.max(1)).max(1);
        Drawn {
            sample,
            robots: (0..n).step_by(sample).collect(),
        }
    }

    /// Their colours among `lights` (empty when there are none).
    fn lights(&self, lights: &[u8]) -> Vec<u8> {
        if lights.is_empty() {
            return Vec::new();
        }
        self.robots.iter().map(|&i| lights[i]).collect()
    }

    /// Their coordinates in `points`, one after the other.
    fn coords<P: Point>(&self, points: &[P]) -> Vec<f32> {
        let mut out = Vec::with_capacity(self.robots.len() * P::DIM);
        for &i in &self.robots {
            coords(&points[i], &mut out);
        }
        out
    }

    /// What the replay says of them, if they are not all of the `n` robots.
    fn note(&self, n: usize) -> Option<String> {
        (self.sample > 1).then(|| {
            format!(
                "{} of {n} robots drawn (every {}); metrics and hull over all robots",
                self.robots.len(),
                ordinal(self.sample)
            )
        })
    }
}

fn frame_bytes(f: &Frame) -> usize {
    4 * f.positions.len() + f.states.len() + f.bits.len() + f.lights.len() + 4 * f.hull.len()
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
