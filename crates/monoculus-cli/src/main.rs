//! `monoculus`: the command line of the simulator, over the paper's algorithms.

use std::process::ExitCode;

fn main() -> ExitCode {
    monoculus_cli::main_with("monoculus", &monoculus_experiments::Registry::builtin())
}
