//! The guide's crate builds as a user writes it: a crate made of the `Cargo.toml`,
//! `src/lib.rs` and `src/main.rs` that docs/algorithms.md shows (monoculus from this
//! checkout), with every other block of code of that page and of docs/state-and-lights.md
//! as a test of it, is built and tested by cargo, offline, outside the workspace. A
//! block that needs a crate the page's `Cargo.toml` does not list fails here.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .unwrap()
}

/// The fenced blocks of a Markdown page: (info string, text, the text since the block
/// before).
fn blocks(page: &str) -> Vec<(String, String, String)> {
    let mut out = Vec::new();
    let mut lines = page.lines();
    let mut before = String::new();
    while let Some(line) = lines.next() {
        if let Some(info) = line.strip_prefix("```") {
            let mut text = String::new();
            for l in lines.by_ref() {
                if l.starts_with("```") {
                    break;
                }
                text.push_str(l);
                text.push('\n');
            }
            out.push((info.to_string(), text, std::mem::take(&mut before)));
        } else {
            before.push_str(line);
            before.push('\n');
        }
    }
    out
}

/// A rustdoc block as source: its hidden lines (`# ...`) shown.
fn shown(text: &str) -> String {
    text.lines()
        .map(|l| {
            if l == "#" {
                ""
            } else if let Some(rest) = l.strip_prefix("# ") {
                rest
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// A rustdoc block as a file: its hidden lines left out.
fn visible(text: &str) -> String {
    text.lines()
        .filter(|l| *l != "#" && !l.starts_with("# "))
        .map(|l| format!("{l}\n"))
        .collect()
}

fn is_rust(info: &str) -> bool {
    info == "rust" || info.starts_with("rust,")
}

#[test]
fn the_guides_crate_builds_and_runs_as_written() {
    let root = root();
    let guide = std::fs::read_to_string(root.join("docs/algorithms.md")).unwrap();
    let state = std::fs::read_to_string(root.join("docs/state-and-lights.md")).unwrap();
    let guide_blocks = blocks(&guide);

    let pick = |file: &str, info: fn(&str) -> bool| {
        guide_blocks
            .iter()
            .position(|(i, _, before)| info(i) && before.contains(&format!("`{file}`")))
            .unwrap_or_else(|| panic!("docs/algorithms.md shows no {file}"))
    };
    let manifest_at = pick("Cargo.toml", |i| i == "toml");
    let lib_at = pick("src/lib.rs", is_rust);
    let main_at = pick("src/main.rs", is_rust);

    let checkout_path = "../monoculus/crates/monoculus";
    let manifest = &guide_blocks[manifest_at].1;
    assert!(
        manifest.contains(checkout_path),
        "the page's Cargo.toml names monoculus at {checkout_path}"
    );
    let manifest = manifest.replace(
        checkout_path,
        &root.join("crates/monoculus").display().to_string(),
    );

    let dir = tempfile::tempdir().unwrap();
    let krate = dir.path().join("toward-anyone");
    std::fs::create_dir_all(krate.join("src")).unwrap();
    std::fs::create_dir_all(krate.join("tests")).unwrap();
    std::fs::write(krate.join("Cargo.toml"), manifest).unwrap();
    // The workspace's versions of every dependency, so that cargo resolves offline.
    std::fs::copy(root.join("Cargo.lock"), krate.join("Cargo.lock")).unwrap();
    std::fs::write(krate.join("src/lib.rs"), visible(&guide_blocks[lib_at].1)).unwrap();
    std::fs::write(krate.join("src/main.rs"), visible(&guide_blocks[main_at].1)).unwrap();

    // Every other block of Rust on both pages, as a test of the crate.
    let mut tests = String::new();
    let mut count = 0;
    let mut run = 0;
    let others = guide_blocks
        .iter()
        .enumerate()
        .filter(|(k, _)| *k != lib_at && *k != main_at)
        .map(|(_, b)| b.clone())
        .chain(blocks(&state));
    for (info, text, _) in others {
        if !is_rust(&info) {
            continue;
        }
        count += 1;
        let body = shown(&text);
        if info.contains("no_run") {
            tests.push_str(&format!(
                "#[allow(dead_code, reason = \"a block the page does not run\")]\nfn block_{count}() {{\n{body}\n}}\n\n"
            ));
        } else {
            run += 1;
            tests.push_str(&format!("#[test]\nfn block_{count}() {{\n{body}\n}}\n\n"));
        }
    }
    assert!(count >= 6, "only {count} blocks of Rust found");
    std::fs::write(krate.join("tests/guide.rs"), tests).unwrap();

    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .args(["test", "--offline", "--quiet"])
        .current_dir(&krate)
        // Its own target folder (the workspace's is locked while its tests run), kept
        // between runs; no debug info, as the workspace's test builds.
        .env("CARGO_TARGET_DIR", root.join("target/guide-crate"))
        .env("CARGO_PROFILE_DEV_DEBUG", "false")
        .env("CARGO_INCREMENTAL", "0")
        .env_remove("RUSTFLAGS")
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "the guide's crate does not build or its blocks fail:\n{}\n{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    // Every block that runs ran: the passes of the test binaries add up.
    let stdout = String::from_utf8_lossy(&output.stdout);
    let passed: usize = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("test result: ok. "))
        .filter_map(|l| l.split(' ').next()?.parse::<usize>().ok())
        .sum();
    assert!(
        passed >= run,
        "{passed} tests passed of {run} blocks:\n{stdout}"
    );
}
