//! `monoculus hunt`: counterexamples found, shrunk, written and replayed by `run`; the
//! same result whatever the thread count; bad input refused; an interrupted hunt keeps
//! its best candidate.

mod common;

use std::path::{Path, PathBuf};

use common::{fails, monoculus, ok, s, summary_field, write_config};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

/// The one row of runs.csv of a results folder: column -> value.
fn run_row(dir: &Path) -> std::collections::HashMap<String, String> {
    let mut r = csv::Reader::from_path(dir.join("runs.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let rows: Vec<csv::StringRecord> = r.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 1);
    h.iter()
        .zip(rows[0].iter())
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

/// Hunts `config` into `dir/hunt` and replays its reproduce.toml into `dir/replayed`.
fn hunt_and_replay(dir: &Path, config: &Path, extra: &[&str]) -> (PathBuf, PathBuf) {
    let out = dir.join("hunt");
    let mut args = vec!["hunt", s(config), "--out", s(&out), "--quiet"];
    args.extend_from_slice(extra);
    ok(&args);
    let replayed = dir.join("replayed");
    ok(&["run", s(&out.join("reproduce.toml")), "--out", s(&replayed)]);
    (out, replayed)
}

#[test]
fn median_and_angle_bisector_grow_the_hull_shrunk_to_at_most_six_robots_and_run_shows_it() {
    for name in ["median", "angle_bisector"] {
        let dir = tempfile::tempdir().unwrap();
        let (out, replayed) =
            hunt_and_replay(dir.path(), &repo(&format!("configs/hunt/{name}.toml")), &[]);
        assert_eq!(summary_field(&out, "found"), "true", "{name}");
        assert_eq!(summary_field(&out, "shrunk"), "true", "{name}");
        let n: usize = summary_field(&out, "n").parse().unwrap();
        assert!(n <= 6, "{name}: shrunk to {n} robots");
        for f in ["positions.csv", "reproduce.toml", "replay.html"] {
            assert!(out.join(f).exists(), "{name}: {f}");
        }
        // FSYNC: the schedule does not matter, and none is written.
        assert!(!out.join("schedule.csv").exists());
        let positions = std::fs::read_to_string(out.join("positions.csv")).unwrap();
        assert_eq!(positions.lines().count(), n + 1);
        // Coordinates on a coarse grid: at most 3 decimals for most of them.
        let row = run_row(&replayed);
        assert_eq!(row["hull_grew"], "true", "{name}: {row:?}");
        assert_eq!(row["n"], n.to_string());
        assert_eq!(row["rounds"], summary_field(&out, "round"));
        // The summary's verdict is the replayed run's (the search stopped its run at
        // the violation; the replay is cut there too).
        for column in ["converged", "stuck"] {
            assert_eq!(row[column], summary_field(&out, column), "{name}: {column}");
        }
        assert_eq!(
            format!("\"{}\"", row["stopped_by"]),
            summary_field(&out, "stopped_by"),
            "{name}"
        );
    }
}

#[test]
fn converge_locality_grows_no_hull_and_says_how_much_was_searched() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("h");
    ok(&[
        "hunt",
        s(&repo("configs/hunt/converge_locality.toml")),
        "--out",
        s(&out),
        "--quiet",
        "--set",
        "hunt.evaluations=3000",
    ]);
    assert_eq!(summary_field(&out, "found"), "false");
    assert_eq!(summary_field(&out, "evaluations"), "3000");
    assert_eq!(summary_field(&out, "failures"), "0");
    // The closest candidate is written, and replays without growth.
    let replayed = dir.path().join("r");
    ok(&["run", s(&out.join("reproduce.toml")), "--out", s(&replayed)]);
    assert_eq!(run_row(&replayed)["hull_grew"], "false");
}

#[test]
fn the_same_seed_finds_the_same_whatever_the_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    // The last searches ASYNC durations (and finds nothing, so every move is made).
    for (config, evaluations, scheduler) in [
        ("median", "20000", "fsync"),
        ("converge_locality", "1500", "fsync"),
        ("converge_locality", "1500", "async"),
    ] {
        let mut seen = Vec::new();
        for threads in ["1", "2"] {
            let out = dir.path().join(format!("{config}-{scheduler}-{threads}"));
            ok(&[
                "hunt",
                s(&repo(&format!("configs/hunt/{config}.toml"))),
                "--out",
                s(&out),
                "--quiet",
                "--threads",
                threads,
                "--set",
                &format!("hunt.evaluations={evaluations}"),
                "--set",
                "hunt.seed=7",
                "--set",
                &format!("scheduler.kind={scheduler}"),
            ]);
            let summary: Vec<String> = std::fs::read_to_string(out.join("summary.json"))
                .unwrap()
                .lines()
                .filter(|l| !l.contains("\"seconds\""))
                .map(String::from)
                .collect();
            let positions = std::fs::read_to_string(out.join("positions.csv")).unwrap();
            let durations = std::fs::read_to_string(out.join("durations.csv")).ok();
            assert_eq!(
                durations.is_some(),
                scheduler == "async",
                "{config} {scheduler}"
            );
            seen.push((summary, positions, durations));
        }
        assert_eq!(seen[0], seen[1], "{config} {scheduler}");
    }
}

#[test]
fn an_ssync_counterexample_carries_its_schedule_and_replays_from_it() {
    let dir = tempfile::tempdir().unwrap();
    let config = write_config(
        dir.path(),
        r#"
name = "ssync-hull"
[swarm]
n = 5
init = "square"
side = 3.0
[algorithm]
name = "median"
[scheduler]
kind = "ssync"
p = 0.5
[stop]
max_rounds = 20
[hunt]
property = "hull_grows"
n_min = 3
n_max = 8
evaluations = 20000
"#,
    );
    let (out, replayed) = hunt_and_replay(dir.path(), &config, &[]);
    assert_eq!(summary_field(&out, "found"), "true");
    assert_eq!(summary_field(&out, "subsets_searched"), "true");
    let reproduce = std::fs::read_to_string(out.join("reproduce.toml")).unwrap();
    assert!(reproduce.contains("kind = \"file\""), "{reproduce}");
    assert!(reproduce.contains("schedule.csv"), "{reproduce}");
    let schedule = std::fs::read_to_string(out.join("schedule.csv")).unwrap();
    assert!(schedule.starts_with("round,robot\n"));
    let round: u64 = summary_field(&out, "round").parse().unwrap();
    let last: u64 = schedule
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .max()
        .unwrap();
    assert_eq!(last, round, "the schedule ends with the violation's round");
    assert_eq!(run_row(&replayed)["hull_grew"], "true");
}

#[test]
fn slow_reports_the_rounds_that_run_replays() {
    let dir = tempfile::tempdir().unwrap();
    let (out, replayed) = hunt_and_replay(
        dir.path(),
        &repo("configs/hunt/converge_quadrant_slow.toml"),
        &[
            "--set",
            "hunt.evaluations=96",
            "--set",
            "swarm.n=6",
            "--set",
            "swarm.side=8",
        ],
    );
    // `slow` is never broken: the folder holds the slowest run found.
    assert_eq!(summary_field(&out, "found"), "false");
    assert_eq!(summary_field(&out, "converged"), "true");
    let row = run_row(&replayed);
    assert_eq!(row["rounds"], summary_field(&out, "rounds"));
    assert_eq!(row["converged"], "true");
    let epochs: u64 = summary_field(&out, "epochs").parse().unwrap();
    let rounds: u64 = summary_field(&out, "rounds").parse().unwrap();
    assert!(
        epochs >= 1 && epochs <= rounds,
        "{epochs} epochs in {rounds} rounds"
    );
}

#[test]
fn an_async_counterexample_carries_its_durations_and_replays_from_them() {
    let dir = tempfile::tempdir().unwrap();
    let config = repo("configs/hunt/stale_view.toml");
    let (out, replayed) = hunt_and_replay(dir.path(), &config, &[]);
    assert_eq!(summary_field(&out, "found"), "true");
    assert_eq!(summary_field(&out, "shrunk"), "true");
    assert_eq!(summary_field(&out, "durations_searched"), "true");
    // Shrunk to the one long phase that makes the view stale.
    assert_eq!(summary_field(&out, "durations_given"), "1");
    let durations = std::fs::read_to_string(out.join("durations.csv")).unwrap();
    assert!(
        durations.starts_with("robot,cycle,phase,ticks\n") && durations.lines().count() == 2,
        "{durations}"
    );
    let reproduce = std::fs::read_to_string(out.join("reproduce.toml")).unwrap();
    assert!(
        reproduce.contains("durations = \"durations.csv\""),
        "{reproduce}"
    );
    // The replay collides: the two robots end at one point.
    assert_eq!(run_row(&replayed)["final_diameter"], "0");
    // Without the given duration, the same start and seed never collide.
    let plain = dir.path().join("plain.toml");
    std::fs::write(
        &plain,
        reproduce.replace("durations = \"durations.csv\"\n", ""),
    )
    .unwrap();
    std::fs::copy(out.join("positions.csv"), dir.path().join("positions.csv")).unwrap();
    let plain_out = dir.path().join("plain");
    ok(&["run", s(&plain), "--out", s(&plain_out)]);
    assert_ne!(run_row(&plain_out)["final_diameter"], "0");
    // Lockstep durations alone (the run's seed searched) find nothing.
    let lockstep = dir.path().join("lockstep");
    ok(&[
        "hunt",
        s(&config),
        "--out",
        s(&lockstep),
        "--quiet",
        "--set",
        "hunt.durations=false",
    ]);
    assert_eq!(summary_field(&lockstep, "found"), "false");
    assert_eq!(summary_field(&lockstep, "durations_given"), "0");
    assert!(!lockstep.join("durations.csv").exists());
}

#[test]
fn bad_hunts_are_refused_with_the_key_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let base = |hunt: &str, extra: &str| {
        format!(
            "name = \"bad\"\n{extra}\n[algorithm]\nname = \"median\"\n[stop]\nmax_rounds = 5\n{hunt}\n"
        )
    };
    let square = "[swarm]\nn = 4\ninit = \"square\"\nside = 3.0";
    let cases: Vec<(String, &str)> = vec![
        (base("", square), "no [hunt] section"),
        (
            base("[hunt]\nproperty = \"hull_grows\"", square),
            "hunt: no budget",
        ),
        (
            base("[hunt]\nproperty = \"hull_grows\"\nevaluations = 0", square),
            "hunt.evaluations",
        ),
        (
            base("[hunt]\nproperty = \"hull_grows\"\nseconds = -1.0", square),
            "hunt.seconds",
        ),
        (
            base(
                "[hunt]\nproperty = \"hull_grows\"\nevaluations = 9\nn_min = 5\nn_max = 4",
                square,
            ),
            "hunt.n_max",
        ),
        (
            base(
                "[hunt]\nproperty = \"hull_grows\"\nevaluations = 9\nn_min = 1\nn_max = 2",
                square,
            ),
            "hunt.property",
        ),
        (
            base(
                "[hunt]\nproperty = \"collision\"\nevaluations = 9\n[vision]\nrobot_radius = 0.1",
                square,
            ),
            "hunt.property",
        ),
        (
            base(
                "[hunt]\nproperty = \"hull_shrinks\"\nevaluations = 9",
                square,
            ),
            "hunt.property",
        ),
        (
            base(
                "[hunt]\nproperty = \"hull_grows\"\nevaluations = 9\nbudget = 3",
                square,
            ),
            "budget",
        ),
        (
            base(
                "[hunt]\nproperty = \"hull_grows\"\nevaluations = 9",
                "[swarm]\ninit = \"file\"\nfile = \"bad.csv\"",
            ),
            "bad.csv",
        ),
        (
            base(
                "[hunt]\nproperty = \"hull_grows\"\nevaluations = 9\nmax_ticks = 0",
                &format!("{square}\n[scheduler]\nkind = \"async\""),
            ),
            "hunt.max_ticks: 0: a phase lasts from 1 to 2^40",
        ),
        (
            base(
                "[hunt]\nproperty = \"hull_grows\"\nevaluations = 9\nmax_ticks = 2000000000000",
                &format!("{square}\n[scheduler]\nkind = \"async\""),
            ),
            "hunt.max_ticks: 2000000000000: a phase lasts from 1 to 2^40",
        ),
        (
            base(
                "[hunt]\nproperty = \"hull_grows\"\nevaluations = 9\nn_min = 3\nn_max = 6",
                &format!("{square}\n[scheduler]\nkind = \"async\"\ndurations = \"d.csv\""),
            ),
            "hunt.n_min: 3: scheduler.durations gives robot 3 a duration, so the hunt needs at least 4 robots",
        ),
    ];
    std::fs::write(dir.path().join("bad.csv"), "x,y\n0,0\n1,zz\n").unwrap();
    std::fs::write(
        dir.path().join("d.csv"),
        "robot,cycle,phase,ticks\n3,1,move,9\n",
    )
    .unwrap();
    for (text, needle) in cases {
        let config = write_config(dir.path(), &text);
        let e = fails(&[
            "hunt",
            s(&config),
            "--out",
            s(&dir.path().join("h")),
            "--quiet",
        ]);
        assert!(e.contains(needle), "{needle}: {e}\n{text}");
    }
}

