//! The command line end to end: run, resume, shards, threads, check, trace, look.

mod common;

use common::{csv_rows_without, monoculus as run, ok, reported, rows_without_wall, write_config};

const SMALL: &str = r#"
name = "small"
seeds = 4

[swarm]
n = [6, 12]
init = "square"
side = 8.0

[algorithm]
name = ["converge_locality", "converge_quadrant"]

[scheduler]
kind = "fsync"
"#;

#[test]
fn run_writes_the_contract_files_and_columns() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let out = tmp.path().join("out");
    ok(&["run", cfg.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let mut r = csv::Reader::from_path(out.join("runs.csv")).unwrap();
    let h: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    for c in [
        "name",
        "algorithm",
        "scheduler",
        "n",
        "dim",
        "side",
        "step",
        "locality",
        "seed",
        "rounds",
        "activations",
        "moves",
        "d_opt",
        "d_max",
        "rho",
        "tau",
        "converged",
        "final_diameter",
        "hull_area_initial",
        "hull_area_final",
        "hull_growth_rounds",
        "wall_ms",
    ] {
        assert!(h.iter().any(|x| x == c), "runs.csv lacks {c}");
    }
    assert_eq!(r.records().count(), 16);
    let mut s = csv::Reader::from_path(out.join("summary.csv")).unwrap();
    let sh: Vec<String> = s.headers().unwrap().iter().map(String::from).collect();
    for c in [
        "runs",
        "converged",
        "rho_median",
        "rho_q1",
        "rho_q3",
        "tau_median",
        "tau_q1",
        "tau_q3",
        "rounds_median",
    ] {
        assert!(sh.iter().any(|x| x == c), "summary.csv lacks {c}");
    }
    assert_eq!(s.records().count(), 4);
    let resolved = std::fs::read_to_string(out.join("config.toml")).unwrap();
    assert!(
        resolved.contains("max_rounds = 100000"),
        "defaults are filled in: {resolved}"
    );
    assert!(resolved.contains("locality = 2.0"));
}

#[test]
fn threads_do_not_change_results() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), &SMALL.replace("n = [6, 12]", "n = [6, 150]"));
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    ok(&[
        "run",
        cfg.to_str().unwrap(),
        "--out",
        a.to_str().unwrap(),
        "--threads",
        "1",
    ]);
    ok(&[
        "run",
        cfg.to_str().unwrap(),
        "--out",
        b.to_str().unwrap(),
        "--threads",
        "2",
    ]);
    assert_eq!(rows_without_wall(&a), rows_without_wall(&b));
    assert_eq!(
        std::fs::read_to_string(a.join("summary.csv")).unwrap(),
        std::fs::read_to_string(b.join("summary.csv")).unwrap()
    );
}

#[test]
fn progress_lines_report_each_run_without_changing_results() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    ok(&["run", cfg.to_str().unwrap(), "--out", a.to_str().unwrap()]);
    let out = run(&[
        "run",
        cfg.to_str().unwrap(),
        "--out",
        b.to_str().unwrap(),
        "--progress",
        "0.000001",
    ]);
    assert!(out.status.success());
    assert_eq!(rows_without_wall(&a), rows_without_wall(&b));
    let stderr = String::from_utf8(out.stderr).unwrap();
    // One closing line per run with its rounds, and lines while the runs went.
    let ends: Vec<&str> = stderr
        .lines()
        .filter(|l| {
            ["(converged)", "(stuck)", "(stopped)"]
                .iter()
                .any(|e| l.ends_with(e))
        })
        .collect();
    assert_eq!(ends.len(), 16, "{stderr}");
    let rows = csv_rows_without(&b.join("runs.csv"), &[]);
    let h = csv::Reader::from_path(b.join("runs.csv"))
        .unwrap()
        .headers()
        .unwrap()
        .clone();
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    for row in &rows {
        let line = format!(
            "small {} seed {}: round {},",
            row[col("cell")],
            row[col("seed")],
            row[col("rounds")]
        );
        assert!(
            ends.iter().any(|l| l.starts_with(&line)),
            "no line `{line}...` in {stderr}"
        );
    }
    assert!(
        stderr.lines().count() > ends.len() && stderr.contains(": round 1, diameter "),
        "{stderr}"
    );
    // Under ASYNC a run counts epochs.
    let c = tmp.path().join("c");
    let out = run(&[
        "run",
        cfg.to_str().unwrap(),
        "--out",
        c.to_str().unwrap(),
        "--set",
        "scheduler.kind=async",
        "--progress",
        "0.000001",
    ]);
    assert!(out.status.success());
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.contains(": epoch 1, diameter ") && !stderr.contains(": round "),
        "{stderr}"
    );
    for bad in ["0", "-1", "soon", "inf"] {
        let flag = format!("--progress={bad}");
        let e = run(&["run", cfg.to_str().unwrap(), &flag]);
        assert_eq!(e.status.code(), Some(2), "--progress {bad}");
        assert!(String::from_utf8_lossy(&e.stderr).contains("--progress"));
    }
}

