//! Lines of sight, radius queries and the single-precision filter against the
//! definition.

use super::*;

/// Blockers at the edge of the blocking cone, on lines of every slope through a
/// corner of the bins they are walked in (so a blocker sits across a band edge and
/// a bin edge from where the line enters the band), in every part of a crowded
/// grid: the walk must find them all.
#[test]
fn blockers_at_the_cone_edge_next_to_bin_corners() {
    for (swarm, seed) in [
        (pinned_square as fn(&mut Stream) -> _, 7),
        (crowded_square, 8),
    ] {
        let v = VisionParams::default();
        let mut rng = Stream::new(seed, 0, 0, 0);
        let mut pts = swarm(&mut rng);
        let like = SegmentGrid::new(&pts);
        let (i, j, k) = (4, 5, 6);
        let (mut checked, mut blocked) = (0, 0);
        while checked < 3000 {
            let grid = grid_like(&like, &pts);
            let g = if rng.coin() {
                &grid.rows
            } else {
                &grid.columns
            };
            let part = &g.parts[rng.below(g.parts.len())];
            let (a, b) = (g.run, 1 - g.run);
            let mut corner = DVec2::ZERO;
            corner[a] = part.origin[0] + (1 + rng.below(part.bins - 2)) as f64 / part.inv_width;
            corner[b] = part.origin[1] + (1 + rng.below(part.bands - 2)) as f64 * part.height;
            let p = DVec2::new(rng.uniform() * 20.0, rng.uniform() * 20.0);
            // Through the corner, or just beside it (by about the cone's width).
            corner[a] += rng.uniform_in(-2.0, 2.0) * v.eps_ang * (corner - p).length();
            let q = p + (corner - p) * rng.uniform_in(1.2, 2.5);
            let d = q - p;
            let inside = (0..2).all(|x| (0.5..19.5).contains(&q[x]));
            // Walked in `g` only if its run axis is the major axis.
            if !inside || (d[a].abs() < d[b].abs()) || (g.run == 1 && d[a].abs() == d[b].abs()) {
                continue;
            }
            let normal = DVec2::new(-d.y, d.x).normalize();
            pts[i] = p;
            pts[j] = q;
            for side in [-1.0, 1.0] {
                for frac in [0.5, 0.999, 1.001] {
                    pts[k] = corner + normal * (side * frac * v.eps_ang * (corner - p).length());
                    let expect = brute(&pts, i, j, &v);
                    assert_eq!(
                        grid_like(&like, &pts).blocked(pts.as_slice(), i, j, &v, 0.0),
                        expect,
                        "{p} -> {q}, blocker {} ({frac})",
                        pts[k]
                    );
                    checked += 1;
                    blocked += usize::from(expect);
                }
            }
        }
        assert!(
            blocked > 1000,
            "only {blocked} of {checked} placements block"
        );
    }
}

/// A moving grid: a blocker on the line of sight whose point in the grid lies almost
/// the drift away from it, on either side, next to a band's and a bin's corner, on
/// lines of every slope, also in a crowded grid's nested parts: the walk, given that
/// drift, visits its bin and finds it.
#[test]
fn a_moving_grid_finds_blockers_a_drift_away_from_their_bins() {
    for (swarm, seed) in [
        (pinned_square as fn(&mut Stream) -> _, 9),
        (crowded_square, 10),
    ] {
        let v = VisionParams::default();
        let mut rng = Stream::new(seed, 0, 0, 0);
        let mut pts = swarm(&mut rng);
        let (i, j, k) = (4, 5, 6);
        let mut checked = 0;
        while checked < 2000 {
            let like = SegmentGrid::new(&pts);
            let bin = like.bin_size();
            let drift = bin * [0.3, 1.0, 2.0][checked % 3];
            let p = DVec2::new(rng.uniform_in(2.0, 18.0), rng.uniform_in(2.0, 18.0));
            let angle = rng.uniform() * std::f64::consts::TAU;
            let mut q = p + DVec2::new(angle.cos(), angle.sin()) * rng.uniform_in(3.0, 8.0);
            let mut on_line = p + (q - p) * rng.uniform_in(0.2, 0.8);
            if rng.coin() {
                // Through the crowded swarm's core.
                on_line = DVec2::new(12.0 + 1.5 * rng.uniform(), 5.0 + 1.5 * rng.uniform());
                q = p + (on_line - p) * rng.uniform_in(1.2, 2.5);
            }
            if !(0..2).all(|x| (0.5..19.5).contains(&q[x])) {
                continue;
            }
            let normal = DVec2::new(p.y - q.y, q.x - p.x).normalize();
            let side = if rng.coin() { 1.0 } else { -1.0 };
            // Where the grid holds it: off the line by almost the drift, across an edge.
            pts[i] = p;
            pts[j] = q;
            pts[k] = on_line + normal * (side * 0.999 * drift);
            let mut grid = SegmentGrid::with_levels(None, &pts, &like.levels(), false);
            // It is now on the line, a point again.
            grid.set_disc(k, [on_line.x, on_line.y], 0.0);
            let mut now = pts.clone();
            now[k] = on_line;
            let expect = (0..now.len()).any(|r| r != i && r != j && blocks(p, now[r], q, &v));
            assert!(expect, "a robot on the line blocks");
            assert!(
                grid.blocked(now.as_slice(), i, j, &v, drift),
                "{p} -> {q}: blocker held {} away",
                0.999 * drift
            );
            checked += 1;
        }
    }
}

