//! `summary.csv`: one row per cell.

use std::path::Path;

use super::ResultsError;
use super::fsio::write_atomic;
use super::record::{METRIC_COLUMNS, RowSchema, fields_of, param_header, param_values, plain};
use super::rows::RunRows;
use crate::config::Experiment;

/// Per-cell accumulator.
#[derive(Clone, Debug, Default)]
pub struct CellStats {
    /// Runs.
    pub runs: usize,
    /// Converged runs.
    pub converged: usize,
    /// Stuck runs: quiescent without their goal.
    pub stuck: usize,
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
    pub fn add(&mut self, rho: f64, tau: f64, rounds: f64, converged: bool, stuck: bool) {
        self.runs += 1;
        self.stuck += usize::from(stuck);
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

fn nan() -> f64 {
    f64::NAN
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
pub const SUMMARY_COLUMNS: [&str; 15] = [
    "runs",
    "converged",
    "stuck",
    "rho_median",
    "rho_q1",
    "rho_q3",
    "tau_median",
    "tau_q1",
    "tau_q3",
    "rounds_median",
    "rounds_q1",
    "rounds_q3",
    "hull_grew_runs",
    "hull_growth_max_median",
    "missing",
];

/// The statistics part of a row of `summary.csv`, after the cell's parameters: the
/// schema of those columns, used by the writer and by `monoculus table`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SummaryStats {
    /// Runs of the cell.
    pub runs: u64,
    /// Converged runs: their stop criterion ended them and their goal held.
    pub converged: u64,
    /// Stuck runs: quiescent without their goal. Absent (0) in folders written before
    /// 0.3.
    #[serde(default)]
    pub stuck: u64,
    /// Median of rho over the converged runs (NaN: none).
    #[serde(with = "plain")]
    pub rho_median: f64,
    /// First quartile of rho.
    #[serde(with = "plain")]
    pub rho_q1: f64,
    /// Third quartile of rho.
    #[serde(with = "plain")]
    pub rho_q3: f64,
    /// Median of tau.
    #[serde(with = "plain")]
    pub tau_median: f64,
    /// First quartile of tau.
    #[serde(with = "plain")]
    pub tau_q1: f64,
    /// Third quartile of tau.
    #[serde(with = "plain")]
    pub tau_q3: f64,
    /// Median of rounds.
    #[serde(with = "plain")]
    pub rounds_median: f64,
    /// First quartile of rounds. Absent (NaN) in folders written before 0.3.
    #[serde(with = "plain", default = "nan")]
    pub rounds_q1: f64,
    /// Third quartile of rounds.
    #[serde(with = "plain")]
    pub rounds_q3: f64,
    /// Runs in which the hull grew.
    pub hull_grew_runs: u64,
    /// Over those runs, the median of the largest relative growth in one round.
    #[serde(with = "plain")]
    pub hull_growth_max_median: f64,
    /// Runs of the cell that are not in the results (0 unless the sweep is unfinished or
    /// the folder was merged with `--partial`). Absent from folders written before 0.3.
    #[serde(default)]
    pub missing: u64,
}

impl SummaryStats {
    /// The statistics of one cell's runs, `missing` of its runs absent.
    pub fn of(s: &CellStats, missing: u64) -> Self {
        SummaryStats {
            missing,
            runs: s.runs as u64,
            converged: s.converged as u64,
            stuck: s.stuck as u64,
            rho_median: quantile(&s.rho, 0.5),
            rho_q1: quantile(&s.rho, 0.25),
            rho_q3: quantile(&s.rho, 0.75),
            tau_median: quantile(&s.tau, 0.5),
            tau_q1: quantile(&s.tau, 0.25),
            tau_q3: quantile(&s.tau, 0.75),
            rounds_median: quantile(&s.rounds, 0.5),
            rounds_q1: quantile(&s.rounds, 0.25),
            rounds_q3: quantile(&s.rounds, 0.75),
            hull_grew_runs: s.hull_grew as u64,
            hull_growth_max_median: quantile(&s.hull_growth, 0.5),
        }
    }

    /// The schema of the statistics columns of `summary.csv` rows with columns `header`.
    pub fn schema(header: &[String]) -> Result<RowSchema, String> {
        RowSchema::new(header, "runs")
    }
}

/// The header: parameters then statistics.
pub fn summary_header(params: &[String]) -> Vec<String> {
    let mut h = params.to_vec();
    h.extend(SUMMARY_COLUMNS.iter().map(|c| c.to_string()));
    h
}

/// One cell's row.
pub fn summary_row(mut params: Vec<String>, s: &CellStats, missing: u64) -> Vec<String> {
    params.extend(fields_of(&SummaryStats::of(s, missing)));
    params
}

/// `summary.csv` from checked rows ([`super::FoundRows::check`]): one row per cell,
/// each run counted once, with the runs the cell lacks.
pub fn summary_bytes(exp: &Experiment, rows: &RunRows) -> Vec<u8> {
    let mut stats: Vec<CellStats> = exp.cells.iter().map(|_| CellStats::default()).collect();
    let mut unique = std::collections::HashSet::new();
    if !rows.rows.is_empty() {
        let read = Summarised::new(&rows.header);
        for (row, id) in rows.rows.iter().zip(&rows.ids) {
            if unique.insert(*id) {
                read.add(row, &mut stats[id.cell]);
            }
        }
    }
    let mut out = csv::WriterBuilder::new().from_writer(vec![]);
    out.write_record(summary_header(&param_header(exp)))
        .expect("memory");
    let seeds = exp.seeds.len();
    for cell in &exp.cells {
        let s = &stats[cell.index];
        let missing = (seeds - s.runs) as u64;
        out.write_record(summary_row(param_values(exp, cell), s, missing))
            .expect("memory");
    }
    out.into_inner().expect("memory")
}

/// The columns of a checked row a summary reads, read as [`super::RunMetrics`] reads them (the
/// rows were read whole when checked: these six alone are read again).
struct Summarised {
    rho: usize,
    tau: usize,
    rounds: usize,
    converged: usize,
    stuck: usize,
    growth: usize,
}

impl Summarised {
    /// For checked rows with columns `header`: this build's, the metric columns last
    /// but one (a parameter column may be named like a metric).
    fn new(header: &[String]) -> Self {
        let metrics = header.len() - METRIC_COLUMNS.len() - 1;
        let col = |name: &str| {
            let at = metrics
                + (METRIC_COLUMNS.iter().position(|&c| c == name)).expect("a metric column");
            debug_assert_eq!(header[at], name, "checked rows have this build's columns");
            at
        };
        Summarised {
            rho: col("rho"),
            tau: col("tau"),
            rounds: col("rounds"),
            converged: col("converged"),
            stuck: col("stuck"),
            growth: col("hull_growth_max"),
        }
    }

    /// Adds a checked row's run to its cell's statistics.
    fn add(&self, row: &csv::StringRecord, s: &mut CellStats) {
        fn read<T: std::str::FromStr>(row: &csv::StringRecord, c: usize) -> T {
            row[c].parse().ok().expect("rows are checked when read")
        }
        let rounds: u64 = read(row, self.rounds);
        s.add(
            read(row, self.rho),
            read(row, self.tau),
            rounds as f64,
            read(row, self.converged),
            read(row, self.stuck),
        );
        s.add_hull(read(row, self.growth));
    }
}

/// Writes `summary.csv`, whole or not at all, from checked rows (see [`summary_bytes`]).
pub fn write_summary(path: &Path, exp: &Experiment, rows: &RunRows) -> Result<(), ResultsError> {
    write_atomic(path, &summary_bytes(exp, rows))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_schema_is_the_header() {
        let row = fields_of(&SummaryStats::of(&CellStats::default(), 0));
        let mut w = csv::Writer::from_writer(vec![]);
        w.serialize(SummaryStats::of(&CellStats::default(), 0))
            .unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        assert_eq!(text.lines().next().unwrap(), SUMMARY_COLUMNS.join(","));
        assert_eq!(row[3], "NaN");
        let header: Vec<String> = SUMMARY_COLUMNS.iter().map(|c| c.to_string()).collect();
        let back: SummaryStats = SummaryStats::schema(&header).unwrap().read(&row).unwrap();
        assert_eq!(fields_of(&back), row);
    }

    /// The six columns a summary reads, read alone, give the statistics that reading
    /// each row whole as a `RunMetrics` gives.
    #[test]
    fn a_summary_reads_its_columns_as_a_whole_row_reads_them() {
        use super::super::record::{CONFIG_HASH_COLUMN, RunMetrics};
        let mut header = vec!["name".to_string(), "rho".to_string(), "seed".to_string()];
        header.extend(METRIC_COLUMNS.iter().map(|c| c.to_string()));
        header.push(CONFIG_HASH_COLUMN.into());
        // The parameter column named like a metric comes first: the metric's is read.
        let read = Summarised::new(&header);
        let schema = RunMetrics::schema(&header).unwrap();
        let values = [
            0.1,
            f64::INFINITY,
            f64::NAN,
            1e-7,
            12345.678,
            0.0,
            1.0 / 3.0,
        ];
        let (mut whole, mut alone) = (CellStats::default(), CellStats::default());
        for (k, &x) in values.iter().enumerate() {
            let m = RunMetrics {
                seed: k as u64,
                rounds: 3 * k as u64 + 1,
                activations: 10,
                moves: 4,
                d_opt: 1.0,
                d_max: 2.0,
                rho: x,
                tau: values[(k + 3) % values.len()],
                converged: k % 2 == 0,
                stuck: k % 3 == 1,
                stopped_by: "diameter".into(),
                goal: "disc".into(),
                final_diameter: 1.5,
                final_radius: 0.75,
                final_extent_x: Some(1.0),
                final_extent_y: Some(0.5),
                final_extent_z: None,
                hull_area_initial: 2.0,
                hull_area_final: 1.0,
                hull_area_max: 2.0,
                hull_growth_rounds: k as u64 % 2,
                hull_grew: k % 2 == 1,
                hull_growth_max: values[(k + 1) % values.len()],
                committed_hull_growth: 0,
                terminated: None,
                distance: 4.0,
                stop_criterion: "diameter".into(),
                ticks: None,
                faulty: 0,
                wall_ms: 0.5,
                config_hash: "00ff".into(),
            };
            let mut fields = vec!["x".to_string(), "not a number".to_string()];
            fields.extend(m.fields());
            let row = csv::StringRecord::from(fields);
            let back: RunMetrics = schema.read_record(&row).unwrap();
            whole.add(
                back.rho,
                back.tau,
                back.rounds as f64,
                back.converged,
                back.stuck,
            );
            whole.add_hull(back.hull_growth_max);
            read.add(&row, &mut alone);
        }
        assert_eq!(format!("{whole:?}"), format!("{alone:?}"));
        assert_eq!((alone.runs, alone.converged, alone.stuck), (7, 4, 2));
    }

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
