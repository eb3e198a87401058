//! `diagonal-corners`: the monoculus command line with DiagonalCorners beside the
//! paper's algorithms.

fn main() -> std::process::ExitCode {
    monoculus::App::new()
        .algorithm::<diagonal_corners::DiagonalCorners>()
        .run()
}
