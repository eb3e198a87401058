//! Positions CSV: header `x,y` (and `z` in 3D), one robot per row.

use std::path::Path;

/// A bad positions file.
#[derive(Debug, thiserror::Error)]
pub enum PositionsError {
    /// The file cannot be opened or read.
    #[error("{}: cannot read: {cause}", crate::one_line(path))]
    Io {
        /// The file.
        path: String,
        /// Why.
        cause: std::io::Error,
    },
    /// A line is malformed.
    #[error("{}:{line}: {}", crate::one_line(path), crate::one_line(message))]
    Parse {
        /// The file.
        path: String,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
}

/// Robots read from a positions file: coordinates (z = 0 when the file has no z column).
#[derive(Clone, Debug, PartialEq)]
pub struct PositionsFile {
    /// Rows.
    pub rows: Vec<[f64; 3]>,
    /// Whether the file has a `z` column.
    pub has_z: bool,
}

impl PositionsFile {
    /// The positions as points of dimension `P::DIM`.
    pub fn points<P: monoculus_core::geometry::Point>(&self) -> Vec<P> {
        self.rows.iter().map(|r| P::from_slice(r)).collect()
    }

    /// The number of robots.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether there are no robots.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }
}

/// Reads a positions CSV (header with columns `x`, `y` and optionally `z`, in any
/// order; other columns are ignored).
pub fn read_positions(path: &Path) -> Result<PositionsFile, PositionsError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|cause| PositionsError::Io {
        path: name.clone(),
        cause,
    })?;
    parse_positions(&text, &name)
}

/// Parses a positions CSV from text; `name` labels errors.
pub fn parse_positions(text: &str, name: &str) -> Result<PositionsFile, PositionsError> {
    let perr = |line: usize, message: String| PositionsError::Parse {
        path: name.to_string(),
        line,
        message,
    };
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = reader
        .headers()
        .map_err(|e| perr(1, e.to_string()))?
        .clone();
    let col = |c: &str| headers.iter().position(|h| h == c);
    let (Some(xi), Some(yi)) = (col("x"), col("y")) else {
        return Err(perr(
            1,
            format!(
                "header must name columns x and y, got `{}`",
                headers.iter().collect::<Vec<_>>().join(",")
            ),
        ));
    };
    let zi = col("z");
    let mut out = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line() as usize);
            perr(line, e.to_string())
        })?;
        let line = record.position().map_or(0, |p| p.line() as usize);
        let get = |i: usize, c: &str| -> Result<f64, PositionsError> {
            let field = record.get(i).unwrap_or("");
            let v = field
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    perr(
                        line,
                        format!("column {c}: `{field}` is not a finite number"),
                    )
                })?;
            if v.abs() > monoculus_engine::MAX_MAGNITUDE {
                return Err(perr(
                    line,
                    format!(
                        "column {c}: `{field}` is larger than {:e} in magnitude (squares could overflow)",
                        monoculus_engine::MAX_MAGNITUDE
                    ),
                ));
            }
            Ok(v)
        };
        let z = match zi {
            Some(zi) => get(zi, "z")?,
            None => 0.0,
        };
        out.push([get(xi, "x")?, get(yi, "y")?, z]);
    }
    if out.is_empty() {
        return Err(perr(1, "no robots".into()));
    }
    Ok(PositionsFile {
        rows: out,
        has_z: zi.is_some(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_and_reports_lines() {
        let p = parse_positions("x,y\n1,2\n3.5, -4\n", "f.csv").unwrap();
        assert_eq!(p.rows, vec![[1.0, 2.0, 0.0], [3.5, -4.0, 0.0]]);
        assert!(!p.has_z);
        let q = parse_positions("z,x,y\n1,2,3\n", "f.csv").unwrap();
        assert_eq!((q.rows[0], q.has_z), ([2.0, 3.0, 1.0], true));
        let e = parse_positions("x,y\n1,2\n3,abc\n", "f.csv")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "f.csv:3: column y: `abc` is not a finite number");
        let e = parse_positions("x,y\n1e200,2\n", "f.csv")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("f.csv:2: column x: `1e200`"), "{e}");
        let e = parse_positions("a,b\n1,2\n", "f.csv")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("f.csv:1: header must name columns x and y"),
            "{e}"
        );
        assert!(
            parse_positions("x,y\n", "f.csv")
                .unwrap_err()
                .to_string()
                .contains("no robots")
        );
    }
}
