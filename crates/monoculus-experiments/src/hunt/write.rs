//! A hunt's folder: positions.csv, schedule.csv (when the schedule matters),
//! durations.csv (when ASYNC durations are given), reproduce.toml, replay.html and
//! summary.json, each written whole or not at all.

use std::fmt::Write as _;
use std::path::Path;

use super::*;
use crate::Registry;
use crate::config::{InitKind, RunSpec, Seeds};
use crate::output::{OutputError, json, write_atomic};
use crate::replay::{Limits, Replay, record};
use crate::results::num;

/// Writes a replay as an HTML page (the plot crate's writer, given by the caller).
pub type HtmlWriter<'a> = dyn Fn(&Replay, &Path) -> Result<(), String> + Sync + 'a;

/// The files of a hunt's folder.
pub const FILES: [&str; 6] = [
    "positions.csv",
    "schedule.csv",
    "durations.csv",
    "reproduce.toml",
    "replay.html",
    "summary.json",
];

/// Writes `report` into `dir`: summary.json always; with a best candidate also its
/// positions, schedule (when it matters), given durations (if any), the config that
/// replays it and (given `html`) its replay page. Files of an earlier best that this one
/// has not (a schedule, durations) are
/// removed, so that the folder describes one candidate; a signal (with
/// [`crate::output::remove_temporaries_on_signal`]) waits until the folder is whole.
pub fn write_found(
    dir: &Path,
    hunt: &Hunt,
    report: &HuntReport,
    registry: &Registry,
    html: Option<&HtmlWriter<'_>>,
) -> Result<(), String> {
    let io = |e: OutputError| e.to_string();
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    // A signal waits for the whole folder: never the start of one candidate beside the
    // summary of another.
    let _together = crate::output::Together::enter();
    if let Some(best) = &report.best {
        let dim = hunt.cell.dim();
        let c = &best.candidate;
        let mut positions = String::from(["x,y", "x,y,z"][usize::from(dim == 3)]);
        positions.push('\n');
        for p in &c.points {
            let row: Vec<String> = p[..dim].iter().map(|&x| num(x + 0.0)).collect();
            positions.push_str(&row.join(","));
            positions.push('\n');
        }
        write_atomic(&dir.join("positions.csv"), positions.as_bytes()).map_err(io)?;
        let schedule_path = dir.join("schedule.csv");
        match c.schedule.as_ref().filter(|_| hunt.schedule_matters()) {
            Some(rounds) => {
                let mut text = String::from("round,robot\n");
                for (k, &m) in rounds.iter().enumerate() {
                    for r in robots_of(m) {
                        let _ = writeln!(text, "{},{r}", k + 1);
                    }
                }
                write_atomic(&schedule_path, text.as_bytes()).map_err(io)?;
            }
            None => {
                let _ = std::fs::remove_file(&schedule_path);
            }
        }
        let durations_path = dir.join("durations.csv");
        match super::evaluate::durations_of(&c.durations) {
            Some(given) => {
                let text = crate::durations::durations_csv(&given);
                write_atomic(&durations_path, text.as_bytes()).map_err(io)?;
            }
            None => {
                let _ = std::fs::remove_file(&durations_path);
            }
        }
        let reproduce = dir.join("reproduce.toml");
        write_atomic(&reproduce, reproduce_toml(hunt, best).as_bytes()).map_err(io)?;
        if let Some(html) = html {
            let exp = Experiment::load(&reproduce, &[], registry)
                .map_err(|e| format!("the written reproduce.toml does not load: {e}"))?;
            let title = format!(
                "{}: {} (n = {}, seed {})",
                hunt.cell.spec.name,
                hunt.property().name(),
                c.len(),
                c.seed
            );
            let replay = record(&exp.cells[0], c.seed, title, Limits::default())
                .map_err(|e| format!("{}: {e}", reproduce.display()))?;
            html(&replay, &dir.join("replay.html"))?;
        }
    }
    write_atomic(
        &dir.join("summary.json"),
        summary_json(hunt, report).as_bytes(),
    )
    .map_err(io)
}

