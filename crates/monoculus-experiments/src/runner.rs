//! Running a sweep: every pending (cell, seed), in parallel, each row written the
//! moment its run finishes.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use glam::{DVec2, DVec3};
use monoculus_engine::{EngineError, IndexPoint, RunOutcome, Simulation};
use rayon::prelude::*;

use crate::config::{Cell, Experiment, RunId, SchedulerKind};
use crate::results::{OpenSpec, ResultsDir, ResultsError, param_values, run_row};
use crate::shard::{Shard, shard_runs};

/// Options of `monoculus run`.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Start over instead of resuming (a shard: only its own file).
    pub force: bool,
    /// Run only this shard's runs (see [`crate::shard::assign`]), into its own file.
    pub shard: Option<Shard>,
    /// The batch job, for provenance.
    pub job: Option<String>,
    /// Set from outside (a binding's Ctrl-C) to stop the sweep: runs not started are
    /// not started, running ones stop at the end of their round and are not written
    /// (so the folder resumes them).
    pub interrupt: Option<Arc<AtomicBool>>,
}

/// What a sweep did.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SweepReport {
    /// The file the rows went to (`runs.csv` or the shard's file).
    pub rows_path: PathBuf,
    /// Duplicated rows found when resuming, dropped.
    pub dropped_duplicates: usize,
    /// Runs in this shard of the experiment.
    pub total: usize,
    /// Runs already in `runs.csv`, skipped.
    pub skipped: usize,
    /// Runs done now.
    pub ran: usize,
    /// Runs whose algorithm failed (recorded in `failures.csv`, not in the rows): each
    /// with its cell's key and seed, and what happened.
    pub failed: Vec<(String, u64, String)>,
    /// Where the failures were recorded.
    pub failures_path: PathBuf,
    /// Whether the sweep was interrupted ([`RunOptions::interrupt`]) before every run
    /// was done.
    pub interrupted: bool,
}

/// Why a sweep failed.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The results folder.
    #[error(transparent)]
    Results(#[from] ResultsError),
    /// A run could not be built.
    #[error("cell {cell}, seed {seed}: {cause}")]
    Engine {
        /// Cell key.
        cell: String,
        /// Seed.
        seed: u64,
        /// Why.
        cause: EngineError,
    },
}

/// Where one run has got to: what [`Progress::round`] and [`Progress::finished`] are told.
#[derive(Clone, Copy, Debug)]
pub struct RunProgress<'a> {
    /// The cell's key.
    pub cell: &'a str,
    /// The seed.
    pub seed: u64,
    /// What a round is called: `"epoch"` under ASYNC, else `"round"`.
    pub unit: &'static str,
    /// Rounds (ASYNC: epochs) completed.
    pub round: u64,
    /// The swarm's diameter after them.
    pub diameter: f64,
    /// Time since the run started.
    pub elapsed: Duration,
}

/// What a sweep tells about its progress. Results never depend on it.
pub trait Progress: Sync {
    /// `done` of the `pending` runs have finished.
    fn runs(&self, done: usize, pending: usize);

    /// How often a running run reports its rounds to [`Progress::round`]; `None` (the
    /// default): never.
    fn interval(&self) -> Option<Duration> {
        None
    }

