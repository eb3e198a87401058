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

const ASYNC: &str = r#"
name = "durations-file"
seeds = 1

[swarm]
n = 25
init = "square"
side = 10.0

[algorithm]
name = "ALGORITHM"

[scheduler]
kind = "async"
start = "random"
DISTRIBUTIONS
"#;

/// `trace --durations` writes every phase an ASYNC run used; a config that gives them
/// (`scheduler.durations`) replays the run bit for bit, even with other distributions,
/// which it then never asks.
#[test]
fn traced_durations_replay_their_run_whatever_the_distributions() {
    for algorithm in ["converge_locality", "converge_quadrant"] {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let drawn = ASYNC.replace("ALGORITHM", algorithm).replace(
            "DISTRIBUTIONS",
            "idle = { kind = \"uniform\", min = 1, max = 9 }\ncompute = { kind = \"uniform\", min = 1, max = 4 }\nmove = { kind = \"exponential\", mean = 3.0 }",
        );
        std::fs::write(dir.join("drawn.toml"), &drawn).unwrap();
        let (durations, first) = (dir.join("d.csv"), dir.join("first.csv"));
        let report = ok(&[
            "trace",
            dir.join("drawn.toml").to_str().unwrap(),
            "--seed",
            "2",
            "--out",
            first.to_str().unwrap(),
            "--positions",
            "--durations",
            durations.to_str().unwrap(),
        ]);
        assert!(report.contains("converged=true"), "{report}");
        let text = std::fs::read_to_string(&durations).unwrap();
        assert!(
            text.starts_with("robot,cycle,phase,ticks\n0,0,idle,"),
            "{text}"
        );
        assert!(text.lines().count() > 3 * 25, "every robot's phases");
        // The same seed, every phase fixed at 7 ticks but for the file's.
        let given = ASYNC.replace("ALGORITHM", algorithm).replace(
            "DISTRIBUTIONS",
            "idle = { kind = \"fixed\", ticks = 7 }\ncompute = { kind = \"fixed\", ticks = 7 }\nmove = { kind = \"fixed\", ticks = 7 }\ndurations = \"d.csv\"",
        );
        std::fs::write(dir.join("given.toml"), given).unwrap();
        let second = dir.join("second.csv");
        let again = ok(&[
            "trace",
            dir.join("given.toml").to_str().unwrap(),
            "--seed",
            "2",
            "--out",
            second.to_str().unwrap(),
            "--positions",
        ]);
        assert_eq!(again, report, "{algorithm}: the same outcome");
        assert_eq!(
            csv_rows_without(&first, &["wall_ms"]),
            csv_rows_without(&second, &["wall_ms"]),
            "{algorithm}: the same epochs"
        );
        assert_eq!(
            std::fs::read(dir.join("first.positions.csv")).unwrap(),
            std::fs::read(dir.join("second.positions.csv")).unwrap(),
            "{algorithm}: the same positions"
        );
        // Without the file, the fixed durations make another run.
        std::fs::write(
            dir.join("given.toml"),
            std::fs::read_to_string(dir.join("given.toml"))
                .unwrap()
                .replace("durations = \"d.csv\"", ""),
        )
        .unwrap();
        let other = ok(&[
            "trace",
            dir.join("given.toml").to_str().unwrap(),
            "--seed",
            "2",
            "--out",
            dir.join("third.csv").to_str().unwrap(),
        ]);
        assert_ne!(other, report);
    }
    // Round schedulers have no phases.
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("s.toml"),
        SSYNC.replace("ALGORITHM", "converge_locality"),
    )
    .unwrap();
    let out = monoculus(&[
        "trace",
        tmp.path().join("s.toml").to_str().unwrap(),
        "--seed",
        "0",
        "--out",
        tmp.path().join("t.csv").to_str().unwrap(),
        "--durations",
        tmp.path().join("d.csv").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr)
            .contains("--durations: lists the phases of an ASYNC run")
    );
}
