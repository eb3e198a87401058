//! What the explorer holds: the settings (a config of one cell), the start, and the run
//! stepped from it so far. Every request of the page is a method here; the server only
//! carries them.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use glam::DVec2;
use monoculus_core::geometry::convex_hull_2d;
use monoculus_core::observe::inspect;
use monoculus_engine::{Activity, IndexedSight, RunOutcome, Simulation};
use monoculus_experiments::config::{InitKind, Seeds};
use monoculus_experiments::positions::{parse_positions, positions_csv};
use monoculus_experiments::replay::{
    Advance, Limits, advance, outcome_line, record_advances, stepped_line, title, verdict,
};
use monoculus_experiments::{Cell, Experiment, Registry};
use serde_json::{Value, json};

/// The most robots the explorer holds.
pub const MAX_ROBOTS: usize = 1_000_000;

/// The config keys that name files: the page may not change them (the explorer reads
/// no file but those of the config it was started with).
const FILE_KEYS: [(&str, &str); 3] = [
    ("swarm", "file"),
    ("scheduler", "file"),
    ("scheduler", "durations"),
];

/// A request the explorer refuses: the message shown in the page (the command line's,
/// for a bad setting).
#[derive(Debug)]
pub struct Refused(pub String);

impl<E: std::fmt::Display> From<E> for Refused {
    fn from(e: E) -> Self {
        Refused(monoculus_experiments::one_line(&e.to_string()))
    }
}

/// The metrics of every state shown since the start.
#[derive(Default)]
struct History {
    time: Vec<u64>,
    diameter: Vec<f64>,
    hull: Vec<f64>,
}

/// One explorer: its settings, start and run.
pub struct Session {
    registry: Registry,
    /// Where the config's relative paths are read from.
    base: PathBuf,
    /// The values of [`FILE_KEYS`] in the config the explorer was started with.
    files: Vec<Option<toml::Value>>,
    exp: Experiment,
    seed: u64,
    start: Vec<DVec2>,
    sim: Simulation<DVec2>,
    advances: Vec<Advance>,
    outcome: Option<RunOutcome>,
    history: History,
    /// Round schedulers: the positions before the last round (what its Looks saw).
    before: Option<Vec<DVec2>>,
}

fn value_at<'a>(table: &'a toml::Table, (t, k): (&str, &str)) -> Option<&'a toml::Value> {
    table.get(t)?.as_table()?.get(k)
}

impl Session {
    /// An explorer of `exp` (one cell, in the plane), from its start.
    pub fn new(exp: Experiment, registry: Registry) -> Result<Self, Refused> {
        let table: toml::Table = toml::from_str(&exp.resolved)?;
        let files = FILE_KEYS
            .iter()
            .map(|&k| value_at(&table, k).cloned())
            .collect();
        let (seed, start) = Self::check(&exp)?;
        let sim = Simulation::new(exp.cells[0].sim_config(seed), start.clone())?;
        let mut s = Session {
            registry,
            base: exp.base.clone(),
            files,
            exp,
            seed,
            start,
            sim,
            advances: Vec::new(),
            outcome: None,
            history: History::default(),
            before: None,
        };
        s.restart()?;
        Ok(s)
    }

