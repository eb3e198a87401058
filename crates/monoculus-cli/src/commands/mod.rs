//! The subcommands.

/// `println!` that reports a failed write (a closed pipe, a full disk) as a [`Failure`]
/// instead of panicking; use inside a function returning `Result<_, Failure>`.
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::commands::write_stdout(format_args!("{}\n", format_args!($($arg)*)))?
    };
}

/// `print!` that reports a failed write as a [`Failure`] (see `outln!`).
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::commands::write_stdout(format_args!($($arg)*))?
    };
}

mod check;
mod explore;
mod hunt;
mod impossibility;
mod look;
mod merge;
mod plot;
mod replay;
mod run;
mod slurm;
mod slurm_script;
mod stress;
mod table;
mod trace;

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use monoculus_experiments::output::{OutputError, Paths};
use monoculus_experiments::results::ResultsError;
use monoculus_experiments::{ConfigError, Experiment, Registry, SweepError};

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
    /// The impossibility construction: two configurations robot 0 cannot tell apart by
    /// directions, and whether each of its moves leaves the hull of one of them.
    Impossibility(impossibility::ImpossibilityArgs),
    /// Tables of rho and tau (median [q1, q3]) per cell from results folders.
    Table(table::TableArgs),
    /// Figures (PNG and SVG) from a results folder, or from a trace CSV.
    Plot(plot::PlotArgs),
    /// Engine throughput: timed FSYNC rounds on a swarm of density 1.
    Stress(stress::StressArgs),
    /// A self-contained HTML replay of one run (and with --gif an animation).
    Replay(replay::ReplayArgs),
    /// Merge the shard files of a results folder into runs.csv and summary.csv.
    Merge(merge::MergeArgs),
    /// Write (and with --submit, submit) Slurm job-array scripts for a sweep or stress runs.
    Slurm(slurm::SlurmArgs),
    /// Search for a start (and schedule) that breaks the config's `[hunt]` property, shrink
    /// it, and write it with a config that replays it.
    Hunt(hunt::HuntArgs),
    /// A live explorer in the browser: place robots, step them, see what each one sees
    /// (a local server on 127.0.0.1 with a token in its address).
    Explore(explore::ExploreArgs),
}

/// How a command failed: bad input (exit status 2), standard output gone (a closed pipe:
/// quiet, 0; anything else: 1), or anything else (1).
pub enum Failure {
    /// A bad config, CSV or argument: one line naming the file, line and key.
    Input(String),
    /// Writing to standard output failed.
    Stdout(std::io::Error),
    /// Anything else.
    Other(anyhow::Error),
}

/// Writes to standard output, a failure as [`Failure::Stdout`].
pub fn write_stdout(args: std::fmt::Arguments<'_>) -> Result<(), Failure> {
    use std::io::Write;
    std::io::stdout()
        .lock()
        .write_fmt(args)
        .map_err(Failure::Stdout)
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
            ResultsError::Io { .. } | ResultsError::Busy { .. } => Failure::Other(e.into()),
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

impl From<OutputError> for Failure {
    fn from(e: OutputError) -> Self {
        Failure::Other(e.into())
    }
}

/// Refuses outputs that are inputs, or two outputs in one file (exit status 2).
pub fn check_paths(paths: &Paths) -> Result<(), Failure> {
    paths.check().map_err(Failure::Input)
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
    /// The files an experiment loaded from this config reads: the config and every file
    /// it names, as the inputs of a command's [`Paths`] (to which the command adds its
    /// outputs).
    pub fn paths(&self, exp: &Experiment) -> Paths {
        let mut paths = Paths::default();
        paths.input("the config", &self.config);
        for f in &exp.inputs {
            paths.input(format!("the config's {}", f.key), &f.path);
        }
        paths
    }

    /// Loads the experiment (its algorithms resolved through `registry`), printing its
    /// warnings.
    pub fn load(&self, registry: &Registry) -> Result<Experiment, Failure> {
        let exp = Experiment::load(&self.config, &self.set, registry)?;
        for w in &exp.warnings {
            eprintln!("warning: {w}");
        }
        Ok(exp)
    }
}

/// The cell `--cell K` names, or the only cell of the config.
pub fn pick_cell<'a>(
    exp: &'a Experiment,
    cell: Option<usize>,
    config: &std::path::Path,
) -> Result<&'a monoculus_experiments::Cell, Failure> {
    match (cell, exp.cells.len()) {
        (Some(k), n) if k < n => Ok(&exp.cells[k]),
        (Some(k), n) => Err(Failure::Input(format!(
            "--cell {k}: the config has {n} cells (0..{n})"
        ))),
        (None, 1) => Ok(&exp.cells[0]),
        (None, n) => Err(Failure::Input(format!(
            "{}: the config has {n} cells; choose one with --cell K or fix the swept keys with --set",
            config.display()
        ))),
    }
}

