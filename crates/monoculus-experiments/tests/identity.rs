//! Every column of `runs.csv` that version 0.2.0 wrote, but `wall_ms` and
//! `config_hash`, is what it wrote, bit for bit (`converged` included: the verdicts of
//! 0.3, a goal per algorithm, give the paper's algorithms the same verdicts), for every config of the paper's experiments and their extensions
//! (`tests/identity/`: four seeds a cell, see its README).

use std::path::{Path, PathBuf};

use monoculus_experiments::{Experiment, run_experiment};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The rows of a CSV without `wall_ms` and `config_hash`, header first.
fn rows(path: &Path) -> Vec<Vec<String>> {
    let mut r = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_path(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let all: Vec<Vec<String>> = r
        .records()
        .map(|x| x.unwrap().iter().map(String::from).collect())
        .collect();
    let keep: Vec<usize> = (0..all[0].len())
        .filter(|&i| !matches!(all[0][i].as_str(), "wall_ms" | "config_hash"))
        .collect();
    all.iter()
        .map(|row| keep.iter().map(|&i| row[i].clone()).collect())
        .collect()
}

#[test]
fn every_config_gives_the_results_of_0_2_0() {
    let refs = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/identity");
    let tmp = tempfile::tempdir().unwrap();
    let mut names: Vec<String> = std::fs::read_dir(&refs)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".csv"))
        .collect();
    names.sort();
    assert_eq!(names.len(), 22, "{names:?}");
    for name in names {
        let (dir, config) = name
            .trim_end_matches(".csv")
            .split_once("__")
            .expect("DIR__NAME.csv");
        let path = root()
            .join("configs")
            .join(dir)
            .join(format!("{config}.toml"));
        let exp = Experiment::load(
            &path,
            &["seeds=4".to_string()],
            &monoculus_experiments::Registry::builtin(),
        )
        .unwrap();
        let out = tmp.path().join(&name);
        run_experiment(&exp, &out, Default::default(), &()).unwrap();
        let (got, want) = (rows(&out.join("runs.csv")), rows(&refs.join(&name)));
        // Every column 0.2.0 wrote, found by name (later versions add columns).
        let at: Vec<usize> = want[0]
            .iter()
            .map(|c| {
                got[0]
                    .iter()
                    .position(|g| g == c)
                    .unwrap_or_else(|| panic!("{name}: no column {c}"))
            })
            .collect();
        assert_eq!(got.len(), want.len(), "{name}: the rows");
        for (k, (g, w)) in got.iter().zip(&want).enumerate().skip(1) {
            let differ: Vec<String> = (0..w.len())
                .filter(|&c| g[at[c]] != w[c])
                .map(|c| format!("{}: {} (0.2.0: {})", want[0][c], g[at[c]], w[c]))
                .collect();
            assert!(differ.is_empty(), "{name} row {k}: {}", differ.join(", "));
        }
    }
}
