//! A CSV file read as strings, addressed by column name.

use std::path::Path;

use crate::PlotError;

pub(crate) struct Table {
    pub path: String,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
    /// The 1-based file line of each row.
    pub lines: Vec<usize>,
}

/// What the cells of a column must hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Cells {
    /// A finite number.
    Finite,
    /// A number >= 0: finite, `inf` (e.g. rho with d_opt = 0) or `NaN` (no value).
    NonNegative,
    /// A whole number >= 0.
    Whole,
    /// `true` or `false`.
    Bool,
}

impl Cells {
    fn accepts(self, v: &str) -> bool {
        match self {
            Cells::Finite => v.parse::<f64>().is_ok_and(f64::is_finite),
            Cells::NonNegative => v.parse::<f64>().is_ok_and(|x| x.is_nan() || x >= 0.0),
            Cells::Whole => v.parse::<u64>().is_ok(),
            Cells::Bool => v == "true" || v == "false",
        }
    }

    fn expected(self) -> &'static str {
        match self {
            Cells::Finite => "a finite number",
            Cells::NonNegative => "a number >= 0 (or NaN, inf)",
            Cells::Whole => "a whole number >= 0",
            Cells::Bool => "true or false",
        }
    }
}

impl Table {
    pub fn read(path: &Path) -> Result<Table, PlotError> {
        let name = path.display().to_string();
        let mut reader = csv::Reader::from_path(path).map_err(|e| PlotError::Io {
            path: name.clone(),
            message: e.to_string(),
        })?;
        let bad = |e: csv::Error| PlotError::Input {
            path: name.clone(),
            message: e.to_string(),
        };
        let header = reader
            .headers()
            .map_err(bad)?
            .iter()
            .map(String::from)
            .collect();
        let mut rows = Vec::new();
        let mut lines = Vec::new();
        for r in reader.records() {
            let r = r.map_err(bad)?;
            lines.push(r.position().map_or(0, |p| p.line() as usize));
            rows.push(r.iter().map(String::from).collect());
        }
        Ok(Table {
            path: name,
            header,
            rows,
            lines,
        })
    }

    /// Fails unless the table has at least one row.
    pub fn require_rows(&self, what: &str) -> Result<(), PlotError> {
        if self.rows.is_empty() {
            return Err(PlotError::Input {
                path: self.path.clone(),
                message: format!("holds no {what} (only a header)"),
            });
        }
        Ok(())
    }

    /// Checks every cell of column `name`, naming the first bad one's line.
    pub fn check(&self, name: &str, cells: Cells) -> Result<usize, PlotError> {
        let c = self.col(name)?;
        for (r, &line) in self.rows.iter().zip(&self.lines) {
            if !cells.accepts(&r[c]) {
                return Err(PlotError::Input {
                    path: format!("{}:{line}", self.path),
                    message: format!("column {name}: `{}` is not {}", r[c], cells.expected()),
                });
            }
        }
        Ok(c)
    }

    pub fn col(&self, name: &str) -> Result<usize, PlotError> {
        self.header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| PlotError::Input {
                path: self.path.clone(),
                message: format!("no column {name}"),
            })
    }

    /// A numeric column, every cell checked against `cells`.
    pub fn numbers(&self, name: &str, cells: Cells) -> Result<Vec<f64>, PlotError> {
        let c = self.check(name, cells)?;
        Ok(self
            .rows
            .iter()
            .map(|r| r[c].parse().unwrap_or(f64::NAN))
            .collect())
    }
}
