//! `scheduler.kind = "file"` from the command line: `trace --schedule` writes the rounds
//! of a run, and a config that replays them gives that run again, round by round.

mod common;

use common::{csv_rows_without, monoculus, ok};

const SSYNC: &str = r#"
name = "sched-file"
seeds = 1

[swarm]
n = 30
init = "square"
side = 10.0

[algorithm]
name = "ALGORITHM"

[scheduler]
kind = "ssync"
p = 0.3
"#;

#[test]
fn a_traced_schedule_replays_its_run() {
    for algorithm in ["converge_locality", "converge_quadrant_termination"] {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let ssync = dir.join("ssync.toml");
        std::fs::write(&ssync, SSYNC.replace("ALGORITHM", algorithm)).unwrap();
        let (schedule, first) = (dir.join("s.csv"), dir.join("first.csv"));
        let report = ok(&[
            "trace",
            ssync.to_str().unwrap(),
            "--seed",
            "3",
            "--out",
            first.to_str().unwrap(),
            "--positions",
            "--schedule",
            schedule.to_str().unwrap(),
        ]);
        assert!(report.contains("converged=true"), "{report}");
        let text = std::fs::read_to_string(&schedule).unwrap();
        assert!(text.starts_with("round,robot\n1,"), "{text}");
        let replay = dir.join("replay.toml");
        let config = SSYNC.replace("ALGORITHM", algorithm).replace(
            "kind = \"ssync\"\np = 0.3",
            "kind = \"file\"\nfile = \"s.csv\"",
        );
        std::fs::write(&replay, config).unwrap();
        let second = dir.join("second.csv");
        let again = ok(&[
            "trace",
            replay.to_str().unwrap(),
            "--seed",
            "3",
            "--out",
            second.to_str().unwrap(),
            "--positions",
        ]);
        assert_eq!(report, again);
        assert_eq!(
            csv_rows_without(&first, &["wall_ms"]),
            csv_rows_without(&second, &["wall_ms"])
        );
        let positions = |p: &std::path::Path| {
            std::fs::read_to_string(p.with_extension("positions.csv")).unwrap()
        };
        assert_eq!(positions(&first), positions(&second));
        // The whole run too, with the scheduler named in runs.csv.
        let out = dir.join("results");
        ok(&[
            "run",
            replay.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let rows = csv_rows_without(&out.join("runs.csv"), &[]);
        let header = csv::Reader::from_path(out.join("runs.csv"))
            .unwrap()
            .headers()
            .unwrap()
            .clone();
        let col = header.iter().position(|h| h == "scheduler").unwrap();
        assert_eq!(rows[0][col], "file");
    }
}

#[test]
fn a_schedule_ends_the_run_after_its_last_round() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("s.csv"), "round,robot\n1,0\n1,1\n4,2\n").unwrap();
    let cfg = dir.join("c.toml");
    let text = SSYNC.replace("ALGORITHM", "converge_locality").replace(
        "kind = \"ssync\"\np = 0.3",
        "kind = \"file\"\nfile = \"s.csv\"",
    );
    std::fs::write(&cfg, text).unwrap();
    let out = dir.join("t.csv");
    let report = ok(&[
        "trace",
        cfg.to_str().unwrap(),
        "--seed",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(report.starts_with("rounds=4 converged=false"), "{report}");
    let activated: Vec<String> = csv_rows_without(&out, &[])
        .into_iter()
        .map(|r| r[2].clone())
        .collect();
    assert_eq!(activated, ["0", "2", "0", "0", "1"]);
}

#[test]
fn schedules_are_written_only_for_round_schedulers() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("a.toml");
    std::fs::write(
        &cfg,
        SSYNC
            .replace("ALGORITHM", "converge_locality")
            .replace("kind = \"ssync\"\np = 0.3", "kind = \"async\""),
    )
    .unwrap();
    let out = monoculus(&[
        "trace",
        cfg.to_str().unwrap(),
        "--seed",
        "1",
        "--out",
        tmp.path().join("t.csv").to_str().unwrap(),
        "--schedule",
        tmp.path().join("s.csv").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        e.contains("--schedule: lists the rounds of a round scheduler"),
        "{e}"
    );
}