/// A moving grid whose robots' discs reach a line of sight by the hundred, in a swarm
/// large enough for the walk to hold its candidates: more than it holds at once, so
/// that a batch of bands is confirmed in several goes. A robot in mid-move on the
/// line, anywhere along it, is found (so neither the first candidates held nor the
/// last are dropped), and a line with none on it is clear, as by the definition.
#[test]
fn a_walk_with_more_candidates_than_it_holds_finds_the_one_on_the_line() {
    let v = VisionParams::default();
    let mut rng = Stream::new(21, 0, 0, 0);
    let mut found = 0;
    for trial in 0..40 {
        // Enough robots for the walk to hold its candidates, in a square of side 100:
        // bins half a unit wide.
        let n = super::walk::HOLD_FROM + 7_232;
        let mut pts: Vec<DVec2> = (0..n)
            .map(|_| DVec2::new(rng.uniform_in(0.0, 100.0), rng.uniform_in(0.0, 100.0)))
            .collect();
        let (i, j) = (0, 1);
        pts[i] = DVec2::new(1.0, rng.uniform_in(40.0, 60.0));
        pts[j] = DVec2::new(99.0, rng.uniform_in(40.0, 60.0));
        let (p, q) = (pts[i], pts[j]);
        let mut grid = SegmentGrid::moving(&pts, false);
        let reach = 2.0 * grid.bin_size();
        // Every other robot may be up to `reach` from its point, and is, off the line.
        let mut now = pts.clone();
        let normal = DVec2::new(p.y - q.y, q.x - p.x).normalize();
        let mut near = Vec::new();
        for k in 2..pts.len() {
            grid.set_disc(k, [pts[k].x, pts[k].y], reach);
            let angle = rng.uniform() * std::f64::consts::TAU;
            now[k] = pts[k] + DVec2::new(angle.cos(), angle.sin()) * (0.9 * reach * rng.uniform());
            if (now[k] - p).dot(normal).abs() < 1e-3 {
                now[k] += normal * 2e-3;
            }
            let off = (pts[k] - p).dot(normal).abs();
            let along = (pts[k] - p).dot(q - p) / (q - p).length_squared();
            if off < 0.9 * reach && (0.05..0.95).contains(&along) {
                near.push((k, p + (q - p) * along));
            }
        }
        assert!(near.len() > 64, "{} robots near the line", near.len());
        if trial % 4 > 0 {
            // One of them is on the line now.
            let (k, on_line) = near[rng.below(near.len())];
            now[k] = on_line;
        }
        let expect = brute(&now, i, j, &v);
        assert_eq!(
            expect,
            trial % 4 > 0,
            "trial {trial}: the robot on the line blocks"
        );
        assert_eq!(
            grid.blocked(now.as_slice(), i, j, &v, reach),
            expect,
            "trial {trial}: {p} -> {q}"
        );
        found += usize::from(expect);
    }
    assert_eq!(found, 30);
}

