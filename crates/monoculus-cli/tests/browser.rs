//! Replays in a real browser: headless Chromium opens generated pages, steps to a
//! round (or tick, or frame), and the page must raise no script error, show the time
//! asked for, and draw the robots where the positions say.
//!
//! These tests need Chromium, so `cargo test` skips them (ignored); `scripts/browser-ci.sh`
//! installs Debian's `chromium` and runs them (`.ci/run` calls it after the tests):
//!     cargo test -p monoculus-cli --test browser -- --ignored
//! The browser is found as `$MONOCULUS_CHROMIUM`, else `chromium` on the PATH. The
//! last test opens the tour notebook as executed and exported by scripts/python-ci.sh
//! (`$MONOCULUS_TOUR_HTML`).

#[path = "common/chromium.rs"]
mod chromium;
mod common;

use std::path::Path;

use chromium::{Browser, is_robot};
use common::ok;

fn configs(name: &str) -> String {
    format!("{}/../../configs/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn url(page: &Path, hash: &str) -> String {
    format!("file://{}#{hash}", page.display())
}

/// Every robot's position per round from a `trace --positions` file.
fn trace_rounds(path: &Path) -> Vec<Vec<[f64; 2]>> {
    let mut rounds: Vec<Vec<[f64; 2]>> = Vec::new();
    let mut r = csv::Reader::from_path(path).unwrap();
    for rec in r.records() {
        let rec = rec.unwrap();
        let round: usize = rec[0].parse().unwrap();
        if round == rounds.len() {
            rounds.push(Vec::new());
        }
        rounds[round].push([rec[2].parse().unwrap(), rec[3].parse().unwrap()]);
    }
    rounds
}

#[test]
#[ignore = "needs headless Chromium: scripts/browser-ci.sh"]
fn a_plane_replay_draws_the_robots_where_the_trace_puts_them() {
    let browser = Browser::new();
    let tmp = tempfile::tempdir().unwrap();
    let config = configs("replay/paper_run.toml");
    let page = tmp.path().join("paper.html");
    ok(&[
        "replay",
        &config,
        "--seed",
        "0",
        "--out",
        page.to_str().unwrap(),
    ]);
    let trace = tmp.path().join("paper.csv");
    ok(&[
        "trace",
        &config,
        "--seed",
        "0",
        "--out",
        trace.to_str().unwrap(),
        "--positions",
    ]);
    let rounds = trace_rounds(&tmp.path().join("paper.positions.csv"));
    let round = 3;
    let (w, h) = (800u32, 600u32);
    let hash = format!("round={round}&w={w}&h={h}");

    let body = browser.body(&url(&page, &hash));
    body.ready("plane replay");
    assert_eq!(
        body.time.as_deref(),
        Some("3"),
        "the round asked for is shown"
    );
    assert!(
        body.dom
            .contains(&format!("{round} of {}", rounds.len() - 1))
    );

    // The view fits the bounding box of every position of the run, 30 pixels of margin.
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in rounds.iter().flatten() {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let s = ((f64::from(w) - 60.0) / (hi[0] - lo[0])).min((f64::from(h) - 60.0) / (hi[1] - lo[1]));
    let (cx, cy) = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
    let pixel = |p: [f64; 2]| {
        (
            (f64::from(w) / 2.0 + (p[0] - cx) * s) as u32,
            (f64::from(h) / 2.0 - (p[1] - cy) * s) as u32,
        )
    };
    let shot = browser.screenshot(&url(&page, &hash), w + 340, h + 60);
    for (i, &p) in rounds[round].iter().enumerate().step_by(9) {
        let (x, y) = pixel(p);
        let c = shot.rgb(x, y);
        assert!(is_robot(c), "robot {i} at {p:?}: pixel ({x}, {y}) is {c:?}");
    }
    // Where no robot is, the background: the corners, and where robots were at the start
    // but are not at the last round (the start is drawn faint, not in robot colours).
    for (x, y) in [(2, 2), (w - 3, 2), (2, h - 3), (w - 3, h - 3)] {
        assert_eq!(shot.rgb(x, y), [255, 255, 255], "corner ({x}, {y})");
    }
    let last = rounds.len() - 1;
    let shot_last = browser.screenshot(
        &url(&page, &format!("round={last}&w={w}&h={h}")),
        w + 340,
        h + 60,
    );
    let away = rounds[0]
        .iter()
        .filter(|&&p| {
            rounds[last]
                .iter()
                .all(|q| (q[0] - p[0]).hypot(q[1] - p[1]) * s > 12.0)
        })
        .take(5)
        .collect::<Vec<_>>();
    assert!(!away.is_empty());
    for &&p in &away {
        let (x, y) = pixel(p);
        assert!(!is_robot(shot_last.rgb(x, y)), "start {p:?} is drawn faint");
    }

    // A selected robot shows its Look: as many visible points as `monoculus look` finds.
    let at = tmp.path().join("at.csv");
    let mut text = String::from("x,y\n");
    for p in &rounds[round] {
        text.push_str(&format!("{},{}\n", p[0], p[1]));
    }
    std::fs::write(&at, text).unwrap();
    let seen = ok(&["look", at.to_str().unwrap(), "--robot", "4"])
        .lines()
        .count()
        - 1;
    let body = browser.body(&url(&page, &format!("{hash}&robot=4")));
    body.ready("selected robot");
    assert!(
        body.dom.contains(&format!("sees {seen} points")),
        "robot 4 sees {seen} points: {}",
        &body.dom[body.dom.find("id=\"robot\"").unwrap()..][..400]
    );
}

/// A value of the page's embedded data: the JSON array after `"key":[`.
fn data_array(html: &str, key: &str) -> Vec<u64> {
    let start = html.find(&format!("\"{key}\":[")).expect(key) + key.len() + 4;
    let end = start + html[start..].find(']').unwrap();
    html[start..end]
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect()
}

#[test]
#[ignore = "needs headless Chromium: scripts/browser-ci.sh"]
fn async_and_three_d_replays_open_at_the_time_asked_for() {
    let browser = Browser::new();
    let tmp = tempfile::tempdir().unwrap();
    let (w, h) = (640u32, 480u32);

    // ASYNC: frame 120 shows its tick, with robots drawn.
    let page = tmp.path().join("async.html");
    ok(&[
        "replay",
        &configs("replay/async.toml"),
        "--out",
        page.to_str().unwrap(),
    ]);
    let html = std::fs::read_to_string(&page).unwrap();
    let rows = data_array(&html, "row");
    let ticks = data_array(&html, "time");
    let frame = 120;
    let body = browser.body(&url(&page, &format!("frame={frame}&w={w}&h={h}&robot=5")));
    body.ready("ASYNC replay");
    assert_eq!(body.frame.as_deref(), Some("120"));
    let tick = ticks[rows[frame] as usize];
    assert_eq!(body.time, Some(tick.to_string()));
    assert!(
        body.dom.contains(&format!("{tick} (epoch ")),
        "the tick and its epoch"
    );
    // #tick=T opens the frame of tick T.
    let body = browser.body(&url(&page, &format!("tick={tick}&w={w}&h={h}")));
    body.ready("ASYNC replay by tick");
    assert_eq!(body.time, Some(tick.to_string()));
    let shot = browser.screenshot(
        &url(&page, &format!("frame={frame}&w={w}&h={h}")),
        w + 340,
        h + 60,
    );
    assert!(shot.robot_pixels(w, h) > 40 * 20, "the 40 robots are drawn");

    // Space: a rotated projection at round 5; another rotation draws another picture.
    let page = tmp.path().join("three_d.html");
    ok(&[
        "replay",
        &configs("replay/three_d.toml"),
        "--out",
        page.to_str().unwrap(),
    ]);
    let body = browser.body(&url(
        &page,
        &format!("round=5&w={w}&h={h}&yaw=1.2&pitch=0.3"),
    ));
    body.ready("3D replay");
    assert_eq!(body.time.as_deref(), Some("5"));
    assert!(body.dom.contains("hull volume"));
    let a = browser.screenshot(
        &url(&page, &format!("round=5&w={w}&h={h}&yaw=1.2&pitch=0.3")),
        w + 340,
        h + 60,
    );
    let b = browser.screenshot(
        &url(&page, &format!("round=5&w={w}&h={h}&yaw=2.4&pitch=-0.5")),
        w + 340,
        h + 60,
    );
    assert!(a.robot_pixels(w, h) > 60 * 10, "the 60 robots are drawn");
    let differ = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| a.rgb(x, y) != b.rgb(x, y))
        .count();
    assert!(
        differ > 500,
        "rotating moves the robots ({differ} pixels differ)"
    );
}

/// Robots that stop for good after three moves, with a light: `fresh`, then `tired`.
struct Tired;

#[derive(Clone, Debug, Default, PartialEq)]
struct Moves(u8);

impl monoculus_core::algorithms::Algorithm for Tired {
    const NAME: &'static str = "tired";
    type Sensing = monoculus_core::algorithms::Ld;
    type Params = monoculus_core::algorithms::NoParams;
    type State = Moves;
    const LIGHTS: &'static [&'static str] = &["fresh", "tired"];

    fn new(_: monoculus_core::algorithms::NoParams) -> Result<Self, String> {
        Ok(Tired)
    }

    fn light(m: &Moves) -> usize {
        usize::from(m.0 >= 3)
    }

    fn decide<V: monoculus_core::geometry::Point>(
        &self,
        obs: &monoculus_core::algorithms::Observation<'_, monoculus_core::algorithms::Ld, V>,
        m: &mut Moves,
        rng: &mut monoculus_core::rng::Stream,
    ) -> monoculus_core::algorithms::Decision<V> {
        use monoculus_core::algorithms::Decision;
        if m.0 >= 3 {
            return Decision::Stay;
        }
        match obs.sole_visible().or_else(|| obs.random_far(rng)) {
            Some(toward) => {
                m.0 += 1;
                Decision::Step(toward)
            }
            None => Decision::Stay,
        }
    }
}

