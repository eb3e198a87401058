//! The indexed path (band grid in the plane, R-tree in space) and the angular sweep against the definition (brute force), on
//! random, lattice, collinear and co-located configurations.

mod common;

use monoculus_core::prelude::*;
use monoculus_core::vision::{blocks, sees_brute, visible_points_brute, visible_points_sweep_2d};

#[test]
fn sweep_and_index_match_the_definition() {
    for seed in 0..4 {
        for (name, pts) in common::zoo(seed) {
            // The crowded core is held in finer nested parts of the grid.
            let parts = monoculus_engine::index::SegmentGrid::new(&pts).parts();
            assert_eq!(parts > 1, name == "core", "{name}: {parts} parts");
            let indexed = monoculus_engine::IndexedSight::new(pts.clone(), VisionParams::default());
            agrees_with_the_definition(&format!("{name} seed {seed}"), &indexed, &pts);
        }
    }
}

/// Every query of `indexed` (over `pts`) against the definition and the brute-force
/// sight.
fn agrees_with_the_definition<S: Sight<glam::DVec2>>(name: &str, indexed: &S, pts: &[glam::DVec2]) {
    let v = VisionParams::default();
    let exact = ExactSight::new(pts.to_vec(), v);
    for i in 0..pts.len() {
        let brute = visible_points_brute(pts, i, &v);
        assert_eq!(
            visible_points_sweep_2d(pts, i, &v),
            brute,
            "{name} robot {i}: sweep"
        );
        assert_eq!(
            indexed.visible_points(i),
            brute,
            "{name} robot {i}: index full look"
        );
        for j in 0..pts.len() {
            let expect = brute.contains(&j);
            assert_eq!(indexed.is_visible_point(i, j), expect, "{name}: {i} -> {j}");
            assert_eq!(
                exact.is_visible_point(i, j),
                expect,
                "{name}: {i} -> {j} exact"
            );
        }
        let mut near_a = vec![];
        indexed.for_each_within(i, 2.0, &mut |k| near_a.push(k));
        let mut near_b = vec![];
        exact.for_each_within(i, 2.0, &mut |k| near_b.push(k));
        near_a.sort_unstable();
        assert_eq!(near_a, near_b, "{name}: radius query");
        // Radii at which robots sit exactly on the boundary (inclusive), none, and the
        // co-location tolerance: the grid's filter on its stored coordinates must keep
        // every robot the exact test keeps.
        let on_boundary = (0..pts.len()).step_by(7).map(|k| pts[k].distance(pts[i]));
        for radius in on_boundary.chain([0.0, v.eps_pos, 0.03]) {
            let (mut a, mut b) = (vec![], vec![]);
            indexed.for_each_within(i, radius, &mut |k| a.push(k));
            exact.for_each_within(i, radius, &mut |k| b.push(k));
            a.sort_unstable();
            assert_eq!(a, b, "{name}: robots within {radius} of {i}");
        }
        let mut found = monoculus_core::vision::Near::new();
        indexed.neighbours(i, &mut found);
        let mut near = found.as_slice().to_vec();
        assert!(near.len() <= 32, "{name}: a few neighbours");
        near.sort_unstable();
        near.dedup();
        assert!(
            near.iter().all(|&k| k != i && k < pts.len()),
            "{name}: neighbours"
        );
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

/// A sight taken after a few robots moved keeps the previous grid and marks them stale:
/// its answers are still the definition's, with robots moved onto others, between two
/// others (blocking them) and back, over several generations; a move out of the grid's
/// box gives a fresh grid.
#[test]
fn a_sight_after_a_few_moves_answers_as_a_fresh_one() {
    use monoculus_engine::IndexedSight;
    let v = VisionParams::default();
    for seed in 0..2 {
        for (name, mut pts) in common::zoo(seed) {
            let mut sight = IndexedSight::new(pts.clone(), v);
            sight.sees(0, 1); // builds the grid
            let moves: [&[(usize, usize, usize)]; 2] = [
                &[(1, 2, 2), (3, 4, 5), (5, 0, 6)],
                &[(3, 3, 3), (7, 8, 8), (1, 9, 10)],
            ];
            for (generation, step) in moves.iter().enumerate() {
                for &(k, a, b) in step.iter() {
                    pts[k] = (pts[a] + pts[b]) * 0.5;
                }
                sight = IndexedSight::after(sight, pts.clone(), v);
                assert!(sight.stale_robots() > 0, "{name}: the grid is kept");
                agrees_with_the_definition(
                    &format!("{name} seed {seed} generation {generation}"),
                    &sight,
                    &pts,
                );
            }
            pts[0] += glam::DVec2::splat(100.0);
            sight = IndexedSight::after(sight, pts.clone(), v);
            assert_eq!(sight.stale_robots(), 0, "{name}: a fresh grid");
            agrees_with_the_definition(&format!("{name} seed {seed} moved out"), &sight, &pts);
        }
    }
}

#[test]
fn sweep_matches_the_index_on_larger_swarms() {
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

/// Limited visibility (SPEC 9.2): the definition sees exactly the unlimited view within
/// the range (a blocker is nearer than what it hides), and the sweep and the index agree
/// with it, on every configuration of the zoo and for ranges that cut through it.
#[test]
fn a_limited_range_sees_the_unlimited_view_within_it() {
    for seed in 0..2 {
        for (name, pts) in common::zoo(seed) {
            for range in [0.7, 2.1, 3.5, 6.0] {
                let v = VisionParams {
                    range,
                    ..VisionParams::default()
                };
                let unlimited = ExactSight::new(pts.clone(), VisionParams::default());
                let exact = ExactSight::new(pts.clone(), v);
                let indexed = monoculus_engine::IndexedSight::new(pts.clone(), v);
                for i in 0..pts.len() {
                    let brute = visible_points_brute(&pts, i, &v);
                    let within: Vec<usize> = unlimited
                        .visible_points(i)
                        .into_iter()
                        .filter(|&j| pts[j].distance(pts[i]) <= range)
                        .collect();
                    // Co-located robots straddling the range are one point: compare seen
                    // robots, then the points.
                    for j in 0..pts.len() {
                        let expect = unlimited.sees(i, j) && pts[j].distance(pts[i]) <= range;
                        assert_eq!(exact.sees(i, j), expect, "{name} V={range}: {i} -> {j}");
                        assert_eq!(
                            indexed.sees(i, j),
                            expect,
                            "{name} V={range}: {i} -> {j} index"
                        );
                        assert_eq!(
                            indexed.is_visible_point(i, j),
                            brute.contains(&j),
                            "{name} V={range}: {i} -> {j} point"
                        );
                    }
                    assert_eq!(brute, within, "{name} V={range} robot {i}");
                    assert_eq!(visible_points_sweep_2d(&pts, i, &v), brute, "{name} sweep");
                    assert_eq!(indexed.visible_points(i), brute, "{name} index");
                }
            }
        }
    }
}

#[test]
fn a_limited_range_in_space_matches_the_definition() {
    use glam::DVec3;
    let mut s = Stream::new(3, 98, 0, 0);
    let random: Vec<DVec3> = (0..80)
        .map(|_| DVec3::new(s.uniform(), s.uniform(), s.uniform()) * 6.0)
        .collect();
    let lattice: Vec<DVec3> = (0..64)
        .map(|k| DVec3::new((k % 4) as f64, ((k / 4) % 4) as f64, (k / 16) as f64))
        .collect();
    for (name, pts) in [("random", random), ("lattice", lattice)] {
        for range in [1.0, 1.5, 3.0] {
            let v = VisionParams {
                range,
                ..VisionParams::default()
            };
            let indexed = monoculus_engine::IndexedSight::new(pts.clone(), v);
            for i in 0..pts.len() {
                assert_eq!(
                    indexed.visible_points(i),
                    visible_points_brute(&pts, i, &v),
                    "{name} V={range} robot {i}"
                );
            }
        }
    }
}

/// The R-tree over the plane answers every question as the definition does.
#[test]
fn an_rtree_in_the_plane_matches_the_definition() {
    use monoculus_engine::SpaceIndex;
    for seed in 0..2 {
        for (name, pts) in common::zoo(seed) {
            let tree: monoculus_engine::IndexedSight<glam::DVec2, SpaceIndex<glam::DVec2>> =
                monoculus_engine::IndexedSight::with_index(pts.clone(), VisionParams::default());
            let v = VisionParams::default();
            let exact = ExactSight::new(pts.clone(), v);
            for i in 0..pts.len() {
                let brute = visible_points_brute(&pts, i, &v);
                assert_eq!(
                    tree.visible_points(i),
                    brute,
                    "{name} seed {seed} robot {i}"
                );
                for j in 0..pts.len() {
                    assert_eq!(
                        tree.is_visible_point(i, j),
                        brute.contains(&j),
                        "{name}: {i} -> {j}"
                    );
                }
                for radius in [0.5, 2.0, 7.0] {
                    let (mut a, mut b) = (vec![], vec![]);
                    tree.for_each_beyond(i, radius, &mut |k| a.push(k));
                    exact.for_each_beyond(i, radius, &mut |k| b.push(k));
                    a.sort_unstable();
                    assert_eq!(a, b, "{name}: beyond {radius}");
                    let (mut a, mut b) = (vec![], vec![]);
                    tree.for_each_within(i, radius, &mut |k| a.push(k));
                    exact.for_each_within(i, radius, &mut |k| b.push(k));
                    a.sort_unstable();
                    assert_eq!(a, b, "{name}: within {radius}");
                }
            }
        }
    }
}

/// Fat robots (SPEC 9.3): a robot hides what lies behind it within its radius.
#[test]
fn a_fat_robot_hides_what_passes_within_its_radius() {
    use glam::DVec2;
    let v = VisionParams {
        robot_radius: 0.5,
        ..VisionParams::default()
    };
    let p = DVec2::ZERO;
    let q = DVec2::new(4.0, 0.0);
    // Beside the segment's middle: within the radius it blocks, beyond it does not.
    assert!(blocks(p, DVec2::new(2.0, 0.49), q, &v));
    assert!(!blocks(p, DVec2::new(2.0, 0.51), q, &v));
    assert!(!blocks(
        p,
        DVec2::new(2.0, 0.49),
        q,
        &VisionParams::default()
    ));
    // Only robots nearer than q block it: one beside q but beyond it does not.
    assert!(!blocks(p, DVec2::new(4.2, 0.3), q, &v));
    assert!(blocks(p, DVec2::new(3.9, 0.3), q, &v));
    // A robot at the observer's own position is excepted.
    assert!(!blocks(p, DVec2::new(1e-10, 0.0), q, &v));
}

/// The index (in the plane and in space, and the R-tree in the plane) sees fat robots
/// as the definition does, on every configuration of the zoo.
#[test]
fn fat_robots_are_seen_as_the_definition_says() {
    use glam::{DVec2, DVec3};
    use monoculus_engine::{IndexedSight, SpaceIndex};
    for seed in 0..2 {
        for (name, pts) in common::zoo(seed) {
            for radius in [0.02, 0.15, 0.6] {
                let v = VisionParams {
                    robot_radius: radius,
                    ..VisionParams::default()
                };
                let grid = IndexedSight::new(pts.clone(), v);
                let tree: IndexedSight<DVec2, SpaceIndex<DVec2>> =
                    IndexedSight::with_index(pts.clone(), v);
                for i in 0..pts.len() {
                    let brute = visible_points_brute(&pts, i, &v);
                    assert_eq!(grid.visible_points(i), brute, "{name} r={radius} {i}");
                    assert_eq!(tree.visible_points(i), brute, "{name} r={radius} {i} tree");
                    for j in 0..pts.len() {
                        let want = sees_brute(&pts, i, j, &v);
                        assert_eq!(tree.sees(i, j), want, "{name} r={radius} {i}->{j}");
                    }
                }
            }
        }
    }
    let mut s = Stream::new(5, 98, 0, 0);
    let random: Vec<DVec3> = (0..70)
        .map(|_| DVec3::new(s.uniform(), s.uniform(), s.uniform()) * 6.0)
        .collect();
    let lattice: Vec<DVec3> = (0..64)
        .map(|k| DVec3::new((k % 4) as f64, ((k / 4) % 4) as f64, (k / 16) as f64))
        .collect();
    let line: Vec<DVec3> = (0..30).map(|k| DVec3::splat(k as f64 * 0.3)).collect();
    for (name, pts) in [("random", random), ("lattice", lattice), ("line", line)] {
        for radius in [0.1, 0.4] {
            let v = VisionParams {
                robot_radius: radius,
                ..VisionParams::default()
            };
            let indexed = IndexedSight::new(pts.clone(), v);
            for i in 0..pts.len() {
                assert_eq!(
                    indexed.visible_points(i),
                    visible_points_brute(&pts, i, &v),
                    "{name} r={radius} robot {i}"
                );
            }
        }
    }
}

/// A moving index (the one ASYNC's Looks see through) with robots in mid-move along
/// segments, each given the disc around its segment: its answers are the definition's
/// at the start, the middle and the end of the moves, on every configuration of the zoo,
/// with short moves (within the limit: the queries widen by the drift, the line filter
/// tests each disc), long ones (stale: onto others, between others, out of the grid's
/// box), and robots that arrived (a point again, away from where the grid holds them).
/// Each index but the first is made in the memory of the one before, done with (its
/// robots followed, some stale, some asked whether they are alone), as ASYNC makes it.
#[test]
fn a_moving_sight_answers_as_a_fresh_one_with_robots_in_mid_move() {
    use glam::DVec2;
    use monoculus_engine::SpatialIndex;
    use monoculus_engine::asynchrony::TickSight;
    use monoculus_engine::index::PlaneIndex;
    let v = VisionParams::default();
    let disc = |from: DVec2, to: DVec2| {
        let scale = from.abs().max(to.abs()).max_element();
        let reach = 0.5 * (to - from).length() * (1.0 + 1e-12) + 16.0 * f64::EPSILON * scale;
        ((from + to) * 0.5, reach)
    };
    // With and without nested parts over a crowded core (an index for one tick has
    // them; it is asked to follow robots here all the same).
    let mut spare: Option<PlaneIndex> = None;
    for (seed, one_tick) in [(0, false), (1, false), (0, true)] {
        for (name, pts) in common::zoo(seed) {
            let n = pts.len();
            let mut index = match spare.take() {
                Some(old) => old
                    .moving_again(|base| base.extend_from_slice(&pts), one_tick)
                    .unwrap(),
                None => PlaneIndex::moving(pts.clone(), one_tick).unwrap(),
            };
            assert_eq!(index.stale_robots(), 0, "{name}: made again, none is stale");
            let bin = index.bin_size();
            index.allow(2.0 * bin);
            let (lo, hi) = monoculus_core::metrics::bounds(&pts);
            let mut moves = Vec::new();
            for k in (0..n).filter(|k| k % 3 == 0) {
                let (from, target) = (pts[k], pts[(k * 7 + 3) % n]);
                let to = match k % 4 {
                    // Short: within the limit.
                    0 => from + (target - from).clamp_length_max(1.5 * bin),
                    // A hair: the drift is tiny.
                    1 => from + (target - from).clamp_length_max(1e-9 * bin),
                    // Onto another robot, or between two: stale unless near.
                    2 => target,
                    _ => (target + pts[(k * 5 + 1) % n]) * 0.5,
                };
                // Out of the grid's box.
                let to = if k == 3 {
                    hi + (hi - lo) + DVec2::ONE
                } else {
                    to
                };
                let (centre, reach) = disc(from, to);
                index.follow(k, centre, reach);
                moves.push((k, from, to));
            }
            let at = |f: f64| {
                let mut now = pts.clone();
                for &(k, from, to) in &moves {
                    now[k] = from + (to - from) * f;
                }
                now
            };
            for f in [0.0, 0.37, 1.0] {
                let now = at(f);
                let sight = TickSight::over(&now, &index, v);
                agrees_with_the_definition(
                    &format!("{name} seed {seed} ({one_tick}) at {f}"),
                    &sight,
                    &now,
                );
            }
            // The robots arrived: each a point again, exactly where its move ended (as
            // the engine settles it, not where the interpolation at the last tick puts it).
            let mut now = at(1.0);
            for &(k, _, to) in &moves {
                index.follow(k, to, 0.0);
                now[k] = to;
            }
            let sight = TickSight::over(&now, &index, v);
            agrees_with_the_definition(&format!("{name} seed {seed} arrived"), &sight, &now);
            assert!(index.stale_robots() > 0, "{name}: some moves were too long");
            spare = Some(index);
        }
    }
}

/// A moving index made again in the memory of one whose robots were all alone does not
/// keep that answer: robots now sharing a point are not alone.
#[test]
fn a_moving_index_made_again_forgets_who_was_alone() {
    use glam::DVec2;
    use monoculus_engine::SpatialIndex;
    use monoculus_engine::index::PlaneIndex;
    let v = VisionParams::default();
    let apart: Vec<DVec2> = (0..64)
        .map(|k| DVec2::new((k % 8) as f64, (k / 8) as f64))
        .collect();
    let index = PlaneIndex::moving(apart.clone(), false).unwrap();
    assert!((0..64).all(|k| index.alone(apart.as_slice(), &v, k)));
    // Robot 2k + 1 on robot 2k.
    let pairs: Vec<DVec2> = (0..64).map(|k| apart[k & !1]).collect();
    let again = index
        .moving_again(|base| base.extend_from_slice(&pairs), false)
        .unwrap();
    for k in 0..64 {
        assert!(
            !again.alone(pairs.as_slice(), &v, k),
            "robot {k} shares its point"
        );
    }
}

/// A sight over at most `FEW_ROBOTS` robots is answered robot by robot, without the
/// grid: every query as the definition says, on the first few robots of every
/// configuration of the zoo (lattice, collinear, co-located among them), and a
/// sight after a few moves too.
#[test]
fn few_robots_are_answered_as_the_definition_says() {
    use monoculus_engine::IndexedSight;
    use monoculus_engine::index::FEW_ROBOTS;
    let v = VisionParams::default();
    for (name, pts) in common::zoo(0) {
        for n in [2, 3, 7, 12, FEW_ROBOTS] {
            let mut few = pts[..n].to_vec();
            let sight = IndexedSight::new(few.clone(), v);
            agrees_with_the_definition(&format!("{name} first {n}"), &sight, &few);
            few[1] = (few[0] + few[n - 1]) * 0.5;
            let sight = IndexedSight::after(sight, few.clone(), v);
            agrees_with_the_definition(&format!("{name} first {n} moved"), &sight, &few);
        }
    }
}

/// The filter that spares the exact test lets every blocker through, up to the widest
/// angular tolerance it is used with: robots on rays just inside and just outside
/// each tolerance, nearer and farther than the robot looked at, and behind the observer.
#[test]
fn few_robots_block_within_the_angular_tolerance() {
    use monoculus_engine::IndexedSight;
    let rotate = |a: f64, r: f64| glam::DVec2::new(a.cos(), a.sin()) * r;
    for eps_ang in [1e-9, 1e-3, 0.1, 0.3, 0.49] {
        let v = VisionParams {
            eps_ang,
            ..VisionParams::default()
        };
        let mut pts = vec![glam::DVec2::new(0.25, -0.5)];
        let o = pts[0];
        for &(angle, r) in &[(0.0, 4.0), (0.0, 8.0), (std::f64::consts::PI, 2.0)] {
            pts.push(o + rotate(angle, r));
        }
        for f in [0.98, 1.02, 1.5] {
            for r in [1.0, 6.0] {
                pts.push(o + rotate(f * eps_ang, r));
                pts.push(o + rotate(-f * eps_ang, r * 1.1));
            }
        }
        let n = pts.len();
        assert!(n <= monoculus_engine::index::FEW_ROBOTS);
        let sight = IndexedSight::new(pts.clone(), v);
        let mut blocked = 0;
        for i in 0..n {
            for j in 0..n {
                let expect = sees_brute(&pts, i, j, &v);
                assert_eq!(sight.sees(i, j), expect, "eps_ang {eps_ang}: {i} -> {j}");
                blocked += usize::from(i != j && !expect);
            }
        }
        assert!(blocked > n, "eps_ang {eps_ang}: robots hide others");
    }
}