    /// A running run, at most once per [`Progress::interval`].
    fn round(&self, _at: &RunProgress<'_>) {}

    /// A run finished (its row is written), when [`Progress::interval`] is set, with its
    /// outcome (its verdict: `converged`, `stuck()`, `stopped_by`).
    fn finished(&self, _at: &RunProgress<'_>, _outcome: &RunOutcome) {}
}

/// No progress reports.
impl Progress for () {
    fn runs(&self, _done: usize, _pending: usize) {}
}

/// Runs one (cell, seed) and times it.
pub fn run_one(cell: &Cell, seed: u64) -> Result<(RunOutcome, f64), EngineError> {
    run_one_with(cell, seed, &mut |_, _| {})
}

/// Runs one (cell, seed) and times it, calling `on_round(rounds, diameter)` with the
/// start (0 rounds) and after every round (ASYNC: every epoch).
pub fn run_one_with(
    cell: &Cell,
    seed: u64,
    on_round: &mut dyn FnMut(u64, f64),
) -> Result<(RunOutcome, f64), EngineError> {
    run_one_stoppable(cell, seed, on_round, None)
}

/// [`run_one_with`], stopped at the end of a round once `interrupt` is set.
pub fn run_one_stoppable(
    cell: &Cell,
    seed: u64,
    on_round: &mut dyn FnMut(u64, f64),
    interrupt: Option<&Arc<AtomicBool>>,
) -> Result<(RunOutcome, f64), EngineError> {
    fn go<P: IndexPoint>(
        cell: &Cell,
        seed: u64,
        on_round: &mut dyn FnMut(u64, f64),
        interrupt: Option<&Arc<AtomicBool>>,
    ) -> Result<RunOutcome, EngineError> {
        with_simulation::<P, _>(cell.sim_config(seed), cell.initial_positions(seed), |sim| {
            if let Some(flag) = interrupt {
                sim.set_interrupt(flag.clone());
            }
            sim.run_with(|r| on_round(r.round, r.diameter))
        })
    }
    let start = Instant::now();
    let outcome = match cell.dim() {
        3 => go::<DVec3>(cell, seed, on_round, interrupt)?,
        _ => go::<DVec2>(cell, seed, on_round, interrupt)?,
    };
    Ok((outcome, start.elapsed().as_secs_f64() * 1e3))
}

thread_local! {
    /// The simulation of this thread's last small run (see [`with_simulation`]).
    static KEPT: std::cell::RefCell<Option<Box<dyn std::any::Any>>> =
        const { std::cell::RefCell::new(None) };
}

/// Runs `f` on a simulation of `config` from `initial`. A small run (at most
/// [`KEPT_ROBOTS`] robots) starts again in the world and schedule that its thread kept
/// from its last small run ([`Simulation::restart`], the same run bit for bit), so that
/// a sweep of small runs costs their activations rather than the making of a world and
/// a schedule for each; a larger run is made afresh and dropped. What the threads keep
/// is dropped by [`drop_kept`] when the sweep (or hunt) ends.
pub(crate) fn with_simulation<P: IndexPoint, R>(
    config: monoculus_engine::SimConfig,
    initial: Vec<P>,
    f: impl FnOnce(&mut Simulation<P>) -> R,
) -> Result<R, EngineError> {
    if initial.len() > KEPT_ROBOTS {
        let mut sim = Simulation::new(config, initial)?;
        return Ok(f(&mut sim));
    }
    let kept = KEPT
        .with_borrow_mut(Option::take)
        .and_then(|b| b.downcast::<Simulation<P>>().ok());
    let mut sim = match kept {
        Some(mut sim) => {
            sim.restart(config, initial)?;
            sim
        }
        None => Box::new(Simulation::new(config, initial)?),
    };
    let out = f(&mut sim);
    KEPT.with_borrow_mut(|k| *k = Some(sim));
    Ok(out)
}

/// Drops the simulations kept by the threads of the current pool, so that none outlives
/// the sweep or hunt that made it (its algorithm may be a binding's, whose objects are
/// dropped while the call lasts).
pub(crate) fn drop_kept() {
    rayon::broadcast(|_| KEPT.with_borrow_mut(|k| *k = None));
    KEPT.with_borrow_mut(|k| *k = None);
}

/// The most robots of a run whose world a thread keeps for the next.
pub(crate) const KEPT_ROBOTS: usize = 1024;

/// Runs one (cell, seed), telling `progress` where it is every `progress.interval()`.
fn run_reported(
    cell: &Cell,
    seed: u64,
    progress: &dyn Progress,
    interrupt: Option<&Arc<AtomicBool>>,
) -> Result<(RunOutcome, f64), EngineError> {
    let Some(every) = progress.interval() else {
        return run_one_stoppable(cell, seed, &mut |_, _| {}, interrupt);
    };
    let unit = match cell.spec.scheduler.kind {
        SchedulerKind::Async => "epoch",
        _ => "round",
    };
    let start = Instant::now();
    let mut due = start + every;
    let at = |round, diameter| RunProgress {
        cell: &cell.key,
        seed,
        unit,
        round,
        diameter,
        elapsed: start.elapsed(),
    };
    let (outcome, ms) = run_one_stoppable(
        cell,
        seed,
        &mut |round, diameter| {
            // One clock read a round: a few tens of nanoseconds against rounds of at least
            // microseconds.
            let now = Instant::now();
            if now >= due {
                due = now + every;
                progress.round(&at(round, diameter));
            }
        },
        interrupt,
    )?;
    progress.finished(&at(outcome.rounds, outcome.final_diameter), &outcome);
    Ok((outcome, ms))
}

/// Runs the experiment into `out`, telling `progress` after each run (and, if it asks,
/// during them).
pub fn run_experiment(
    exp: &Experiment,
    out: &Path,
    options: RunOptions,
    progress: &dyn Progress,
) -> Result<SweepReport, SweepError> {
    let results = ResultsDir::open(
        out,
        exp,
        &OpenSpec {
            shard: options.shard,
            force: options.force,
            job: options.job.clone(),
        },
    )?;
    let runs = shard_runs(exp, options.shard);
    let total = runs.len();
    let pending: Vec<RunId> = runs
        .into_iter()
        .filter(|r| !results.done.contains(r))
        .collect();
    let skipped = total - pending.len();
    let params: Vec<Vec<String>> = exp.cells.iter().map(|c| param_values(exp, c)).collect();
    let finished = AtomicUsize::new(0);
    let failure: Mutex<Option<SweepError>> = Mutex::new(None);
    let failed: Mutex<Vec<(RunId, String)>> = Mutex::new(Vec::new());
    progress.runs(0, pending.len());
    let interrupt = options.interrupt.as_ref();
    let stopped = || interrupt.is_some_and(|f| f.load(Ordering::Relaxed));
    pending.par_iter().with_max_len(1).for_each(|run| {
        if failure.lock().map(|f| f.is_some()).unwrap_or(true) || stopped() {
            return;
        }
        let cell = &exp.cells[run.cell];
        let result = run_reported(cell, run.seed, progress, interrupt)
            .map_err(|cause| SweepError::Engine {
                cell: cell.key.clone(),
                seed: run.seed,
                cause,
            })
            .and_then(|(outcome, ms)| match &outcome.failure {
                // Stopped from outside: not a result; a rerun resumes it.
                _ if outcome.interrupted() => Ok(false),
                // The algorithm failed: the run is recorded as such, the sweep goes on.
                Some(f) => {
                    results.fail(cell, run.seed, f)?;
                    failed
                        .lock()
                        .unwrap_or_else(|p| p.into_inner())
                        .push((*run, f.to_string()));
                    Ok(true)
                }
                None => {
                    results.append(
                        *run,
                        run_row(&params[run.cell], exp, cell, run.seed, &outcome, ms),
                    )?;
                    Ok(true)
                }
            });
        match result {
            Err(e) => {
                let mut f = failure.lock().unwrap_or_else(|p| p.into_inner());
                f.get_or_insert(e);
            }
            Ok(true) => {
                progress.runs(finished.fetch_add(1, Ordering::SeqCst) + 1, pending.len());
            }
            Ok(false) => {}
        }
    });
    drop_kept();
    if let Some(e) = failure.into_inner().unwrap_or_else(|p| p.into_inner()) {
        results.finish(exp)?;
        return Err(e);
    }
    results.finish(exp)?;
    let mut failed = failed.into_inner().unwrap_or_else(|p| p.into_inner());
    failed.sort_by_key(|(r, _)| (r.cell, r.seed));
    Ok(SweepReport {
        rows_path: results.rows_path().to_path_buf(),
        dropped_duplicates: results.dropped_duplicates,
        total,
        skipped,
        ran: finished.load(Ordering::SeqCst) - failed.len(),
        failed: failed
            .into_iter()
            .map(|(r, m)| (exp.cells[r.cell].key.clone(), r.seed, m))
            .collect(),
        failures_path: results.failures_path().to_path_buf(),
        interrupted: stopped(),
    })
}
