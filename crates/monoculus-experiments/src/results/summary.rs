//! `summary.csv`: one row per cell.

use std::path::Path;

use super::ResultsError;
use super::fsio::write_atomic;
use super::record::{num, param_header, param_values};
use super::rows::RunRows;
use crate::config::Experiment;

/// Per-cell accumulator.
#[derive(Clone, Debug, Default)]
pub struct CellStats {
    /// Runs.
    pub runs: usize,
    /// Converged runs.
    pub converged: usize,
    /// Runs in which the hull grew at least once.
    pub hull_grew: usize,
    rho: Vec<f64>,
    tau: Vec<f64>,
    rounds: Vec<f64>,
    hull_growth: Vec<f64>,
}

impl CellStats {
    /// Adds one run's hull: its largest relative growth in one round (0: never grew).
    pub fn add_hull(&mut self, growth_max: f64) {
        if growth_max > 0.0 {
            self.hull_grew += 1;
            self.hull_growth.push(growth_max);
        }
    }

    /// Adds one run; rho, tau and rounds count only for converged runs.
    pub fn add(&mut self, rho: f64, tau: f64, rounds: f64, converged: bool) {
        self.runs += 1;
        if converged {
            self.converged += 1;
            if rho.is_finite() {
                self.rho.push(rho);
            }
            if tau.is_finite() {
                self.tau.push(tau);
            }
            self.rounds.push(rounds);
        }
    }
}

/// The q-quantile (0..=1) by linear interpolation between order statistics (numpy's
/// default, "type 7"); NaN for no values.
pub fn quantile(values: &[f64], q: f64) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let h = (v.len() - 1) as f64 * q;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    v[lo] + (h - lo as f64) * (v[hi] - v[lo])
}

/// Statistic columns of `summary.csv`.
pub const SUMMARY_COLUMNS: [&str; 12] = [
    "runs",
    "converged",
    "rho_median",
    "rho_q1",
    "rho_q3",
    "tau_median",
    "tau_q1",
    "tau_q3",
    "rounds_median",
    "rounds_q3",
    "hull_grew_runs",
    "hull_growth_max_median",
];

/// The header: parameters then statistics.
pub fn summary_header(params: &[String]) -> Vec<String> {
    let mut h = params.to_vec();
    h.extend(SUMMARY_COLUMNS.iter().map(|c| c.to_string()));
    h
}

/// One cell's row.
pub fn summary_row(mut params: Vec<String>, s: &CellStats) -> Vec<String> {
    params.extend([
        s.runs.to_string(),
        s.converged.to_string(),
        num(quantile(&s.rho, 0.5)),
        num(quantile(&s.rho, 0.25)),
        num(quantile(&s.rho, 0.75)),
        num(quantile(&s.tau, 0.5)),
        num(quantile(&s.tau, 0.25)),
        num(quantile(&s.tau, 0.75)),
        num(quantile(&s.rounds, 0.5)),
        num(quantile(&s.rounds, 0.75)),
        s.hull_grew.to_string(),
        num(quantile(&s.hull_growth, 0.5)),
    ]);
    params
}

/// Writes `summary.csv` (atomically) from checked rows: one row per cell that has runs,
/// each run counted once.
pub fn write_summary(path: &Path, exp: &Experiment, rows: &RunRows) -> Result<(), ResultsError> {
    let col = |name: &str| {
        rows.header
            .iter()
            .position(|h| h == name)
            .expect("runs header")
    };
    let (rho, tau, rounds, converged, growth) = (
        col("rho"),
        col("tau"),
        col("rounds"),
        col("converged"),
        col("hull_growth_max"),
    );
    let mut stats: Vec<CellStats> = exp.cells.iter().map(|_| CellStats::default()).collect();
    let mut unique = std::collections::HashSet::new();
    for ((row, id), &line) in rows.rows.iter().zip(&rows.ids).zip(&rows.lines) {
        if !unique.insert(*id) {
            continue;
        }
        let parse = |c: usize| -> Result<f64, ResultsError> {
            row[c].parse::<f64>().map_err(|_| ResultsError::Corrupt {
                path: path.with_file_name("runs.csv").display().to_string(),
                line,
                message: format!("column {}: `{}` is not a number", rows.header[c], row[c]),
            })
        };
        let s = &mut stats[id.cell];
        s.add(
            parse(rho)?,
            parse(tau)?,
            parse(rounds)?,
            row[converged] == "true",
        );
        s.add_hull(parse(growth)?);
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
    write_atomic(path, &out.into_inner().expect("memory"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_match_numpy() {
        let v = [3.0, 1.0, 4.0, 1.0, 5.0, 9.0, 2.0, 6.0];
        // numpy.quantile(v, [0.25, 0.5, 0.75]) = [1.75, 3.5, 5.25]
        assert_eq!(quantile(&v, 0.25), 1.75);
        assert_eq!(quantile(&v, 0.5), 3.5);
        assert_eq!(quantile(&v, 0.75), 5.25);
        assert!(quantile(&[], 0.5).is_nan());
    }
}
