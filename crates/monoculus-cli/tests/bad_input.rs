//! Bad input: one line naming the file, line and key, exit status 2, never a panic.

mod common;

use common::monoculus;

fn fails(args: &[&str]) -> String {
    let out = monoculus(args);
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    stderr
}

const GOOD: &str = "name = \"x\"\nseeds = 2\n\n[swarm]\nn = 10\ninit = \"square\"\nside = 10.0\n\n[algorithm]\nname = \"converge_locality\"\nstep = 1.0\nlocality = 2.0\n";

fn config_error(text: &str) -> (String, String) {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("bad.toml");
    std::fs::write(&path, text).unwrap();
    let p = path.to_str().unwrap().to_string();
    let e = fails(&["check", &p]);
    // `run` reports the same error before touching the output folder.
    let out = tmp.path().join("out");
    assert_eq!(fails(&["run", &p, "--out", out.to_str().unwrap()]), e);
    assert!(!out.exists());
    (e.replace(&p, "bad.toml"), p)
}

fn one_line(e: &str) -> &str {
    assert_eq!(e.lines().count(), 1, "one line: {e}");
    e.trim_end()
}

#[test]
fn the_good_config_passes() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("good.toml");
    std::fs::write(&path, GOOD).unwrap();
    let out = monoculus(&["check", path.to_str().unwrap()]);
    assert!(out.status.success());
}

#[test]
fn unknown_key() {
    let (e, _) = config_error(&GOOD.replace("side = 10.0", "side = 10.0\nsidee = 3"));
    let e = one_line(&e);
    assert!(
        e.starts_with("error: bad.toml:8: swarm.sidee: unknown field `sidee`"),
        "{e}"
    );
    let (e, _) = config_error(&format!("{GOOD}\n[stopp]\nmax_rounds = 3\n"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:14: stopp: unknown field `stopp`"),
        "{e}"
    );
}

#[test]
fn wrong_type() {
    let (e, _) = config_error(&GOOD.replace("n = 10", "n = \"ten\""));
    assert!(
        one_line(&e).starts_with("error: bad.toml:5: swarm.n: invalid type: string \"ten\""),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("n = 10", "n = [10, \"x\"]"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:5: swarm.n: invalid type"),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("\"converge_locality\"", "\"converge_everything\""));
    assert!(
        one_line(&e).starts_with(
            "error: bad.toml:10: algorithm.name: unknown variant `converge_everything`"
        ),
        "{e}"
    );
}

#[test]
fn out_of_range_values() {
    let (e, _) = config_error(&GOOD.replace("n = 10", "n = 0"));
    assert_eq!(
        one_line(&e),
        "error: bad.toml:5: swarm.n: must be at least 1"
    );
    let (e, _) = config_error(&GOOD.replace("n = 10", "n = [10, 0]"));
    assert_eq!(
        one_line(&e),
        "error: bad.toml:5: swarm.n: must be at least 1"
    );
    let (e, _) = config_error(&GOOD.replace("step = 1.0", "step = 0.0"));
    assert_eq!(
        one_line(&e),
        "error: bad.toml:11: algorithm.step: must be positive, got 0"
    );
    let (e, _) = config_error(&GOOD.replace("step = 1.0", "step = -2"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:11: algorithm.step:"),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("side = 10.0", "side = -1.0"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:7: swarm.side:"),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("n = 10", "n = []"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:5: swarm.n: empty list"),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("n = 10\n", ""));
    assert!(
        one_line(&e).starts_with("error: bad.toml:4: swarm.n: missing"),
        "{e}"
    );
    let (e, _) = config_error(&GOOD.replace("seeds = 2", "seeds = 0"));
    assert!(one_line(&e).starts_with("error: bad.toml:2: seeds:"), "{e}");
    let (e, _) = config_error(&GOOD.replace("init = \"square\"", "init = \"square\"\ndim = 7"));
    assert!(
        one_line(&e).starts_with("error: bad.toml:7: swarm.dim:"),
        "{e}"
    );
}

#[test]
fn syntax_error_names_the_line() {
    let (e, _) = config_error(&GOOD.replace("side = 10.0", "side = = 10.0"));
    assert!(one_line(&e).starts_with("error: bad.toml:7:"), "{e}");
}

#[test]
fn locality_below_twice_the_step_warns() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("warn.toml");
    std::fs::write(&path, GOOD.replace("locality = 2.0", "locality = 1.5")).unwrap();
    let out = monoculus(&["check", path.to_str().unwrap()]);
    assert!(out.status.success());
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.contains("warning:") && stderr.contains(":12: algorithm.locality: c = 1.5 < 2b = 2"),
        "{stderr}"
    );
}

#[test]
fn missing_and_malformed_position_files() {
    let (e, _) = config_error(
        &GOOD
            .replace(
                "init = \"square\"",
                "init = \"file\"\nfile = \"nowhere.csv\"",
            )
            .replace("n = 10\n", ""),
    );
    let e = one_line(&e);
    assert!(
        e.starts_with("error: bad.toml:6: swarm.file: ") && e.contains("nowhere.csv: cannot read"),
        "{e}"
    );
    let (e, _) = config_error(
        &GOOD
            .replace("init = \"square\"", "init = \"file\"")
            .replace("n = 10\n", ""),
    );
    assert!(
        one_line(&e).starts_with("error: bad.toml:4: swarm.file: init = \"file\" needs swarm.file"),
        "{e}"
    );
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("p.csv");
    std::fs::write(&csv, "x,y\n0,0\n1,oops\n").unwrap();
    let e = fails(&["look", csv.to_str().unwrap(), "--robot", "0"]);
    assert!(
        one_line(&e).ends_with("p.csv:3: column y: `oops` is not a finite number"),
        "{e}"
    );
    std::fs::write(&csv, "x,y\n0,0\n1,1\n").unwrap();
    let e = fails(&["look", csv.to_str().unwrap(), "--robot", "5"]);
    assert!(one_line(&e).contains("--robot 5:"), "{e}");
}

#[test]
fn bad_arguments() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("good.toml");
    std::fs::write(&path, GOOD).unwrap();
    let p = path.to_str().unwrap();
    let e = fails(&["run", p, "--shard", "3/3"]);
    assert!(one_line(&e).contains("--shard 3/3"), "{e}");
    let e = fails(&["run", p, "--threads", "0"]);
    assert!(one_line(&e).contains("--threads"), "{e}");
    let e = fails(&["check", p, "--set", "swarm.n"]);
    assert!(one_line(&e).contains("--set: expected KEY=VALUE"), "{e}");
    let e = fails(&["check", p, "--set", "swarm.n=0"]);
    assert_eq!(one_line(&e), "error: --set: swarm.n: must be at least 1");
    let e = fails(&["check", p, "--set", "swarm.bogus=1"]);
    assert!(
        one_line(&e).starts_with("error: --set: swarm.bogus: unknown field"),
        "{e}"
    );
    fails(&["check", "/nonexistent/config.toml"]);
    fails(&["frobnicate"]);
}
