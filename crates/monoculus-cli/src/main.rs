//! `monoculus`: the command line of the simulator.

mod allocator;
mod commands;

use std::process::ExitCode;

use clap::Parser;

use crate::commands::{Cli, Failure};

fn main() -> ExitCode {
    allocator::map_large_blocks();
    let cli = Cli::parse();
    match commands::dispatch(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Input(message)) => {
            eprintln!("error: {message}");
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
