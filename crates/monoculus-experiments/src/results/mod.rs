//! Results files: `runs.csv` (or one file per shard), `summary.csv`, `config.toml`,
//! `provenance.toml`; written so that no kill and no second process can corrupt them.

mod fields;
mod fsio;
mod lock;
mod merge;
mod provenance;
mod record;
mod rows;
mod store;
mod stress_log;
mod summary;
mod text;

pub use fsio::{create_if_absent, write_atomic};
pub use lock::{Lock, LockKind};
pub use merge::{MergeReport, MissingRuns, merge};
pub use provenance::{Attempt, GIT_COMMIT, Provenance, VERSION, config_hash, host_name};
pub use record::{
    CONFIG_HASH_COLUMN, METRIC_COLUMNS, PARAM_COLUMNS, RowSchema, RunMetrics, num, param_header,
    param_values, run_row, runs_header,
};
pub use rows::{FoundRows, RunRows, read_rows, write_rows};
pub use store::{
    LOCK_FILE, OpenSpec, ResultsDir, ResultsError, SHARDS_DIR, folder_outputs, shard_files,
};
pub use stress_log::{
    StressLog, StressMerge, StressRow, merge_stress, read_stress, stress_shard_path,
};
pub use summary::{
    CellStats, SUMMARY_COLUMNS, SummaryStats, quantile, summary_bytes, write_summary,
};
