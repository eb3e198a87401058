//! WaitForMovers through the library and its own binary: robots see the light of a robot
//! that moved in the last round and wait, so that under FSYNC they move every other
//! round; the sweep's results do not depend on the thread count.

use std::path::Path;
use std::process::Command;

use monoculus::DVec2;
use monoculus::{AlgorithmBox, SimConfig, Simulation};
use wait_for_movers::WaitForMovers;

#[test]
fn under_fsync_robots_that_see_a_mover_wait_a_round() {
    // Three robots far apart: each sees the others far, so ConvergeLocality moves
    // every one of them every round; here they move in rounds 1, 3, 5, ...
    let start = vec![DVec2::ZERO, DVec2::new(10.0, 0.0), DVec2::new(0.0, 10.0)];
    for seed in 0..5 {
        let config = SimConfig::paper(AlgorithmBox::new(WaitForMovers), seed, 100);
        let mut sim = Simulation::new(config, start.clone()).unwrap();
        let mut last = sim.positions().to_vec();
        for round in 1..=6 {
            sim.step();
            let now = sim.positions().to_vec();
            let moved = now.iter().zip(&last).filter(|(a, b)| a != b).count();
            let lit: Vec<u8> = sim.robot_views().iter().map(|v| v.light.unwrap()).collect();
            assert_eq!(sim.lights_now(), lit);
            if round % 2 == 1 {
                assert_eq!(moved, 3, "seed {seed} round {round}");
                assert_eq!(lit, vec![1, 1, 1], "moving: seed {seed} round {round}");
            } else {
                assert_eq!(moved, 0, "seed {seed} round {round}");
                assert_eq!(lit, vec![0, 0, 0], "resting: seed {seed} round {round}");
            }
            last = now;
        }
    }
}

/// runs.csv without wall_ms.
fn rows(dir: &Path) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_path(dir.join("runs.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let keep: Vec<usize> = (0..h.len()).filter(|&i| &h[i] != "wall_ms").collect();
    r.records()
        .map(|x| {
            let x = x.unwrap();
            keep.iter().map(|&i| x[i].to_string()).collect()
        })
        .collect()
}

#[test]
fn the_comparison_runs_alike_on_any_thread_count_and_waiting_doubles_the_fsync_rounds() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = Path::new(env!("CARGO_MANIFEST_DIR")).join("compare.toml");
    for threads in ["1", "2"] {
        let out = tmp.path().join(threads);
        let run = Command::new(env!("CARGO_BIN_EXE_wait-for-movers"))
            .args(["run", cfg.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .args([
                "--threads",
                threads,
                "--set",
                "swarm.n=10",
                "--set",
                "seeds=4",
            ])
            .args(["--set", "stop.max_rounds=300"])
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
    }
    let one = rows(&tmp.path().join("1"));
    assert_eq!(
        one,
        rows(&tmp.path().join("2")),
        "the thread count changes nothing"
    );
    assert_eq!(one.len(), 16);
    let mut r = csv::Reader::from_path(tmp.path().join("1").join("runs.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let (alg, sched, rounds, conv) = (
        col("algorithm"),
        col("scheduler"),
        col("rounds"),
        col("converged"),
    );
    let fsync_rounds = |name: &str| -> u64 {
        one.iter()
            .filter(|x| x[alg] == name && x[sched] == "fsync")
            .inspect(|x| assert_eq!(x[conv], "true", "{name} converges under FSYNC"))
            .map(|x| x[rounds].parse::<u64>().unwrap())
            .sum()
    };
    let (waiting, plain) = (
        fsync_rounds("wait_for_movers"),
        fsync_rounds("converge_locality"),
    );
    assert!(waiting > plain * 3 / 2, "{waiting} rounds against {plain}");
}

/// The binary with the example's algorithm, with `args`; must succeed.
fn binary(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_wait-for-movers"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// Lights are shown wherever robots are: each robot's light in the trace's positions, a
/// replay of the config or of the trace colours the robots by them (the palette and
/// every frame's colours in the page's data), and the GIF is drawn.
#[test]
fn traces_and_replays_show_each_robots_light() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = Path::new(env!("CARGO_MANIFEST_DIR")).join("compare.toml");
    let cfg = cfg.to_str().unwrap();
    let one = [
        "--set",
        "swarm.n=12",
        "--set",
        "algorithm.name=\"wait_for_movers\"",
    ];
    let fsync = ["--set", "scheduler.kind=\"fsync\""];
    let trace = tmp.path().join("t.csv");
    let mut args = vec![
        "trace",
        cfg,
        "--seed",
        "2",
        "--out",
        trace.to_str().unwrap(),
    ];
    args.extend(["--positions"].iter().chain(&one).chain(&fsync));
    let said = binary(&args);
    assert!(said.contains("goal=disc"), "{said}");
    let positions = tmp.path().join("t.positions.csv");
    let text = std::fs::read_to_string(&positions).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("round,robot,x,y,light"));
    // Round 0: every robot resting; round 1: every robot that stepped is moving.
    let light_of = |round: &str| -> Vec<String> {
        text.lines()
            .skip(1)
            .map(|l| l.split(',').collect::<Vec<_>>())
            .filter(|f| f[0] == round)
            .map(|f| f[4].to_string())
            .collect()
    };
    assert!(light_of("0").iter().all(|l| l == "resting"));
    assert!(light_of("1").iter().any(|l| l == "moving"));
    // Replays of the run and of its trace: the same colours, frame by frame.
    let page = tmp.path().join("run.html");
    let gif = tmp.path().join("run.gif");
    let mut args = vec![
        "replay",
        cfg,
        "--seed",
        "2",
        "--out",
        page.to_str().unwrap(),
    ];
    args.extend(["--gif", gif.to_str().unwrap()]);
    args.extend(one.iter().chain(&fsync));
    binary(&args);
    let from_trace = tmp.path().join("trace.html");
    binary(&[
        "replay",
        positions.to_str().unwrap(),
        "--out",
        from_trace.to_str().unwrap(),
    ]);
    let field = |html: &str, key: &str| -> String {
        let start = html.find(&format!("\"{key}\":")).expect(key) + key.len() + 3;
        let end = start + html[start..].find([',', '}']).unwrap();
        html[start..end].to_string()
    };
    let (run, traced) = (
        std::fs::read_to_string(&page).unwrap(),
        std::fs::read_to_string(&from_trace).unwrap(),
    );
    assert!(run.contains("\"lights\":[\"resting\",\"moving\"]"));
    assert!(run.contains("\"light_colors\":[\"#4e79a7\",\"#f28e2b\"]"));
    assert!(traced.contains("\"lights\":[\"resting\",\"moving\"]"));
    let colours = field(&run, "light");
    assert!(colours.len() > 4, "{colours}");
    assert_eq!(
        colours,
        field(&traced, "light"),
        "the trace's lights are the run's"
    );
    assert!(std::fs::read(&gif).unwrap().starts_with(b"GIF89a"));
}