/// What the replay of a counterexample shows, in words (the first lines of
/// reproduce.toml).
fn shows(hunt: &Hunt, best: &Found) -> String {
    let e = &best.evaluation;
    let unit = if hunt.cell.spec.scheduler.kind == SchedulerKind::Async {
        "epoch"
    } else {
        "round"
    };
    match (hunt.property(), e.violated) {
        (Property::HullGrows, true) => format!(
            "the hull grows in {unit} {}: runs.csv says hull_grew = true",
            e.round
        ),
        (Property::DiameterGrows, true) => format!(
            "the diameter grows in {unit} {} (see `monoculus trace`, column diameter)",
            e.round
        ),
        (Property::BoxGrows, true) => format!(
            "the bounding box grows in {unit} {} (see `monoculus trace`, columns extent_*)",
            e.round
        ),
        (Property::Collision, true) => format!(
            "two robots reach one point in {unit} {} (see `monoculus trace --positions`)",
            e.round
        ),
        (Property::NoConvergence, true) if e.stuck => format!(
            "stuck in {unit} {}: quiescent short of its goal; runs.csv says converged = false, stuck = true",
            e.rounds
        ),
        (Property::NoConvergence, true) => format!(
            "no convergence within stop.max_rounds = {}: runs.csv says converged = false",
            hunt.max_rounds
        ),
        (Property::Stuck, true) => format!(
            "stuck in {unit} {}: quiescent short of its goal ({}); runs.csv says stuck = true",
            e.rounds,
            hunt.cell.goal().describe()
        ),
        (Property::Slow, _) => format!(
            "{} {unit}s to {} ({} epochs): runs.csv column rounds",
            e.rounds,
            if e.converged {
                "converge"
            } else {
                "the cap, not converged"
            },
            e.epochs
        ),
        (p, false) => format!(
            "the candidate that came closest to {} (score {}); it does not break it",
            p.name(),
            num(e.score)
        ),
    }
}

/// The config that replays a candidate with `monoculus run`: its positions from
/// positions.csv, its seed, its schedule from schedule.csv when it matters, its given
/// durations from durations.csv, and for a violation found in round k, k rounds.
fn reproduce_toml(hunt: &Hunt, best: &Found) -> String {
    let c = &best.candidate;
    let mut spec: RunSpec = hunt.cell.spec.clone();
    spec.hunt = None;
    spec.seeds = Seeds::List(vec![c.seed]);
    spec.swarm.init = InitKind::File;
    spec.swarm.file = Some("positions.csv".into());
    spec.swarm.n = None;
    if hunt.schedule_matters() {
        spec.scheduler.kind = SchedulerKind::File;
        spec.scheduler.file = Some("schedule.csv".into());
    }
    spec.scheduler.durations = (!c.durations.is_empty()).then(|| "durations.csv".into());
    let e = &best.evaluation;
    if e.violated && hunt.property().cut_at_violation() {
        spec.stop.max_rounds = e.round.max(1);
    }
    format!(
        "# Written by `monoculus hunt`: {}.\n# Replay it with the `run` (or `replay`) command of the binary that found it: `monoculus run reproduce.toml --out DIR`, or your own binary's.\n{}",
        shows(hunt, best),
        toml::to_string(&spec).expect("a RunSpec serialises")
    )
}

/// summary.json: the property, what was found, and how much was searched (the fields
/// of the best run are `null` while there is none).
#[derive(serde::Serialize)]
struct Summary<'a> {
    property: &'a str,
    found: bool,
    shrunk: bool,
    interrupted: bool,
    score: Option<f64>,
    n: Option<usize>,
    round: Option<u64>,
    rounds: Option<u64>,
    epochs: Option<u64>,
    converged: Option<bool>,
    stuck: Option<bool>,
    stopped_by: Option<&'a str>,
    goal: &'a str,
    above: Option<f64>,
    run_seed: Option<u64>,
    evaluations: u64,
    shrink_evaluations: u64,
    generations: u64,
    seconds: f64,
    seed: u64,
    algorithm: &'a str,
    scheduler: &'a str,
    subsets_searched: bool,
    durations_searched: bool,
    durations_given: Option<usize>,
    n_min: usize,
    n_max: usize,
    max_rounds: u64,
    failures: u64,
    first_failure: Option<&'a str>,
}

/// summary.json: the property, what was found, and how much was searched.
pub fn summary_json(hunt: &Hunt, report: &HuntReport) -> String {
    let best = report.best.as_ref();
    let e = best.map(|b| &b.evaluation);
    json::to_string_pretty(&Summary {
        property: report.property.name(),
        found: report.found,
        shrunk: report.shrunk,
        interrupted: report.interrupted,
        score: e.map(|e| e.score),
        n: best.map(|b| b.candidate.len()),
        round: e.map(|e| e.round),
        rounds: e.map(|e| e.rounds),
        epochs: e.map(|e| e.epochs),
        converged: e.map(|e| e.converged),
        stuck: e.map(|e| e.stuck),
        stopped_by: e.and_then(|e| e.stopped_by).map(|s| s.name()),
        goal: hunt.cell.goal().name(),
        above: hunt.spec.above,
        run_seed: best.map(|b| b.candidate.seed),
        evaluations: report.evaluations,
        shrink_evaluations: report.shrink_evaluations,
        generations: report.generations,
        seconds: (report.seconds * 1000.0).round() / 1000.0,
        seed: hunt.spec.seed,
        algorithm: hunt.cell.algorithm().name(),
        scheduler: hunt.cell.sim_config(0).scheduler.name(),
        subsets_searched: hunt.subsets,
        durations_searched: hunt.durations,
        durations_given: best.map(|b| b.candidate.durations.len()),
        n_min: hunt.n_min,
        n_max: hunt.n_max,
        max_rounds: hunt.max_rounds,
        failures: report.failures,
        first_failure: report.first_failure.as_deref(),
    })
}

