//! Results files: `runs.csv`, `summary.csv`, `config.toml`.

mod record;
mod store;
mod summary;

pub use record::{METRIC_COLUMNS, PARAM_COLUMNS, num, param_header, run_row, runs_header};
pub use store::{ResultsDir, ResultsError, write_atomic};
pub use summary::{CellStats, SUMMARY_COLUMNS, quantile};