#[test]
fn an_interrupted_hunt_keeps_its_best_candidate_marked_interrupted() {
    // ConvergeLocality's hull never grows: the hunt improves its best for as long as it
    // runs, and Ctrl-C stops it some seconds in.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("h");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_monoculus"))
        .args([
            "hunt",
            s(&repo("configs/hunt/converge_locality.toml")),
            "--out",
            s(&out),
            "--quiet",
            "--threads",
            "2",
            "--set",
            "hunt.seconds=600",
        ])
        .spawn()
        .unwrap();
    let summary = out.join("summary.json");
    let start = std::time::Instant::now();
    while !summary.exists() && start.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    assert!(summary.exists(), "the first best is written at once");
    let first: u64 = summary_field(&out, "evaluations").parse().unwrap();
    std::thread::sleep(std::time::Duration::from_secs(4));
    // Within about 2 s of a better best, the folder has it (the hunt is still running).
    let meanwhile: u64 = summary_field(&out, "evaluations").parse().unwrap();
    assert_eq!(summary_field(&out, "interrupted"), "false");
    std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    assert!(
        meanwhile > first,
        "the folder followed the best: {first} evaluations, then {meanwhile}"
    );
    // The signal stopped the hunt, which wrote its last state, marked interrupted.
    assert_eq!(summary_field(&out, "interrupted"), "true");
    assert_eq!(summary_field(&out, "found"), "false");
    assert_eq!(summary_field(&out, "shrunk"), "false");
    let last: u64 = summary_field(&out, "evaluations").parse().unwrap();
    assert!(last >= meanwhile, "{last} evaluations after {meanwhile}");
    assert!(out.join("positions.csv").exists());
    // What it kept replays.
    let replayed = dir.path().join("r");
    let run = monoculus(&["run", s(&out.join("reproduce.toml")), "--out", s(&replayed)]);
    assert!(run.status.success());
}

#[test]
fn the_guide_s_config_hunts() {
    let guide = std::fs::read_to_string(repo("docs/hunt.md")).unwrap();
    let block = guide
        .split("```toml\n")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("docs/hunt.md has a TOML example");
    assert!(block.contains("name = \"my_rule\""));
    let dir = tempfile::tempdir().unwrap();
    let config = write_config(dir.path(), &block.replace("\"my_rule\"", "\"median\""));
    let out = dir.path().join("h");
    ok(&["hunt", s(&config), "--out", s(&out), "--quiet"]);
    assert_eq!(summary_field(&out, "found"), "true");
}
