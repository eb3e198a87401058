//! The monoculus command line as a library: every command (`run`, `check`, `trace`,
//! `replay`, `slurm`, ...) over the algorithms of a [`Registry`]. The `monoculus` binary
//! is [`main_with`] over the paper's algorithms; a user's binary (through the
//! `monoculus` crate's `App`) is the same over theirs.

mod allocator;
mod commands;

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches};
use monoculus_experiments::Registry;

use crate::commands::{Cli, Failure};

/// Runs the command line of a binary called `name` whose algorithms are `registry`'s:
/// parses the process's arguments, runs the command, and returns its exit status (0
/// success, 2 bad input, 1 other failures, 130 interrupted).
///
/// ```no_run
/// use monoculus_experiments::Registry;
///
/// fn main() -> std::process::ExitCode {
///     monoculus_cli::main_with("monoculus", &Registry::builtin())
/// }
/// ```
pub fn main_with(name: &'static str, registry: &Registry) -> ExitCode {
    allocator::map_large_blocks();
    // A signal leaves every output as it was: temporaries removed, exit status 130.
    monoculus_experiments::output::remove_temporaries_on_signal();
    quiet_algorithm_panics();
    commands::set_bin_name(name);
    let matches = Cli::command().name(name).bin_name(name).get_matches();
    let cli = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    match commands::dispatch(cli, registry) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Input(message)) => {
            // One line, and no value quoted at more than 100 characters.
            let message = monoculus_experiments::one_line(&message);
            eprintln!("error: {}", monoculus_experiments::short_quotes(&message));
            ExitCode::from(2)
        }
        // A closed pipe (`monoculus ... | head -1`) ends quietly, as Unix tools do.
        Err(Failure::Stdout(e)) if e.kind() == std::io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(Failure::Stdout(e)) => {
            eprintln!("error: standard output: {e}");
            ExitCode::from(1)
        }
        Err(Failure::Other(e)) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}

/// A panic inside an algorithm's `decide` is the run's failure, reported with the run
/// (algorithm, robot, round, message): the default hook's lines are left out for it.
/// Any other panic is a bug of monoculus and is reported as usual.
fn quiet_algorithm_panics() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if !monoculus_core::algorithms::in_algorithm() {
            default(info);
        }
    }));
}