/// Lines of sight between random robots of a crowded swarm, inside the core, from it
/// out and past it, some blocked by a robot placed on them: the walk agrees with the
/// definition, also with the core's robots in mid-move (a moving grid).
#[test]
fn lines_of_sight_through_a_crowded_core_agree_with_the_definition() {
    let v = VisionParams::default();
    let mut rng = Stream::new(12, 0, 0, 0);
    let mut pts = crowded_square(&mut rng);
    let n = pts.len();
    let like = SegmentGrid::new(&pts);
    let (mut blocked, mut clear) = (0, 0);
    for t in 0..3000 {
        let (i, j) = (rng.below(n), rng.below(n));
        if i == j {
            continue;
        }
        if t % 2 == 0 {
            // A blocker on the line, or just off it.
            let k = 4 + rng.below(n - 4);
            if k != i && k != j {
                let (p, q) = (pts[i], pts[j]);
                let d = q - p;
                let s = rng.uniform_in(0.05, 0.95);
                let normal = DVec2::new(-d.y, d.x).normalize();
                let frac = rng.uniform_in(-1.5, 1.5);
                pts[k] = p + d * s + normal * (frac * v.eps_ang * s * d.length());
            }
        }
        let expect = brute(&pts, i, j, &v);
        let grid = grid_like(&like, &pts);
        assert_eq!(
            grid.blocked(pts.as_slice(), i, j, &v, 0.0),
            expect,
            "{i} -> {j}"
        );
        // The walk as compiled for a CPU without AVX2 (its bins found through the
        // saturating conversion).
        assert_eq!(
            grid.walk::<false, _, _>(pts.as_slice(), i, j, &v, 0.0),
            expect,
            "{i} -> {j}, generic"
        );
        // The same robots held a drift away, in a moving grid.
        let drift = like.bin_size() * 0.7;
        let base: Vec<DVec2> = pts
            .iter()
            .map(|&p| {
                let angle = rng.uniform() * std::f64::consts::TAU;
                let moved = p + DVec2::new(angle.cos(), angle.sin()) * drift * rng.uniform();
                if like.covers(moved.x, moved.y) {
                    moved
                } else {
                    p
                }
            })
            .collect();
        let moving = SegmentGrid::with_levels(None, &base, &like.levels(), false);
        assert_eq!(
            moving.blocked(pts.as_slice(), i, j, &v, drift),
            expect,
            "{i} -> {j}, moving"
        );
        blocked += usize::from(expect);
        clear += usize::from(!expect);
    }
    assert!(
        blocked > 500 && clear > 500,
        "{blocked} blocked, {clear} clear"
    );
}

/// Robots with company within the radius (pairs at and around the radius, some
/// across bin edges and corners, far from the origin) are never marked isolated;
/// lone robots are.
#[test]
fn isolated_robots_have_nobody_within_the_radius() {
    let mut rng = Stream::new(5, 0, 0, 0);
    let offset = DVec2::new(-4.0e4, 7.0e3);
    let radius = 1e-6;
    // The first two robots pin the box, so adding robots inside keeps the bins.
    let mut pts = vec![offset, offset + DVec2::splat(40.0)];
    pts.extend((0..2000).map(|_| offset + DVec2::new(rng.uniform(), rng.uniform()) * 40.0));
    let first = SegmentGrid::new(&pts);
    let g = &first.rows;
    for k in 0..600 {
        let angle = rng.uniform() * std::f64::consts::TAU;
        let at = [0.0, 0.5, 0.999_999, 1.0, 1.000_001, 3.0][k % 6] * radius;
        let dir = DVec2::new(angle.cos(), angle.sin()) * at;
        if k % 3 == 2 {
            // Beside a robot.
            pts.push(pts[2 + rng.below(2000)] + dir);
        } else {
            // Either side of a bin corner.
            let part = &g.parts[0];
            let (x, y) = part.corner(1 + rng.below(part.bins - 2), 1 + rng.below(part.bands - 2));
            let corner = DVec2::new(x, y);
            pts.extend([corner + dir * 0.5, corner - dir * 0.5]);
        }
    }
    // The same bins as `first`.
    let grid = SegmentGrid::with_spacing(&pts, first.bin_size(), first.lo, first.hi, false);
    let (mut lone, mut missed) = (0, 0);
    for (k, &p) in pts.iter().enumerate() {
        let alone = pts
            .iter()
            .enumerate()
            .all(|(t, &q)| t == k || (q - p).length() > radius);
        let marked = grid.isolated(k, radius);
        assert!(!marked || alone, "robot {k} at {p} has company");
        // Beyond the room left for rounding (about 1e-5 here), robots are marked.
        let remote = pts
            .iter()
            .enumerate()
            .all(|(t, &q)| t == k || (q - p).length() > 1e-4);
        lone += usize::from(remote);
        missed += usize::from(remote && !marked);
    }
    assert!(
        lone > 1700 && missed == 0,
        "{missed} of {lone} lone robots not marked"
    );
    assert!(!grid.isolated(0, grid.bin_size()));
}

