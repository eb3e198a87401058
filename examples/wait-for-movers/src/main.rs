//! `wait-for-movers`: the monoculus command line with WaitForMovers beside the paper's
//! algorithms.

fn main() -> std::process::ExitCode {
    monoculus::App::new()
        .algorithm::<wait_for_movers::WaitForMovers>()
        .run()
}
