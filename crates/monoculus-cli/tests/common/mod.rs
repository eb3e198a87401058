//! What every command-line test needs: running the binary, reading its report.

#![allow(dead_code, reason = "each test binary uses a part")]

use std::process::{Command, Output};

/// Runs `monoculus` with `args`; whatever the outcome, it must not panic.
pub fn monoculus(args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_monoculus"))
        .args(args)
        .output()
        .expect("monoculus runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    out
}

/// The number after `key=` in a command's report (e.g. `rounds=12` from `trace`).
pub fn reported(stdout: &str, key: &str) -> usize {
    stdout
        .split(&format!("{key}="))
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no {key}= in {stdout}"))
}
