//! ASYNC and error models from the command line.

mod common;

use common::{csv_rows_without, monoculus, reported};
use std::path::Path;

fn rows(dir: &Path, drop: &[&str]) -> Vec<Vec<String>> {
    csv_rows_without(&dir.join("runs.csv"), drop)
}

const BASE: &str = r#"
name = "sched"
seeds = 3

[swarm]
n = 25
init = "square"
side = 10.0

[algorithm]
name = ["converge_locality", "converge_quadrant", "converge_quadrant_termination"]

[scheduler]
kind = "fsync"
idle = { kind = "fixed", ticks = 3 }
compute = { kind = "fixed", ticks = 2 }
move = { kind = "fixed", ticks = 4 }
start = "together"
"#;

#[test]
fn async_with_fixed_durations_gives_the_fsync_rows() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("c.toml");
    std::fs::write(&cfg, BASE).unwrap();
    let (f, a) = (tmp.path().join("f"), tmp.path().join("a"));
    let c = cfg.to_str().unwrap();
    assert!(
        monoculus(&["run", c, "--out", f.to_str().unwrap()])
            .status
            .success()
    );
    assert!(
        monoculus(&[
            "run",
            c,
            "--out",
            a.to_str().unwrap(),
            "--set",
            "scheduler.kind=async"
        ])
        .status
        .success()
    );
    // The configs differ in scheduler.kind, so do their hashes.
    let drop = ["scheduler", "ticks", "wall_ms", "config_hash"];
    assert_eq!(rows(&f, &drop), rows(&a, &drop));
    let ticks_col = |dir: &Path| -> Vec<String> {
        let mut r = csv::Reader::from_path(dir.join("runs.csv")).unwrap();
        let t = r
            .headers()
            .unwrap()
            .iter()
            .position(|c| c == "ticks")
            .unwrap();
        r.records().map(|rec| rec.unwrap()[t].to_string()).collect()
    };
    let ticks = ticks_col(&a);
    assert!(
        ticks.iter().all(|t| t.parse::<u64>().is_ok()),
        "async rows carry ticks: {ticks:?}"
    );
    assert!(
        ticks_col(&f).iter().all(|t| t.is_empty()),
        "fsync rows leave ticks empty"
    );
}

#[test]
fn async_random_timing_and_errors_run_and_are_thread_independent() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("c.toml");
    let text = BASE
        .replace("kind = \"fsync\"", "kind = \"async\"")
        .replace(
            "{ kind = \"fixed\", ticks = 3 }",
            "{ kind = \"uniform\", min = 1, max = 8 }",
        )
        .replace(
            "{ kind = \"fixed\", ticks = 4 }",
            "{ kind = \"exponential\", mean = 3 }",
        )
        .replace("start = \"together\"", "start = \"random\"")
        + "\n[errors]\nangle_sigma = 0.03\nflip_p = 0.1\nstep_factor = { kind = \"uniform\", min = 0.9, max = 1.1 }\nnon_rigid = { delta_min = 0.5 }\n";
    std::fs::write(&cfg, text).unwrap();
    let (one, two) = (tmp.path().join("1"), tmp.path().join("2"));
    let c = cfg.to_str().unwrap();
    assert!(
        monoculus(&["run", c, "--out", one.to_str().unwrap(), "--threads", "1"])
            .status
            .success()
    );
    assert!(
        monoculus(&["run", c, "--out", two.to_str().unwrap(), "--threads", "2"])
            .status
            .success()
    );
    assert_eq!(rows(&one, &["wall_ms"]), rows(&two, &["wall_ms"]));
    let resolved = std::fs::read_to_string(one.join("config.toml")).unwrap();
    assert!(
        resolved.contains("[errors]") && resolved.contains("delta_min = 0.5"),
        "{resolved}"
    );
    // A trace under ASYNC has one row per epoch.
    let trace = tmp.path().join("t.csv");
    let out = monoculus(&[
        "trace",
        c,
        "--seed",
        "1",
        "--cell",
        "0",
        "--out",
        trace.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let rounds = reported(&String::from_utf8_lossy(&out.stdout), "rounds");
    assert_eq!(
        std::fs::read_to_string(&trace).unwrap().lines().count(),
        rounds + 2
    );
}

fn check_fails(text: &str) -> String {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("bad.toml");
    std::fs::write(&cfg, text).unwrap();
    let out = monoculus(&["check", cfg.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let e = String::from_utf8(out.stderr)
        .unwrap()
        .replace(cfg.to_str().unwrap(), "bad.toml");
    assert_eq!(e.lines().count(), 1, "{e}");
    e
}

#[test]
fn bad_timing_and_error_keys() {
    let e = check_fails(&BASE.replace(
        "{ kind = \"fixed\", ticks = 3 }",
        "{ kind = \"fixed\", ticks = 0 }",
    ));
    assert!(
        e.starts_with("error: bad.toml:15: scheduler.idle: ticks must be at least 1"),
        "{e}"
    );
    let e = check_fails(&BASE.replace(
        "{ kind = \"fixed\", ticks = 2 }",
        "{ kind = \"uniform\", min = 5, max = 2 }",
    ));
    assert!(
        e.starts_with("error: bad.toml:16: scheduler.compute: needs 1 <= min <= max"),
        "{e}"
    );
    let e = check_fails(&BASE.replace(
        "{ kind = \"fixed\", ticks = 4 }",
        "{ kind = \"gamma\", shape = 2 }",
    ));
    assert!(
        e.starts_with("error: bad.toml:17: scheduler.move.kind: unknown variant `gamma`"),
        "{e}"
    );
    let e = check_fails(&BASE.replace("start = \"together\"", "start = \"whenever\""));
    assert!(
        e.starts_with("error: bad.toml:18: scheduler.start: unknown variant `whenever`"),
        "{e}"
    );
    let e = check_fails(&format!("{BASE}\n[errors]\nflip_p = 1.5\n"));
    assert!(
        e.starts_with("error: bad.toml:21: errors.flip_p: must be in [0, 1]"),
        "{e}"
    );
    let e = check_fails(&format!("{BASE}\n[errors]\nangle_sigmaa = 0.1\n"));
    assert!(
        e.starts_with("error: bad.toml:21: errors.angle_sigmaa: unknown field"),
        "{e}"
    );
    let e = check_fails(&format!(
        "{BASE}\n[errors]\nnon_rigid = {{ delta_min = -1 }}\n"
    ));
    assert!(
        e.starts_with("error: bad.toml:21: errors.non_rigid: delta_min must be non-negative"),
        "{e}"
    );
}
