//! DiagonalCorners through its own binary: every command takes it, its corner robots
//! move diagonally, its results do not depend on the thread count, and the Slurm
//! scripts it writes call it.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_diagonal-corners")
}

fn ok(args: &[&str]) -> String {
    let out = Command::new(bin()).args(args).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    String::from_utf8(out.stdout).unwrap()
}

fn here() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// runs.csv without wall_ms, rows sorted.
fn rows(dir: &Path) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_path(dir.join("runs.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let keep: Vec<usize> = (0..h.len()).filter(|&i| &h[i] != "wall_ms").collect();
    let mut v: Vec<Vec<String>> = r
        .records()
        .map(|x| {
            let x = x.unwrap();
            keep.iter().map(|&i| x[i].to_string()).collect()
        })
        .collect();
    v.sort();
    v
}

#[test]
fn a_corner_robot_moves_along_the_diagonal() {
    let tmp = tempfile::tempdir().unwrap();
    // Robot 0 at a corner: every other robot up and to the right; robot 4 is inner.
    std::fs::write(
        tmp.path().join("start.csv"),
        "x,y\n0,0\n6,2\n2,6\n6,6\n3,3\n",
    )
    .unwrap();
    let cfg = tmp.path().join("c.toml");
    std::fs::write(
        &cfg,
        "name = \"corner\"\n[swarm]\ninit = \"file\"\nfile = \"start.csv\"\n[algorithm]\nname = \"diagonal_corners\"\n[stop]\nmax_rounds = 1\n",
    )
    .unwrap();
    let trace = tmp.path().join("t.csv");
    for seed in ["0", "1", "2"] {
        ok(&[
            "trace",
            s(&cfg),
            "--seed",
            seed,
            "--out",
            s(&trace),
            "--positions",
        ]);
        let text = std::fs::read_to_string(tmp.path().join("t.positions.csv")).unwrap();
        let after: Vec<f64> = text
            .lines()
            .find(|l| l.starts_with("1,0,"))
            .unwrap()
            .split(',')
            .skip(2)
            .map(|x| x.parse().unwrap())
            .collect();
        let d = std::f64::consts::FRAC_1_SQRT_2;
        assert!(
            (after[0] - d).abs() < 1e-12 && (after[1] - d).abs() < 1e-12,
            "seed {seed}: {after:?}"
        );
        // The inner robot stays.
        assert!(text.lines().any(|l| l == "1,4,3,3"), "{text}");
    }
}

#[test]
fn every_command_takes_it_and_threads_change_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = here().join("compare.toml");
    let small = ["--set", "seeds=3", "--set", "swarm.n=[12, 25]"];
    let checked = ok(&[&["check", s(&cfg)][..], &small].concat());
    assert!(checked.contains("diagonal_corners"), "{checked}");
    let (one, two) = (tmp.path().join("one"), tmp.path().join("two"));
    ok(&[
        &["run", s(&cfg), "--out", s(&one), "--threads", "1"][..],
        &small,
    ]
    .concat());
    ok(&[
        &["run", s(&cfg), "--out", s(&two), "--threads", "2"][..],
        &small,
    ]
    .concat());
    let (a, b) = (rows(&one), rows(&two));
    assert_eq!(a, b);
    assert_eq!(a.len(), 2 * 2 * 2 * 3);
    assert!(
        a.iter()
            .filter(|r| r.contains(&"diagonal_corners".to_string()))
            .count()
            == 12
    );
    let table = ok(&["table", s(&one)]);
    assert!(table.contains("diagonal_corners"), "{table}");
    let page = tmp.path().join("r.html");
    let replayed = ok(&[
        "replay",
        s(&cfg),
        "--set",
        "swarm.n=12",
        "--set",
        "swarm.dim=2",
        "--set",
        "algorithm.name=diagonal_corners",
        "--out",
        s(&page),
    ]);
    assert!(replayed.contains("converged"), "{replayed}");
    assert!(
        std::fs::read_to_string(&page)
            .unwrap()
            .contains("diagonal_corners")
    );
    let stressed = ok(&[
        "stress",
        "--n",
        "400",
        "--rounds",
        "2",
        "--algorithm",
        "diagonal_corners",
    ]);
    assert!(stressed.contains("activations_per_s="), "{stressed}");
    // Its Slurm scripts call this binary, not `monoculus`.
    let out = tmp.path().join("cluster");
    ok(&[
        &["slurm", s(&cfg), "--shards", "2", "--out", s(&out)][..],
        &small,
    ]
    .concat());
    let script = std::fs::read_to_string(out.join("slurm/array.sh")).unwrap();
    let exec = script.lines().find(|l| l.starts_with("exec ")).unwrap();
    assert!(exec.starts_with(&format!("exec {} run ", bin())), "{exec}");
}

/// `diagonal-corners explore`: the explorer of this binary offers DiagonalCorners beside
/// the paper's algorithms, and steps it.
#[test]
fn its_explorer_offers_and_steps_its_algorithm() {
    use std::io::{BufRead, BufReader, Read, Write};
    struct Killed(std::process::Child);
    impl Drop for Killed {
        fn drop(&mut self) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
    let mut child = Command::new(bin())
        .args(["explore", "--set", "algorithm.name=diagonal_corners"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let stdout = child.stdout.take().unwrap();
    let _child = Killed(child);
    let mut line = String::new();
    BufReader::new(stdout).read_line(&mut line).unwrap();
    let url = line
        .trim()
        .strip_prefix("monoculus explore: ")
        .unwrap()
        .to_string();
    let (base, token) = url.split_once("/?token=").unwrap();
    let addr = base.strip_prefix("http://").unwrap().to_string();
    // One request over a plain socket (this example keeps to its one dependency).
    let request = |method: &str, path: &str, body: &str| -> String {
        let mut stream = std::net::TcpStream::connect(&addr).unwrap();
        write!(
            stream,
            "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nx-monoculus-token: {token}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
            body.len()
        )
        .unwrap();
        let mut answer = String::new();
        stream.read_to_string(&mut answer).unwrap();
        assert!(
            answer.starts_with("HTTP/1.1 200"),
            "{method} {path}: {answer}"
        );
        answer
    };
    let setup = request("GET", "/api/setup", "");
    assert!(
        setup.contains("\"algorithm\":\"diagonal_corners\""),
        "{setup}"
    );
    assert!(setup.contains("\"name\":\"converge_quadrant\""), "{setup}");
    let state = request("POST", "/api/step", r#"{"count": 2}"#);
    assert!(state.contains("\"rounds\":2"), "{state}");
}
