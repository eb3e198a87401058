//! What every command-line test needs: running the binary, reading its report.

#![allow(dead_code, reason = "each test binary uses a part")]

use std::path::{Path, PathBuf};
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

/// Runs `monoculus` with `args`, which must fail as bad input: exit status 2 and a
/// one-line message; the message.
pub fn fails(args: &[&str]) -> String {
    let out = monoculus(args);
    let e = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{args:?}: {e}");
    assert_eq!(e.lines().count(), 1, "{args:?}: one line: {e}");
    e
}

/// A path as an argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `monoculus` with `args`, which must succeed; its stdout.
pub fn ok(args: &[&str]) -> String {
    let out = monoculus(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// Writes `text` as `dir/cfg.toml`.
pub fn write_config(dir: &Path, text: &str) -> PathBuf {
    let path = dir.join("cfg.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// The rows of a CSV without the named columns, in file order.
pub fn csv_rows_without(path: &Path, drop: &[&str]) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let h = r.headers().unwrap().clone();
    let keep: Vec<usize> = (0..h.len()).filter(|&i| !drop.contains(&&h[i])).collect();
    r.records()
        .map(|rec| {
            let rec = rec.unwrap();
            keep.iter().map(|&i| rec[i].to_string()).collect()
        })
        .collect()
}

/// runs.csv of a results folder as rows without the wall_ms column, sorted.
pub fn rows_without_wall(dir: &Path) -> Vec<Vec<String>> {
    let mut rows = csv_rows_without(&dir.join("runs.csv"), &["wall_ms"]);
    rows.sort();
    rows
}

/// The value of `key` in a hunt folder's summary.json (its text after the colon).
pub fn summary_field(dir: &Path, key: &str) -> String {
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    text.lines()
        .find_map(|l| {
            l.trim()
                .strip_prefix(&format!("\"{key}\": "))
                .map(|v| v.trim_end_matches(',').to_string())
        })
        .unwrap_or_else(|| panic!("no {key} in {text}"))
}

/// Starts `program` (a monoculus binary) as `explore ARGS`; the process and the address it
/// printed (`http://127.0.0.1:PORT/?token=...`). The caller stops the process.
pub fn explore(program: &str, args: &[&str]) -> (std::process::Child, String) {
    use std::io::{BufRead, BufReader};
    let mut child = Command::new(program)
        .arg("explore")
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let url = line
        .trim()
        .strip_prefix("monoculus explore: ")
        .unwrap_or_else(|| panic!("the address line: {line:?}"))
        .to_string();
    (child, url)
}
