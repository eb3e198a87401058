//! The results folder: `config.toml`, `provenance.toml`, and the rows of the runs, either
//! in `runs.csv` (a whole run) or in one file per shard (`shards/I-of-N.csv`), each
//! appended run by run and resumable.
//!
//! No two processes ever write the same file: a whole run holds the folder's lock
//! exclusively; shards hold it shared, and each its own shard's lock exclusively.

use std::collections::HashSet;
use std::fs::{self, File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::fsio::{create_if_absent, io, write_atomic};
use super::lock::{Lock, LockKind, holder, take_exclusive};
use super::provenance::{Attempt, Provenance, this_build};
use super::record::runs_header;
use super::rows::{RunRows, read_rows, write_rows};
use super::summary::write_summary;
use crate::config::{Experiment, RunId};
use crate::shard::Shard;

/// A results-folder failure.
#[derive(Debug, thiserror::Error)]
pub enum ResultsError {
    /// Reading or writing failed.
    #[error("{}: {cause}", crate::one_line(path))]
    Io {
        /// The file.
        path: String,
        /// Why (shown in the message, so not a `source` that would print it twice).
        cause: std::io::Error,
    },
    /// The folder holds results of a different experiment or build.
    #[error("{}: {}", crate::one_line(path), crate::one_line(message))]
    Mismatch {
        /// The file.
        path: String,
        /// What differs.
        message: String,
    },
    /// A row of a results file is malformed.
    #[error("{}:{line}: {}", crate::one_line(path), crate::short_quotes(&crate::one_line(message)))]
    Corrupt {
        /// The file.
        path: String,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// Another process is writing into the folder or shard.
    #[error("{path}: in use by {holder}; wait for it to end, or use another --out")]
    Busy {
        /// The folder or shard file.
        path: String,
        /// Who holds it.
        holder: String,
    },
}

impl From<crate::output::OutputError> for ResultsError {
    fn from(e: crate::output::OutputError) -> Self {
        ResultsError::Io {
            path: e.path,
            cause: e.cause,
        }
    }
}

/// The folder's lock file.
pub const LOCK_FILE: &str = ".monoculus.lock";
/// The folder of shard files.
pub const SHARDS_DIR: &str = "shards";

/// The shard files present in `dir/shards`: (shard, rows file).
pub fn shard_files(dir: &Path) -> Result<Vec<(Shard, PathBuf)>, ResultsError> {
    let sd = dir.join(SHARDS_DIR);
    let entries = match fs::read_dir(&sd) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(io(&sd)(e)),
    };
    let mut out = Vec::new();
    for e in entries {
        let e = e.map_err(io(&sd))?;
        let name = e.file_name().to_string_lossy().into_owned();
        if let Some(stem) = name.strip_suffix(".csv")
            && let Some(s) = Shard::from_stem(stem)
        {
            out.push((s, e.path()));
        }
    }
    out.sort_by_key(|(s, _)| (s.count, s.index));
    Ok(out)
}

/// The files a run into `dir` may write (the shard's own with `shard`), each with its
/// name: what a command checks against its inputs before it starts.
pub fn folder_outputs(dir: &Path, shard: Option<Shard>) -> Vec<(String, PathBuf)> {
    let mut files: Vec<PathBuf> = ["config.toml", "runs.csv", "summary.csv", "provenance.toml"]
        .iter()
        .map(|f| dir.join(f))
        .collect();
    if let Some(s) = shard {
        let rows = dir.join(SHARDS_DIR).join(format!("{}.csv", s.stem()));
        files.push(rows.with_extension("toml"));
        files.push(rows);
    }
    files
        .into_iter()
        .map(|p| {
            (
                format!("--out's {}", p.strip_prefix(dir).unwrap_or(&p).display()),
                p,
            )
        })
        .collect()
}

/// Who holds the folder: the shards running in it, or the holder of its lock.
pub fn who_holds(dir: &Path) -> String {
    let mut running = Vec::new();
    if let Ok(files) = shard_files(dir) {
        for (s, path) in files {
            let lock = path.with_extension("lock");
            if Lock::is_held(&lock) {
                let who = holder(&lock).unwrap_or_else(|| "a process".into());
                running.push(format!("shard {s} ({who})"));
            }
        }
    }
    if running.is_empty() {
        holder(&dir.join(LOCK_FILE)).unwrap_or_else(|| "another process".into())
    } else {
        running.join(", ")
    }
}

/// Takes the folder's lock: exclusive for a whole run or a merge, shared for a shard.
pub fn lock_folder(dir: &Path, kind: LockKind, who: &str) -> Result<Lock, ResultsError> {
    Lock::try_take(&dir.join(LOCK_FILE), kind, who)?.ok_or_else(|| ResultsError::Busy {
        path: dir.display().to_string(),
        holder: who_holds(dir),
    })
}

/// Writes `config.toml` if the folder has none (safe when many shards start at once), or
/// checks that it holds this experiment.
fn settle_config(
    dir: &Path,
    exp: &Experiment,
    replace: bool,
    advice: &str,
) -> Result<(), ResultsError> {
    let config = dir.join("config.toml");
    if replace {
        return write_atomic(&config, exp.resolved.as_bytes());
    }
    if !create_if_absent(&config, exp.resolved.as_bytes())? {
        let old = fs::read_to_string(&config).map_err(io(&config))?;
        if old != exp.resolved {
            return Err(ResultsError::Mismatch {
                path: config.display().to_string(),
                message: match exp.changed_input(&old) {
                    Some(changed) => changed,
                    None => format!("holds a different experiment; {advice}"),
                },
            });
        }
    }
    Ok(())
}

/// Removes the temporary files a killed process left in `dir` for files whose name starts
/// with `prefix` (called with the lock on those files held, so none is in use).
fn remove_stale_temporaries(dir: &Path, prefix: &str) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with(&format!(".{prefix}")) && name.ends_with(".tmp") {
            let _ = fs::remove_file(e.path());
        }
    }
}

