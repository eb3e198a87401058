//! `monoculus explore` driven through its HTTP API with a real client: the token, Origin
//! and Host checks, editing, stepping, the robot panel, settings refused with the
//! command line's messages, and exports that `monoculus run` reproduces bit for bit.

mod common;

use std::io::{Read, Write};
use std::path::Path;
use std::process::{Child, Command};

use common::{monoculus, ok, s};
use serde_json::{Value, json};

/// One explorer process, killed when dropped.
struct Explorer {
    child: Child,
    /// `http://127.0.0.1:PORT`.
    base: String,
    token: String,
    agent: ureq::Agent,
}

impl Explorer {
    fn start(args: &[&str]) -> Explorer {
        let (child, url) = common::explore(env!("CARGO_BIN_EXE_monoculus"), args);
        let (base, token) = url.split_once("/?token=").unwrap();
        let agent = ureq::Agent::config_builder()
            .http_status_as_error(false)
            .build()
            .into();
        Explorer {
            child,
            base: base.to_string(),
            token: token.to_string(),
            agent,
        }
    }

    /// GET `path` with the token; the status and body.
    fn get(&self, path: &str) -> (u16, String) {
        let mut r = self
            .agent
            .get(format!("{}{path}", self.base))
            .header("x-monoculus-token", &self.token)
            .call()
            .unwrap();
        (r.status().as_u16(), r.body_mut().read_to_string().unwrap())
    }

    /// POST `body` to `path` with the token; the status and body.
    fn post(&self, path: &str, body: &str) -> (u16, String) {
        let mut r = self
            .agent
            .post(format!("{}{path}", self.base))
            .header("x-monoculus-token", &self.token)
            .content_type("application/json")
            .send(body)
            .unwrap();
        (r.status().as_u16(), r.body_mut().read_to_string().unwrap())
    }

    /// POST `body` as JSON; the JSON answer, which must be a success.
    fn call(&self, path: &str, body: Value) -> Value {
        let (status, text) = self.post(path, &body.to_string());
        assert_eq!(status, 200, "{path}: {text}");
        serde_json::from_str(&text).unwrap()
    }

    fn fetch(&self, path: &str) -> Value {
        let (status, text) = self.get(path);
        assert_eq!(status, 200, "{path}: {text}");
        serde_json::from_str(&text).unwrap()
    }

    /// A raw request (request line and headers as given), its status.
    fn raw(&self, request: &str) -> u16 {
        let addr = self.base.strip_prefix("http://").unwrap();
        let mut stream = std::net::TcpStream::connect(addr).unwrap();
        stream.write_all(request.as_bytes()).unwrap();
        let mut answer = String::new();
        stream.read_to_string(&mut answer).unwrap();
        answer.split_whitespace().nth(1).unwrap().parse().unwrap()
    }
}

impl Drop for Explorer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

const CONFIG: &str = r#"name = "t"
seeds = [4]

[swarm]
n = 5
init = "square"
side = 3.0

[algorithm]
name = "converge_locality"
step = 1.0
locality = 2.0

[stop]
max_rounds = 200
"#;

fn config(dir: &Path) -> String {
    let path = dir.join("t.toml");
    std::fs::write(&path, CONFIG).unwrap();
    s(&path).to_string()
}

