//! `monoculus impossibility`: the two configurations robot 0 cannot tell apart by
//! directions, and every one of its moves leaving the hull of one of them.

mod common;

use common::{monoculus, ok};

#[test]
fn every_move_leaves_a_hull_unless_the_near_robots_are_too_far() {
    let tmp = tempfile::tempdir().unwrap();
    let out = ok(&[
        "impossibility",
        "--moves",
        "72",
        "--out",
        tmp.path().to_str().unwrap(),
    ]);
    assert!(out.contains("in the same directions in both: yes"), "{out}");
    assert!(out.contains("every point is near in the near configuration and far in the far one"));
    assert!(out.contains("leaves the hull of one of them: yes"), "{out}");
    // 72 rows; the moves into the cone of the others (20 to 80 degrees) stay in the far
    // hull, and only they.
    let rows: Vec<&str> = out.lines().filter(|l| l.ends_with(",false")).collect();
    assert!(!rows.is_empty());
    for row in rows {
        let angle: f64 = row.split(',').next().unwrap().parse().unwrap();
        assert!((20.0..=80.0).contains(&angle), "{row}");
    }
    assert!(tmp.path().join("impossibility.png").is_file());
    assert!(tmp.path().join("impossibility.svg").is_file());
    // With the near robots at more than b / 2 a move into their cone can stay inside
    // both hulls: the construction needs 2 * near < b.
    let out = ok(&["impossibility", "--near", "3", "--moves", "72"]);
    assert!(out.contains("leaves the hull of one of them: no"), "{out}");
}

#[test]
fn bad_arguments_are_named() {
    for (args, expected) in [
        (vec!["--near", "0"], "--near 0: must be positive"),
        (vec!["--step", "inf"], "--step inf: must be positive"),
        (vec!["--moves", "0"], "--moves 0: between 1 and 100000"),
    ] {
        let mut all = vec!["impossibility"];
        all.extend(args);
        let out = monoculus(&all);
        assert_eq!(out.status.code(), Some(2));
        let e = String::from_utf8_lossy(&out.stderr);
        assert!(e.contains(expected), "{e}");
    }
}