fn remove_if_present(path: &Path) -> Result<(), ResultsError> {
    match fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(io(path)(e)),
        _ => Ok(()),
    }
}

/// How a results folder is opened.
#[derive(Clone, Debug, Default)]
pub struct OpenSpec {
    /// Write one shard's file instead of `runs.csv`.
    pub shard: Option<Shard>,
    /// Start over (a whole run: the whole folder; a shard: its own file).
    pub force: bool,
    /// The batch job, for provenance.
    pub job: Option<String>,
}

/// An open results folder, locked for this process.
pub struct ResultsDir {
    dir: PathBuf,
    rows_path: PathBuf,
    shard: Option<Shard>,
    runs: Mutex<Appender>,
    failures_path: PathBuf,
    failures: Mutex<Option<File>>,
    /// The runs already in the rows file.
    pub done: HashSet<RunId>,
    /// Duplicated rows found (and dropped) when resuming.
    pub dropped_duplicates: usize,
    _locks: Vec<Lock>,
}

/// The rows file, open for appending, and (for a whole run) every row it holds: those
/// checked when the folder was opened and those appended since. No other process writes
/// the file while the folder is locked, so the summary is made from these rows without
/// reading the file back.
struct Appender {
    file: File,
    rows: Option<RunRows>,
    /// The line being written (its buffer kept from row to row).
    line: Vec<u8>,
}