/// The most worker threads a command starts.
pub const MAX_THREADS: usize = 1024;

/// A variable of this process's environment (unset or not UTF-8: `None`).
pub fn env_var(name: &str) -> Option<String> {
    std::env::var(name).ok()
}

/// The threads a command uses: `--threads`, else the CPUs Slurm gave the task
/// (`SLURM_CPUS_PER_TASK`), else all cores (`None`).
pub fn threads_wanted(threads: Option<usize>) -> Result<Option<usize>, Failure> {
    match threads {
        Some(0) => Err(Failure::Input("--threads: must be at least 1".into())),
        Some(t) if t > MAX_THREADS => Err(Failure::Input(format!(
            "--threads {t}: at most {MAX_THREADS}"
        ))),
        Some(t) => Ok(Some(t)),
        None => Ok(monoculus_experiments::shard::cpus_from_env(&env_var)
            .map_err(Failure::Input)?
            .map(|t| t.min(MAX_THREADS))),
    }
}

/// Builds the rayon pool for `--threads` (see [`threads_wanted`]).
pub fn thread_pool(threads: Option<usize>) -> Result<rayon::ThreadPool, Failure> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads_wanted(threads)?.unwrap_or(0))
        .build()
        .map_err(|e| Failure::Other(e.into()))
}

/// Runs a subcommand, then flushes standard output.
/// The name of the binary that runs (`monoculus`, or a user's binary through `App`), as
/// the messages that suggest a command name it.
static BIN_NAME: std::sync::OnceLock<&'static str> = std::sync::OnceLock::new();

/// Sets the name [`bin_name`] gives (once; later calls change nothing).
pub fn set_bin_name(name: &'static str) {
    let _ = BIN_NAME.set(name);
}

/// The running binary's name, for the commands a message suggests.
pub fn bin_name() -> &'static str {
    BIN_NAME.get().copied().unwrap_or("monoculus")
}

pub fn dispatch(cli: Cli, registry: &Registry) -> Result<(), Failure> {
    run_command(cli, registry)?;
    std::io::Write::flush(&mut std::io::stdout()).map_err(Failure::Stdout)
}

fn run_command(cli: Cli, registry: &Registry) -> Result<(), Failure> {
    match cli.command {
        Command::Run(a) => run::run(a, registry),
        Command::Check(a) => check::check(a, registry),
        Command::Trace(a) => trace::trace(a, registry),
        Command::Look(a) => look::look(a),
        Command::Impossibility(a) => impossibility::impossibility(a),
        Command::Table(a) => table::table(a),
        Command::Plot(a) => plot::plot(a),
        Command::Stress(a) => stress::stress(a, registry),
        Command::Merge(a) => merge::merge(a, registry),
        Command::Replay(a) => replay::replay(a, registry),
        Command::Slurm(a) => slurm::slurm(a, registry),
        Command::Hunt(a) => hunt::hunt(a, registry),
        Command::Explore(a) => explore::explore(a, registry),
    }
}