/// Decodes the base64 f64s of a state's `positions`.
fn positions(state: &Value) -> Vec<f64> {
    let text = state["positions"].as_str().unwrap();
    let abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut bits = 0u32;
    let mut have = 0;
    let mut bytes = Vec::new();
    for c in text.chars().filter(|&c| c != '=') {
        bits = (bits << 6) | abc.find(c).unwrap() as u32;
        have += 6;
        if have >= 8 {
            have -= 8;
            bytes.push((bits >> have) as u8);
        }
    }
    bytes
        .chunks(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

#[test]
fn every_request_needs_the_token_the_host_and_no_other_origin() {
    let dir = tempfile::tempdir().unwrap();
    let ex = Explorer::start(&[&config(dir.path())]);
    assert_eq!(ex.token.len(), 32);
    let addr = ex.base.strip_prefix("http://").unwrap().to_string();
    let url = |p: &str| format!("{}{p}", ex.base);
    // The token: missing, wrong, in the query, in the header.
    let status =
        |r: Result<ureq::http::Response<ureq::Body>, ureq::Error>| r.unwrap().status().as_u16();
    assert_eq!(status(ex.agent.get(url("/api/setup")).call()), 401);
    assert_eq!(status(ex.agent.get(url("/?token=0123")).call()), 401);
    let wrong: String = ex.token.chars().rev().collect();
    assert_eq!(
        status(
            ex.agent
                .get(url("/api/state"))
                .header("x-monoculus-token", &wrong)
                .call()
        ),
        401
    );
    assert_eq!(
        status(ex.agent.get(url(&format!("/?token={}", ex.token))).call()),
        200
    );
    assert_eq!(ex.get("/api/setup").0, 200);
    // Another origin, even with the token: refused, for reads and for writes.
    for origin in ["http://evil.example", "http://127.0.0.1:1", "null"] {
        let r = ex
            .agent
            .post(url("/api/step"))
            .header("x-monoculus-token", &ex.token)
            .header("origin", origin)
            .send(r#"{"count": 1}"#);
        assert_eq!(status(r), 403, "{origin}");
    }
    let same = format!("http://{addr}");
    let r = ex
        .agent
        .get(url("/api/setup"))
        .header("x-monoculus-token", &ex.token)
        .header("origin", &same);
    assert_eq!(status(r.call()), 200);
    assert_eq!(
        ex.fetch("/api/state")["rounds"],
        0,
        "refused steps took none"
    );
    // Another Host (DNS rebinding), even with the token: refused.
    let t = &ex.token;
    assert_eq!(
        ex.raw(&format!("GET /api/setup?token={t} HTTP/1.1\r\nHost: evil.example:{}\r\nConnection: close\r\n\r\n", addr.split(':').nth(1).unwrap())),
        403
    );
    assert_eq!(
        ex.raw(&format!(
            "GET /api/setup?token={t} HTTP/1.1\r\nConnection: close\r\n\r\n"
        )),
        403
    );
    assert_eq!(
        ex.raw(&format!(
            "GET /api/setup?token={t} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
        )),
        200
    );
    // The page itself forbids framing and other sources.
    let r = ex.agent.get(url(&format!("/?token={t}"))).call().unwrap();
    let csp = r
        .headers()
        .get("content-security-policy")
        .unwrap()
        .to_str()
        .unwrap();
    assert!(csp.contains("frame-ancestors 'none'"), "{csp}");
    assert_eq!(r.headers().get("referrer-policy").unwrap(), "no-referrer");
}

#[test]
fn request_bodies_and_swarms_are_bounded() {
    let dir = tempfile::tempdir().unwrap();
    let ex = Explorer::start(&[&config(dir.path())]);
    // 65 MiB of CSV: refused before it is read, the explorer still serving.
    let big = "x".repeat(65 << 20);
    let (status, _) = ex.post("/api/positions", &big);
    assert_eq!(status, 413);
    assert_eq!(ex.fetch("/api/state")["n"], 5);
    let (status, text) = ex.post("/api/edit", r#"{"op": "teleport"}"#);
    assert_eq!(status, 400);
    assert!(text.contains("expected add, move or delete"), "{text}");
    let (status, text) = ex.post("/api/edit", r#"{"op": "delete", "robot": 5}"#);
    assert_eq!(
        (status, text.contains("the swarm has 5 robots")),
        (400, true),
        "{text}"
    );
    let (status, text) = ex.post("/api/step", "not json");
    assert_eq!(status, 400, "{text}");
}

#[test]
fn edits_steps_and_the_robot_panel() {
    let dir = tempfile::tempdir().unwrap();
    let ex = Explorer::start(&[&config(dir.path())]);
    let setup = ex.fetch("/api/setup");
    assert_eq!(setup["algorithm"], "converge_locality");
    assert_eq!(setup["model"], "ld");
    assert!(setup["settings"].as_str().unwrap().contains("n = 5"));
    let names: Vec<&str> = setup["algorithms"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a["name"].as_str().unwrap())
        .collect();
    assert!(names.contains(&"median") && names.contains(&"converge_quadrant"));

    // Three robots by hand: add far away, move one, delete one.
    let st = ex.call("/api/edit", json!({"op": "add", "x": 9.0, "y": 0.5}));
    assert_eq!(st["n"], 6);
    assert_eq!(&positions(&st)[10..], &[9.0, 0.5]);
    let st = ex.call(
        "/api/edit",
        json!({"op": "move", "robot": 0, "x": -4.0, "y": 0.25}),
    );
    assert_eq!(&positions(&st)[..2], &[-4.0, 0.25]);
    let st = ex.call("/api/edit", json!({"op": "delete", "robot": 1}));
    assert_eq!(st["n"], 5);
    assert_eq!(st["rounds"], 0);
    let start = positions(&st);

    // What robot 0 sees and would do now; a step does what it said.
    let r = ex.fetch("/api/robot?i=0");
    assert_eq!(r["at"], json!([-4.0, 0.25]));
    let seen = r["seen"].as_array().unwrap();
    assert!(!seen.is_empty());
    assert!(seen.iter().all(|s| s["far"].is_boolean()));
    assert!(r["last"].is_null(), "no Look before the first round");
    let d = r["decision"]
        .as_array()
        .expect("robot 0, far from the rest, moves");
    let st = ex.call("/api/step", json!({"count": 1}));
    assert_eq!(st["rounds"], 1);
    let now = positions(&st);
    assert!((now[0] - (-4.0 + d[0].as_f64().unwrap())).abs() < 1e-12);
    assert!((now[1] - (0.25 + d[1].as_f64().unwrap())).abs() < 1e-12);
    assert_eq!(st["metrics"]["time"], json!([0, 1]));
    let r = ex.fetch("/api/robot?i=0");
    assert_eq!(
        r["last"]["from"],
        json!([-4.0, 0.25]),
        "the last Look: before the round"
    );
    // Asking changed nothing: the run goes on as before.
    let again = ex.fetch("/api/state");
    assert_eq!(positions(&again), now);

    // Back to the start; then to the end: the verdict as `run` reports it.
    let st = ex.call("/api/reset", json!({}));
    assert_eq!(
        (st["rounds"].as_u64(), positions(&st)),
        (Some(0), start.clone())
    );
    let st = ex.call("/api/step", json!({"count": null}));
    assert_eq!(st["ended"], true);
    assert_eq!(st["verdict"], "converged");
    assert!(
        st["outcome"]
            .as_str()
            .unwrap()
            .starts_with("converged after"),
        "{st}"
    );
    // A run that ended takes no more steps.
    let more = ex.call("/api/step", json!({"count": 3}));
    assert_eq!(more["rounds"], st["rounds"]);
}

#[test]
fn settings_are_refused_with_the_command_line_s_message() {
    let dir = tempfile::tempdir().unwrap();
    let ex = Explorer::start(&[&config(dir.path())]);
    let settings = ex.fetch("/api/setup")["settings"]
        .as_str()
        .unwrap()
        .to_string();
    let bad = settings.replace("step = 1.0", "step = -1.0");
    let (status, text) = ex.post("/api/settings", &json!({"settings": bad}).to_string());
    assert_eq!(status, 400);
    let page: Value = serde_json::from_str(&text).unwrap();
    // `monoculus check` of the same text in a file called `settings` says the same.
    std::fs::write(dir.path().join("settings"), &bad).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_monoculus"))
        .current_dir(dir.path())
        .args(["check", "settings"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let cli = String::from_utf8(out.stderr).unwrap();
    assert_eq!(
        cli.trim().strip_prefix("error: ").unwrap(),
        page["error"].as_str().unwrap()
    );
    assert!(cli.contains("algorithm.step"), "{cli}");
    // Nothing changed.
    assert!(
        ex.fetch("/api/setup")["settings"]
            .as_str()
            .unwrap()
            .contains("step = 1.0")
    );

    // A file the explorer was not started with is never read.
    let sneaky = settings.replace(
        "init = \"square\"",
        "init = \"file\"\nfile = \"/etc/passwd\"",
    );
    let (status, text) = ex.post("/api/settings", &json!({"settings": sneaky}).to_string());
    assert_eq!(status, 400, "{text}");
    assert!(text.contains("swarm.file"), "{text}");
    // A sweep is not one run.
    let swept = settings.replace("n = 5", "n = [5, 6]");
    let (status, text) = ex.post("/api/settings", &json!({"settings": swept}).to_string());
    assert_eq!((status, text.contains("one cell")), (400, true), "{text}");

    // Good settings: another algorithm and scheduler, the start generated anew.
    let other = settings
        .replace("name = \"converge_locality\"", "name = \"median\"")
        .replace("kind = \"fsync\"", "kind = \"ssync\"")
        .replace("n = 5", "n = 9");
    let r = ex.call(
        "/api/settings",
        json!({"settings": other, "generate": true}),
    );
    assert_eq!(r["setup"]["algorithm"], "median");
    assert_eq!(r["setup"]["scheduler"], "ssync");
    assert_eq!(r["state"]["n"], 9);
}

#[test]
fn the_export_reproduces_with_monoculus_run_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let ex = Explorer::start(&[&config(dir.path()), "--set", "scheduler.kind=ssync"]);
    ex.call("/api/edit", json!({"op": "add", "x": 1.0 / 3.0, "y": -2.7}));
    ex.call(
        "/api/edit",
        json!({"op": "move", "robot": 2, "x": 0.1, "y": 0.2}),
    );
    ex.call("/api/step", json!({"count": 2}));
    let end = ex.call("/api/step", json!({"count": null}));
    assert_eq!(end["ended"], true);

    let out = tempfile::tempdir().unwrap();
    let (status, config) = ex.get("/api/export/config");
    assert_eq!(status, 200);
    std::fs::write(out.path().join("explore.toml"), &config).unwrap();
    let (_, csv) = ex.get("/api/export/positions.csv");
    std::fs::write(out.path().join("positions.csv"), &csv).unwrap();
    assert_eq!(csv.lines().count(), 7, "{csv}");
    // The run: the same rounds and final positions, bit for bit.
    let trace = out.path().join("trace.csv");
    ok(&[
        "trace",
        s(&out.path().join("explore.toml")),
        "--seed",
        "4",
        "--out",
        s(&trace),
        "--positions",
    ]);
    let rounds = end["rounds"].as_u64().unwrap();
    let text = std::fs::read_to_string(out.path().join("trace.positions.csv")).unwrap();
    let last: Vec<f64> = text
        .lines()
        .skip(1)
        .filter(|l| l.starts_with(&format!("{rounds},")))
        .flat_map(|l| {
            l.split(',')
                .skip(2)
                .map(|v| v.parse::<f64>().unwrap())
                .collect::<Vec<_>>()
        })
        .collect();
    assert_eq!(last, positions(&end));
    let results = out.path().join("results");
    ok(&[
        "run",
        s(&out.path().join("explore.toml")),
        "--out",
        s(&results),
    ]);
    let runs = std::fs::read_to_string(results.join("runs.csv")).unwrap();
    let mut r = csv::Reader::from_reader(runs.as_bytes());
    let h = r.headers().unwrap().clone();
    let row = r.records().next().unwrap().unwrap();
    let col = |k: &str| row[h.iter().position(|x| x == k).unwrap()].to_string();
    assert_eq!(col("rounds"), rounds.to_string());
    assert_eq!(col("converged"), "true");
    let outcome = end["outcome"].as_str().unwrap();
    assert!(
        outcome.contains(&format!("{} moves", col("moves"))),
        "{outcome} vs {runs}"
    );

    // The run so far as a replay page.
    let (status, page) = ex.get("/api/export/replay.html");
    assert_eq!(status, 200);
    assert!(page.contains("from monoculus explore") && page.contains("converged after"));
}

#[test]
fn a_hunt_s_reproduce_toml_opens_in_the_explorer() {
    let dir = tempfile::tempdir().unwrap();
    let hunt = dir.path().join("hunt");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    ok(&[
        "hunt",
        s(&root.join("configs/hunt/median.toml")),
        "--out",
        s(&hunt),
        "--set",
        "hunt.evaluations=300",
    ]);
    let reproduce = hunt.join("reproduce.toml");
    assert!(reproduce.exists());
    let ex = Explorer::start(&[s(&reproduce)]);
    let st = ex.fetch("/api/state");
    let csv = std::fs::read_to_string(hunt.join("positions.csv")).unwrap();
    assert_eq!(st["n"].as_u64().unwrap() as usize, csv.lines().count() - 1);
    assert_eq!(ex.fetch("/api/setup")["algorithm"], "median");
}

#[test]
fn bad_arguments_fail_as_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = config(dir.path());
    for (args, says) in [
        (vec!["explore", &cfg, "--host", "localhost:80"], "--host"),
        (vec!["explore", &cfg, "--host", "0.0.0.0"], "one address"),
        (vec!["explore", &cfg, "--set", "swarm.n=[3, 4]"], "one cell"),
        (vec!["explore", &cfg, "--set", "swarm.dim=3"], "plane"),
        (vec!["explore", "missing.toml"], "missing.toml"),
    ] {
        let out = monoculus(&args);
        let e = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(e.contains(says), "{args:?}: {e}");
    }
}

#[test]
fn a_positions_csv_loads_and_a_bad_one_is_refused_by_line() {
    let dir = tempfile::tempdir().unwrap();
    let ex = Explorer::start(&[&config(dir.path())]);
    let st: Value = {
        let (status, text) = ex.post("/api/positions?name=mine.csv", "x,y\n0,0\n1,0.5\n2,2\n");
        assert_eq!(status, 200, "{text}");
        serde_json::from_str(&text).unwrap()
    };
    assert_eq!(st["n"], 3);
    assert_eq!(positions(&st), vec![0.0, 0.0, 1.0, 0.5, 2.0, 2.0]);
    let (status, text) = ex.post("/api/positions?name=mine.csv", "x,y\n0,0\n1,zero\n");
    assert_eq!(status, 400);
    assert!(text.contains("mine.csv:3"), "{text}");
    let (status, text) = ex.post("/api/positions?name=mine.csv", "x,y,z\n0,0,1\n");
    assert_eq!((status, text.contains("plane")), (400, true), "{text}");
    assert_eq!(
        ex.fetch("/api/state")["n"],
        3,
        "refused files change nothing"
    );
    // The start generated from the settings' [swarm] again.
    assert_eq!(ex.call("/api/generate", json!({}))["n"], 5);
}

#[test]
fn under_async_a_step_is_an_epoch_and_robots_can_be_asked() {
    let dir = tempfile::tempdir().unwrap();
    let ex = Explorer::start(&[&config(dir.path()), "--set", "scheduler.kind=async"]);
    let st = ex.call("/api/step", json!({"count": 1}));
    assert_eq!(st["ticks"], true);
    assert_eq!(st["rounds"], 1, "one epoch");
    assert!(st["time"].as_u64().unwrap() > 1, "over several ticks: {st}");
    let ticks = st["metrics"]["time"].as_array().unwrap().len();
    assert!(ticks > 2, "a row per tick");
    for i in 0..5 {
        let r = ex.fetch(&format!("/api/robot?i={i}"));
        assert!(r["failure"].is_null() && r["seen"].is_array(), "{r}");
    }
    let end = ex.call("/api/step", json!({"count": null}));
    assert_eq!(end["ended"], true);
    assert!(end["outcome"].as_str().unwrap().contains("epochs"), "{end}");
}

#[test]
fn ctrl_c_stops_the_explorer() {
    let dir = tempfile::tempdir().unwrap();
    let mut ex = Explorer::start(&[&config(dir.path())]);
    assert_eq!(ex.get("/api/setup").0, 200);
    let pid = ex.child.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-INT", &pid])
            .status()
            .unwrap()
            .success()
    );
    let t0 = std::time::Instant::now();
    let status = loop {
        if let Some(s) = ex.child.try_wait().unwrap() {
            break s;
        }
        assert!(t0.elapsed().as_secs() < 10, "still running after Ctrl-C");
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    assert_eq!(status.code(), Some(130));
}
