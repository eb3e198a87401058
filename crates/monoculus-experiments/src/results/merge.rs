//! `monoculus merge DIR`: the shard files of a results folder into `runs.csv` and
//! `summary.csv`, checked to hold every run of the experiment exactly once.

use std::collections::HashMap;
use std::fs;
use std::path::{Path, PathBuf};

use super::ResultsError;
use super::fsio::io;
use super::fsio::write_atomic;
use super::lock::LockKind;
use super::provenance::{Attempt, Provenance, config_hash, this_build};
use super::record::runs_header;
use super::rows::{RunRows, read_rows, write_rows};
use super::store::{SHARDS_DIR, lock_folder, shard_files};
use super::summary::summary_bytes;
use crate::config::{Experiment, RunId};
use crate::shard::{Shard, assign};

/// The runs one shard lacks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MissingRuns {
    /// The shard.
    pub shard: Shard,
    /// Its rows file, if it was ever started.
    pub file: Option<PathBuf>,
    /// Runs assigned to it.
    pub assigned: usize,
    /// Those not in its file.
    pub missing: Vec<RunId>,
}

/// What a merge found and did.
#[derive(Clone, Debug)]
pub struct MergeReport {
    /// The experiment, as `config.toml` holds it.
    pub experiment: Experiment,
    /// Into how many shards the runs were split.
    pub shards: usize,
    /// Runs of the experiment.
    pub total: usize,
    /// Runs found.
    pub present: usize,
    /// Shards lacking runs.
    pub missing: Vec<MissingRuns>,
    /// Partial last lines (a task killed mid-write) left out: (file, line).
    pub cut_lines: Vec<(PathBuf, usize)>,
    /// Whether `runs.csv` and `summary.csv` were written.
    pub written: bool,
}

fn mismatch(path: &Path, message: impl Into<String>) -> ResultsError {
    ResultsError::Mismatch {
        path: path.display().to_string(),
        message: message.into(),
    }
}

/// Rebuilds the experiment of a shard record, checked to be the one `config.toml` holds.
fn load_experiment(
    dir: &Path,
    text: &str,
    (record, record_path): (&Provenance, &Path),
    registry: &crate::Registry,
) -> Result<Experiment, ResultsError> {
    let path = dir.join("config.toml");
    let exp = record
        .experiment(&record_path.display().to_string(), registry)
        .map_err(|e| mismatch(record_path, format!("its config cannot be read back: {e}")))?;
    if exp.resolved != text {
        return Err(mismatch(
            &path,
            exp.changed_input(text).unwrap_or_else(|| {
                format!(
                    "is not the experiment {} ran (another config or another monoculus)",
                    record_path.display()
                )
            }),
        ));
    }
    Ok(exp)
}

