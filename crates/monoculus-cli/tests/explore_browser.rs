//! `monoculus explore` in a real browser: headless Chromium, driven through the DevTools
//! protocol (chromiumoxide), opens the page, adds robots by clicks, drags one, selects
//! one, steps, and the page must draw what the server holds: robots where it put them,
//! the selected robot's Look rays and the move it would make.
//!
//! Needs Chromium, so `cargo test` skips it (ignored); `scripts/browser-ci.sh` installs
//! Debian's `chromium` and runs it:
//!     cargo test -p monoculus-cli --test explore_browser -- --ignored
//! With `MONOCULUS_EXPLORE_SHOT=FILE` the last screenshot is kept there.

#[path = "common/chromium.rs"]
mod chromium;
mod common;

use std::process::Child;
use std::time::{Duration, Instant};

use chromiumoxide::browser::{Browser, BrowserConfig};
use chromiumoxide::cdp::browser_protocol::input::{
    DispatchMouseEventParams, DispatchMouseEventType, MouseButton,
};
use chromiumoxide::layout::Point;
use chromiumoxide::page::{Page, ScreenshotParams};
use futures::StreamExt;

/// The explorer, killed when dropped.
struct Server(Child);

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Headless Chromium with a profile of its own, its event loop, on the explorer at `url`:
/// the page once its script says it is ready.
async fn open(
    url: &str,
) -> (
    Browser,
    tokio::task::JoinHandle<()>,
    tempfile::TempDir,
    Page,
) {
    let profile = chromium::scratch();
    let (browser, mut handler) = Browser::launch(
        BrowserConfig::builder()
            .chrome_executable(chromium::exe())
            .no_sandbox()
            .arg("--disable-gpu")
            .user_data_dir(profile.path())
            .window_size(1400, 800)
            .viewport(None)
            .build()
            .unwrap(),
    )
    .await
    .unwrap();
    let events = tokio::spawn(async move { while handler.next().await.is_some() {} });
    let page = browser.new_page(url).await.unwrap();
    wait_for(&page, "status", "ready").await;
    (browser, events, profile, page)
}

/// Closes what [`open`] opened.
async fn close(mut browser: Browser, events: tokio::task::JoinHandle<()>) {
    browser.close().await.unwrap();
    let _ = browser.wait().await;
    events.abort();
}

/// A value of the page's `document.body.dataset`.
async fn data(page: &Page, key: &str) -> String {
    page.evaluate(format!("document.body.dataset['{key}'] || ''"))
        .await
        .unwrap()
        .into_value()
        .unwrap()
}