/// Writes a hunt's folder as the hunt goes: at once for a counterexample, at most every
/// [`FolderWriter::EVERY`] while a best that breaks nothing keeps changing, and at the end
/// (a write that fails is kept and reported by [`FolderWriter::finish`]).
///
/// ```
/// use monoculus_experiments::hunt::{FolderWriter, Hunt, HuntOptions};
/// use monoculus_experiments::{Experiment, Registry};
///
/// let config = "name = \"h\"\n[swarm]\nn = 4\ninit = \"square\"\nside = 3.0\n\
///               [algorithm]\nname = \"angle_bisector\"\n[stop]\nmax_rounds = 5\n\
///               [hunt]\nproperty = \"hull_grows\"\nn_min = 3\nevaluations = 2000\n";
/// let registry = Registry::builtin();
/// let exp = Experiment::parse(config, "h.toml", ".".as_ref(), &[], &registry)?;
/// let hunt = Hunt::new(&exp, &exp.cells[0], "h.toml")?;
/// let dir = tempfile::tempdir()?;
/// let writer = FolderWriter::new(dir.path(), &hunt, &registry, None); // no replay page
/// let report = hunt.run(&HuntOptions {
///     on_best: Some(&|r| writer.on_best(r)),
///     on_progress: Some(&|_| writer.on_progress()),
///     ..HuntOptions::default()
/// });
/// writer.finish(&report)?;
/// assert!(dir.path().join("reproduce.toml").exists());
/// assert!(std::fs::read_to_string(dir.path().join("summary.json"))?.contains("\"found\": true"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct FolderWriter<'a> {
    dir: &'a Path,
    hunt: &'a Hunt,
    registry: &'a Registry,
    html: Option<&'a HtmlWriter<'a>>,
    last: std::sync::Mutex<Option<std::time::Instant>>,
    /// A best not written yet (it came within [`FolderWriter::EVERY`] of the last write).
    pending: std::sync::Mutex<Option<HuntReport>>,
    failed: std::sync::Mutex<Option<String>>,
}

impl<'a> FolderWriter<'a> {
    /// How often a changing best is written at most.
    pub const EVERY: std::time::Duration = std::time::Duration::from_secs(2);

    /// A writer of `dir`.
    pub fn new(
        dir: &'a Path,
        hunt: &'a Hunt,
        registry: &'a Registry,
        html: Option<&'a HtmlWriter<'a>>,
    ) -> Self {
        FolderWriter {
            dir,
            hunt,
            registry,
            html,
            last: std::sync::Mutex::new(None),
            pending: std::sync::Mutex::new(None),
            failed: std::sync::Mutex::new(None),
        }
    }

    /// For [`HuntOptions::on_best`]: a counterexample is written at once, another best
    /// once [`FolderWriter::EVERY`] has passed since the last write (kept until then, and
    /// written by [`FolderWriter::on_progress`] or [`FolderWriter::finish`]).
    pub fn on_best(&self, report: &HuntReport) {
        let violated = report.best.as_ref().is_some_and(|b| b.evaluation.violated);
        let mut last = self.last.lock().unwrap_or_else(|p| p.into_inner());
        let mut pending = self.pending.lock().unwrap_or_else(|p| p.into_inner());
        if !violated && last.is_some_and(|t| t.elapsed() < Self::EVERY) {
            *pending = Some(report.clone());
            return;
        }
        *pending = None;
        *last = Some(std::time::Instant::now());
        self.write(report);
    }

    /// For [`HuntOptions::on_progress`]: writes a best kept back by
    /// [`FolderWriter::on_best`] once [`FolderWriter::EVERY`] has passed, so that the
    /// folder is never more than about that much behind the hunt.
    pub fn on_progress(&self) {
        let mut last = self.last.lock().unwrap_or_else(|p| p.into_inner());
        if last.is_some_and(|t| t.elapsed() < Self::EVERY) {
            return;
        }
        let pending = self
            .pending
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take();
        if let Some(report) = pending {
            *last = Some(std::time::Instant::now());
            self.write(&report);
        }
    }

    fn write(&self, report: &HuntReport) {
        if let Err(e) = write_found(self.dir, self.hunt, report, self.registry, self.html) {
            self.failed
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .get_or_insert(e);
        }
    }

    /// Writes the final report; the first failed write, if any.
    pub fn finish(self, report: &HuntReport) -> Result<(), String> {
        if let Some(e) = self.failed.into_inner().unwrap_or_else(|p| p.into_inner()) {
            return Err(e);
        }
        write_found(self.dir, self.hunt, report, self.registry, self.html)
    }
}
