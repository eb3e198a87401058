//! What monoculus promises about a results folder, and about the files it reads: a kill
//! at any moment loses no finished row, duplicates are dropped and reported, corrupted
//! result files are named by file, line and column, and standard output going away is not
//! a crash. (Locks and rows of another experiment: `tests/cluster.rs`.)

mod common;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::Duration;

use common::{csv_rows_without, fails, monoculus, ok, s, write_config};

/// Many quick runs: a runs.csv of 20,000 rows in well under a second.
const MANY: &str = r#"
name = "many"
seeds = 20000

[swarm]
n = 2
init = "square"
side = 1.0

[algorithm]
name = "converge_locality"
"#;

#[test]
fn a_kill_during_the_resume_repair_loses_no_row() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), MANY);
    let out = tmp.path().join("o");
    ok(&["run", s(&cfg), "--out", s(&out)]);
    let runs = out.join("runs.csv");
    let full = std::fs::read_to_string(&runs).unwrap();
    let lines: Vec<&str> = full.lines().collect();
    // What a kill in mid-append leaves: 15,000 rows and half of the next one.
    let kept = 15_000;
    std::fs::write(
        &runs,
        format!("{}\n{}", lines[..=kept].join("\n"), &lines[kept + 1][..20]),
    )
    .unwrap();
    // The repair replaces the file, never rewrites it in place: whoever holds the old file
    // (as a kill mid-rewrite would leave it) still reads every row of it.
    let before = std::fs::read(&runs).unwrap();
    let mut held = std::fs::File::open(&runs).unwrap();
    ok(&["run", s(&cfg), "--out", s(&out), "--threads", "1"]);
    let mut old = Vec::new();
    std::io::Read::read_to_end(&mut held, &mut old).unwrap();
    assert_eq!(old, before, "runs.csv was rewritten in place");
    std::fs::write(
        &runs,
        format!("{}\n{}", lines[..=kept].join("\n"), &lines[kept + 1][..20]),
    )
    .unwrap();
    // Resume, and kill the moment the repair starts: when a temporary file appears beside
    // runs.csv (an atomic rewrite) or runs.csv shrinks (a rewrite in place), or later.
    for k in 0..8u64 {
        let size = std::fs::metadata(&runs).unwrap().len();
        // A killed rewrite leaves its temporary (the next run removes it): not this one's.
        for e in std::fs::read_dir(&out).unwrap() {
            let e = e.unwrap();
            if e.file_name().to_string_lossy().ends_with(".tmp") {
                std::fs::remove_file(e.path()).unwrap();
            }
        }
        let mut child = Command::new(env!("CARGO_BIN_EXE_monoculus"))
            .args(["run", s(&cfg), "--out", s(&out), "--threads", "1"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let start = std::time::Instant::now();
        loop {
            let repairing = std::fs::read_dir(&out)
                .unwrap()
                .any(|e| e.unwrap().file_name().to_string_lossy().ends_with(".tmp"))
                || std::fs::metadata(&runs).map_or(true, |m| m.len() < size);
            if repairing || start.elapsed() > Duration::from_secs(10) {
                break;
            }
            if child.try_wait().unwrap().is_some() {
                break;
            }
        }
        // Later kills land in the runs that follow the repair.
        std::thread::sleep(Duration::from_millis(k * 2));
        let _ = child.kill();
        child.wait().unwrap();
        let text = std::fs::read_to_string(&runs).unwrap();
        let complete = text.lines().count() - usize::from(!text.ends_with('\n')) - 1;
        assert!(complete >= kept, "kill {k}: {complete} of {kept} rows left");
        assert!(text.starts_with(lines[0]), "kill {k}: header gone");
        // The next resume has a cut line to repair again.
        if text.ends_with('\n') {
            let mut t = text.clone();
            t.push_str(&lines[1][..20]);
            std::fs::write(&runs, t).unwrap();
        }
    }
    let done = ok(&["run", s(&cfg), "--out", s(&out)]);
    assert!(
        done.contains("20000 runs") || done.contains("already done"),
        "{done}"
    );
    let rows = |t: &str| -> Vec<String> {
        let mut v: Vec<String> = t
            .lines()
            .map(|l| l.rsplitn(3, ',').nth(2).unwrap().to_string())
            .collect();
        v.sort();
        v
    };
    // Everything but wall_ms (and the hash after it) is as the first, whole run had it.
    assert_eq!(rows(&std::fs::read_to_string(&runs).unwrap()), rows(&full));
    // No temporary file is left behind by a finished run (killed ones may leave theirs).
    ok(&["run", s(&cfg), "--out", s(&out)]);
    let leftovers: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

const SMALL: &str = r#"
name = "small"
seeds = 4

[swarm]
n = [6, 12]
init = "square"
side = 8.0

[algorithm]
name = "converge_locality"
"#;

#[test]
fn duplicated_rows_are_dropped_on_resume_and_reported() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let out = tmp.path().join("o");
    ok(&["run", s(&cfg), "--out", s(&out)]);
    let summary = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let runs = out.join("runs.csv");
    let text = std::fs::read_to_string(&runs).unwrap();
    let second = text.lines().nth(2).unwrap().to_string();
    std::fs::write(&runs, format!("{text}{second}\n{second}\n")).unwrap();
    let o = monoculus(&["run", s(&cfg), "--out", s(&out)]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{e}");
    assert!(e.contains("runs.csv: dropped 2 duplicated rows"), "{e}");
    assert_eq!(std::fs::read_to_string(&runs).unwrap(), text);
    assert_eq!(
        std::fs::read_to_string(out.join("summary.csv")).unwrap(),
        summary
    );
}

#[test]
fn corrupted_result_files_are_named_by_line_and_column() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let out = tmp.path().join("o");
    ok(&["run", s(&cfg), "--out", s(&out)]);
    let summary = out.join("summary.csv");
    let good = std::fs::read_to_string(&summary).unwrap();
    let header: Vec<&str> = good.lines().next().unwrap().split(',').collect();
    let rho = header.iter().position(|c| *c == "rho_median").unwrap();
    let runs_col = header.iter().position(|c| *c == "runs").unwrap();
    for (col, bad) in [
        (rho, "1.2.3"),
        (rho, "maybe"),
        (rho, "-inf"),
        (runs_col, "4.5"),
    ] {
        let mut lines: Vec<String> = good.lines().map(String::from).collect();
        let mut cells: Vec<String> = lines[2].split(',').map(String::from).collect();
        cells[col] = bad.into();
        lines[2] = cells.join(",");
        std::fs::write(&summary, lines.join("\n") + "\n").unwrap();
        let e = fails(&["table", s(&out)]);
        assert!(
            e.contains(&format!("summary.csv:3: column {}: `{bad}`", header[col])),
            "{e}"
        );
    }
    std::fs::write(&summary, format!("{}\n", good.lines().next().unwrap())).unwrap();
    assert!(fails(&["table", s(&out)]).contains("holds no cells"));
    // plot reads runs.csv.
    let runs = out.join("runs.csv");
    let text = std::fs::read_to_string(&runs).unwrap();
    let head: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    for (name, bad) in [
        ("rho", "1.2.3"),
        ("tau", "-inf"),
        ("converged", "maybe"),
        ("seed", "x"),
    ] {
        let c = head.iter().position(|h| *h == name).unwrap();
        let mut lines: Vec<String> = text.lines().map(String::from).collect();
        let mut cells: Vec<String> = lines[4].split(',').map(String::from).collect();
        cells[c] = bad.into();
        lines[4] = cells.join(",");
        std::fs::write(&runs, lines.join("\n") + "\n").unwrap();
        let e = fails(&["plot", s(&out)]);
        assert!(
            e.contains(&format!("runs.csv:5: column {name}: `{bad}`")),
            "{e}"
        );
    }
    std::fs::write(&runs, format!("{}\n", text.lines().next().unwrap())).unwrap();
    assert!(fails(&["plot", s(&out)]).contains("holds no runs"));
}

#[test]
fn a_trace_naming_a_robot_outside_the_swarm_is_fails() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let trace = tmp.path().join("t.csv");
    ok(&[
        "trace",
        s(&cfg),
        "--seed",
        "1",
        "--out",
        s(&trace),
        "--cell",
        "0",
        "--positions",
    ]);
    let positions = tmp.path().join("t.positions.csv");
    let text = std::fs::read_to_string(&positions).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let last = lines.len() - 1;
    let mut cells: Vec<String> = lines[last].split(',').map(String::from).collect();
    cells[1] = "4000000000".into();
    lines[last] = cells.join(",");
    std::fs::write(&positions, lines.join("\n") + "\n").unwrap();
    let e = fails(&["plot", s(&trace)]);
    assert!(
        e.contains(&format!(
            "t.positions.csv:{}: column robot: 4000000000 is not a robot",
            last + 1
        )),
        "{e}"
    );
    cells[1] = "-1".into();
    lines[last] = cells.join(",");
    std::fs::write(&positions, lines.join("\n") + "\n").unwrap();
    assert!(fails(&["plot", s(&trace)]).contains("column robot: `-1` is not a whole number"));
}

