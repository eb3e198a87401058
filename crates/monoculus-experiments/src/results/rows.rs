//! The rows of `runs.csv` or of a shard file: read (a last line cut short by a kill is
//! left out), checked against the experiment, deduplicated, sorted, written atomically.

use std::collections::{HashMap, HashSet};
use std::path::Path;

use super::ResultsError;
use super::fsio::{read_complete_lines, write_atomic};
use super::record::{CONFIG_HASH_COLUMN, RunMetrics, param_values, runs_header};
use crate::config::{Experiment, RunId};

/// One CSV record as bytes, newline included.
pub(crate) fn line_of<I, T>(record: I) -> Vec<u8>
where
    I: IntoIterator<Item = T>,
    T: AsRef<[u8]>,
{
    let mut line = Vec::new();
    super::text::push_record(&mut line, record);
    line
}

/// What a rows file holds, unchecked.
#[derive(Clone, Debug)]
pub struct FoundRows {
    /// The header (empty for an empty file).
    pub header: Vec<String>,
    /// The complete rows (a record keeps its fields in one buffer: a few hundred bytes
    /// a run, so that millions of rows fit in memory).
    pub rows: Vec<csv::StringRecord>,
    /// The file ended in a line cut short (left out of `rows`).
    pub partial: bool,
}

/// Reads a rows file.
pub fn read_rows(path: &Path) -> Result<FoundRows, ResultsError> {
    let (bytes, partial) = read_complete_lines(path)?;
    let corrupt = |e: csv::Error| ResultsError::Corrupt {
        path: path.display().to_string(),
        line: e.position().map_or(1, |p| p.line() as usize),
        message: e.to_string(),
    };
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(bytes.as_slice());
    let header: Vec<String> = reader
        .headers()
        .map_err(corrupt)?
        .iter()
        .map(String::from)
        .collect();
    let mut rows = Vec::new();
    for r in reader.records() {
        rows.push(r.map_err(corrupt)?);
    }
    Ok(FoundRows {
        header,
        rows,
        partial,
    })
}

/// Rows checked to belong to one experiment: each with its run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunRows {
    /// The header.
    pub header: Vec<String>,
    /// The rows, in file order.
    pub rows: Vec<csv::StringRecord>,
    /// The run of each row.
    pub ids: Vec<RunId>,
    /// The 1-based file line of each row.
    pub lines: Vec<usize>,
}

impl FoundRows {
    /// Checks the header and every row: its config hash, that it is a run of `exp`
    /// (its cell and seed), that its parameter columns are its cell's, and that every
    /// metric reads as its column's type. The first bad row is named by file and line.
    pub fn check(self, exp: &Experiment, path: &Path) -> Result<RunRows, ResultsError> {
        let header = runs_header(exp);
        if self.header.is_empty() {
            return Ok(RunRows::empty(header));
        }
        if self.header != header {
            return Err(ResultsError::Mismatch {
                path: path.display().to_string(),
                message: "its columns differ from this experiment's (results of another experiment or of an older monoculus); use --force to start over, or another --out".into(),
            });
        }
        let col = |name: &str| header.iter().position(|h| h == name).expect("own header");
        let (ci, si, hi) = (col("cell"), col("seed"), col(CONFIG_HASH_COLUMN));
        let cells: HashMap<&str, usize> = exp
            .cells
            .iter()
            .map(|c| (c.key.as_str(), c.index))
            .collect();
        let params: Vec<Vec<String>> = exp.cells.iter().map(|c| param_values(exp, c)).collect();
        let schema = RunMetrics::schema(&header).expect("runs.csv has a seed column");
        let seeds: HashSet<u64> = exp.seeds.iter().copied().collect();
        let mut ids = Vec::with_capacity(self.rows.len());
        let mut lines = Vec::with_capacity(self.rows.len());
        for (k, row) in self.rows.iter().enumerate() {
            let line = k + 2;
            let bad = |message: String| ResultsError::Corrupt {
                path: path.display().to_string(),
                line,
                message,
            };
            if row[hi] != exp.hash {
                return Err(ResultsError::Mismatch {
                    path: format!("{}:{line}", path.display()),
                    message: format!(
                        "a row of another experiment (config hash {}, this one's is {}); use --force to start over, or another --out",
                        crate::shown(&row[hi]),
                        exp.hash
                    ),
                });
            }
            let cell = *cells.get(&row[ci]).ok_or_else(|| {
                bad(format!(
                    "column cell: {} is not a cell of this experiment",
                    crate::shown(&row[ci])
                ))
            })?;
            if let Some(c) = (0..params[cell].len()).find(|&c| row[c] != *params[cell][c]) {
                return Err(bad(format!(
                    "column {}: {} is not cell {}'s value ({})",
                    header[c],
                    crate::shown(&row[c]),
                    crate::shown(&row[ci]),
                    crate::shown(&params[cell][c])
                )));
            }
            let seed: u64 = row[si]
                .parse()
                .ok()
                .filter(|s| seeds.contains(s))
                .ok_or_else(|| {
                    bad(format!(
                        "column seed: {} is not a seed of this experiment",
                        crate::shown(&row[si])
                    ))
                })?;
            schema.read_record::<RunMetrics>(row).map_err(bad)?;
            ids.push(RunId { cell, seed });
            lines.push(line);
        }
        Ok(RunRows {
            header,
            rows: self.rows,
            ids,
            lines,
        })
    }
}

