//! A stuck run reads as stuck on every surface of the command line: `runs.csv`,
//! `summary.csv`, `run`'s printed table and progress lines, `table`, `trace` and the
//! replay page; `converged`
//! is the goal's (`stop.goal` may set it), and `stopped_by` says what ended each run.

mod common;

use std::path::Path;

use common::{fails, ok, s, write_config};

fn repo(path: &str) -> String {
    format!("{}/../../{path}", env!("CARGO_MANIFEST_DIR"))
}

/// A column of a CSV, by name.
fn column(path: &Path, name: &str) -> Vec<String> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let c = r
        .headers()
        .unwrap()
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("{}: no column {name}", path.display()));
    r.records().map(|x| x.unwrap()[c].to_string()).collect()
}

#[test]
fn stuck_runs_read_as_stuck_in_the_results_the_tables_the_trace_and_the_replay() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("r");
    let config = repo("configs/extensions/stuck_clusters.toml");
    let run = common::monoculus(&["run", &config, "--out", s(&out), "--progress", "0.000001"]);
    assert!(run.status.success());
    let printed = String::from_utf8(run.stdout).unwrap();
    // --progress: each run's closing line says its verdict.
    let stderr = String::from_utf8(run.stderr).unwrap();
    let ends = |how: &str| stderr.lines().filter(|l| l.ends_with(how)).count();
    assert_eq!((ends("(stuck)"), ends("(converged)")), (9, 1), "{stderr}");
    // runs.csv: seed 8's clusters merge, the nine others are stuck.
    let runs = out.join("runs.csv");
    let stuck = column(&runs, "stuck");
    let converged = column(&runs, "converged");
    let stopped_by = column(&runs, "stopped_by");
    for k in 0..10 {
        let merged = k == 8;
        assert_eq!(stuck[k], (!merged).to_string(), "seed {k}");
        assert_eq!(converged[k], merged.to_string(), "seed {k}");
        assert_eq!(stopped_by[k], if merged { "diameter" } else { "quiescent" });
    }
    assert!(column(&runs, "goal").iter().all(|g| g == "disc"));
    assert!(
        column(&runs, "final_radius")
            .iter()
            .zip(&stuck)
            .all(|(r, st)| (r.parse::<f64>().unwrap() > 2.0) == (st == "true"))
    );
    // summary.csv counts them; run's table and `table` show them.
    let summary = out.join("summary.csv");
    assert_eq!(column(&summary, "stuck"), ["9"]);
    assert_eq!(column(&summary, "converged"), ["1"]);
    assert!(printed.contains("1/10, 9 stuck"), "{printed}");
    for format in ["markdown", "text"] {
        let table = ok(&["table", s(&out), "--format", format]);
        assert!(table.contains("1/10, 9 stuck"), "{table}");
    }
    // trace: one run's verdict.
    let trace = tmp.path().join("t.csv");
    let said = ok(&["trace", &config, "--seed", "0", "--out", s(&trace)]);
    assert!(
        said.contains("converged=false stuck=true stopped_by=quiescent goal=disc"),
        "{said}"
    );
    // The replay page: the verdict as a badge, and why.
    let page = tmp.path().join("p.html");
    ok(&["replay", &config, "--seed", "0", "--out", s(&page)]);
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(html.contains("\"verdict\":\"stuck\""));
    assert!(html.contains(
        "stuck after 4 rounds: quiescent short of its goal (every robot within a disc of radius c)"
    ));
    let merged = tmp.path().join("m.html");
    ok(&["replay", &config, "--seed", "8", "--out", s(&merged)]);
    assert!(
        std::fs::read_to_string(&merged)
            .unwrap()
            .contains("\"verdict\":\"converged\"")
    );
}

/// A 3 x 3 lattice of spacing 0.8 is quiescent for ConvergeLocality at diameter 2.26 >
/// c = 2: converged by its goal (a disc of radius c), stuck by the diameter's.
#[test]
fn the_goal_decides_converged_and_stop_goal_sets_it() {
    let tmp = tempfile::tempdir().unwrap();
    let positions = tmp.path().join("lattice.csv");
    let rows: Vec<String> = (0..9)
        .map(|k| format!("{},{}", (k % 3) as f64 * 0.8, (k / 3) as f64 * 0.8))
        .collect();
    std::fs::write(&positions, format!("x,y\n{}\n", rows.join("\n"))).unwrap();
    let config = write_config(
        tmp.path(),
        "name = \"lattice\"\nseeds = 1\n[swarm]\ninit = \"file\"\nfile = \"lattice.csv\"\n[algorithm]\nname = \"converge_locality\"\n[stop]\ngoal = [\"default\", \"diameter\", \"disc\"]\n",
    );
    let out = tmp.path().join("r");
    ok(&["run", s(&config), "--out", s(&out)]);
    let runs = out.join("runs.csv");
    assert_eq!(column(&runs, "goal"), ["disc", "diameter", "disc"]);
    assert_eq!(column(&runs, "converged"), ["true", "false", "true"]);
    assert_eq!(column(&runs, "stuck"), ["false", "true", "false"]);
    assert_eq!(column(&runs, "stopped_by"), ["quiescent"; 3]);
    assert_eq!(column(&runs, "rounds"), ["0"; 3]);
    // An unknown goal is refused, naming the key and the goals.
    let e = fails(&["check", s(&config), "--set", "stop.goal=circle"]);
    assert!(e.contains("stop.goal"), "{e}");
    assert!(
        e.contains("diameter") && e.contains("disc") && e.contains("box"),
        "{e}"
    );
}