    /// The seed and start of an experiment the explorer can show.
    fn check(exp: &Experiment) -> Result<(u64, Vec<DVec2>), Refused> {
        if exp.cells.len() != 1 {
            return Err(Refused(format!(
                "the explorer shows one cell; this config sweeps {} cells ({}): give one value per key (--set KEY=VALUE)",
                exp.cells.len(),
                exp.axes
                    .iter()
                    .map(|a| a.path.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
        let cell = &exp.cells[0];
        if cell.dim() != 2 {
            return Err(Refused(format!(
                "swarm.dim = {}: the explorer shows the plane (dim = 2)",
                cell.dim()
            )));
        }
        let seed = exp.seeds.first().copied().unwrap_or(0);
        let start: Vec<DVec2> = cell.initial_positions(seed);
        check_n(start.len())?;
        Ok((seed, start))
    }

    fn cell(&self) -> &Cell {
        &self.exp.cells[0]
    }

    /// Back to the start: a new run of the settings from it.
    pub fn restart(&mut self) -> Result<(), Refused> {
        self.sim = Simulation::new(self.cell().sim_config(self.seed), self.start.clone())?;
        self.advances.clear();
        self.outcome = None;
        self.history = History::default();
        self.before = None;
        self.push_metrics();
        Ok(())
    }

    fn push_metrics(&mut self) {
        let (hull, diameter) = self.sim.shape();
        self.history.time.push(self.sim.time());
        self.history.diameter.push(diameter);
        self.history.hull.push(hull);
    }

    /// The settings as TOML: the cell's config in full, defaults filled in.
    pub fn settings(&self) -> String {
        toml::to_string(&self.cell().spec).expect("a RunSpec serialises")
    }

    /// New settings from the page: `text` is a config of one cell; the start is kept
    /// unless `generate` (then it is the one the settings' `[swarm]` and seed give).
    pub fn set_settings(&mut self, text: &str, generate: bool) -> Result<(), Refused> {
        let table: toml::Table = toml::from_str(text).map_err(|e| {
            Refused(format!(
                "settings: {}",
                monoculus_experiments::one_line(&e.to_string())
            ))
        })?;
        for (k, was) in FILE_KEYS.iter().zip(&self.files) {
            if value_at(&table, *k) != was.as_ref() {
                return Err(Refused(format!(
                    "settings: {}.{}: the explorer reads no file but those of the config it was started with; load a positions CSV in the page instead",
                    k.0, k.1
                )));
            }
        }
        let exp = Experiment::parse(text, "settings", &self.base, &[], &self.registry)?;
        let (seed, generated) = Self::check(&exp)?;
        let start = if generate {
            generated
        } else {
            self.start.clone()
        };
        // The run is made before anything changes: settings it refuses change nothing.
        let sim = Simulation::new(exp.cells[0].sim_config(seed), start.clone())?;
        self.exp = exp;
        self.seed = seed;
        self.start = start;
        self.sim = sim;
        self.restart()
    }

    /// The start generated from the settings' `[swarm]` and seed.
    pub fn generate(&mut self) -> Result<(), Refused> {
        let (_, start) = Self::check(&self.exp)?;
        self.set_start(start)
    }

    /// A new start (the run goes back to it).
    pub fn set_start(&mut self, start: Vec<DVec2>) -> Result<(), Refused> {
        check_n(start.len())?;
        if let Some(p) = start.iter().find(|p| !p.is_finite()) {
            return Err(Refused(format!(
                "a robot at ({}, {}): not finite",
                p.x, p.y
            )));
        }
        let sim = Simulation::new(self.cell().sim_config(self.seed), start.clone())?;
        self.start = start;
        self.sim = sim;
        self.restart()
    }

    /// An edit of the robots as they are now, which become the start: `add` at a point,
    /// `move` robot `robot` to a point, `delete` robot `robot`.
    pub fn edit(
        &mut self,
        op: &str,
        robot: Option<usize>,
        at: Option<DVec2>,
    ) -> Result<(), Refused> {
        let mut now = self.sim.positions_now();
        let robot_index = || {
            robot.filter(|&r| r < now.len()).ok_or_else(|| {
                Refused(format!(
                    "robot {robot:?}: the swarm has {} robots",
                    now.len()
                ))
            })
        };
        let point = || at.ok_or_else(|| Refused(format!("{op}: a point (x, y) is needed")));
        match op {
            "add" => now.push(point()?),
            "move" => {
                let r = robot_index()?;
                now[r] = point()?;
            }
            "delete" => {
                let r = robot_index()?;
                now.remove(r);
            }
            _ => {
                return Err(Refused(format!(
                    "edit `{op}`: expected add, move or delete"
                )));
            }
        }
        self.set_start(now)
    }

    /// A positions CSV as the start.
    pub fn load_positions(&mut self, text: &str, name: &str) -> Result<(), Refused> {
        let file = parse_positions(text, name)?;
        if file.has_z {
            return Err(Refused(format!(
                "{name}: a z column: the explorer shows the plane"
            )));
        }
        self.set_start(file.points())
    }

    /// Steps `count` rounds (ASYNC: epochs), stopping where the run ends (its stop
    /// criterion, its cap, a failure); `count = None` runs to the end.
    pub fn step(&mut self, count: Option<u64>) {
        let ticks = self.sim.async_progress().is_some();
        let mut left = count.unwrap_or(u64::MAX);
        while left > 0 && self.outcome.is_none() {
            if !ticks {
                self.before = Some(self.sim.positions().to_vec());
            }
            let history = &mut self.history;
            advance(&mut self.sim, Advance::Step, |s| {
                let (hull, diameter) = s.shape();
                history.time.push(s.time());
                history.diameter.push(diameter);
                history.hull.push(hull);
            });
            self.advances.push(Advance::Step);
            left -= 1;
            let capped = self.sim.rounds_done() >= self.cell().spec.stop.max_rounds;
            if self.sim.failure().is_some() || capped || self.sim.criterion_met_now().is_some() {
                // The run's own ending: `run` from here takes no step, and reports it.
                let outcome = advance(&mut self.sim, Advance::Run(None), |_| {});
                self.advances.push(Advance::Run(None));
                self.outcome = outcome;
            }
        }
    }

    /// The verdict and outcome line: the run's, once it ended; else a run ending now.
    fn verdict(&mut self) -> (&'static str, String) {
        let ticks = self.sim.async_progress().is_some();
        match &self.outcome {
            Some(o) => (verdict(o), outcome_line(o, ticks)),
            None => stepped_line(&mut self.sim),
        }
    }

    /// The state the page draws: robots, their hull, states and lights, the metrics from
    /// row `since` on (and with `since = 0` the start), the verdict.
    pub fn state(&mut self, since: usize) -> Value {
        let (v, line) = self.verdict();
        let now = self.sim.positions_now();
        let views = self.sim.robot_views();
        let kind = self.cell().algorithm().clone();
        let states: Vec<u8> = views
            .iter()
            .map(|v| monoculus_experiments::replay::State::from(v.activity) as u8)
            .collect();
        let bits: Vec<u8> = views.iter().map(|v| v.bits.unwrap_or(0)).collect();
        let lights = self.sim.lights_now();
        let from = since.min(self.history.time.len());
        let ticks = self.sim.async_progress();
        json!({
            "n": now.len(),
            "positions": f64s(now.iter().flat_map(|p| [p.x, p.y])),
            // The start and the history change only when the run starts again.
            "start": if from == 0 { Some(f64s(self.start.iter().flat_map(|p| [p.x, p.y]))) } else { None },
            "hull": f64s(convex_hull_2d(&now).iter().flat_map(|p| [p.x, p.y])),
            "states": base64(&states),
            "bits": if kind.shows_bits() { base64(&bits) } else { String::new() },
            "lights": base64(&lights),
            "time": self.sim.time(),
            "rounds": self.sim.rounds_done(),
            "ticks": ticks.is_some(),
            "ended": self.outcome.is_some(),
            "verdict": v,
            "outcome": line,
            "metrics": {
                "from": from,
                "time": &self.history.time[from..],
                "diameter": &self.history.diameter[from..],
                "hull": &self.history.hull[from..],
            },
        })
    }

    /// What the page shows beside the robots: the algorithm and its model, b and c,
    /// the lights' names and colours, the settings and the registered algorithms.
    pub fn setup(&self) -> Value {
        let cell = self.cell();
        let kind = cell.algorithm();
        let algorithms: Vec<Value> = self
            .registry
            .names()
            .into_iter()
            .map(|name| {
                let entry = self.registry.get(name).expect("a registered name");
                let params = entry
                    .make(&toml::Table::new())
                    .map(|(_, p)| toml::to_string(&p).unwrap_or_default())
                    .unwrap_or_default();
                json!({"name": name, "model": entry.model().name(), "params": params})
            })
            .collect();
        json!({
            "title": title(&self.exp.name, cell, self.seed),
            "settings": self.settings(),
            "algorithm": kind.name(),
            "model": kind.model().name(),
            "scheduler": format!("{:?}", cell.spec.scheduler.kind).to_lowercase(),
            "step": cell.spec.algorithm.step,
            "locality": cell.spec.algorithm.locality,
            "termination": kind.shows_bits(),
            "light_names": kind.lights(),
            "light_colors": (0..kind.lights().len()).map(|k| {
                let (r, g, b) = monoculus_plot::light_colour(k);
                format!("#{r:02x}{g:02x}{b:02x}")
            }).collect::<Vec<_>>(),
            "algorithms": algorithms,
            "max_robots": MAX_ROBOTS,
        })
    }

    /// What robot `robot` sees now and would decide now (a fresh activation that
    /// changes nothing), and, after a round, what it saw at its last Look and decided.
    pub fn robot(&mut self, robot: usize) -> Result<Value, Refused> {
        let now = self.sim.positions_now();
        if robot >= now.len() {
            return Err(Refused(format!(
                "robot {robot}: the swarm has {} robots",
                now.len()
            )));
        }
        let views = self.sim.robot_views();
        let lights = self.sim.lights_now();
        let decision = self.sim.decide_now(robot);
        let now_look = self.look(&now, robot, &lights);
        let last = match (&self.before, views[robot].looked) {
            (Some(before), true) => {
                let d = views[robot].decision;
                json!({
                    "from": [before[robot].x, before[robot].y],
                    "seen": self.look(before, robot, &lights),
                    "destination": d.map(|d| [before[robot].x + d.x, before[robot].y + d.y]),
                })
            }
            _ => Value::Null,
        };
        let (decision, failure) = match decision {
            Ok(d) => (d.map(|d| [d.x, d.y]), None),
            Err(f) => (None, Some(f.message)),
        };
        Ok(json!({
            "robot": robot,
            "at": [now[robot].x, now[robot].y],
            "state": format!("{:?}", views[robot].activity).to_lowercase(),
            "moving": views[robot].activity == Activity::Moving,
            "light": lights.get(robot),
            "bits": views[robot].bits,
            "seen": now_look,
            "decision": decision,
            "failure": failure,
            "last": last,
        }))
    }

    /// The points robot `robot` sees among `points`: index, direction, far bit (LD) or
    /// sides (OLA), and the light each shows.
    fn look(&self, points: &[DVec2], robot: usize, lights: &[u8]) -> Vec<Value> {
        let cell = self.cell();
        let sight = IndexedSight::new(points.to_vec(), self.sim.config().vision);
        inspect(&sight, robot, cell.spec.algorithm.locality)
            .iter()
            .map(|s| {
                json!({
                    "index": s.index,
                    "at": [points[s.index].x, points[s.index].y],
                    "far": s.far,
                    "sides": s.sides,
                    "light": lights.get(s.index),
                })
            })
            .collect()
    }

    /// The config that starts this run again with `monoculus run`: the settings with
    /// this seed and `init = "file"` from `positions.csv` beside it (files the settings
    /// name, as absolute paths).
    pub fn export_config(&self) -> String {
        let mut spec = self.cell().spec.clone();
        spec.hunt = None;
        spec.seeds = Seeds::List(vec![self.seed]);
        spec.swarm.init = InitKind::File;
        spec.swarm.file = Some("positions.csv".into());
        spec.swarm.n = None;
        let absolute = |f: &mut Option<String>, base: &Path| {
            if let Some(path) = f.as_mut() {
                *path = base.join(&*path).display().to_string();
            }
        };
        absolute(&mut spec.scheduler.file, &self.base);
        absolute(&mut spec.scheduler.durations, &self.base);
        format!(
            "# Written by `monoculus explore`: {}, from the start in positions.csv beside it.\n# Run it with `monoculus run explore.toml --out DIR` (or your own binary's `run`).\n{}",
            self.cell().algorithm().name(),
            toml::to_string(&spec).expect("a RunSpec serialises")
        )
    }

    /// The start as a positions CSV.
    pub fn export_positions(&self) -> String {
        positions_csv(&self.start)
    }

    /// The run so far as a replay page (recorded again from the start: the same run).
    pub fn export_replay(&self) -> Result<String, Refused> {
        let heading = format!(
            "{}, from monoculus explore",
            title(&self.exp.name, self.cell(), self.seed)
        );
        let replay = record_advances(
            self.cell(),
            self.seed,
            self.start.clone(),
            &self.advances,
            heading,
            Limits::default(),
            Arc::new(AtomicBool::new(false)),
        )?;
        Ok(monoculus_plot::replay_html(&replay))
    }
}

fn check_n(n: usize) -> Result<(), Refused> {
    if n > MAX_ROBOTS {
        return Err(Refused(format!(
            "{n} robots: the explorer holds at most {MAX_ROBOTS}"
        )));
    }
    Ok(())
}

/// `values` as little-endian f64s in base64 (the page reads them as a Float64Array).
fn f64s(values: impl Iterator<Item = f64>) -> String {
    let bytes: Vec<u8> = values.flat_map(f64::to_le_bytes).collect();
    base64(&bytes)
}

fn base64(bytes: &[u8]) -> String {
    monoculus_plot::base64(bytes)
}
