//! The results folder: `config.toml`, `runs.csv` (appended run by run, resumable),
//! `summary.csv`.

use std::collections::{HashMap, HashSet};
use std::fs::{self, File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::record::{param_header, param_values, runs_header};
use super::summary::{CellStats, summary_header, summary_row};
use crate::config::Experiment;

/// A results-folder failure.
#[derive(Debug, thiserror::Error)]
pub enum ResultsError {
    /// Reading or writing failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// The folder holds results of a different experiment.
    #[error("{path}: {message}")]
    Mismatch {
        /// The file.
        path: String,
        /// What differs.
        message: String,
    },
    /// A row of `runs.csv` is malformed.
    #[error("{path}:{line}: {message}")]
    Corrupt {
        /// The file.
        path: String,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> ResultsError + '_ {
    move |source| ResultsError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Writes `text` to `path` atomically (temporary file, then rename).
pub fn write_atomic(path: &Path, text: &[u8]) -> Result<(), ResultsError> {
    let tmp = path.with_extension("tmp");
    fs::write(&tmp, text).map_err(io(&tmp))?;
    fs::rename(&tmp, path).map_err(io(path))
}

/// An open results folder.
pub struct ResultsDir {
    dir: PathBuf,
    header: Vec<String>,
    runs: Mutex<File>,
    /// (cell key, seed) of the runs already in `runs.csv`.
    pub done: HashSet<(String, u64)>,
}

fn line_of(record: &[String]) -> Vec<u8> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(vec![]);
    w.write_record(record).expect("writing to memory");
    w.into_inner().expect("writing to memory")
}

/// Reads `runs.csv`: header and rows. A last line cut short by a kill is dropped (and
/// truncated away when `repair`).
fn read_runs(path: &Path, repair: bool) -> Result<(Vec<String>, Vec<Vec<String>>), ResultsError> {
    let mut bytes = fs::read(path).map_err(io(path))?;
    if let Some(last_newline) = bytes.iter().rposition(|&b| b == b'\n') {
        if last_newline + 1 != bytes.len() {
            bytes.truncate(last_newline + 1);
            if repair {
                fs::write(path, &bytes).map_err(io(path))?;
            }
        }
    } else {
        bytes.clear();
    }
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(bytes.as_slice());
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| ResultsError::Corrupt {
            path: path.display().to_string(),
            line: 1,
            message: e.to_string(),
        })?
        .iter()
        .map(String::from)
        .collect();
    let mut rows = Vec::new();
    for r in reader.records() {
        let r = r.map_err(|e| ResultsError::Corrupt {
            path: path.display().to_string(),
            line: e.position().map_or(0, |p| p.line() as usize),
            message: e.to_string(),
        })?;
        rows.push(r.iter().map(String::from).collect());
    }
    Ok((header, rows))
}

impl ResultsDir {
    /// Opens (creating) the folder for `exp`. Without `force`, a folder holding another
    /// experiment is refused and finished runs are kept; with `force`, it starts over.
    pub fn open(dir: &Path, exp: &Experiment, force: bool) -> Result<ResultsDir, ResultsError> {
        fs::create_dir_all(dir).map_err(io(dir))?;
        let config = dir.join("config.toml");
        let runs = dir.join("runs.csv");
        if !force && config.exists() {
            let old = fs::read_to_string(&config).map_err(io(&config))?;
            if old != exp.resolved {
                return Err(ResultsError::Mismatch {
                    path: config.display().to_string(),
                    message:
                        "holds a different experiment; use --force to start over, or another --out"
                            .into(),
                });
            }
        }
        write_atomic(&config, exp.resolved.as_bytes())?;
        let header = runs_header(exp);
        let mut done = HashSet::new();
        if force || !runs.exists() {
            fs::write(&runs, line_of(&header)).map_err(io(&runs))?;
        } else {
            let (old_header, rows) = read_runs(&runs, true)?;
            if old_header.is_empty() {
                fs::write(&runs, line_of(&header)).map_err(io(&runs))?;
            } else if old_header != header {
                return Err(ResultsError::Mismatch {
                    path: runs.display().to_string(),
                    message: "its columns differ from this experiment's; use --force to start over, or another --out".into(),
                });
            }
            let (ci, si) = (col(&header, "cell"), col(&header, "seed"));
            for row in rows {
                if let Ok(seed) = row[si].parse::<u64>() {
                    done.insert((row[ci].clone(), seed));
                }
            }
        }
        let file = OpenOptions::new()
            .append(true)
            .open(&runs)
            .map_err(io(&runs))?;
        Ok(ResultsDir {
            dir: dir.to_path_buf(),
            header,
            runs: Mutex::new(file),
            done,
        })
    }

    /// Appends one finished run (one `write` call, flushed at once, so a killed sweep
    /// keeps every finished row).
    pub fn append(&self, row: &[String]) -> Result<(), ResultsError> {
        debug_assert_eq!(row.len(), self.header.len());
        let bytes = line_of(row);
        let path = self.dir.join("runs.csv");
        let mut f = self.runs.lock().unwrap_or_else(|p| p.into_inner());
        f.write_all(&bytes).map_err(io(&path))?;
        f.flush().map_err(io(&path))
    }

    /// Writes `summary.csv` from every row in `runs.csv`, and, once every run of the
    /// experiment is there, rewrites `runs.csv` sorted by cell and seed (so the file is
    /// the same whatever order runs finished in).
    pub fn finish(&self, exp: &Experiment) -> Result<(), ResultsError> {
        let runs = self.dir.join("runs.csv");
        let (header, rows) = read_runs(&runs, false)?;
        let (ci, si) = (col(&header, "cell"), col(&header, "seed"));
        let cell_index: HashMap<&str, usize> = exp
            .cells
            .iter()
            .map(|c| (c.key.as_str(), c.index))
            .collect();
        let mut stats: Vec<CellStats> = exp.cells.iter().map(|_| CellStats::default()).collect();
        let mut unique = HashSet::new();
        for (k, row) in rows.iter().enumerate() {
            let Some(&c) = cell_index.get(row[ci].as_str()) else {
                continue;
            };
            let parse = |name: &str| -> Result<f64, ResultsError> {
                let v = &row[col(&header, name)];
                v.parse::<f64>().map_err(|_| ResultsError::Corrupt {
                    path: runs.display().to_string(),
                    line: k + 2,
                    message: format!("column {name}: `{v}` is not a number"),
                })
            };
            if unique.insert((row[ci].clone(), row[si].clone())) {
                stats[c].add(
                    parse("rho")?,
                    parse("tau")?,
                    parse("rounds")?,
                    row[col(&header, "converged")] == "true",
                );
                stats[c].add_hull(parse("hull_growth_max")?);
            }
        }
        let mut out = csv::WriterBuilder::new().from_writer(vec![]);
        out.write_record(summary_header(&param_header(exp)))
            .expect("memory");
        for cell in &exp.cells {
            if stats[cell.index].runs > 0 {
                out.write_record(summary_row(param_values(exp, cell), &stats[cell.index]))
                    .expect("memory");
            }
        }
        write_atomic(
            &self.dir.join("summary.csv"),
            &out.into_inner().expect("memory"),
        )?;
        if unique.len() == exp.cells.len() * exp.seeds.len() && rows.len() == unique.len() {
            let mut sorted = rows.clone();
            sorted.sort_by_key(|r| {
                (
                    cell_index.get(r[ci].as_str()).copied(),
                    r[si].parse::<u64>().unwrap_or(0),
                )
            });
            if sorted != rows {
                let mut bytes = line_of(&header);
                for r in &sorted {
                    bytes.extend(line_of(r));
                }
                let _guard = self.runs.lock().unwrap_or_else(|p| p.into_inner());
                write_atomic(&runs, &bytes)?;
            }
        }
        Ok(())
    }
}

fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("runs.csv has a column {name}"))
}
