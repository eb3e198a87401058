//! The CSV of `monoculus stress --csv FILE`: one row per measurement, appended and flushed
//! as each ends, resumable, locked against a second writer. With a shard, rows go to a
//! file of the shard's own (`FILE` = `stress.csv` gives `stress.2-of-4.csv`), and
//! [`merge_stress`] joins the shard files into `FILE`, checked complete.

use std::collections::HashSet;
use std::fs::{self, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::{Deserialize, Serialize};

use super::ResultsError;
use super::fsio::{create_if_absent, io, read_complete_lines, write_atomic};
use super::lock::{Lock, ensure_free, take_exclusive};
use crate::shard::Shard;

/// One measurement of `monoculus stress`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StressRow {
    /// Its index in the sweep (n-major, then threads).
    pub measurement: usize,
    /// Measurements in the sweep.
    pub measurements: usize,
    /// Robots.
    pub n: usize,
    /// Worker threads.
    pub threads: usize,
    /// Algorithm.
    pub algorithm: String,
    /// Scheduler.
    pub scheduler: String,
    /// Visibility backend: `index` (band grid in the plane, R-tree in space), `rtree`
    /// or `exact`.
    pub backend: String,
    /// ASYNC: the phase durations (`idle=uniform:1:10 compute=uniform:1:5 move=exp:4
    /// start=random`); empty otherwise.
    pub timing: String,
    /// Start configuration.
    pub init: String,
    /// Seed.
    pub seed: u64,
    /// Rounds timed (ASYNC: epochs).
    pub rounds: u64,
    /// Building the swarm and the simulation, seconds.
    pub setup_s: f64,
    /// All timed rounds, seconds.
    pub total_s: f64,
    /// The fastest round, seconds.
    pub round_s_min: f64,
    /// The median round, seconds.
    pub round_s_median: f64,
    /// The slowest round, seconds.
    pub round_s_max: f64,
    /// Activations in the timed rounds.
    pub activations: u64,
    /// activations / total_s.
    pub activations_per_s: f64,
    /// Peak resident memory during this measurement, MB (empty where unknown).
    pub peak_memory_mb: Option<f64>,
    /// Host.
    pub host: String,
    /// Batch job, if any.
    pub job: Option<String>,
    /// monoculus version.
    pub monoculus_version: String,
    /// Its git commit.
    pub git_commit: String,
}

/// What identifies a measurement for resuming: index, count, n, threads, algorithm,
/// backend, init, seed, rounds.
pub type MeasurementKey = (usize, usize, usize, usize, String, String, String, u64, u64);

impl StressRow {
    /// What identifies a measurement for resuming.
    pub fn key(&self) -> MeasurementKey {
        (
            self.measurement,
            self.measurements,
            self.n,
            self.threads,
            self.algorithm.clone(),
            self.backend.clone(),
            self.init.clone(),
            self.seed,
            self.rounds,
        )
    }
}

/// The file a shard of a stress sweep writes: `stress.csv` -> `stress.2-of-4.csv`.
pub fn stress_shard_path(path: &Path, shard: Shard) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(|| "stress".into(), |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map_or_else(|| "csv".into(), |s| s.to_string_lossy().into_owned());
    path.with_file_name(format!("{stem}.{}.{ext}", shard.stem()))
}

fn header() -> Vec<u8> {
    let mut w = csv::Writer::from_writer(vec![]);
    w.serialize(StressRow::default()).expect("memory");
    let bytes = w.into_inner().expect("memory");
    let end = bytes
        .iter()
        .position(|&b| b == b'\n')
        .expect("a header line")
        + 1;
    bytes[..end].to_vec()
}

fn row_bytes(row: &StressRow) -> Vec<u8> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(vec![]);
    w.serialize(row).expect("memory");
    w.into_inner().expect("memory")
}

/// Reads a stress CSV: its rows (a last line cut short left out) and whether one was.
pub fn read_stress(path: &Path) -> Result<(Vec<StressRow>, bool), ResultsError> {
    let (bytes, cut) = read_complete_lines(path)?;
    if bytes.is_empty() {
        return Ok((Vec::new(), cut));
    }
    if !bytes.starts_with(&header()) {
        return Err(ResultsError::Mismatch {
            path: path.display().to_string(),
            message: "is not a monoculus stress CSV of this version (its header differs); use another --csv".into(),
        });
    }
    let mut reader = csv::Reader::from_reader(bytes.as_slice());
    let mut rows = Vec::new();
    for r in reader.deserialize() {
        rows.push(r.map_err(|e: csv::Error| ResultsError::Corrupt {
            path: path.display().to_string(),
            line: e.position().map_or(0, |p| p.line() as usize),
            message: e.to_string(),
        })?);
    }
    Ok((rows, cut))
}