/// Merges the shard files of `dir`. With `partial`, writes what is there even if runs
/// are missing; without, writes nothing then. `job` is the batch job, for provenance;
/// `registry` resolves the config's algorithms.
pub fn merge(
    dir: &Path,
    partial: bool,
    job: Option<String>,
    registry: &crate::Registry,
) -> Result<MergeReport, ResultsError> {
    let attempt = Attempt::this_process(Some("merge".into()), job);
    let _lock = lock_folder(dir, LockKind::Exclusive, &attempt.describe())?;
    let files = shard_files(dir)?;
    let Some(&(first, _)) = files.first() else {
        return Err(mismatch(
            &dir.join(SHARDS_DIR),
            "holds no shard files (shards/I-of-N.csv): run the shards with `monoculus run CONFIG --out DIR --shard I/N` first",
        ));
    };
    let count = first.count;
    if let Some((other, path)) = files.iter().find(|(s, _)| s.count != count) {
        return Err(mismatch(
            path,
            format!("is shard {other}, another is of a split into {count} shards; keep one split"),
        ));
    }
    let config_text =
        fs::read_to_string(dir.join("config.toml")).map_err(io(&dir.join("config.toml")))?;
    let hash = config_hash(&config_text);
    let mut records = Vec::new();
    for (s, path) in &files {
        let record_path = path.with_extension("toml");
        let record = Provenance::read(&record_path)?.ok_or_else(|| {
            mismatch(
                &record_path,
                format!("is missing: shard {s} has no provenance"),
            )
        })?;
        if record.config_hash != hash {
            return Err(mismatch(
                &record_path,
                format!(
                    "shard {s} ran another config (hash {}, config.toml's is {hash})",
                    record.config_hash
                ),
            ));
        }
        if !record.is_this_build() {
            return Err(mismatch(
                &record_path,
                format!(
                    "shard {s} was run by {}, this is {}; rerun it with --force, or merge with that build",
                    record.build(),
                    this_build()
                ),
            ));
        }
        records.push((record, record_path));
    }
    let exp = load_experiment(dir, &config_text, (&records[0].0, &records[0].1), registry)?;
    let runs = exp.runs();
    let of = assign(&exp, count);
    let share: HashMap<RunId, usize> = runs.iter().copied().zip(of.iter().copied()).collect();
    // Every row checked before anything is written: its run, its parameters and metrics
    // (`check`), its shard, and that no other row is that run.
    let mut all: Option<RunRows> = None;
    let mut origin: HashMap<RunId, (PathBuf, usize)> = HashMap::new();
    let mut cut_lines = Vec::new();
    for (shard, path) in &files {
        let found = read_rows(path)?;
        if found.partial {
            cut_lines.push((path.clone(), found.rows.len() + 2));
        }
        let rows = found.check(&exp, path)?;
        for (id, &line) in rows.ids.iter().zip(&rows.lines) {
            if share[id] != shard.index {
                return Err(ResultsError::Corrupt {
                    path: path.display().to_string(),
                    line,
                    message: format!(
                        "cell {}, seed {} is a run of shard {}/{count}, not of shard {shard}: this file holds another shard's rows",
                        crate::shown(&exp.cells[id.cell].key),
                        id.seed,
                        share[id]
                    ),
                });
            }
            if let Some((other, other_line)) = origin.insert(*id, (path.clone(), line)) {
                return Err(ResultsError::Corrupt {
                    path: path.display().to_string(),
                    line,
                    message: format!(
                        "cell {}, seed {} is also at {}:{other_line}; each run must be in the results once",
                        crate::shown(&exp.cells[id.cell].key),
                        id.seed,
                        other.display()
                    ),
                });
            }
        }
        match &mut all {
            None => all = Some(rows),
            Some(a) => a.extend(rows),
        }
    }
    let mut rows = all.expect("at least one shard file");
    let by_path: HashMap<usize, PathBuf> =
        files.iter().map(|(s, p)| (s.index, p.clone())).collect();
    let mut missing = Vec::new();
    for index in 0..count {
        let assigned: Vec<RunId> = runs
            .iter()
            .zip(&of)
            .filter(|&(_, &k)| k == index)
            .map(|(r, _)| *r)
            .collect();
        let lacking: Vec<RunId> = assigned
            .iter()
            .filter(|r| !origin.contains_key(r))
            .copied()
            .collect();
        if !lacking.is_empty() {
            missing.push(MissingRuns {
                shard: Shard { index, count },
                file: by_path.get(&index).cloned(),
                assigned: assigned.len(),
                missing: lacking,
            });
        }
    }
    let absent: usize = missing.iter().map(|m| m.missing.len()).sum();
    let written = absent == 0 || partial;
    if written {
        rows.sort();
        let summary = summary_bytes(&exp, &rows);
        let mut merged = Provenance::new(&exp);
        merged.missing_runs = absent as u64;
        for (r, _) in records {
            merged.attempts.extend(r.attempts);
        }
        merged.attempts.push(attempt);
        write_rows(&dir.join("runs.csv"), &runs_header(&exp), &rows.rows)?;
        write_atomic(&dir.join("summary.csv"), &summary)?;
        merged.write(&dir.join("provenance.toml"))?;
    }
    Ok(MergeReport {
        shards: count,
        total: runs.len(),
        present: origin.len(),
        missing,
        cut_lines,
        written,
        experiment: exp,
    })
}