impl ResultsDir {
    /// Opens (creating) the folder for `exp`, locked. Without `force`, a folder holding
    /// another experiment or rows of another build is refused and finished runs are kept;
    /// with `force`, it starts over.
    pub fn open(dir: &Path, exp: &Experiment, spec: &OpenSpec) -> Result<ResultsDir, ResultsError> {
        fs::create_dir_all(dir).map_err(io(dir))?;
        let attempt = Attempt::this_process(spec.shard.map(|s| s.to_string()), spec.job.clone());
        let who = attempt.describe();
        let mut locks = Vec::new();
        let (rows_path, record_path) = match spec.shard {
            None => {
                locks.push(lock_folder(dir, LockKind::Exclusive, &who)?);
                remove_stale_temporaries(dir, "");
                settle_config(
                    dir,
                    exp,
                    spec.force,
                    "use --force to start over, or another --out",
                )?;
                let runs = dir.join("runs.csv");
                if spec.force {
                    let sd = dir.join(SHARDS_DIR);
                    if sd.exists() {
                        fs::remove_dir_all(&sd).map_err(io(&sd))?;
                    }
                    for f in ["runs.csv", "summary.csv", "provenance.toml"] {
                        remove_if_present(&dir.join(f))?;
                    }
                } else if !shard_files(dir)?.is_empty() && !complete(&runs, exp)? {
                    return Err(ResultsError::Mismatch {
                        path: dir.join(SHARDS_DIR).display().to_string(),
                        message: "holds shard files: finish them (run --shard I/N) and `monoculus merge` the folder, or use --force to start over".into(),
                    });
                }
                (runs, dir.join("provenance.toml"))
            }
            Some(s) => {
                locks.push(lock_folder(dir, LockKind::Shared, &who)?);
                settle_config(
                    dir,
                    exp,
                    false,
                    "a shard cannot replace it: use another --out",
                )?;
                let sd = dir.join(SHARDS_DIR);
                fs::create_dir_all(&sd).map_err(io(&sd))?;
                if let Some((other, path)) = shard_files(dir)?
                    .into_iter()
                    .find(|(o, _)| o.count != s.count)
                {
                    return Err(ResultsError::Mismatch {
                        path: path.display().to_string(),
                        message: format!(
                            "is shard {other} of a split into {} shards, this is {s}; use the same N for every shard, or another --out",
                            other.count
                        ),
                    });
                }
                let rows = sd.join(format!("{}.csv", s.stem()));
                locks.push(take_exclusive(&rows.with_extension("lock"), &rows, &who)?);
                remove_stale_temporaries(&sd, &s.stem());
                if spec.force {
                    remove_if_present(&rows)?;
                    remove_if_present(&rows.with_extension("toml"))?;
                }
                (rows.clone(), rows.with_extension("toml"))
            }
        };
        // Provenance: rows are continued only by the build that wrote them.
        let mut record = Provenance::new(exp);
        if let Some(old) = Provenance::read(&record_path)? {
            if !old.is_this_build() && rows_path.exists() {
                return Err(ResultsError::Mismatch {
                    path: rows_path.display().to_string(),
                    message: format!(
                        "was written by {}, this is {}; use --force to start over",
                        old.build(),
                        this_build()
                    ),
                });
            }
            if old.config_hash == record.config_hash {
                record.attempts = old.attempts;
            }
        }
        record.attempts.push(attempt);
        record.write(&record_path)?;

        let header = runs_header(exp);
        let mut done = HashSet::new();
        let mut dropped_duplicates = 0;
        let mut kept = RunRows::empty(header.clone());
        if rows_path.exists() {
            let found = read_rows(&rows_path)?;
            let (partial, headless) = (found.partial, found.header.is_empty());
            let mut rows = found.check(exp, &rows_path)?;
            let before = rows.rows.len();
            rows.dedup();
            dropped_duplicates = before - rows.rows.len();
            if partial || dropped_duplicates > 0 || rows.rows.is_empty() && headless {
                write_rows(&rows_path, &header, &rows.rows)?;
            }
            done = rows.ids.iter().copied().collect();
            kept = rows;
        } else {
            write_rows(&rows_path, &header, &[])?;
        }
        let file = OpenOptions::new()
            .append(true)
            .open(&rows_path)
            .map_err(io(&rows_path))?;
        // The failures of this attempt only: the failed runs of an earlier one are not in
        // the rows, so they run again, and fail again or not.
        let failures_path = failures_path(&rows_path);
        remove_if_present(&failures_path)?;
        Ok(ResultsDir {
            dir: dir.to_path_buf(),
            failures_path,
            failures: Mutex::new(None),
            rows_path,
            shard: spec.shard,
            runs: Mutex::new(Appender {
                file,
                rows: spec.shard.is_none().then_some(kept),
                line: Vec::with_capacity(512),
            }),
            done,
            dropped_duplicates,
            _locks: locks,
        })
    }