/// Waits until `data(key)` is `want` (10 s at most).
async fn wait_for(page: &Page, key: &str, want: &str) {
    let t0 = Instant::now();
    loop {
        let got = data(page, key).await;
        if got == want {
            return;
        }
        let error = data(page, "error").await;
        assert!(error.is_empty(), "the page says: {error}");
        assert!(
            t0.elapsed() < Duration::from_secs(10),
            "{key}: {got:?}, waited for {want:?}"
        );
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// Where robot `k` is drawn, page pixels.
async fn screen(page: &Page, k: usize) -> [f64; 2] {
    page.evaluate(format!("monoculusExplore.screen({k})"))
        .await
        .unwrap()
        .into_value()
        .unwrap()
}

async fn mouse(page: &Page, kind: DispatchMouseEventType, at: [f64; 2]) {
    let mut e = DispatchMouseEventParams::new(kind, at[0], at[1]);
    e.button = Some(MouseButton::Left);
    e.click_count = Some(1);
    page.execute(e).await.unwrap();
}

/// Pixels of the screenshot within `r` of `at` whose colour is within 40 of `rgb`.
fn count_near(png: &[u8], at: [f64; 2], r: f64, rgb: [u8; 3]) -> usize {
    let decoder = png::Decoder::new(std::io::Cursor::new(png));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let mut count = 0;
    for y in 0..info.height as usize {
        for x in 0..info.width as usize {
            if (x as f64 - at[0]).hypot(y as f64 - at[1]) > r {
                continue;
            }
            let p = &buf[(y * info.width as usize + x) * channels..][..3];
            if p.iter().zip(rgb).all(|(&a, b)| a.abs_diff(b) <= 40) {
                count += 1;
            }
        }
    }
    count
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
#[ignore = "needs headless Chromium: scripts/browser-ci.sh"]
async fn robots_added_by_clicks_are_stepped_and_one_shows_what_it_sees() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("two.csv"), "x,y\n0,0\n4,0\n").unwrap();
    let config = dir.path().join("two.toml");
    std::fs::write(
        &config,
        "name = \"two\"\n[swarm]\ninit = \"file\"\nfile = \"two.csv\"\n[algorithm]\nname = \"converge_locality\"\ntarget = \"random_rejection\"\n",
    )
    .unwrap();
    let (child, url) =
        common::explore(env!("CARGO_BIN_EXE_monoculus"), &[config.to_str().unwrap()]);
    let _server = Server(child);
    let (browser, events, _profile, page) = open(&url).await;
    assert_eq!(data(&page, "n").await, "2");

    // Three robots by clicks on empty ground: each lands where it was clicked.
    let a = screen(&page, 0).await;
    let b = screen(&page, 1).await;
    let mid = [(a[0] + b[0]) / 2.0, a[1]];
    let clicks = [
        [mid[0], mid[1] - 150.0],
        [mid[0], mid[1] + 150.0],
        [a[0] + 60.0, a[1] - 90.0],
    ];
    for (k, at) in clicks.iter().enumerate() {
        page.click(Point::new(at[0], at[1])).await.unwrap();
        wait_for(&page, "n", &(3 + k).to_string()).await;
        let drawn = screen(&page, 2 + k).await;
        assert!(
            (drawn[0] - at[0]).abs() < 1.0 && (drawn[1] - at[1]).abs() < 1.0,
            "robot {} clicked at {at:?}, drawn at {drawn:?}",
            2 + k
        );
    }

    // Drag robot 1 a little to the left: it is moved, nothing added.
    let to = [b[0] - 80.0, b[1] + 20.0];
    mouse(&page, DispatchMouseEventType::MousePressed, b).await;
    for k in 1..=5 {
        let f = k as f64 / 5.0;
        let at = [b[0] + (to[0] - b[0]) * f, b[1] + (to[1] - b[1]) * f];
        mouse(&page, DispatchMouseEventType::MouseMoved, at).await;
    }
    mouse(&page, DispatchMouseEventType::MouseReleased, to).await;
    wait_for(&page, "selected", "1").await;
    let moved = screen(&page, 1).await;
    assert!(
        (moved[0] - to[0]).abs() < 1.0 && (moved[1] - to[1]).abs() < 1.0,
        "{moved:?}"
    );
    assert_eq!(data(&page, "n").await, "5");

    // Select robot 0, far from the others: it sees them and would move.
    let a = screen(&page, 0).await;
    page.click(Point::new(a[0], a[1])).await.unwrap();
    wait_for(&page, "selected", "0").await;
    wait_for(&page, "decision", "move").await;
    assert_eq!(data(&page, "seen").await, "4");

    // Step: the server's round is drawn, the panel follows the robot.
    page.find_element("#step")
        .await
        .unwrap()
        .click()
        .await
        .unwrap();
    wait_for(&page, "rounds", "1").await;
    let verdict = data(&page, "verdict").await;
    assert!(["converged", "not converged", "stuck"].contains(&verdict.as_str()));
    tokio::time::sleep(Duration::from_millis(300)).await;
    let shot = page
        .screenshot(ScreenshotParams::builder().build())
        .await
        .unwrap();
    if let Some(path) = std::env::var_os("MONOCULUS_EXPLORE_SHOT") {
        std::fs::write(path, &shot).unwrap();
    }
    let at = screen(&page, 0).await;
    // The selection ring, the Look rays (near or far) and, if it still moves, its arrow.
    assert!(
        count_near(&shot, at, 12.0, [0x11, 0x18, 0x27]) > 20,
        "no selection ring"
    );
    let rays = count_near(&shot, at, 60.0, [0x02, 0x84, 0xc7])
        + count_near(&shot, at, 60.0, [0xea, 0x58, 0x0c]);
    assert!(rays > 20, "no Look rays drawn: {rays}");
    if data(&page, "decision").await == "move" {
        assert!(
            count_near(&shot, at, 80.0, [0x05, 0x96, 0x69]) > 10,
            "no move arrow"
        );
    }
    // The panel says what the server says.
    let text: String = page
        .evaluate("document.getElementById('robot').textContent")
        .await
        .unwrap()
        .into_value()
        .unwrap();
    assert!(text.starts_with("robot 0 at"), "{text}");
    assert!(text.contains("last Look"), "{text}");
    close(browser, events).await;
}

/// The explorer's play rate, a benchmark rather than a test: with
/// `MONOCULUS_EXPLORE_BENCH=N` (robots; otherwise it does nothing), the page plays a
/// swarm of N robots (ConvergeLocality, FSYNC, density 1) as fast as it goes for 10
/// seconds (or to the run's end) and prints the rounds stepped and drawn per second.
/// `scripts/performance.sh` runs it at 10^4 and 10^5 robots (docs/performance.md).
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
#[ignore = "needs headless Chromium: scripts/browser-ci.sh"]
async fn play_rate_benchmark() {
    let Some(n) = std::env::var("MONOCULUS_EXPLORE_BENCH")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    else {
        return;
    };
    let bin = std::env::var("MONOCULUS_BIN")
        .unwrap_or_else(|_| env!("CARGO_BIN_EXE_monoculus").to_string());
    let side = (n as f64).sqrt();
    let (child, url) = common::explore(
        &bin,
        &[
            "--set",
            &format!("swarm.n={n}"),
            "--set",
            &format!("swarm.side={side}"),
            "--set",
            "stop.max_rounds=100000",
        ],
    );
    let _server = Server(child);
    let (browser, events, _profile, page) = open(&url).await;
    // Count the frames the page draws while it plays.
    page.evaluate("(() => { const d = document.body.dataset; d.frames = '0'; const c = document.getElementById('view'); const ctx = c.getContext('2d'); const fill = ctx.fillRect.bind(ctx); ctx.fillRect = function (x, y, w, h) { if (x === 0 && y === 0 && w === c.width) d.frames = String(+d.frames + 1); return fill(x, y, w, h); }; })()")
        .await
        .unwrap();
    page.evaluate("document.getElementById('speed').value = '0'")
        .await
        .unwrap();
    let t0 = Instant::now();
    page.find_element("#play")
        .await
        .unwrap()
        .click()
        .await
        .unwrap();
    while t0.elapsed() < Duration::from_secs(10) && data(&page, "ended").await != "true" {
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    let seconds = t0.elapsed().as_secs_f64();
    let rounds: f64 = data(&page, "rounds").await.parse().unwrap();
    let frames: f64 = data(&page, "frames").await.parse().unwrap();
    println!(
        "explore play: n={n}: {rounds} rounds stepped and {frames} frames drawn in {seconds:.1} s: {:.1} rounds/s, {:.1} frames/s",
        rounds / seconds,
        frames / seconds
    );
    close(browser, events).await;
}
