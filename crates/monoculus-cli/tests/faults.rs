//! `[faults]` from the command line: runs.csv says how many robots were faulty, and no
//! faulty robot is the run without faults.

mod common;

use common::{csv_rows_without, ok};

const BASE: &str = r#"
name = "faults"
seeds = 3

[swarm]
n = 20
init = "square"
side = 8.0

[algorithm]
name = "converge_locality"
"#;

#[test]
fn runs_csv_counts_the_faulty_robots() {
    let tmp = tempfile::tempdir().unwrap();
    let (plain, faulty) = (
        tmp.path().join("plain.toml"),
        tmp.path().join("faulty.toml"),
    );
    std::fs::write(&plain, BASE).unwrap();
    std::fs::write(
        &faulty,
        format!("{BASE}\n[faults]\nkind = \"crash\"\ncount = [0, 3]\nat = \"random\"\nuntil = 4\n"),
    )
    .unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    ok(&["run", plain.to_str().unwrap(), "--out", a.to_str().unwrap()]);
    ok(&[
        "run",
        faulty.to_str().unwrap(),
        "--out",
        b.to_str().unwrap(),
    ]);
    let header = |dir: &std::path::Path| -> Vec<String> {
        csv::Reader::from_path(dir.join("runs.csv"))
            .unwrap()
            .headers()
            .unwrap()
            .iter()
            .map(String::from)
            .collect()
    };
    let h = header(&b);
    let faulty_col = h.iter().position(|c| c == "faulty").unwrap();
    let count_col = h.iter().position(|c| c == "faults.count").unwrap();
    let drop = ["cell", "faults.count", "wall_ms", "config_hash", "name"];
    let rows_b = csv_rows_without(&b.join("runs.csv"), &[]);
    let mut zero = Vec::new();
    for row in &rows_b {
        assert_eq!(row[faulty_col], row[count_col]);
    }
    for (row, kept) in rows_b
        .iter()
        .zip(csv_rows_without(&b.join("runs.csv"), &drop))
    {
        if row[count_col] == "0" {
            zero.push(kept);
        }
    }
    assert_eq!(zero.len(), 3);
    assert_eq!(csv_rows_without(&a.join("runs.csv"), &drop), zero);
    assert!(header(&a).contains(&"faulty".to_string()));
}

#[test]
fn faults_run_under_async_too() {
    let tmp = tempfile::tempdir().unwrap();
    let cfg = tmp.path().join("a.toml");
    std::fs::write(
        &cfg,
        format!(
            "{BASE}\n[scheduler]\nkind = \"async\"\nidle = {{ kind = \"uniform\", min = 1, max = 4 }}\n\n[faults]\nkind = \"crash\"\ncount = 2\nat = 1\n"
        ),
    )
    .unwrap();
    let out = tmp.path().join("r");
    ok(&["run", cfg.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let mut r = csv::Reader::from_path(out.join("runs.csv")).unwrap();
    let h = r.headers().unwrap().clone();
    let col = h.iter().position(|c| c == "faulty").unwrap();
    let ticks = h.iter().position(|c| c == "ticks").unwrap();
    for row in r.records() {
        let row = row.unwrap();
        assert_eq!(&row[col], "2");
        assert!(!row[ticks].is_empty());
    }
}
