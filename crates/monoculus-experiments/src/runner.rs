//! Running a sweep: every pending (cell, seed), in parallel, each row written the
//! moment its run finishes.

use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use glam::{DVec2, DVec3};
use monoculus_engine::{EngineError, IndexPoint, RunOutcome, Simulation};
use rayon::prelude::*;

use crate::config::{Cell, Experiment, RunId};
use crate::results::{ResultsDir, ResultsError, run_row};

/// Options of `monoculus run`.
#[derive(Clone, Copy, Debug, Default)]
pub struct RunOptions {
    /// Start over instead of resuming.
    pub force: bool,
    /// Run only runs whose index k (cell-major, then seed) has k mod N == I.
    pub shard: Option<(usize, usize)>,
}

/// What a sweep did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SweepReport {
    /// Runs in this shard of the experiment.
    pub total: usize,
    /// Runs already in `runs.csv`, skipped.
    pub skipped: usize,
    /// Runs done now.
    pub ran: usize,
}

/// Why a sweep failed.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The results folder.
    #[error(transparent)]
    Results(#[from] ResultsError),
    /// A run could not be built.
    #[error("cell {cell}, seed {seed}: {source}")]
    Engine {
        /// Cell key.
        cell: String,
        /// Seed.
        seed: u64,
        /// Why.
        source: EngineError,
    },
}

/// Runs one (cell, seed) and times it.
pub fn run_one(cell: &Cell, seed: u64) -> Result<(RunOutcome, f64), EngineError> {
    fn go<P: IndexPoint>(cell: &Cell, seed: u64) -> Result<RunOutcome, EngineError> {
        Ok(Simulation::<P>::new(cell.sim_config(seed), cell.initial_positions(seed))?.run())
    }
    let start = Instant::now();
    let outcome = match cell.dim() {
        3 => go::<DVec3>(cell, seed)?,
        _ => go::<DVec2>(cell, seed)?,
    };
    Ok((outcome, start.elapsed().as_secs_f64() * 1e3))
}

/// The runs of this shard.
pub fn shard_runs(exp: &Experiment, shard: Option<(usize, usize)>) -> Vec<RunId> {
    exp.runs()
        .into_iter()
        .enumerate()
        .filter(|(k, _)| shard.is_none_or(|(i, n)| k % n == i))
        .map(|(_, r)| r)
        .collect()
}

/// Runs the experiment into `out`, calling `progress(done, pending)` after each run.
pub fn run_experiment(
    exp: &Experiment,
    out: &Path,
    options: RunOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<SweepReport, SweepError> {
    let results = ResultsDir::open(out, exp, options.force)?;
    let runs = shard_runs(exp, options.shard);
    let total = runs.len();
    let pending: Vec<RunId> = runs
        .into_iter()
        .filter(|r| {
            !results
                .done
                .contains(&(exp.cells[r.cell].key.clone(), r.seed))
        })
        .collect();
    let skipped = total - pending.len();
    let finished = AtomicUsize::new(0);
    let failure: Mutex<Option<SweepError>> = Mutex::new(None);
    progress(0, pending.len());
    pending.par_iter().with_max_len(1).for_each(|run| {
        if failure.lock().map(|f| f.is_some()).unwrap_or(true) {
            return;
        }
        let cell = &exp.cells[run.cell];
        let result = run_one(cell, run.seed)
            .map_err(|source| SweepError::Engine {
                cell: cell.key.clone(),
                seed: run.seed,
                source,
            })
            .and_then(|(outcome, ms)| {
                Ok(results.append(&run_row(exp, cell, run.seed, &outcome, ms))?)
            });
        if let Err(e) = result {
            let mut f = failure.lock().unwrap_or_else(|p| p.into_inner());
            f.get_or_insert(e);
            return;
        }
        progress(finished.fetch_add(1, Ordering::SeqCst) + 1, pending.len());
    });
    if let Some(e) = failure.into_inner().unwrap_or_else(|p| p.into_inner()) {
        results.finish(exp)?;
        return Err(e);
    }
    results.finish(exp)?;
    Ok(SweepReport {
        total,
        skipped,
        ran: pending.len(),
    })
}
