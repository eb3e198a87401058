//! `toward-anyone`: the monoculus command line with TowardAnyone beside the paper's
//! algorithms.

fn main() -> std::process::ExitCode {
    monoculus::App::new()
        .algorithm::<toward_anyone::TowardAnyone>()
        .run()
}
