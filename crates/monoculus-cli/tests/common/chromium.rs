//! Headless Chromium for the browser tests: a page's DOM after its script ran, and
//! screenshots read back as pixels.

#![allow(dead_code, reason = "each test binary uses a part")]

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The Chromium the tests use: `$MONOCULUS_CHROMIUM`, else `chromium` on the PATH.
pub fn exe() -> PathBuf {
    std::env::var_os("MONOCULUS_CHROMIUM")
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("PATH").and_then(|paths| {
                std::env::split_paths(&paths)
                    .map(|p| p.join("chromium"))
                    .find(|p| p.is_file())
            })
        })
        .expect("no Chromium: set MONOCULUS_CHROMIUM or install it (scripts/browser-ci.sh does)")
}

/// A profile folder for one Chromium, under `$MONOCULUS_BROWSER_TMP` when set (where
/// scripts/browser-ci.sh stops any Chromium left).
pub fn scratch() -> tempfile::TempDir {
    match std::env::var_os("MONOCULUS_BROWSER_TMP") {
        Some(b) => tempfile::tempdir_in(b).unwrap(),
        None => tempfile::tempdir().unwrap(),
    }
}

/// One headless Chromium, each call a fresh process with its own profile folder under
/// `dir` (killed if it outlives its deadline).
pub struct Browser {
    exe: PathBuf,
    dir: tempfile::TempDir,
    runs: std::cell::Cell<usize>,
}

impl Browser {
    pub fn new() -> Browser {
        let (exe, dir) = (exe(), scratch());
        Browser {
            exe,
            dir,
            runs: std::cell::Cell::new(0),
        }
    }

    /// Runs Chromium on `url` with `extra` arguments; its standard output.
    pub fn run(&self, url: &str, extra: &[String]) -> String {
        let k = self.runs.get();
        self.runs.set(k + 1);
        let profile = self.dir.path().join(format!("profile-{k}"));
        let mut child = Command::new(&self.exe)
            .args([
                "--headless=new",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                "--hide-scrollbars",
                "--force-device-scale-factor=1",
                "--virtual-time-budget=5000",
            ])
            .arg(format!("--user-data-dir={}", profile.display()))
            .args(extra)
            .arg(url)
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromium starts");
        let deadline = Instant::now() + Duration::from_secs(90);
        let mut stdout = child.stdout.take().unwrap();
        let reader = std::thread::spawn(move || {
            let mut s = String::new();
            std::io::Read::read_to_string(&mut stdout, &mut s).ok();
            s
        });
        loop {
            if let Some(status) = child.try_wait().unwrap() {
                assert!(status.success(), "chromium failed on {url}: {status}");
                break;
            }
            if Instant::now() > deadline {
                child.kill().ok();
                child.wait().ok();
                panic!("chromium did not finish on {url} within 90 s");
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        reader.join().unwrap()
    }

    /// The page's body attributes after its script ran: `data-status`, `data-time`...
    pub fn body(&self, url: &str) -> Body {
        let dom = self.run(url, &["--dump-dom".to_string()]);
        let start = dom.find("<body").expect("a body in the DOM");
        let tag = &dom[start..start + dom[start..].find('>').unwrap()];
        let attr = |name: &str| {
            let key = format!("{name}=\"");
            tag.find(&key).map(|i| {
                let rest = &tag[i + key.len()..];
                rest[..rest.find('"').unwrap()].to_string()
            })
        };
        Body {
            status: attr("data-status").unwrap_or_default(),
            time: attr("data-time"),
            frame: attr("data-frame"),
            error: attr("data-error"),
            dom,
        }
    }

    /// A screenshot of the window (`w` x `h` pixels) as RGB rows.
    pub fn screenshot(&self, url: &str, w: u32, h: u32) -> Shot {
        let png = self
            .dir
            .path()
            .join(format!("shot-{}.png", self.runs.get()));
        self.run(
            url,
            &[
                format!("--window-size={w},{h}"),
                format!("--screenshot={}", png.display()),
            ],
        );
        let decoder = png::Decoder::new(std::io::BufReader::new(
            std::fs::File::open(&png).expect("chromium wrote the screenshot"),
        ));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        let channels = info.color_type.samples();
        Shot {
            width: info.width,
            height: info.height,
            channels,
            data: buf[..info.buffer_size()].to_vec(),
        }
    }
}

pub struct Body {
    pub status: String,
    pub time: Option<String>,
    pub frame: Option<String>,
    pub error: Option<String>,
    pub dom: String,
}

impl Body {
    pub fn ready(&self, what: &str) {
        assert_eq!(self.error, None, "{what}: script error");
        assert_eq!(self.status, "ready", "{what}: the page did not finish");
    }
}

pub struct Shot {
    pub width: u32,
    pub height: u32,
    pub channels: usize,
    pub data: Vec<u8>,
}

impl Shot {
    pub fn rgb(&self, x: u32, y: u32) -> [u8; 3] {
        let i = (y as usize * self.width as usize + x as usize) * self.channels;
        [self.data[i], self.data[i + 1], self.data[i + 2]]
    }

    /// Pixels of the canvas (`w` x `h` at the top left) in a robot colour.
    pub fn robot_pixels(&self, w: u32, h: u32) -> usize {
        let mut n = 0;
        for y in 0..h.min(self.height) {
            for x in 0..w.min(self.width) {
                if is_robot(self.rgb(x, y)) {
                    n += 1;
                }
            }
        }
        n
    }
}

/// The page's robot colours (idle, stays, computing, moving; in space also by depth).
const ROBOT: [[u8; 3]; 4] = [
    [0x6b, 0x72, 0x80],
    [0x25, 0x63, 0xeb],
    [0xd9, 0x77, 0x06],
    [0xdc, 0x26, 0x26],
];

pub fn is_robot(c: [u8; 3]) -> bool {
    ROBOT
        .iter()
        .any(|r| r.iter().zip(&c).all(|(a, b)| a.abs_diff(*b) <= 6))
}
