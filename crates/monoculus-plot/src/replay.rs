//! A recorded run ([`Replay`]) as a self-contained HTML player, or as an animated GIF.
//!
//! The page embeds its data (numbers in base64 little-endian arrays) and its script; it
//! loads nothing. Its view fits every drawn position into the canvas with a margin of 30
//! pixels, y up: a plane point (x, y) is drawn at `(W/2 + (x - cx) s, H/2 - (y - cy) s)`,
//! `(cx, cy)` the centre of the bounding box and `s = min((W - 60)/(x extent),
//! (H - 60)/(y extent))`. The address can ask for a frame and the canvas size:
//! `#round=R` (ASYNC `#tick=T`, or `#frame=K`), `&w=W&h=H`, `&robot=I`, `&yaw=..&pitch=..`
//! (3D), `&play=1`. The page sets `data-status` on its body to `ready` (or `error`, with
//! `data-error`, on a script error) and `data-time` to the round or tick shown.

use std::path::Path;

use monoculus_experiments::output::AtomicFile;
use monoculus_experiments::output::json;

use monoculus_experiments::replay::Replay;
use plotters::prelude::*;

use crate::PlotError;

static TEMPLATE: &str = include_str!("../assets/replay.html");
const SLOT: &str = "/*REPLAY_DATA*/";

/// The script the replay page and `monoculus explore`'s page share: the colours of robots
/// and Look rays, the hull, the arrow of a move, the log-scale chart (it defines
/// `window.MonoculusView`). A page includes it where it has the slot [`VIEW_SLOT`].
///
/// ```
/// assert!(monoculus_plot::VIEW_JS.contains("window.MonoculusView"));
/// assert!(!monoculus_plot::VIEW_JS.contains("</script"));
/// ```
pub static VIEW_JS: &str = include_str!("../assets/view.js");

/// Where a page takes [`VIEW_JS`]: `<script>/*VIEW_JS*/</script>`.
pub const VIEW_SLOT: &str = "/*VIEW_JS*/";

/// The replay page's template with the shared script in place.
fn template() -> &'static str {
    static PAGE: std::sync::LazyLock<String> =
        std::sync::LazyLock::new(|| TEMPLATE.replacen(VIEW_SLOT, VIEW_JS, 1));
    &PAGE
}