impl RunRows {
    /// No rows yet, under `header`.
    pub fn empty(header: Vec<String>) -> Self {
        RunRows {
            header,
            rows: Vec::new(),
            ids: Vec::new(),
            lines: Vec::new(),
        }
    }

    /// Adds the row of `run`, as the next line of the file.
    ///
    /// ```
    /// use monoculus_experiments::RunId;
    /// use monoculus_experiments::results::RunRows;
    /// let mut rows = RunRows::empty(vec!["seed".into()]);
    /// rows.push(RunId { cell: 0, seed: 3 }, csv::StringRecord::from(vec!["3"]));
    /// assert_eq!((rows.ids.len(), rows.lines[0]), (1, 2));
    /// ```
    pub fn push(&mut self, run: RunId, row: csv::StringRecord) {
        self.lines.push(self.rows.len() + 2);
        self.rows.push(row);
        self.ids.push(run);
    }

    /// Keeps the first row of every run.
    pub fn dedup(&mut self) {
        let mut seen = HashSet::new();
        let keep: Vec<bool> = self.ids.iter().map(|id| seen.insert(*id)).collect();
        let mut k = keep.iter();
        self.rows.retain(|_| *k.next().expect("one flag a row"));
        let mut k = keep.iter();
        self.ids.retain(|_| *k.next().expect("one flag a row"));
        let mut k = keep.iter();
        self.lines.retain(|_| *k.next().expect("one flag a row"));
    }

    /// Whether every run of `exp` is here exactly once.
    pub fn is_complete(&self, exp: &Experiment) -> bool {
        let unique: HashSet<RunId> = self.ids.iter().copied().collect();
        unique.len() == self.ids.len() && unique.len() == exp.cells.len() * exp.seeds.len()
    }

    /// Sorts by cell, then seed; whether the order changed.
    pub fn sort(&mut self) -> bool {
        let mut order: Vec<usize> = (0..self.rows.len()).collect();
        order.sort_by_key(|&k| (self.ids[k].cell, self.ids[k].seed, k));
        if order.iter().enumerate().all(|(i, &k)| i == k) {
            return false;
        }
        let mut rows: Vec<Option<csv::StringRecord>> = std::mem::take(&mut self.rows)
            .into_iter()
            .map(Some)
            .collect();
        self.rows = order
            .iter()
            .map(|&k| rows[k].take().expect("each row once"))
            .collect();
        self.ids = order.iter().map(|&k| self.ids[k]).collect();
        self.lines = order.iter().map(|&k| self.lines[k]).collect();
        true
    }

    /// Appends other rows of the same experiment.
    pub fn extend(&mut self, other: RunRows) {
        self.rows.extend(other.rows);
        self.ids.extend(other.ids);
        self.lines.extend(other.lines);
    }
}

/// Replaces `path` by the header and rows, atomically.
pub fn write_rows(
    path: &Path,
    header: &[String],
    rows: &[csv::StringRecord],
) -> Result<(), ResultsError> {
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::with_capacity(rows.len() * 256));
    w.write_record(header).expect("writing to memory");
    for r in rows {
        w.write_record(r).expect("writing to memory");
    }
    write_atomic(path, &w.into_inner().expect("writing to memory"))
}
