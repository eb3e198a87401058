//! The command examples of the README and of docs/cli.md run as written, with the output
//! they show (`console` blocks, run by trycmd as cargo and clap run theirs): a page that
//! drifts from the code fails here.
//!
//! The commands run in a scratch folder that holds the repository's `configs/` and
//! `examples/` (linked), so that their paths are the pages' and their outputs go
//! nowhere near the repository. The README's first command, `cargo run --release --
//! run ...`, runs first as its build would run it (the binary, with the same arguments):
//! the README's later commands read its results.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The arguments of the README's first `cargo run --release -- ...` command.
fn readme_first_command(readme: &str) -> Vec<String> {
    let line = readme
        .lines()
        .find_map(|l| l.trim().strip_prefix("cargo run --release -- "))
        .expect("the README's quick start runs `cargo run --release -- ...`");
    line.split_whitespace().map(String::from).collect()
}

#[test]
fn the_readme_and_the_command_line_page_run_as_written() {
    let root = root().canonicalize().unwrap();
    let bin = env!("CARGO_BIN_EXE_monoculus");
    let work = tempfile::tempdir().unwrap();
    for dir in ["configs", "examples"] {
        std::os::unix::fs::symlink(root.join(dir), work.path().join(dir)).unwrap();
    }
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let first = readme_first_command(&readme);
    let status = Command::new(bin)
        .args(&first)
        .current_dir(work.path())
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "the README's first command, {first:?}: {}",
        String::from_utf8_lossy(&status.stderr)
    );
    // trycmd runs a page's commands in the current folder (no `.in` folder beside it):
    // this test's process is its own, so the scratch folder can be it.
    std::env::set_current_dir(work.path()).unwrap();
    trycmd::TestCases::new()
        .register_bin("monoculus", Path::new(bin))
        .register_bin("target/release/monoculus", Path::new(bin))
        .case(root.join("README.md"))
        .case(root.join("docs/cli.md"))
        .run();
}
