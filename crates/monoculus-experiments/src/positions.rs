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
    #[error("{}:{line}: {}", crate::one_line(path), crate::short_quotes(&crate::one_line(message)))]
    Parse {
        /// The file.
        path: String,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
}

/// `points` as a positions CSV (header `x,y`, or `x,y,z` in space), every coordinate
/// written so that it reads back to the same `f64` (a negative zero as `0`): a config
/// with `init = "file"` starts from exactly these points.
///
/// ```
/// use glam::DVec2;
/// use monoculus_experiments::positions::{parse_positions, positions_csv};
///
/// let pts = [DVec2::new(0.1, -0.0), DVec2::new(1.0 / 3.0, 2.5)];
/// let text = positions_csv(&pts);
/// assert_eq!(text, "x,y\n0.1,0\n0.3333333333333333,2.5\n");
/// assert_eq!(parse_positions(&text, "t").unwrap().points::<DVec2>(), pts);
/// ```
pub fn positions_csv<P: monoculus_core::geometry::Point>(points: &[P]) -> String {
    let mut out = String::from(["x,y", "x,y,z"][usize::from(P::DIM == 3)]);
    out.push('\n');
    for p in points {
        let row: Vec<String> = (0..P::DIM)
            .map(|k| crate::results::num(p.axis(k) + 0.0))
            .collect();
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
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

/// The text of an input file, an error naming it.
pub fn read_text(path: &Path) -> Result<String, PositionsError> {
    std::fs::read_to_string(path).map_err(|cause| PositionsError::Io {
        path: path.display().to_string(),
        cause,
    })
}

/// Reads a positions CSV (header with columns `x`, `y` and optionally `z`, in any
/// order, and no others).
pub fn read_positions(path: &Path) -> Result<PositionsFile, PositionsError> {
    parse_positions(&read_text(path)?, &path.display().to_string())
}

/// Parses a positions CSV from text; `name` labels errors.
pub fn parse_positions(text: &str, name: &str) -> Result<PositionsFile, PositionsError> {
    parse_rows(text, name, &[], None).map(|(file, ..)| file)
}

/// Every robot's position per round, from a `monoculus trace --positions` file
/// (columns `round`, `robot`, `x`, `y`, in space `z`, and for an algorithm with lights
/// `light`, the name of the colour the robot shows).
#[derive(Clone, Debug, PartialEq)]
pub struct TracePositions {
    /// Whether the file has a z column.
    pub has_z: bool,
    /// Per round, in order from round 0: every robot's coordinates, by robot.
    pub rounds: Vec<Vec<[f64; 3]>>,
    /// The names of the colours in the file, in the order first seen (empty without a
    /// `light` column).
    pub light_names: Vec<String>,
    /// Per round, every robot's colour (an index into `light_names`); empty without a
    /// `light` column.
    pub lights: Vec<Vec<u8>>,
}

/// Reads a trace positions file (see [`TracePositions`]): rounds 0, 1, ... in order,
/// each listing robots 0..n once.
pub fn read_trace_positions(path: &Path) -> Result<TracePositions, PositionsError> {
    parse_trace_positions(&read_text(path)?, &path.display().to_string())
}

/// Parses a trace positions file from text; `name` labels errors.
pub fn parse_trace_positions(text: &str, name: &str) -> Result<TracePositions, PositionsError> {
    let perr = |line: usize, message: String| PositionsError::Parse {
        path: name.to_string(),
        line,
        message,
    };
    let (file, keys, labels) = parse_rows(text, name, &["round", "robot"], Some("light"))?;
    // Colours by name, numbered in the order first seen (the palette's order when every
    // colour shows in round 0).
    let mut light_names: Vec<String> = Vec::new();
    let mut colours: Vec<u8> = Vec::new();
    for (label, key) in labels.iter().flatten().zip(&keys) {
        let k = match light_names.iter().position(|n| n == label) {
            Some(k) => k,
            None if label.is_empty() => {
                return Err(perr(key[2] as usize, "column light: empty".into()));
            }
            None if light_names.len() == monoculus_core::algorithms::MAX_LIGHTS => {
                return Err(perr(
                    key[2] as usize,
                    format!(
                        "column light: more than {} colours",
                        monoculus_core::algorithms::MAX_LIGHTS
                    ),
                ));
            }
            None => {
                light_names.push(label.clone());
                light_names.len() - 1
            }
        };
        colours.push(k as u8);
    }
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
    let lights = if colours.is_empty() {
        Vec::new()
    } else {
        colours
            .chunks(rounds[0].len())
            .map(<[u8]>::to_vec)
            .collect()
    };
    Ok(TracePositions {
        has_z: file.has_z,
        rounds,
        light_names,
        lights,
    })
}

/// The trace CSV a trace positions file belongs to: `run.positions.csv` -> `run.csv`.
pub fn trace_of_positions(positions: &Path) -> Option<std::path::PathBuf> {
    let name = positions.file_name()?.to_str()?;
    let stem = name.strip_suffix(".positions.csv")?;
    Some(positions.with_file_name(format!("{stem}.csv")))
}

/// Checks that a trace positions file listing `robots` robots over `rounds` rounds
/// (round 0 included) belongs to the trace CSV `trace` (`monoculus trace` writes both
/// together): one row per round there, and its `robots` column (traces written before
/// that column are checked by their rounds alone).
pub fn check_trace_matches(
    trace: &Path,
    positions: &Path,
    rounds: usize,
    robots: usize,
) -> Result<(), PositionsError> {
    let text = read_text(trace)?;
    let name = trace.display().to_string();
    let mut csv = Csv::new(&text, &name)?;
    let robots_col = csv.column("robots");
    let mut rows = 0;
    let mut listed = None;
    for row in csv.rows() {
        let (line, record) = row?;
        if rows == 0
            && let Some(c) = robots_col
        {
            let field = record.get(c).unwrap_or("");
            listed = Some(field.parse::<usize>().map_err(|_| {
                parse_error(
                    &name,
                    line,
                    format!(
                        "column robots: {} is not a count of robots",
                        crate::shown(field)
                    ),
                )
            })?);
        }
        rows += 1;
    }
    if rows != rounds || listed.is_some_and(|n| n != robots) {
        let theirs = match listed {
            Some(n) => format!("{n} robots over {rows} rounds"),
            None => format!("{rows} rounds"),
        };
        return Err(parse_error(
            &positions.display().to_string(),
            1,
            format!(
                "belongs to another run: it lists {robots} robots over {rounds} rounds, {} lists {theirs} (`monoculus trace --positions` writes the two together; trace the run again)",
                crate::one_line(&name)
            ),
        ));
    }
    Ok(())
}

/// A CSV with a header, read from `text` (fields trimmed); `name` labels its errors.
///
/// Read strictly: the header names each column once and only the columns the file kind
/// has ([`Csv::exact`]), and every row has a field for every column. As RFC 4180 allows,
/// the last row need not end with a line break (many tools write files that way): a file
/// cut short is told by its content, a row missing fields (named by line and column) or a
/// field that is not a value of its column (`1.2e` is no number), not by its last byte.
pub(crate) struct Csv<'a> {
    name: &'a str,
    reader: csv::Reader<&'a [u8]>,
    headers: csv::StringRecord,
}

impl<'a> Csv<'a> {
    /// Reads the header.
    pub(crate) fn new(text: &'a str, name: &'a str) -> Result<Self, PositionsError> {
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes());
        let headers = match reader.headers() {
            Ok(h) => h.clone(),
            Err(e) => return Err(parse_error(name, 1, e.to_string())),
        };
        Ok(Csv {
            name,
            reader,
            headers,
        })
    }

    /// Checks the header: it names every column of `required`, any of `optional`, no
    /// other column and none twice.
    pub(crate) fn exact(&self, required: &[&str], optional: &[&str]) -> Result<(), PositionsError> {
        let allowed = || {
            let mut a = required.join(",");
            if !optional.is_empty() {
                a.push_str(&format!(" (and optionally {})", optional.join(",")));
            }
            a
        };
        self.columns_of(required)?;
        for (k, h) in self.headers.iter().enumerate() {
            if self.headers.iter().take(k).any(|e| e == h) {
                return Err(self.error(1, format!("header names column {} twice", crate::shown(h))));
            }
            if !required.contains(&h) && !optional.contains(&h) {
                return Err(self.error(
                    1,
                    format!(
                        "header has column {}, which this file does not take: its columns are {}",
                        crate::shown(h),
                        allowed()
                    ),
                ));
            }
        }
        Ok(())
    }

    fn columns_of(&self, columns: &[&str]) -> Result<Vec<usize>, PositionsError> {
        let found: Vec<usize> = columns.iter().filter_map(|c| self.column(c)).collect();
        if found.len() == columns.len() {
            return Ok(found);
        }
        let plural = if columns.len() == 1 {
            "column"
        } else {
            "columns"
        };
        Err(self.error(
            1,
            format!(
                "header must name {plural} {}, got `{}`",
                match columns.split_last() {
                    Some((last, rest)) if !rest.is_empty() => {
                        format!("{} and {last}", rest.join(", "))
                    }
                    _ => columns.join(""),
                },
                self.headers.iter().collect::<Vec<_>>().join(",")
            ),
        ))
    }

    /// The index of column `c`, if the header names it.
    pub(crate) fn column(&self, c: &str) -> Option<usize> {
        self.headers.iter().position(|h| h == c)
    }

    /// The indices of `columns`, or an error at line 1 naming them all.
    pub(crate) fn columns<const N: usize>(
        &self,
        columns: [&str; N],
    ) -> Result<[usize; N], PositionsError> {
        let found = self.columns_of(&columns)?;
        Ok(found.try_into().expect("one index a column"))
    }

    /// An error at `line` of this file.
    pub(crate) fn error(&self, line: usize, message: String) -> PositionsError {
        parse_error(self.name, line, message)
    }

    /// The rows with their 1-based lines.
    pub(crate) fn rows(
        &mut self,
    ) -> impl Iterator<Item = Result<(usize, csv::StringRecord), PositionsError>> + '_ {
        let name = self.name;
        let headers = &self.headers;
        self.reader.records().map(move |record| {
            let line_of = |p: Option<&csv::Position>| p.map_or(0, |p| p.line() as usize);
            match record {
                Ok(r) => Ok((line_of(r.position()), r)),
                Err(e) => {
                    let line = line_of(e.position());
                    let message = match e.kind() {
                        // A row with fields missing (a file cut short, a lost comma): the
                        // first column without a field.
                        csv::ErrorKind::UnequalLengths { len, .. } if (*len as usize) < headers.len() => {
                            format!(
                                "column {}: missing (the row has {len} of the {} fields of the header: is the file cut short?)",
                                headers.get(*len as usize).unwrap_or(""),
                                headers.len()
                            )
                        }
                        csv::ErrorKind::UnequalLengths { len, .. } => format!(
                            "{len} fields, but the header names {} columns",
                            headers.len()
                        ),
                        _ => e.to_string(),
                    };
                    Err(parse_error(name, line, message))
                }
            }
        })
    }
}

