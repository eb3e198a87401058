//! monoculus experiments: TOML configs swept over parameters and seeds, run in
//! parallel, with results as CSV (`runs.csv`, `summary.csv`) beside the resolved
//! `config.toml`.

pub mod config;
pub mod limits;
pub mod positions;
pub mod results;
pub mod runner;
pub mod shard;

pub use config::{Cell, ConfigError, Experiment, RunId};
pub use runner::{RunOptions, SweepError, SweepReport, run_experiment, run_one};
