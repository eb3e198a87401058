//! `monoculus replay`: self-contained pages and GIFs from configs and traces, and its
//! errors. (The pages in a real browser: `browser.rs`, run by `scripts/browser-ci.sh`.)

mod common;

use common::{fails, ok};

fn configs(name: &str) -> String {
    format!("{}/../../configs/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// The page loads nothing: no address of another resource, no external script or font.
fn self_contained(html: &str) {
    for needle in ["http://", "https://", "src=", "@import", "url(", "<link"] {
        assert!(!html.contains(needle), "the page references `{needle}`");
    }
    assert!(html.contains("id=\"replay-data\""));
    assert!(!html.contains("/*REPLAY_DATA*/"), "the data slot is filled");
}

#[test]
fn bundled_configs_replay_in_one_command() {
    let tmp = tempfile::tempdir().unwrap();
    for (config, frames) in [
        ("replay/paper_run.toml", "15 frames of 15 rounds"),
        ("replay/three_d.toml", "frames of"),
        ("replay/async.toml", "ticks"),
        ("replay/termination.toml", "rounds"),
    ] {
        let out = tmp.path().join("page.html");
        let said = ok(&["replay", &configs(config), "--out", out.to_str().unwrap()]);
        assert!(said.contains(frames), "{config}: {said}");
        let html = std::fs::read_to_string(&out).unwrap();
        self_contained(&html);
        assert!(html.len() < 50 << 20);
    }
    // The Figure 1 scenarios: a page and an animation per cell into a folder.
    let dir = format!("{}/fig1/", tmp.path().display());
    let said = ok(&[
        "replay",
        &configs("scenarios/figure1.toml"),
        "--out",
        &dir,
        "--gif",
        &dir,
    ]);
    assert_eq!(said.lines().count(), 3, "{said}");
    for algorithm in ["median", "angle_bisector", "converge_locality"] {
        let html = std::fs::read_to_string(format!("{dir}figure1_{algorithm}.html")).unwrap();
        self_contained(&html);
        let gif = std::fs::read(format!("{dir}figure1_{algorithm}.gif")).unwrap();
        assert!(gif.starts_with(b"GIF89a"), "{algorithm}: a GIF");
        // One image per frame (an image descriptor follows each graphic control block).
        let images = gif.windows(2).filter(|w| w == &[0x21, 0xf9]).count();
        assert!(images >= 4, "{algorithm}: {images} frames");
    }
}

#[test]
fn a_trace_replays_like_its_run() {
    let tmp = tempfile::tempdir().unwrap();
    let trace = tmp.path().join("t.csv");
    let said = ok(&[
        "trace",
        &configs("replay/paper_run.toml"),
        "--seed",
        "0",
        "--out",
        trace.to_str().unwrap(),
        "--positions",
    ]);
    let rounds = common::reported(&said, "rounds");
    let page = tmp.path().join("t.html");
    let positions = tmp.path().join("t.positions.csv");
    let said = ok(&[
        "replay",
        positions.to_str().unwrap(),
        "--out",
        page.to_str().unwrap(),
    ]);
    assert!(
        said.contains(&format!("{} frames of {} rounds", rounds + 1, rounds + 1)),
        "{said}"
    );
    self_contained(&std::fs::read_to_string(&page).unwrap());
}

#[test]
fn large_runs_stay_small_and_say_how_they_were_thinned() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("big.html");
    ok(&[
        "replay",
        &configs("replay/paper_run.toml"),
        "--set",
        "swarm.n=3000",
        "--set",
        "swarm.side=150.0",
        "--max-drawn",
        "1500",
        "--max-mb",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    let html = std::fs::read_to_string(&out).unwrap();
    assert!(html.len() < 3 << 20, "{} bytes", html.len());
    assert!(html.contains("1500 of 3000 robots drawn (every 2nd)"));
    assert!(html.contains("nd round kept as a frame"));
    assert!(html.contains("Looks are recorded for runs of at most"));
}

#[test]
fn bad_replay_arguments_are_one_line_errors() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("x.html");
    let out = out.to_str().unwrap();
    let fig1 = configs("scenarios/figure1.toml");
    let e = fails(&["replay", &fig1, "--out", out]);
    assert!(e.contains("3 cells") && e.contains("folders"), "{e}");
    let e = fails(&["replay", &fig1, "--cell", "7", "--out", out]);
    assert!(e.contains("--cell 7"), "{e}");
    let e = fails(&["replay", &configs("replay/async.toml")]);
    assert!(e.contains("--out"), "{e}");
    let e = fails(&[
        "replay",
        &configs("replay/async.toml"),
        "--gif",
        out,
        "--gif-size",
        "5x5",
    ]);
    assert!(e.contains("WIDTHxHEIGHT"), "{e}");
    let trace = tmp.path().join("bad.positions.csv");
    std::fs::write(&trace, "round,robot,x,y\n0,0,0,0\n2,0,1,1\n").unwrap();
    let e = fails(&["replay", trace.to_str().unwrap(), "--out", out]);
    assert!(e.contains("bad.positions.csv:3: column round"), "{e}");
    let e = fails(&[
        "replay",
        trace.to_str().unwrap(),
        "--seed",
        "1",
        "--out",
        out,
    ]);
    assert!(e.contains("a trace is one run"), "{e}");
    let e = fails(&[
        "replay",
        &configs("replay/async.toml"),
        "--set",
        "swarm.n=-1",
        "--out",
        out,
    ]);
    assert!(e.contains("swarm.n"), "{e}");
    assert!(!std::path::Path::new(out).exists());
}