fn write_stress(path: &Path, rows: &[StressRow]) -> Result<(), ResultsError> {
    let mut bytes = header();
    for r in rows {
        bytes.extend(row_bytes(r));
    }
    write_atomic(path, &bytes)
}

/// An open stress CSV, locked for this process.
pub struct StressLog {
    path: PathBuf,
    file: Mutex<fs::File>,
    /// Measurements already in the file.
    pub done: HashSet<MeasurementKey>,
    _lock: Lock,
}

impl StressLog {
    /// Opens (creating) `path` for appending, refusing a second writer.
    pub fn open(path: &Path, who: &str) -> Result<StressLog, ResultsError> {
        if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            fs::create_dir_all(parent).map_err(io(parent))?;
        }
        let lock = take_exclusive(&path.with_extension("lock"), path, who)?;
        create_if_absent(path, &header())?;
        let (rows, cut) = read_stress(path)?;
        if cut || fs::metadata(path).map_err(io(path))?.len() == 0 {
            write_stress(path, &rows)?;
        }
        let file = OpenOptions::new()
            .append(true)
            .open(path)
            .map_err(io(path))?;
        Ok(StressLog {
            path: path.to_path_buf(),
            file: Mutex::new(file),
            done: rows.iter().map(StressRow::key).collect(),
            _lock: lock,
        })
    }

    /// Appends one measurement, flushed.
    pub fn append(&self, row: &StressRow) -> Result<(), ResultsError> {
        let mut f = self.file.lock().unwrap_or_else(|p| p.into_inner());
        f.write_all(&row_bytes(row)).map_err(io(&self.path))?;
        f.flush().map_err(io(&self.path))
    }
}

/// What [`merge_stress`] found.
#[derive(Clone, Debug, PartialEq)]
pub struct StressMerge {
    /// Shard files read.
    pub files: Vec<PathBuf>,
    /// Measurements in the sweep.
    pub total: usize,
    /// Measurement indices missing.
    pub missing: Vec<usize>,
    /// Whether `path` was written.
    pub written: bool,
}

/// Joins the shard files of the stress CSV `path` (`stress.I-of-N.csv` beside it) into
/// `path`, sorted by measurement; writes nothing when measurements are missing unless
/// `partial`.
pub fn merge_stress(path: &Path, partial: bool) -> Result<StressMerge, ResultsError> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let stem = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map_or_else(|| "csv".into(), |s| s.to_string_lossy().into_owned());
    let mut files = Vec::new();
    for e in fs::read_dir(&dir).map_err(io(&dir))? {
        let e = e.map_err(io(&dir))?;
        let name = e.file_name().to_string_lossy().into_owned();
        if let Some(mid) = name
            .strip_prefix(&format!("{stem}."))
            .and_then(|r| r.strip_suffix(&format!(".{ext}")))
            && Shard::from_stem(mid).is_some()
        {
            files.push(e.path());
        }
    }
    files.sort();
    if files.is_empty() {
        return Err(ResultsError::Mismatch {
            path: path.display().to_string(),
            message: format!(
                "no shard files beside it ({stem}.I-of-N.{ext}): run `monoculus stress ... --csv {} --shard I/N` first",
                path.display()
            ),
        });
    }
    let mut rows: Vec<StressRow> = Vec::new();
    let mut total = None;
    for f in &files {
        ensure_free(&f.with_extension("lock"), f)?;
        let (r, _) = read_stress(f)?;
        for row in r {
            if *total.get_or_insert(row.measurements) != row.measurements {
                return Err(ResultsError::Mismatch {
                    path: f.display().to_string(),
                    message: "its measurements are of another sweep (another measurement count)"
                        .into(),
                });
            }
            if let Some(other) = rows.iter().find(|o| o.measurement == row.measurement) {
                if other.key() != row.key() {
                    return Err(ResultsError::Mismatch {
                        path: f.display().to_string(),
                        message: format!(
                            "measurement {} differs from the one in another shard file (another sweep)",
                            row.measurement
                        ),
                    });
                }
                continue;
            }
            rows.push(row);
        }
    }
    let total = total.unwrap_or(0);
    rows.sort_by_key(|r| r.measurement);
    let missing: Vec<usize> = (0..total)
        .filter(|k| rows.binary_search_by_key(k, |r| r.measurement).is_err())
        .collect();
    let written = partial || (missing.is_empty() && total > 0);
    if written {
        write_stress(path, &rows)?;
    }
    Ok(StressMerge {
        files,
        total,
        missing,
        written,
    })
}