#[test]
fn standard_output_going_away_is_not_a_crash() {
    let tmp = tempfile::tempdir().unwrap();
    // 2000 cells: a listing far longer than a pipe holds.
    let ns: Vec<String> = (1..=2000).map(|k| k.to_string()).collect();
    let cfg = write_config(
        tmp.path(),
        &SMALL.replace("n = [6, 12]", &format!("n = [{}]", ns.join(", "))),
    );
    let mut child = Command::new(env!("CARGO_BIN_EXE_monoculus"))
        .args(["check", s(&cfg)])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert!(first.contains("2000 cells"), "{first}");
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(0), "a closed pipe ends quietly");
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // A full disk: one line, exit 1.
    let full = std::fs::File::create("/dev/full").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_monoculus"))
        .args(["check", s(&cfg)])
        .stdout(full)
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{e}");
    assert_eq!(
        e.trim(),
        "error: standard output: No space left on device (os error 28)"
    );
}

#[test]
fn io_errors_name_the_file_and_their_cause_once() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let file = tmp.path().join("plain");
    std::fs::write(&file, "").unwrap();
    let o = monoculus(&["run", s(&cfg), "--out", s(&file.join("sub"))]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(e.contains("plain/sub: "), "{e}");
    assert_eq!(e.matches("os error").count(), 1, "{e}");
}