/// Blockers inside the cone, a few hundred units from the swarm's corner and far
/// from the origin: the cone is a million times thinner than the rounding of the
/// stored single-precision coordinates, which the line filter must allow for.
#[test]
fn the_single_precision_filter_keeps_blockers_it_cannot_resolve() {
    let v = VisionParams::default();
    let mut rng = Stream::new(11, 0, 0, 0);
    let offset = DVec2::new(1.0e5, -3.0e4);
    let mut pts: Vec<DVec2> = (0..3000)
        .map(|_| offset + DVec2::new(rng.uniform() * 1000.0, rng.uniform() * 1000.0))
        .collect();
    let (i, j, k) = (0, 1, 2);
    let mut blocked = 0;
    for _ in 0..400 {
        let (p, q) = (pts[i], pts[j]);
        let (d, t) = (q - p, rng.uniform_in(0.05, 0.95));
        let normal = DVec2::new(-d.y, d.x).normalize();
        // Within the cone, or just outside it.
        let frac = rng.uniform_in(-1.2, 1.2);
        pts[k] = p + d * t + normal * (frac * v.eps_ang * t * d.length());
        let expect = brute(&pts, i, j, &v);
        assert_eq!(
            SegmentGrid::new(&pts).blocked(pts.as_slice(), i, j, &v, 0.0),
            expect,
            "{p} -> {q}, blocker {} ({frac})",
            pts[k]
        );
        blocked += usize::from(expect);
        pts[i] = offset + DVec2::new(rng.uniform() * 1000.0, rng.uniform() * 1000.0);
        pts[j] = offset + DVec2::new(rng.uniform() * 1000.0, rng.uniform() * 1000.0);
    }
    assert!(blocked > 200, "only {blocked} of 400 placements block");
}

/// A radius query lists every robot within its radius, also those exactly on it: the
/// single-precision box the query tests first never drops one that the double-precision
/// test keeps. Random, crowded and lattice swarms, near the origin and shifted far from
/// it (large stored and query coordinates), asked from a robot or from far outside;
/// radii at which robots sit exactly on the boundary, tiny ones, and those of a grid
/// whose robots carry discs just reaching the query point.
#[test]
fn radius_queries_keep_robots_on_the_boundary() {
    let mut rng = Stream::new(11, 0, 0, 0);
    for (name, base) in [
        ("random", pinned_square(&mut rng)),
        ("crowded", crowded_square(&mut rng)),
        ("lattice", lattice_30()),
    ] {
        for shift in [DVec2::ZERO, DVec2::new(3.0e6, -7.5e5)] {
            let pts: Vec<DVec2> = base.iter().map(|&p| p + shift).collect();
            let at_rest = SegmentGrid::new(&pts);
            // Each robot of the moving grid carries a disc of its own around its
            // point: reach `reach[k]`, every one within the drift.
            let mut moving = SegmentGrid::moving(&pts, false);
            let reach: Vec<f64> = (0..pts.len()).map(|k| (k % 5) as f64 * 0.01).collect();
            let drift = 0.04 * (1.0 + 1e-9);
            for (k, &p) in pts.iter().enumerate() {
                moving.set_disc(k, [p.x, p.y], reach[k]);
            }
            for t in 0..90 {
                let i = rng.below(pts.len());
                let j = rng.below(pts.len());
                // From far outside the swarm's box (a stale robot's query: the radius
                // is large, and the query point's rounding to single precision more
                // than the stored points' room), from straight across robot `j` along
                // an axis (where the square is as tight as the disc), or from a robot.
                let far = rng.uniform_in(1e3, 4e5);
                let p = match t % 4 {
                    0 => {
                        pts[i]
                            + DVec2::new(rng.uniform_in(-1.0, 1.0), rng.uniform_in(-1.0, 1.0)) * 4e5
                    }
                    1 => {
                        pts[j] + [DVec2::X, DVec2::NEG_X, DVec2::Y, DVec2::NEG_Y][(t / 4) % 4] * far
                    }
                    _ => pts[i],
                };
                for radius in [p.distance(pts[j]), 0.0, 1e-9, 0.5, 2.5] {
                    let mut got = vec![];
                    at_rest.for_each_reaching(p.x, p.y, radius, 0.0, &mut |k| got.push(k));
                    for (k, &q) in pts.iter().enumerate() {
                        if q.distance(p) <= radius {
                            assert!(
                                got.contains(&k),
                                "{name} {shift}: {k} within {radius} of {i}"
                            );
                        }
                    }
                    // Discs that come within the radius, those just touching it too.
                    let mut got = vec![];
                    moving.for_each_reaching(p.x, p.y, radius, drift, &mut |k| got.push(k));
                    for (k, &q) in pts.iter().enumerate() {
                        if q.distance(p) <= radius + reach[k] {
                            assert!(got.contains(&k), "{name} {shift}: disc {k} near {i}");
                        }
                    }
                }
            }
        }
    }
}
