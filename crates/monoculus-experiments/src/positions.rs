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
    parse_rows(text, name, &[]).map(|(file, _)| file)
}

/// Every robot's position per round, from a `monoculus trace --positions` file
/// (columns `round`, `robot`, `x`, `y` and, in space, `z`).
#[derive(Clone, Debug, PartialEq)]
pub struct TracePositions {
    /// Whether the file has a z column.
    pub has_z: bool,
    /// Per round, in order from round 0: every robot's coordinates, by robot.
    pub rounds: Vec<Vec<[f64; 3]>>,
}

/// Reads a trace positions file (see [`TracePositions`]): rounds 0, 1, ... in order,
/// each listing robots 0..n once.
pub fn read_trace_positions(path: &Path) -> Result<TracePositions, PositionsError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|cause| PositionsError::Io {
        path: name.clone(),
        cause,
    })?;
    parse_trace_positions(&text, &name)
}

/// Parses a trace positions file from text; `name` labels errors.
pub fn parse_trace_positions(text: &str, name: &str) -> Result<TracePositions, PositionsError> {
    let perr = |line: usize, message: String| PositionsError::Parse {
        path: name.to_string(),
        line,
        message,
    };
    let (file, keys) = parse_rows(text, name, &["round", "robot"])?;
    // The last round listed as many robots as round 0.
    let complete = |rounds: &[Vec<[f64; 3]>], line: usize| match rounds {
        [first, .., last] if last.len() != first.len() => Err(perr(
            line,
            format!(
                "round {} lists {} robots, round 0 lists {}",
                rounds.len() - 1,
                last.len(),
                first.len()
            ),
        )),
        _ => Ok(()),
    };
    let mut rounds: Vec<Vec<[f64; 3]>> = Vec::new();
    for (row, &[round, robot, line]) in file.rows.iter().zip(&keys) {
        let line = line as usize;
        if round as usize == rounds.len() {
            complete(&rounds, line)?;
            rounds.push(Vec::new());
        }
        let count = rounds.len();
        let Some(current) = rounds.last_mut().filter(|_| round as usize + 1 == count) else {
            return Err(perr(
                line,
                format!(
                    "column round: {round} out of order (rounds must run 0, 1, 2, ... without gaps; expected {} or {})",
                    count.saturating_sub(1),
                    count
                ),
            ));
        };
        if robot as usize != current.len() {
            return Err(perr(
                line,
                format!(
                    "column robot: {robot} out of order (expected robot {} of round {round})",
                    current.len()
                ),
            ));
        }
        current.push(*row);
    }
    complete(&rounds, keys.last().map_or(1, |k| k[2] as usize))?;
    Ok(TracePositions {
        has_z: file.has_z,
        rounds,
    })
}

/// The rows of a positions CSV, and per row the values of the integer columns `ints`
/// followed by the row's 1-based line.
fn parse_rows(
    text: &str,
    name: &str,
    ints: &[&str],
) -> Result<(PositionsFile, Vec<[u64; 3]>), PositionsError> {
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
    let int_cols: Vec<usize> = ints
        .iter()
        .map(|c| {
            col(c).ok_or_else(|| {
                perr(
                    1,
                    format!(
                        "header must name column {c}, got `{}`",
                        headers.iter().collect::<Vec<_>>().join(",")
                    ),
                )
            })
        })
        .collect::<Result<_, _>>()?;
    let mut keys = Vec::new();
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
        let mut key = [0u64, 0, line as u64];
        for (k, (&i, c)) in int_cols.iter().zip(ints).enumerate() {
            let field = record.get(i).unwrap_or("");
            key[k] = field.parse::<u64>().map_err(|_| {
                perr(
                    line,
                    format!("column {c}: `{field}` is not a non-negative integer"),
                )
            })?;
        }
        keys.push(key);
    }
    if out.is_empty() {
        return Err(perr(1, "no robots".into()));
    }
    Ok((
        PositionsFile {
            rows: out,
            has_z: zi.is_some(),
        },
        keys,
    ))
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
