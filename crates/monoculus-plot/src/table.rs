//! A CSV file read as strings, addressed by column name.

use std::path::Path;

use crate::PlotError;

pub(crate) struct Table {
    pub path: String,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
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
        for r in reader.records() {
            rows.push(r.map_err(bad)?.iter().map(String::from).collect());
        }
        Ok(Table {
            path: name,
            header,
            rows,
        })
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

    /// A numeric column (unparseable cells become NaN).
    pub fn numbers(&self, name: &str) -> Result<Vec<f64>, PlotError> {
        let c = self.col(name)?;
        Ok(self
            .rows
            .iter()
            .map(|r| r[c].parse().unwrap_or(f64::NAN))
            .collect())
    }
}