#[test]
#[ignore = "needs headless Chromium: scripts/browser-ci.sh"]
fn a_luminous_replay_colours_each_robot_by_its_light_and_shows_what_it_saw() {
    use monoculus_experiments::{Experiment, Registry};
    let browser = Browser::new();
    let tmp = tempfile::tempdir().unwrap();
    let mut registry = Registry::builtin();
    registry.register::<Tired>();
    // SSYNC: the robots tire at different rounds.
    let config = "name = \"tired\"\n[swarm]\nn = 14\ninit = \"square\"\nside = 12.0\n[algorithm]\nname = \"tired\"\n[scheduler]\nkind = \"ssync\"\np = 0.5\n";
    let exp = Experiment::parse(config, "tired.toml", tmp.path(), &[], &registry).unwrap();
    let replay =
        monoculus_experiments::replay::record(&exp.cells[0], 1, "tired".into(), Default::default())
            .unwrap();
    assert_eq!(replay.lights, ["fresh", "tired"]);
    assert_eq!(replay.verdict, "stuck", "{}", replay.outcome);
    let page = tmp.path().join("tired.html");
    monoculus_plot::write_replay_html(&replay, &page).unwrap();
    // A frame where both colours show.
    let k = replay
        .frames
        .iter()
        .position(|f| f.lights.contains(&0) && f.lights.contains(&1))
        .expect("a frame with fresh and tired robots");
    let (w, h) = (700u32, 500u32);
    let hash = format!("frame={k}&w={w}&h={h}&robot=0");
    let body = browser.body(&url(&page, &hash));
    body.ready("luminous replay");
    assert_eq!(body.frame, Some(k.to_string()));
    for needle in [
        "Lights: ",
        "fresh",
        "tired",
        "shows ",
        "saw lights: ",
        "class=\"verdict stuck\"",
    ] {
        assert!(body.dom.contains(needle), "the page shows {needle:?}");
    }
    // Every robot drawn in its light's colour, where the frame puts it.
    let mut all: Vec<f32> = replay.start.clone();
    for f in &replay.frames {
        all.extend(&f.positions);
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in all.chunks(2) {
        for a in 0..2 {
            lo[a] = lo[a].min(f64::from(p[a]));
            hi[a] = hi[a].max(f64::from(p[a]));
        }
    }
    let s = ((f64::from(w) - 60.0) / (hi[0] - lo[0])).min((f64::from(h) - 60.0) / (hi[1] - lo[1]));
    let (cx, cy) = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
    let shot = browser.screenshot(
        &url(&page, &format!("frame={k}&w={w}&h={h}")),
        w + 340,
        h + 60,
    );
    let frame = &replay.frames[k];
    let mut right = 0;
    for (p, &l) in frame.positions.chunks(2).zip(&frame.lights) {
        let x = (f64::from(w) / 2.0 + (f64::from(p[0]) - cx) * s) as u32;
        let y = (f64::from(h) / 2.0 - (f64::from(p[1]) - cy) * s) as u32;
        let (r, g, b) = monoculus_plot::light_colour(usize::from(l));
        let c = shot.rgb(x, y);
        if c.iter().zip([r, g, b]).all(|(a, b)| a.abs_diff(b) <= 6) {
            right += 1;
        }
    }
    // (Robots drawn over one another may hide a few.)
    assert!(
        right * 10 >= frame.lights.len() * 8,
        "{right} of {} robots in their light's colour",
        frame.lights.len()
    );
}

/// The page of `html` with scripts blocked in every inline replay's frame: the page's
/// static parts show, its canvas stays blank.
fn without_scripts(html: &str) -> String {
    html.replace("sandbox=\"allow-scripts\"", "sandbox=\"\"")
}

#[test]
#[ignore = "needs headless Chromium and the executed tour notebook: scripts/browser-ci.sh"]
fn the_tour_notebook_s_replays_draw_inside_it() {
    let exported = std::env::var_os("MONOCULUS_TOUR_HTML").expect(
        "MONOCULUS_TOUR_HTML: the tour notebook exported as HTML (scripts/python-ci.sh writes it)",
    );
    let html = std::fs::read_to_string(&exported).expect("the exported notebook");
    let frames = html.matches("<iframe class=\"monoculus-replay\"").count();
    assert_eq!(frames, 2, "the stepped simulation's replay and the hunt's");
    assert_eq!(html.matches("sandbox=\"allow-scripts\"").count(), 2);
    let tmp = tempfile::tempdir().unwrap();
    let (live, still) = (tmp.path().join("tour.html"), tmp.path().join("still.html"));
    std::fs::write(&live, &html).unwrap();
    std::fs::write(&still, without_scripts(&html)).unwrap();
    // The whole notebook in one tall window, once as exported and once with the
    // replays' scripts blocked: the robots the replay pages draw are the difference.
    let browser = Browser::new();
    let (w, h) = (1200, 7000);
    let robots = |page: &Path| browser.screenshot(&url(page, ""), w, h).robot_pixels(w, h);
    let (drawn, static_parts) = (robots(&live), robots(&still));
    // Six robots of the stepped simulation and the hunt's few, a disc of tens of pixels
    // each, and what the scripts colour around them (about 2,300 pixels in all here).
    assert!(
        drawn >= static_parts + 500,
        "robot pixels: {drawn} with the replays' scripts, {static_parts} without"
    );
}
