//! monoculus experiments: TOML configs swept over parameters and seeds, run in
//! parallel, with results as CSV (`runs.csv`, `summary.csv`) beside the resolved
//! `config.toml`.

pub mod config;
pub mod limits;
pub mod positions;
pub mod replay;
pub mod results;
pub mod runner;
pub mod schedule;
pub mod shard;

pub use config::{Cell, ConfigError, Experiment, RunId};

/// `text` with line breaks and other control characters escaped (`\n`), so that a
/// message quoting what a user wrote stays one line.
pub fn one_line(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}
pub use runner::{
    Progress, RunOptions, RunProgress, SweepError, SweepReport, run_experiment, run_one,
    run_one_with,
};
