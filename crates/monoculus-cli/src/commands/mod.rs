//! The subcommands.

mod check;
mod look;
mod plot;
mod run;
mod stress;
mod table;
mod trace;

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use monoculus_experiments::results::ResultsError;
use monoculus_experiments::{ConfigError, Experiment, SweepError};

/// monoculus: a simulator for swarms of monoculus robots (robots that cannot measure
/// distances), after Pattanayak, Mondal, Mandal and Schmid.
#[derive(Parser, Debug)]
#[command(name = "monoculus", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run every cell x seed of an experiment into a results folder.
    Run(run::RunArgs),
    /// Validate a config and print its cells and run count; runs nothing.
    Check(check::CheckArgs),
    /// One run, one row per round (hull area, diameter, extents, moving robots).
    Trace(trace::TraceArgs),
    /// What one robot sees in a configuration, as CSV on stdout.
    Look(look::LookArgs),
    /// Tables of rho and tau (median [q1, q3]) per cell from results folders.
    Table(table::TableArgs),
    /// Figures (PNG and SVG) from a results folder, or from a trace CSV.
    Plot(plot::PlotArgs),
    /// Engine throughput: timed FSYNC rounds on a swarm of density 1.
    Stress(stress::StressArgs),
}

/// How a command failed: bad input (exit status 2) or anything else (1).
pub enum Failure {
    /// A bad config, CSV or argument: one line naming the file, line and key.
    Input(String),
    /// Anything else.
    Other(anyhow::Error),
}

impl From<ConfigError> for Failure {
    fn from(e: ConfigError) -> Self {
        Failure::Input(e.to_string())
    }
}

impl From<monoculus_experiments::positions::PositionsError> for Failure {
    fn from(e: monoculus_experiments::positions::PositionsError) -> Self {
        Failure::Input(e.to_string())
    }
}

impl From<ResultsError> for Failure {
    fn from(e: ResultsError) -> Self {
        match e {
            ResultsError::Mismatch { .. } | ResultsError::Corrupt { .. } => {
                Failure::Input(e.to_string())
            }
            ResultsError::Io { .. } => Failure::Other(e.into()),
        }
    }
}

impl From<SweepError> for Failure {
    fn from(e: SweepError) -> Self {
        match e {
            SweepError::Results(r) => r.into(),
            other => Failure::Other(other.into()),
        }
    }
}

impl From<std::io::Error> for Failure {
    fn from(e: std::io::Error) -> Self {
        Failure::Other(e.into())
    }
}

/// Config path plus `--set` overrides, shared by `run`, `check` and `trace`.
#[derive(clap::Args, Debug)]
pub struct ConfigArgs {
    /// The experiment config (TOML).
    pub config: PathBuf,
    /// Override a config key by its dotted path, e.g. `--set swarm.n=1000` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

impl ConfigArgs {
    /// Loads the experiment, printing its warnings.
    pub fn load(&self) -> Result<Experiment, Failure> {
        let exp = Experiment::load(&self.config, &self.set)?;
        for w in &exp.warnings {
            eprintln!("warning: {w}");
        }
        Ok(exp)
    }
}

/// Builds the rayon pool for `--threads` (default: all cores).
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool, Failure> {
    if threads == Some(0) {
        return Err(Failure::Input("--threads: must be at least 1".into()));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| Failure::Other(e.into()))
}

/// Runs a subcommand.
pub fn dispatch(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::Run(a) => run::run(a),
        Command::Check(a) => check::check(a),
        Command::Trace(a) => trace::trace(a),
        Command::Look(a) => look::look(a),
        Command::Table(a) => table::table(a),
        Command::Plot(a) => plot::plot(a),
        Command::Stress(a) => stress::stress(a),
    }
}
