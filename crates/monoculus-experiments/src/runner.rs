//! Running a sweep: every pending (cell, seed), in parallel, each row written the
//! moment its run finishes.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use glam::{DVec2, DVec3};
use monoculus_engine::{EngineError, IndexPoint, RunOutcome, Simulation};
use rayon::prelude::*;

use crate::config::{Cell, Experiment, RunId};
use crate::results::{OpenSpec, ResultsDir, ResultsError, run_row};
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

/// Runs the experiment into `out`, calling `progress(done, pending)` after each run.
pub fn run_experiment(
    exp: &Experiment,
    out: &Path,
    options: RunOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
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
    let finished = AtomicUsize::new(0);
    let failure: Mutex<Option<SweepError>> = Mutex::new(None);
    progress(0, pending.len());
    pending.par_iter().with_max_len(1).for_each(|run| {
        if failure.lock().map(|f| f.is_some()).unwrap_or(true) {
            return;
        }
        let cell = &exp.cells[run.cell];
        let result = run_one(cell, run.seed)
            .map_err(|cause| SweepError::Engine {
                cell: cell.key.clone(),
                seed: run.seed,
                cause,
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
        rows_path: results.rows_path().to_path_buf(),
        dropped_duplicates: results.dropped_duplicates,
        total,
        skipped,
        ran: pending.len(),
    })
}
