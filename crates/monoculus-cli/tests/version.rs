//! One version, said everywhere: the workspace's, which `monoculus --version`,
//! `provenance.toml`, the Python package and the CHANGELOG say alike.

mod common;

use std::path::{Path, PathBuf};

use common::{ok, s, write_config};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `version = "..."` of a Cargo.toml's `[package]` or `[workspace.package]`.
fn version_in(manifest: &Path) -> String {
    let text = std::fs::read_to_string(manifest).unwrap();
    text.lines()
        .find_map(|l| l.strip_prefix("version = \""))
        .and_then(|v| v.strip_suffix('"'))
        .unwrap_or_else(|| panic!("{}: no version", manifest.display()))
        .to_string()
}

#[test]
fn every_place_says_the_workspace_version() {
    let version = version_in(&root().join("Cargo.toml"));
    assert_eq!(version, env!("CARGO_PKG_VERSION"));
    assert_eq!(version, "0.3.0");
    assert_eq!(ok(&["--version"]).trim(), format!("monoculus {version}"));
    // The Python package is built from its own crate, at the same version, and takes it
    // from there.
    assert_eq!(version_in(&root().join("python/Cargo.toml")), version);
    let pyproject = std::fs::read_to_string(root().join("python/pyproject.toml")).unwrap();
    assert!(pyproject.contains("dynamic = [\"version\"]"), "{pyproject}");
    // What changed in it, and what a user of the version before must change.
    let changes = std::fs::read_to_string(root().join("CHANGELOG.md")).unwrap();
    assert!(
        changes.contains(&format!("\n## {version} ")),
        "CHANGELOG names {version}"
    );
    assert!(changes.contains("### Upgrading from 0.2.0"));
    // The results say which version wrote them.
    let tmp = tempfile::tempdir().unwrap();
    let config = write_config(
        tmp.path(),
        "name = \"v\"\n[swarm]\nn = 5\ninit = \"square\"\n[algorithm]\nname = \"converge_locality\"\n",
    );
    let out = tmp.path().join("r");
    ok(&["run", s(&config), "--out", s(&out)]);
    let provenance = std::fs::read_to_string(out.join("provenance.toml")).unwrap();
    assert!(
        provenance.contains(&format!("monoculus_version = \"{version}\"")),
        "{provenance}"
    );
}