/// A [`PositionsError::Parse`] at `line` of `name`.
pub(crate) fn parse_error(name: &str, line: usize, message: String) -> PositionsError {
    PositionsError::Parse {
        path: name.to_string(),
        line,
        message,
    }
}

/// The rows of a positions CSV, and per row the values of the integer columns `ints`
/// followed by the row's 1-based line.
/// The rows of a positions file: the positions, the integer columns `ints` of each row
/// (with its line), and the text of the optional column `label`, if the file has it.
type Rows = (PositionsFile, Vec<[u64; 3]>, Option<Vec<String>>);

fn parse_rows(
    text: &str,
    name: &str,
    ints: &[&str],
    label: Option<&str>,
) -> Result<Rows, PositionsError> {
    let perr = |line: usize, message: String| parse_error(name, line, message);
    let mut csv = Csv::new(text, name)?;
    let mut required = ints.to_vec();
    required.extend(["x", "y"]);
    let mut optional = vec!["z"];
    optional.extend(label);
    csv.exact(&required, &optional)?;
    let [xi, yi] = csv.columns(["x", "y"])?;
    let zi = csv.column("z");
    let li = label.and_then(|l| csv.column(l));
    let mut labels = li.map(|_| Vec::new());
    let int_cols: Vec<usize> = ints
        .iter()
        .map(|&c| csv.columns([c]).map(|[i]| i))
        .collect::<Result<_, _>>()?;
    let mut keys = Vec::new();
    let mut out = Vec::new();
    for row in csv.rows() {
        let (line, record) = row?;
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
        if let (Some(i), Some(l)) = (li, labels.as_mut()) {
            l.push(record.get(i).unwrap_or("").to_string());
        }
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
        labels,
    ))
}

#[cfg(test)]
mod tests;