/// `bytes` in standard base64 with padding: how the replay page and the explorer carry
/// arrays of numbers (the page decodes them with `atob` into typed arrays).
///
/// ```
/// assert_eq!(monoculus_plot::base64(b"robots"), "cm9ib3Rz");
/// assert_eq!(monoculus_plot::base64(&[0xff]), "/w==");
/// ```
pub fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let v = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ABC[(v >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

fn f32s(values: impl IntoIterator<Item = f32>) -> String {
    base64(
        &values
            .into_iter()
            .flat_map(f32::to_le_bytes)
            .collect::<Vec<u8>>(),
    )
}

fn u32s(values: impl IntoIterator<Item = u32>) -> String {
    base64(
        &values
            .into_iter()
            .flat_map(u32::to_le_bytes)
            .collect::<Vec<u8>>(),
    )
}

/// The colour of light `k` of an algorithm's palette, as the replay page and the GIF
/// draw it: Tableau's ten qualitative colours, then hues a golden angle apart.
///
/// ```
/// assert_eq!(monoculus_plot::light_colour(0), (0x4e, 0x79, 0xa7));
/// assert_ne!(monoculus_plot::light_colour(10), monoculus_plot::light_colour(11));
/// ```
pub fn light_colour(k: usize) -> (u8, u8, u8) {
    const TEN: [(u8, u8, u8); 10] = [
        (0x4e, 0x79, 0xa7),
        (0xf2, 0x8e, 0x2b),
        (0xe1, 0x57, 0x59),
        (0x76, 0xb7, 0xb2),
        (0x59, 0xa1, 0x4f),
        (0xed, 0xc9, 0x48),
        (0xb0, 0x7a, 0xa1),
        (0xff, 0x9d, 0xa7),
        (0x9c, 0x75, 0x5f),
        (0xba, 0xb0, 0xac),
    ];
    if let Some(&c) = TEN.get(k) {
        return c;
    }
    // HSL with s = 0.6, l = 0.5, the hue turned by the golden angle per colour.
    let h = (k as f64 * 137.507_764) % 360.0 / 60.0;
    let (c, l) = (0.6, 0.5);
    let x = c * (1.0 - (h % 2.0 - 1.0).abs());
    let (r, g, b) = match h as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let to = |v: f64| ((v + l - c / 2.0) * 255.0).round().clamp(0.0, 255.0) as u8;
    (to(r), to(g), to(b))
}

/// The replay's data as the page reads it: numbers in base64 little-endian arrays.
#[derive(serde::Serialize)]
struct PageData<'a> {
    title: &'a str,
    subtitle: &'a str,
    outcome: &'a str,
    verdict: &'a str,
    dim: usize,
    n: usize,
    drawn: usize,
    sample: usize,
    stride: usize,
    ticks: bool,
    model: &'a str,
    locality: f64,
    termination: bool,
    lights: &'a [String],
    light_colors: Vec<String>,
    notes: &'a [String],
    looks_note: Option<&'a str>,
    start: String,
    frames: PageFrames,
    metrics: PageMetrics<'a>,
    looks: PageLooks,
}

#[derive(serde::Serialize)]
struct PageFrames {
    step: Vec<u64>,
    row: Vec<u64>,
    pos: String,
    state: String,
    bits: String,
    light: String,
    hull_off: Vec<u64>,
    hull: String,
}

#[derive(serde::Serialize)]
struct PageMetrics<'a> {
    time: &'a [u64],
    epoch: &'a [u64],
    hull: &'a [f64],
    diameter: &'a [f64],
    moving: &'a [u64],
}

#[derive(serde::Serialize)]
struct PageLooks {
    frame: String,
    robot: String,
    dest: String,
    off: String,
    seen: String,
    flags: String,
}

/// The replay's data as the page reads it (JSON, safe inside the page's `<script>`).
pub fn replay_json(r: &Replay) -> String {
    let mut hull_off = vec![0u64];
    for f in &r.frames {
        hull_off.push(hull_off.last().copied().unwrap_or(0) + f.hull.len() as u64);
    }
    let mut look_off = vec![0u32];
    for l in &r.looks {
        look_off.push(look_off.last().copied().unwrap_or(0) + l.seen.len() as u32);
    }
    let bytes = |f: &dyn Fn(&monoculus_experiments::replay::Frame) -> &[u8]| {
        base64(
            &r.frames
                .iter()
                .flat_map(|x| f(x).iter().copied())
                .collect::<Vec<u8>>(),
        )
    };
    let frames = PageFrames {
        step: r.frames.iter().map(|f| f.step as u64).collect(),
        row: r.frames.iter().map(|f| f.row as u64).collect(),
        pos: f32s(r.frames.iter().flat_map(|f| f.positions.iter().copied())),
        state: bytes(&|f| &f.states),
        bits: if r.termination {
            bytes(&|f| &f.bits)
        } else {
            String::new()
        },
        light: bytes(&|f| &f.lights),
        hull_off,
        hull: f32s(r.frames.iter().flat_map(|f| f.hull.iter().copied())),
    };
    let looks = PageLooks {
        frame: u32s(r.looks.iter().map(|l| l.frame as u32)),
        robot: u32s(r.looks.iter().map(|l| l.robot)),
        dest: f32s(r.looks.iter().flat_map(|l| match &l.destination {
            Some(d) => d.clone(),
            None => vec![f32::NAN; r.dim],
        })),
        off: u32s(look_off),
        seen: u32s(r.looks.iter().flat_map(|l| l.seen.iter().copied())),
        flags: base64(
            &r.looks
                .iter()
                .flat_map(|l| l.flags.iter().copied())
                .collect::<Vec<u8>>(),
        ),
    };
    let m = &r.metrics;
    json::to_string(&PageData {
        title: &r.title,
        subtitle: &r.subtitle,
        outcome: &r.outcome,
        verdict: r.verdict,
        dim: r.dim,
        n: r.n,
        drawn: r.start.len() / r.dim,
        sample: r.sample,
        stride: r.stride,
        ticks: r.ticks,
        model: r.model,
        locality: r.locality,
        termination: r.termination,
        lights: &r.lights,
        light_colors: (0..r.lights.len())
            .map(|k| {
                let (red, green, blue) = light_colour(k);
                format!("#{red:02x}{green:02x}{blue:02x}")
            })
            .collect(),
        notes: &r.notes,
        looks_note: r.looks_note.as_deref(),
        start: f32s(r.start.iter().copied()),
        frames,
        metrics: PageMetrics {
            time: &m.time,
            epoch: &m.epoch,
            hull: &m.hull,
            diameter: &m.diameter,
            moving: &m.moving,
        },
        looks,
    })
}