    /// The file rows are appended to.
    pub fn rows_path(&self) -> &Path {
        &self.rows_path
    }

    /// Appends one finished run, `row` (as [`run_row`](super::run_row) gives it): one
    /// `write` call, flushed at once, so a killed sweep keeps every finished row.
    pub fn append(&self, run: RunId, row: csv::StringRecord) -> Result<(), ResultsError> {
        let mut guard = self.runs.lock().unwrap_or_else(|p| p.into_inner());
        let appender = &mut *guard;
        appender.line.clear();
        super::text::push_record(&mut appender.line, &row);
        (appender.file.write_all(&appender.line))
            .and_then(|()| appender.file.flush())
            .map_err(io(&self.rows_path))?;
        if let Some(rows) = &mut appender.rows {
            rows.push(run, row);
        }
        Ok(())
    }

    /// Records a run whose algorithm failed (appended to `failures.csv`, or the shard's
    /// `I-of-N.failures.csv`, at once): its cell, seed, algorithm, robot, round and what
    /// happened.
    pub fn fail(
        &self,
        cell: &crate::Cell,
        seed: u64,
        failure: &monoculus_engine::RunFailure,
    ) -> Result<(), ResultsError> {
        let mut f = self.failures.lock().unwrap_or_else(|p| p.into_inner());
        if f.is_none() {
            let mut file = OpenOptions::new()
                .create(true)
                .append(true)
                .open(&self.failures_path)
                .map_err(io(&self.failures_path))?;
            file.write_all(&super::rows::line_of(FAILURE_COLUMNS))
                .map_err(io(&self.failures_path))?;
            *f = Some(file);
        }
        let row = [
            cell.key.clone(),
            seed.to_string(),
            cell.algorithm().name().to_string(),
            failure.robot.to_string(),
            failure.round.to_string(),
            failure.message.clone(),
        ];
        let file = f.as_mut().expect("opened above");
        file.write_all(&super::rows::line_of(&row))
            .map_err(io(&self.failures_path))?;
        file.flush().map_err(io(&self.failures_path))
    }

    /// The file failed runs are recorded in.
    pub fn failures_path(&self) -> &Path {
        &self.failures_path
    }

    /// A whole run: writes `summary.csv` from every row (those found when the folder was
    /// opened and those appended since), and, once every run of the
    /// experiment is there, rewrites `runs.csv` sorted by cell and seed (the same file
    /// whatever order runs finished in). A shard writes nothing more: `merge` does.
    pub fn finish(&self, exp: &Experiment) -> Result<(), ResultsError> {
        if self.shard.is_some() {
            return Ok(());
        }
        let mut guard = self.runs.lock().unwrap_or_else(|p| p.into_inner());
        let rows = guard.rows.as_mut().expect("a whole run keeps its rows");
        write_summary(&self.dir.join("summary.csv"), exp, rows)?;
        if rows.is_complete(exp) && rows.sort() {
            write_rows(&self.rows_path, &runs_header(exp), &rows.rows)?;
        }
        Ok(())
    }
}

/// The columns of `failures.csv`.
pub const FAILURE_COLUMNS: [&str; 6] = ["cell", "seed", "algorithm", "robot", "round", "message"];

/// The failures file beside a rows file: `runs.csv` -> `failures.csv`,
/// `shards/0-of-4.csv` -> `shards/0-of-4.failures.csv`.
pub fn failures_path(rows: &Path) -> PathBuf {
    if rows.file_name().is_some_and(|n| n == "runs.csv") {
        rows.with_file_name("failures.csv")
    } else {
        rows.with_extension("failures.csv")
    }
}

/// Whether `runs` holds every run of `exp` (so that shards, if any, were merged).
fn complete(runs: &Path, exp: &Experiment) -> Result<bool, ResultsError> {
    if !runs.exists() {
        return Ok(false);
    }
    let rows: RunRows = read_rows(runs)?.check(exp, runs)?;
    Ok(rows.is_complete(exp))
}
