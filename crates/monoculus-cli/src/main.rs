//! `monoculus`: the command line of the simulator.

mod allocator;
mod commands;

use std::process::ExitCode;

use clap::Parser;

use crate::commands::{Cli, Failure};

fn main() -> ExitCode {
    allocator::map_large_blocks();
    // A signal leaves every output as it was: temporaries removed, exit status 130.
    monoculus_experiments::output::remove_temporaries_on_signal();
    let cli = Cli::parse();
    match commands::dispatch(cli) {
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