#[test]
fn a_killed_sweep_resumes_and_force_starts_over() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let out = tmp.path().join("out");
    let c = cfg.to_str().unwrap();
    let o = out.to_str().unwrap();
    ok(&["run", c, "--out", o]);
    let full = rows_without_wall(&out);
    let summary = || std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let full_summary = summary();
    // Simulate a kill: keep the header and 5 rows, plus half of a sixth.
    let text = std::fs::read_to_string(out.join("runs.csv")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let cut = format!("{}\n{}", lines[..6].join("\n"), &lines[6][..10]);
    std::fs::write(out.join("runs.csv"), cut).unwrap();
    let stdout = ok(&["run", c, "--out", o]);
    assert!(stdout.contains("ran 11 runs, 5 already done"), "{stdout}");
    assert_eq!(rows_without_wall(&out), full);
    // The summary counts the rows found on resuming and those run since.
    assert_eq!(summary(), full_summary);
    let stdout = ok(&["run", c, "--out", o]);
    assert!(stdout.contains("ran 0 runs, 16 already done"), "{stdout}");
    let stdout = ok(&["run", c, "--out", o, "--force"]);
    assert!(stdout.contains("ran 16 runs, 0 already done"), "{stdout}");
    // A different experiment into the same folder is refused.
    let other = run(&["run", c, "--out", o, "--set", "seeds=2"]);
    assert_eq!(other.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&other.stderr)
            .contains("config.toml: holds a different experiment")
    );
}

#[test]
fn shards_partition_the_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let (whole, parts) = (tmp.path().join("whole"), tmp.path().join("parts"));
    let c = cfg.to_str().unwrap();
    ok(&["run", c, "--out", whole.to_str().unwrap()]);
    let ran: usize = (0..3)
        .map(|k| {
            let out = ok(&[
                "run",
                c,
                "--out",
                parts.to_str().unwrap(),
                "--shard",
                &format!("{k}/3"),
            ]);
            reported(&out.replace("ran ", "ran="), "ran")
        })
        .sum();
    assert_eq!(ran, 16);
    assert!(
        !parts.join("runs.csv").exists(),
        "shards write only their own files"
    );
    ok(&["merge", parts.to_str().unwrap()]);
    assert_eq!(rows_without_wall(&whole), rows_without_wall(&parts));
    assert_eq!(
        std::fs::read_to_string(whole.join("summary.csv")).unwrap(),
        std::fs::read_to_string(parts.join("summary.csv")).unwrap()
    );
}

#[test]
fn set_overrides_any_key() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let out = ok(&[
        "check",
        cfg.to_str().unwrap(),
        "--set",
        "swarm.n=7",
        "--set",
        "scheduler.kind=ssync",
    ]);
    assert!(out.contains("2 cells x 4 seeds = 8 runs"), "{out}");
    assert!(out.contains("ssync n=7"), "{out}");
    let out = ok(&[
        "check",
        cfg.to_str().unwrap(),
        "--set",
        "stop.max_rounds=[10, 20]",
    ]);
    assert!(out.contains("8 cells x 4 seeds = 32 runs"), "{out}");
}

#[test]
fn trace_writes_one_row_per_round() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let out = tmp.path().join("trace.csv");
    let c = cfg.to_str().unwrap();
    let stdout = ok(&[
        "trace",
        c,
        "--seed",
        "3",
        "--out",
        out.to_str().unwrap(),
        "--set",
        "swarm.n=9",
        "--set",
        "algorithm.name=converge_locality",
        "--positions",
    ]);
    let rounds = reported(&stdout, "rounds");
    let text = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "round,robots,activated,moving,hull_area,diameter,extent_x,extent_y,wall_ms"
    );
    assert_eq!(
        lines.len(),
        rounds + 2,
        "header, round 0, then one row per round"
    );
    let areas: Vec<f64> = lines[1..]
        .iter()
        .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
        .collect();
    assert!(
        areas.windows(2).all(|w| w[1] <= w[0] * (1.0 + 1e-9)),
        "converge_locality never grows the hull"
    );
    let pos = std::fs::read_to_string(tmp.path().join("trace.positions.csv")).unwrap();
    assert_eq!(pos.lines().count(), 1 + 9 * (rounds + 1));
    // A sweep needs a cell.
    let e = run(&["trace", c, "--seed", "1", "--out", out.to_str().unwrap()]);
    assert_eq!(e.status.code(), Some(2));
    ok(&[
        "trace",
        c,
        "--seed",
        "1",
        "--out",
        out.to_str().unwrap(),
        "--cell",
        "3",
    ]);
}

#[test]
fn look_lists_visible_points() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("pos.csv");
    std::fs::write(&csv, "x,y\n0,0\n1,0\n3,0\n0,5\n0,5\n").unwrap();
    let out = ok(&["look", csv.to_str().unwrap(), "--robot", "0"]);
    assert_eq!(out, "index,far,dx,dy\n1,false,1,0\n3,true,0,1\n");
    let out = ok(&[
        "look",
        csv.to_str().unwrap(),
        "--robot",
        "0",
        "--locality",
        "6",
    ]);
    assert_eq!(out, "index,far,dx,dy\n1,false,1,0\n3,false,0,1\n");
    let out = ok(&[
        "look",
        csv.to_str().unwrap(),
        "--robot",
        "1",
        "--model",
        "ola",
    ]);
    assert_eq!(out.lines().next().unwrap(), "index,side_x,side_y,dx,dy");
    assert_eq!(out.lines().count(), 4, "{out}");
    assert!(out.contains("\n2,1,0,1,0\n"));
}

#[test]
fn table_summarises_results_folders() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = write_config(tmp.path(), SMALL);
    let out = tmp.path().join("out");
    ok(&["run", cfg.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let md = ok(&["table", out.to_str().unwrap()]);
    let lines: Vec<&str> = md.lines().filter(|l| l.starts_with('|')).collect();
    assert_eq!(lines.len(), 2 + 4, "header, rule, one row per cell: {md}");
    assert!(lines[0].contains("rho median [q1, q3]") && lines[0].contains("tau median [q1, q3]"));
    assert!(
        lines[2].contains("converge_locality") && lines[2].contains("4/4"),
        "{md}"
    );
    let text = ok(&["table", out.to_str().unwrap(), "--format", "text"]);
    assert!(!text.contains('|'));
    let missing = run(&["table", tmp.path().to_str().unwrap()]);
    assert_eq!(missing.status.code(), Some(2));
}