/// The self-contained page of `replay`.
pub fn replay_html(replay: &Replay) -> String {
    template().replacen(SLOT, &replay_json(replay), 1)
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> PlotError + '_ {
    move |e| PlotError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// Writes the page of `replay` to `path`.
/// The page is written whole or not at all: an error (a full disk) or a signal leaves
/// the page that was there.
pub fn write_replay_html(replay: &Replay, path: &Path) -> Result<(), PlotError> {
    crate::save(path, replay_html(replay).as_bytes())
}

/// Frames of the animation at most (the replay's frames are thinned evenly to it).
const GIF_FRAMES: usize = 240;

/// Writes `replay` as an animated GIF of `size` pixels (the plane, or the x-y
/// projection in space): robots coloured as on the page, the hull, the start faint; at
/// most 240 frames, about 8 seconds (2.5 to 20 frames per second).
pub fn write_replay_gif(replay: &Replay, path: &Path, size: (u32, u32)) -> Result<(), PlotError> {
    crate::font::ensure()?;
    let fail = |message: String| PlotError::Draw {
        path: path.display().to_string(),
        message,
    };
    if replay.frames.is_empty() {
        return Err(fail("the replay has no frames".into()));
    }
    let dim = replay.dim;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let all = replay
        .start
        .chunks(dim)
        .chain(replay.frames.iter().flat_map(|f| f.positions.chunks(dim)));
    for p in all {
        for k in 0..2 {
            lo[k] = lo[k].min(f64::from(p[k]));
            hi[k] = hi[k].max(f64::from(p[k]));
        }
    }
    let (w, h) = (f64::from(size.0), f64::from(size.1));
    const MARGIN: f64 = 30.0;
    let top = 24.0;
    let sx = (w - 2.0 * MARGIN) / (hi[0] - lo[0]);
    let sy = (h - top - 2.0 * MARGIN) / (hi[1] - lo[1]);
    let s = match sx.min(sy) {
        s if s.is_finite() && s > 0.0 => s,
        _ => 1.0,
    };
    let (cx, cy) = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
    let px = |x: f32, y: f32| {
        (
            (w / 2.0 + (f64::from(x) - cx) * s) as i32,
            (top + (h - top) / 2.0 - (f64::from(y) - cy) * s) as i32,
        )
    };
    let keep: Vec<usize> = {
        let n = replay.frames.len();
        let k = n.div_ceil(GIF_FRAMES).max(1);
        let mut v: Vec<usize> = (0..n).step_by(k).collect();
        if v.last() != Some(&(n - 1)) {
            v.push(n - 1);
        }
        v
    };
    // About 8 seconds whatever the number of frames, 2.5 to 20 frames per second.
    let delay = (8000 / keep.len() as u32).clamp(50, 400);
    // Encoded into a temporary file beside `path`, renamed over it once complete.
    let file = AtomicFile::create(path).map_err(|e| io(path)(e.cause))?;
    let root = BitMapBackend::gif(file.temporary(), size, delay)
        .map_err(|e| fail(e.to_string()))?
        .into_drawing_area();
    let colors = [
        RGBColor(0x6b, 0x72, 0x80),
        RGBColor(0x25, 0x63, 0xeb),
        RGBColor(0xd9, 0x77, 0x06),
        RGBColor(0xdc, 0x26, 0x26),
    ];
    let label = if replay.ticks { "tick" } else { "round" };
    let radius = if replay.start.len() / dim > 500 { 2 } else { 3 };
    for &k in &keep {
        let f = &replay.frames[k];
        let draw = || -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
            root.fill(&WHITE)?;
            for p in replay.start.chunks(dim) {
                root.draw(&Circle::new(
                    px(p[0], p[1]),
                    1,
                    RGBColor(0xd1, 0xd5, 0xdb).filled(),
                ))?;
            }
            if f.hull.len() >= 6 {
                let mut pts: Vec<(i32, i32)> = f.hull.chunks(2).map(|v| px(v[0], v[1])).collect();
                pts.push(pts[0]);
                root.draw(&PathElement::new(pts, RGBColor(0x94, 0xa3, 0xb8)))?;
            }
            for (j, p) in f.positions.chunks(dim).enumerate() {
                let state = colors[usize::from(f.states[j]).min(3)];
                match f.lights.get(j) {
                    // As on the page: robots filled with their light, movers ringed.
                    Some(&l) => {
                        let (red, green, blue) = light_colour(usize::from(l));
                        let at = px(p[0], p[1]);
                        root.draw(&Circle::new(
                            at,
                            radius,
                            RGBColor(red, green, blue).filled(),
                        ))?;
                        if f.states[j] == 3 {
                            root.draw(&Circle::new(at, radius + 1, state.stroke_width(1)))?;
                        }
                    }
                    None => root.draw(&Circle::new(px(p[0], p[1]), radius, state.filled()))?,
                }
            }
            // The lights' legend along the bottom.
            let mut x = 8;
            for (k, name) in replay.lights.iter().enumerate().take(12) {
                let (red, green, blue) = light_colour(k);
                let y = size.1 as i32 - 12;
                root.draw(&Circle::new(
                    (x + 5, y),
                    5,
                    RGBColor(red, green, blue).filled(),
                ))?;
                root.draw(&Text::new(
                    name.clone(),
                    (x + 14, y - 7),
                    ("sans-serif", 13).into_font().color(&BLACK),
                ))?;
                x += 24 + 7 * name.chars().count() as i32;
            }
            let t = replay.metrics.time[f.row];
            let d = replay.metrics.diameter[f.row];
            root.draw(&Text::new(
                format!(
                    "{label} {t}   diameter {d:.3}   moving {}",
                    replay.metrics.moving[f.step]
                ),
                (8, 6),
                ("sans-serif", 15).into_font().color(&BLACK),
            ))?;
            root.present()?;
            Ok(())
        };
        draw().map_err(|e| fail(e.to_string()))?;
    }
    drop(root);
    file.commit().map_err(|e| io(path)(e.cause))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_the_standard_alphabet_and_padding() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
        assert_eq!(base64(&[0xff, 0xfe, 0x00]), "//4A");
    }

    #[test]
    fn no_name_can_close_the_script_element() {
        let r = Replay {
            title: "a</script><script>alert(1)</script>".into(),
            subtitle: "<!-- & -->".into(),
            outcome: String::new(),
            verdict: "converged",
            dim: 2,
            n: 1,
            sample: 1,
            stride: 1,
            ticks: false,
            model: "ld",
            locality: 2.0,
            termination: false,
            lights: vec!["</script>".into()],
            start: vec![0.0, 0.0],
            frames: Vec::new(),
            metrics: Default::default(),
            looks: Vec::new(),
            looks_note: None,
            notes: vec!["</SCRIPT>".into()],
        };
        let page = replay_html(&r);
        let closing = TEMPLATE.matches("</script>").count();
        assert_eq!(page.to_lowercase().matches("</script>").count(), closing);
        let data: serde_json::Value = serde_json::from_str(&replay_json(&r)).unwrap();
        assert_eq!(data["title"], "a</script><script>alert(1)</script>");
        assert_eq!(data["lights"][0], "</script>");
    }
}
