//! The R-tree path and the angular sweep against the definition (brute force), on
//! random, lattice, collinear and co-located configurations.

mod common;

use monoculus_core::prelude::*;
use monoculus_core::vision::{visible_points_brute, visible_points_sweep_2d};

#[test]
fn sweep_and_rtree_match_the_definition() {
    for seed in 0..4 {
        for (name, pts) in common::zoo(seed) {
            let v = VisionParams::default();
            let indexed = monoculus_engine::IndexedSight::new(pts.clone(), v);
            let exact = ExactSight::new(pts.clone(), v);
            for i in 0..pts.len() {
                let brute = visible_points_brute(&pts, i, &v);
                assert_eq!(
                    visible_points_sweep_2d(&pts, i, &v),
                    brute,
                    "{name} seed {seed} robot {i}: sweep"
                );
                assert_eq!(
                    indexed.visible_points(i),
                    brute,
                    "{name} seed {seed} robot {i}: index full look"
                );
                for j in 0..pts.len() {
                    let expect = brute.contains(&j);
                    assert_eq!(
                        indexed.is_visible_point(i, j),
                        expect,
                        "{name} seed {seed}: {i} -> {j}"
                    );
                    assert_eq!(
                        exact.is_visible_point(i, j),
                        expect,
                        "{name} seed {seed}: {i} -> {j} exact"
                    );
                }
                let mut near_a = vec![];
                indexed.for_each_within(i, 2.0, &mut |k| near_a.push(k));
                let mut near_b = vec![];
                exact.for_each_within(i, 2.0, &mut |k| near_b.push(k));
                near_a.sort_unstable();
                assert_eq!(near_a, near_b, "{name}: radius query");
                for radius in [0.5, 2.0, 7.0] {
                    let mut a = vec![];
                    indexed.for_each_beyond(i, radius, &mut |k| a.push(k));
                    let mut b = vec![];
                    exact.for_each_beyond(i, radius, &mut |k| b.push(k));
                    a.sort_unstable();
                    assert_eq!(a, b, "{name}: robots beyond {radius}");
                }
                let (fa, fb) = (indexed.farthest(i), exact.farthest(i));
                assert!(
                    (fa - fb).abs() <= 1e-12 * fb.max(1.0),
                    "{name}: farthest {fa} vs {fb}"
                );
                let dist = |k: usize| pts[k].distance(pts[i]);
                let order: Vec<f64> = indexed.nearest_first(i).map(dist).collect();
                assert_eq!(order.len(), pts.len() - 1);
                assert!(
                    order.windows(2).all(|w| w[0] <= w[1]),
                    "{name}: nearest_first order"
                );
            }
        }
    }
}

#[test]
fn sweep_matches_rtree_on_larger_swarms() {
    let v = VisionParams::default();
    for (name, pts) in [
        ("random", common::square(2000, 40.0, 5)),
        (
            "lattice",
            monoculus_core::init::generate(
                &monoculus_core::init::InitShape::Lattice { side: 30.0 },
                900,
                0,
            ),
        ),
    ] {
        let indexed = monoculus_engine::IndexedSight::new(pts.clone(), v);
        for i in (0..pts.len()).step_by(97) {
            let sweep = visible_points_sweep_2d(&pts, i, &v);
            let by_tree: Vec<usize> = (0..pts.len())
                .filter(|&j| indexed.is_visible_point(i, j))
                .collect();
            assert_eq!(sweep, by_tree, "{name} robot {i}");
        }
    }
}

#[test]
fn hand_built_occlusion() {
    use glam::DVec2;
    let v = VisionParams::default();
    // 0 at the origin, 1 at (1,0) hides 2 at (3,0); 3 at (0,1) is seen; 4 co-located with 3.
    let pts = vec![
        DVec2::ZERO,
        DVec2::new(1.0, 0.0),
        DVec2::new(3.0, 0.0),
        DVec2::new(0.0, 1.0),
        DVec2::new(0.0, 1.0),
    ];
    let s = monoculus_engine::IndexedSight::new(pts.clone(), v);
    assert_eq!(s.visible_points(0), vec![1, 3]);
    assert!(!s.sees(0, 2));
    assert!(
        s.sees(0, 4) && !s.is_visible_point(0, 4),
        "co-located robots are one point, lowest index"
    );
    // A robot at the observer's own position is neither seen nor a blocker.
    let pts2 = vec![DVec2::ZERO, DVec2::ZERO, DVec2::new(2.0, 0.0)];
    let s2 = monoculus_engine::IndexedSight::new(pts2, v);
    assert_eq!(s2.visible_points(0), vec![2]);
    // Angles just above eps_ang do not block; just below do.
    let pts3 = vec![
        DVec2::ZERO,
        DVec2::new(1.0, 0.0),
        DVec2::new(2.0, 2.0 * 2e-9),
        DVec2::new(2.0, -2.0 * 0.5e-9),
    ];
    let s3 = monoculus_engine::IndexedSight::new(pts3, v);
    assert!(s3.sees(0, 2));
    assert!(!s3.sees(0, 3));
}
