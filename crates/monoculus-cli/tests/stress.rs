//! `monoculus stress`: the throughput report and its last line.

mod common;

use common::monoculus;

#[test]
fn stress_reports_rounds_memory_and_throughput_last() {
    for algorithm in ["converge_locality", "converge_quadrant"] {
        let out = monoculus(&[
            "stress",
            "--n",
            "2000",
            "--rounds",
            "2",
            "--algorithm",
            algorithm,
            "--threads",
            "2",
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8(out.stdout).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert!(
            lines[0].starts_with("round 1: ") && lines[1].starts_with("round 2: "),
            "{text}"
        );
        let last = lines.last().unwrap();
        let rate: f64 = last
            .strip_prefix("activations_per_s=")
            .expect("last line")
            .parse()
            .unwrap();
        // The rate is the activations (2 rounds of 2000) over the total the report gives.
        let total: f64 = text
            .split("total_s=")
            .nth(1)
            .and_then(|s| s.split_whitespace().next())
            .and_then(|s| s.parse().ok())
            .expect("total_s=");
        // total_s is printed to the millisecond.
        let (lo, hi) = (
            4000.0 / (total + 0.0005),
            4000.0 / (total - 0.0005).max(1e-9),
        );
        assert!(
            lo - 1.0 <= rate && rate <= hi + 1.0,
            "{rate} outside [{lo}, {hi}]: {text}"
        );
        assert!(
            text.contains("2000 activations"),
            "FSYNC activates everybody: {text}"
        );
    }
    let lattice = monoculus(&["stress", "--n", "900", "--rounds", "1", "--init", "lattice"]);
    assert!(lattice.status.success());
}

#[test]
fn stress_measures_async_epochs() {
    let tmp = tempfile::tempdir().unwrap();
    let csv = tmp.path().join("s.csv");
    let out = monoculus(&[
        "stress",
        "--n",
        "300",
        "--rounds",
        "2",
        "--scheduler",
        "async",
        "--idle",
        "uniform:1:20",
        "--move",
        "exp:8",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let epochs: Vec<&str> = text.lines().filter(|l| l.starts_with("epoch ")).collect();
    assert_eq!(epochs.len(), 2, "{text}");
    // In an epoch every robot completes a cycle: at least one Look each.
    for e in &epochs {
        let looks: u64 = e
            .split(", ")
            .nth(1)
            .unwrap()
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert!(looks >= 300, "{e}");
    }
    let mut r = csv::Reader::from_path(&csv).unwrap();
    let h = r.headers().unwrap().clone();
    let row = r.records().next().unwrap().unwrap();
    let col = |name: &str| &row[h.iter().position(|c| c == name).unwrap()];
    assert_eq!(col("scheduler"), "async");
    assert_eq!(
        col("timing"),
        "idle=uniform:1:20 compute=uniform:1:5 move=exp:8 start=random"
    );
    assert_eq!(col("rounds"), "2");
}

#[test]
fn stress_rejects_bad_arguments() {
    for args in [
        &["stress", "--n", "0", "--rounds", "1"][..],
        &[
            "stress",
            "--n",
            "10",
            "--rounds",
            "1",
            "--algorithm",
            "teleport",
        ][..],
        &["stress", "--n", "10"][..],
        &["stress", "--n", "10", "--rounds", "1", "--move", "exp:4"][..],
        &[
            "stress",
            "--n",
            "10",
            "--rounds",
            "1",
            "--scheduler",
            "async",
            "--idle",
            "uniform:5:2",
        ][..],
    ] {
        let out = monoculus(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(!String::from_utf8_lossy(&out.stderr).contains("panicked"));
    }
}