#[test]
fn a_header_only_runs_csv_resumes_from_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let out = tmp.path().join("o");
    ok(&["run", s(&cfg), "--out", s(&out)]);
    let whole = csv_rows_without(&out.join("runs.csv"), &["wall_ms"]);
    let text = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    std::fs::write(
        out.join("runs.csv"),
        format!("{}\n", text.lines().next().unwrap()),
    )
    .unwrap();
    let again = ok(&["run", s(&cfg), "--out", s(&out)]);
    assert!(again.contains("ran 8 runs, 0 already done"), "{again}");
    assert_eq!(csv_rows_without(&out.join("runs.csv"), &["wall_ms"]), whole);
}

/// A seeded byte-level mutation of `text`: cut, insert a hostile token, or truncate.
fn mutate(seed: u64, text: &str) -> String {
    const TOKENS: &[&str] = &[
        ",",
        "\"",
        "\n",
        "-inf",
        "1.2.3",
        "maybe",
        "NaN",
        "",
        "99999999999999999999",
        "-1",
        "x",
        "\u{0}",
        "é",
    ];
    let mut z = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
    let mut next = || {
        z ^= z << 13;
        z ^= z >> 7;
        z ^= z << 17;
        z
    };
    let mut s: Vec<char> = text.chars().collect();
    for _ in 0..1 + next() % 3 {
        let at = (next() % (s.len() as u64 + 1)) as usize;
        match next() % 3 {
            0 => {
                let end = (at + 1 + (next() % 8) as usize).min(s.len());
                s.drain(at.min(end)..end);
            }
            1 => {
                let t = TOKENS[(next() % TOKENS.len() as u64) as usize];
                s.splice(at..at, t.chars());
            }
            _ => s.truncate(at.max(text.len() / 2)),
        }
    }
    s.into_iter().collect()
}

#[test]
fn mutated_result_files_give_exit_0_or_2_with_one_line() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let out = tmp.path().join("o");
    ok(&["run", s(&cfg), "--out", s(&out)]);
    let trace = tmp.path().join("t.csv");
    ok(&[
        "trace",
        s(&cfg),
        "--seed",
        "1",
        "--out",
        s(&trace),
        "--cell",
        "1",
        "--positions",
    ]);
    let figures = tmp.path().join("f");
    let files = [
        (out.join("summary.csv"), vec!["table", s(&out)]),
        (
            out.join("runs.csv"),
            vec!["plot", s(&out), "--out", s(&figures)],
        ),
        (trace.clone(), vec!["plot", s(&trace)]),
        (tmp.path().join("t.positions.csv"), vec!["plot", s(&trace)]),
        (cfg.clone(), vec!["check", s(&cfg)]),
    ];
    for (path, args) in &files {
        let good = std::fs::read_to_string(path).unwrap();
        for seed in 0..12 {
            std::fs::write(path, mutate(seed, &good)).unwrap();
            let o = monoculus(args);
            let e = String::from_utf8_lossy(&o.stderr);
            let code = o.status.code();
            assert!(
                matches!(code, Some(0) | Some(2)),
                "{args:?} on mutation {seed} of {}: {code:?} {e}",
                path.display()
            );
            if code == Some(2) {
                assert_eq!(e.lines().count(), 1, "{args:?}: {e}");
            }
        }
        std::fs::write(path, good).unwrap();
    }
}
