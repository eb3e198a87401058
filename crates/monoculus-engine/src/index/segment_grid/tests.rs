//! The band grid against the definition.

use super::*;
use glam::DVec2;
use monoculus_core::rng::Stream;
use monoculus_core::vision::{VisionParams, blocks};

fn brute(points: &[DVec2], i: usize, j: usize, v: &VisionParams) -> bool {
    (0..points.len()).any(|k| k != i && k != j && blocks(points[i], points[k], points[j], v))
}

/// 404 robots in a square of side 20: the first four at its corners pin the bounds, so
/// that moving robots 4, 5 and 6 about inside keeps the grid's cells.
fn pinned_square(rng: &mut Stream) -> Vec<DVec2> {
    let mut pts = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(20.0, 0.0),
        DVec2::new(0.0, 20.0),
        DVec2::new(20.0, 20.0),
    ];
    pts.extend((0..400).map(|_| DVec2::new(rng.uniform() * 20.0, rng.uniform() * 20.0)));
    pts
}

/// Blockers at the edge of the blocking cone, on lines of every slope through a
/// corner of the cells they are walked in (so a blocker sits across a band edge and
/// a cell edge from where the line enters the band): the walk must find them all.
#[test]
fn blockers_at_the_cone_edge_next_to_cell_corners() {
    let v = VisionParams::default();
    let mut rng = Stream::new(7, 0, 0, 0);
    let mut pts = pinned_square(&mut rng);
    let (i, j, k) = (4, 5, 6);
    let (mut checked, mut blocked) = (0, 0);
    while checked < 3000 {
        let grid = SegmentGrid::new(&pts);
        let g = if rng.coin() {
            &grid.rows
        } else {
            &grid.columns
        };
        let (a, b) = (g.run, 1 - g.run);
        let mut corner = DVec2::ZERO;
        corner[a] = g.origin[0] + (1 + rng.below(g.cells - 2)) as f64 / g.inv_width;
        corner[b] = g.origin[1] + (1 + rng.below(g.bands - 2)) as f64 * g.height;
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
                    SegmentGrid::new(&pts).blocked(pts.as_slice(), i, j, &v, 0.0),
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
/// A moving grid: a blocker on the line of sight whose point in the grid lies almost
/// the drift away from it, on either side, next to a band's and a cell's corner, on
/// lines of every slope: the walk, given that drift, visits its cell and finds it.
#[test]
fn a_moving_grid_finds_blockers_a_drift_away_from_their_cells() {
    let v = VisionParams::default();
    let mut rng = Stream::new(9, 0, 0, 0);
    let mut pts = pinned_square(&mut rng);
    let (i, j, k) = (4, 5, 6);
    let mut checked = 0;
    while checked < 2000 {
        let cell = SegmentGrid::new(&pts).cell_size();
        let drift = cell * [0.3, 1.0, 2.0][checked % 3];
        let p = DVec2::new(rng.uniform_in(2.0, 18.0), rng.uniform_in(2.0, 18.0));
        let angle = rng.uniform() * std::f64::consts::TAU;
        let q = p + DVec2::new(angle.cos(), angle.sin()) * rng.uniform_in(3.0, 8.0);
        if !(0..2).all(|x| (0.5..19.5).contains(&q[x])) {
            continue;
        }
        let on_line = p + (q - p) * rng.uniform_in(0.2, 0.8);
        let normal = DVec2::new(p.y - q.y, q.x - p.x).normalize();
        let side = if rng.coin() { 1.0 } else { -1.0 };
        // Where the grid holds it: off the line by almost the drift, across an edge.
        pts[i] = p;
        pts[j] = q;
        pts[k] = on_line + normal * (side * 0.999 * drift);
        let mut grid = SegmentGrid::moving(&pts);
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

/// Robots with company within the radius (pairs at and around the radius, some
/// across cell edges and corners, far from the origin) are never marked isolated;
/// lone robots are.
#[test]
fn isolated_robots_have_nobody_within_the_radius() {
    let mut rng = Stream::new(5, 0, 0, 0);
    let offset = DVec2::new(-4.0e4, 7.0e3);
    let radius = 1e-6;
    // The first two robots pin the box, so adding robots inside keeps the cells.
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
            // Either side of a cell corner.
            let (x, y) = g.corner(1 + rng.below(g.cells - 2), 1 + rng.below(g.bands - 2));
            let corner = DVec2::new(x, y);
            pts.extend([corner + dir * 0.5, corner - dir * 0.5]);
        }
    }
    // The same cells as `first`.
    let grid = SegmentGrid::with_spacing(&pts, first.spacing, first.lo, first.hi, false);
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
    assert!(!grid.isolated(0, grid.cell_size()));
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
