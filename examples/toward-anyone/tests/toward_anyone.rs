//! TowardAnyone, an algorithm of the directions model, grows the hull from the start in
//! grows.csv, as the impossibility result says some start makes every such algorithm
//! do; ConvergeLocality (LD) never does (Lemma 2).

use std::path::Path;
use std::process::Command;

#[test]
fn it_grows_the_hull_where_converge_locality_cannot() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = Path::new(env!("CARGO_MANIFEST_DIR")).join("grows.toml");
    for threads in ["1", "2"] {
        let out = tmp.path().join(threads);
        let run = Command::new(env!("CARGO_BIN_EXE_toward-anyone"))
            .args(["run", cfg.to_str().unwrap(), "--out", out.to_str().unwrap()])
            .args(["--threads", threads])
            .output()
            .unwrap();
        assert!(
            run.status.success(),
            "{}",
            String::from_utf8_lossy(&run.stderr)
        );
    }
    let read = |dir: &str| {
        let mut r = csv::Reader::from_path(tmp.path().join(dir).join("runs.csv")).unwrap();
        let h = r.headers().unwrap().clone();
        let col = |name: &str| h.iter().position(|c| c == name).unwrap();
        let (alg, grew, wall) = (col("algorithm"), col("hull_grew"), col("wall_ms"));
        r.records()
            .map(|x| {
                let x = x.unwrap();
                let rest: Vec<String> = (0..x.len())
                    .filter(|&i| i != wall)
                    .map(|i| x[i].to_string())
                    .collect();
                (x[alg].to_string(), &x[grew] == "true", rest)
            })
            .collect::<Vec<_>>()
    };
    let (one, two) = (read("1"), read("2"));
    assert_eq!(one, two, "the thread count changes nothing");
    let grew = |name: &str| one.iter().filter(|(a, g, _)| a == name && *g).count();
    assert!(grew("toward_anyone") >= 5, "{}", grew("toward_anyone"));
    assert_eq!(grew("converge_locality"), 0);
}

/// `hunt` run by the user's own binary catches TowardAnyone growing the hull from random
/// starts, and the user's binary replays what it wrote.
#[test]
fn the_hunt_catches_it_growing_the_hull() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = Path::new(env!("CARGO_MANIFEST_DIR")).join("hunt.toml");
    let out = tmp.path().join("hunt");
    let bin = env!("CARGO_BIN_EXE_toward-anyone");
    // Runs the binary, which must succeed.
    let succeed = |args: &[&str]| {
        let o = Command::new(bin).args(args).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    let path = |p: &Path| p.to_str().unwrap().to_string();
    succeed(&["hunt", &path(&cfg), "--out", &path(&out), "--quiet"]);
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"found\": true"), "{summary}");
    assert!(
        summary.contains("\"algorithm\": \"toward_anyone\""),
        "{summary}"
    );
    let replayed = tmp.path().join("replayed");
    succeed(&[
        "run",
        &path(&out.join("reproduce.toml")),
        "--out",
        &path(&replayed),
    ]);
    let runs = std::fs::read_to_string(replayed.join("runs.csv")).unwrap();
    let mut lines = runs.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let grew = header.iter().position(|c| *c == "hull_grew").unwrap();
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(row[grew], "true", "{runs}");
}
