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

/// `pinned_square` with a crowded core: 3000 more robots in a box of side 1.5 off its
/// centre, so that the grid nests finer parts over it.
fn crowded_square(rng: &mut Stream) -> Vec<DVec2> {
    let mut pts = pinned_square(rng);
    pts.extend(
        (0..3000).map(|_| DVec2::new(12.0 + 1.5 * rng.uniform(), 5.0 + 1.5 * rng.uniform())),
    );
    pts
}

/// 900 robots on the unit lattice, 30 by 30.
fn lattice_30() -> Vec<DVec2> {
    (0..900)
        .map(|k| DVec2::new((k % 30) as f64, (k / 30) as f64))
        .collect()
}

/// A grid over `pts` with the parts of `like` (whose box must hold `pts`).
fn grid_like(like: &SegmentGrid, pts: &[DVec2]) -> SegmentGrid {
    SegmentGrid::with_levels(None, pts, &like.levels(), false)
}

#[test]
fn a_crowded_core_gets_finer_nested_parts() {
    let mut rng = Stream::new(3, 0, 0, 0);
    let plain = SegmentGrid::new(&pinned_square(&mut rng));
    assert_eq!(plain.parts(), 1);
    let pts = crowded_square(&mut rng);
    let grid = SegmentGrid::new(&pts);
    assert!(grid.parts() >= 2, "{:?}", grid.levels());
    let inner = &grid.levels()[1];
    assert!((0..2).all(|a| inner.lo[a] >= [11.9, 4.9][a] && inner.hi[a] <= [13.6, 6.6][a]));
    assert!(inner.spacing * 4.0 <= grid.levels()[0].spacing);
    assert_eq!(grid.cell_size(), grid.levels().last().unwrap().spacing);
    // Every robot is held once, in the innermost part whose box holds it.
    for layout in [&grid.rows, &grid.columns] {
        let mut seen = vec![0; pts.len()];
        for (x, part) in layout.parts.iter().enumerate() {
            for r in 0..part.bands {
                for s in layout.cells_range(part, r, 0, part.cells - 1) {
                    let k = layout.items[s] as usize;
                    seen[k] += 1;
                    let deepest = grid.levels()[1..]
                        .iter()
                        .rposition(|l| l.holds(&pts[k]))
                        .map_or(0, |l| l + 1);
                    assert_eq!(x, deepest, "robot {k} at {}", pts[k]);
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1));
    }
}

/// A core whose density falls off around it, as a converging swarm's does (measured at
/// epoch 40 of the coarse ASYNC run at 10^5: 11,500 robots per unit area in the box
/// between the 10th and 90th percentiles, 1,300 in the ring out to the 5th and 95th,
/// 42 beyond): 72% of the robots in a square of side 1, 17% in a shell around it out
/// to side 2, 7% out to side 6, 4% stragglers over side 60. The box between the 10th
/// and 90th percentiles is about the core alone, and would leave the shell in the
/// outer part, whose cells are sized for the few robots outside the nested box over
/// the whole swarm: tens of robots to a cell, tested by every line through the
/// shell. The wider box, between the 5th and 95th percentiles, takes the shell in.
#[test]
fn a_shell_around_the_core_is_nested_with_it() {
    let mut rng = Stream::new(5, 0, 0, 0);
    let mut pts: Vec<DVec2> = Vec::new();
    let mut fill = |rng: &mut Stream, count: usize, lo: f64, side: f64, hole: (f64, f64)| {
        let end = pts.len() + count;
        while pts.len() < end {
            let p = DVec2::new(lo + side * rng.uniform(), lo + side * rng.uniform());
            let inside = |v: f64| (hole.0..=hole.1).contains(&v);
            if !(inside(p.x) && inside(p.y)) {
                pts.push(p);
            }
        }
    };
    // (An empty hole for the core.)
    fill(&mut rng, 14_400, 0.0, 1.0, (1.0, 0.0));
    fill(&mut rng, 3_400, -0.5, 2.0, (0.0, 1.0));
    fill(&mut rng, 1_400, -2.5, 6.0, (-0.5, 1.5));
    fill(&mut rng, 800, -29.5, 60.0, (-2.5, 3.5));
    let grid = SegmentGrid::new(&pts);
    let levels = grid.levels();
    let nested = &levels[1];
    let held = pts.iter().filter(|p| nested.holds(*p)).count();
    assert!(
        held * 20 >= pts.len() * 17 && (0..2).all(|a| nested.lo[a] < -0.3 && nested.hi[a] > 1.3),
        "{held} robots in {levels:?}"
    );
}

/// The shortcut that spares an uncrowded swarm its percentiles (its first nested box could
/// be crowded only if the first cells were made for 16 times the quartile box's area
/// per robot) never leaves out a part: the levels are those found without it, for
/// both limits on the cells, on a square of 100 robots whose core of 4000 more shrinks
/// step by step to a 500th of the square's side (across the threshold of crowding), then
/// stretched by stragglers up to 10^17 times its side.
#[test]
fn the_crowding_shortcut_never_leaves_out_a_part() {
    let mut rng = Stream::new(9, 0, 0, 0);
    let (mut nested, mut skipped) = (0, 0);
    for step in 0..160 {
        // The core shrinks by 0.95 a step over the first 120 steps; then the square,
        // with a core of side 0.04, is stretched by two stragglers.
        let side = 20.0 * 0.95f64.powi(step.min(120));
        let within = |rng: &mut Stream, side: f64| side * rng.uniform();
        let mut pts = vec![DVec2::ZERO, DVec2::new(20.0, 20.0)];
        pts.extend((0..100).map(|_| DVec2::new(within(&mut rng, 20.0), within(&mut rng, 20.0))));
        pts.extend(
            (0..4000)
                .map(|_| DVec2::new(4.0 + within(&mut rng, side), 4.0 + within(&mut rng, side))),
        );
        if step > 120 {
            let far = 20.0 * 1.4f64.powi(step - 120);
            pts.extend([DVec2::new(-far, 0.0), DVec2::new(0.0, far)]);
        }
        for most in [MOST_CELLS, MOST_MOVING_CELLS] {
            let (first, sample, quartile) = first_level(&pts, most, false);
            // The sides ranked on two threads: the same area.
            let (_, _, twice) = first_level(&pts, most, true);
            assert_eq!(quartile.to_bits(), twice.to_bits(), "step {step}");
            let levels = sample.levels(first, quartile);
            let without = sample.levels(first, 0.0);
            let boxes = |l: &[Level]| {
                l.iter()
                    .map(|l| (l.lo, l.hi, l.spacing))
                    .collect::<Vec<_>>()
            };
            assert_eq!(boxes(&levels), boxes(&without), "step {step}");
            nested += usize::from(levels.len() > 1);
            skipped += usize::from(first.spacing.powi(2) < (CROWDED - 1.0) * quartile);
        }
    }
    assert!(
        nested > 20 && skipped > 20,
        "{nested} nested, {skipped} skipped"
    );
}

/// Blockers at the edge of the blocking cone, on lines of every slope through a
/// corner of the cells they are walked in (so a blocker sits across a band edge and
/// a cell edge from where the line enters the band), in every part of a crowded
/// grid: the walk must find them all.
#[test]
fn blockers_at_the_cone_edge_next_to_cell_corners() {
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
            corner[a] = part.origin[0] + (1 + rng.below(part.cells - 2)) as f64 / part.inv_width;
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
/// the drift away from it, on either side, next to a band's and a cell's corner, on
/// lines of every slope, also in a crowded grid's nested parts: the walk, given that
/// drift, visits its cell and finds it.
#[test]
fn a_moving_grid_finds_blockers_a_drift_away_from_their_cells() {
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
            let cell = like.cell_size();
            let drift = cell * [0.3, 1.0, 2.0][checked % 3];
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
        // cells half a unit wide.
        let n = super::walk::HOLD_FROM + 7_232;
        let mut pts: Vec<DVec2> = (0..n)
            .map(|_| DVec2::new(rng.uniform_in(0.0, 100.0), rng.uniform_in(0.0, 100.0)))
            .collect();
        let (i, j) = (0, 1);
        pts[i] = DVec2::new(1.0, rng.uniform_in(40.0, 60.0));
        pts[j] = DVec2::new(99.0, rng.uniform_in(40.0, 60.0));
        let (p, q) = (pts[i], pts[j]);
        let mut grid = SegmentGrid::moving(&pts, false);
        let reach = 2.0 * grid.cell_size();
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
        // The walk as compiled for a CPU without AVX2 (its cells found through the
        // saturating conversion).
        assert_eq!(
            grid.walk::<false, _, _>(pts.as_slice(), i, j, &v, 0.0),
            expect,
            "{i} -> {j}, generic"
        );
        // The same robots held a drift away, in a moving grid.
        let drift = like.cell_size() * 0.7;
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
            let part = &g.parts[0];
            let (x, y) = part.corner(1 + rng.below(part.cells - 2), 1 + rng.below(part.bands - 2));
            let corner = DVec2::new(x, y);
            pts.extend([corner + dir * 0.5, corner - dir * 0.5]);
        }
    }
    // The same cells as `first`.
    let grid = SegmentGrid::with_spacing(&pts, first.cell_size(), first.lo, first.hi, false);
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

/// The cells a walk reads in a band, computed afresh in coordinates (both widened
/// edges, their room for rounding, then `Part::cell`): what [`Crossing`] must contain.
fn cells_afresh(
    part: &bands::Part,
    track: &crossing::Track,
    r: usize,
    (a_lo, a_hi): (f64, f64),
    narrowed: bool,
    nested: bool,
) -> Option<(usize, usize)> {
    let (mut lo, mut hi) = (a_lo, a_hi);
    if narrowed {
        let edge0 = part.origin[1] + r as f64 * part.height - track.tol_b;
        let edge1 = part.origin[1] + (r + 1) as f64 * part.height + track.tol_b;
        let (t0, t1) = (
            (edge0 - track.pb) * track.inv_slope,
            (edge1 - track.pb) * track.inv_slope,
        );
        let room = 64.0 * f64::EPSILON * (track.scale + t0.abs() + t1.abs());
        lo = lo.max(track.pa + t0.min(t1) - room);
        hi = hi.min(track.pa + t0.max(t1) + room);
    }
    let beside = nested && ((hi < part.origin[0]) | (lo > part.top[0]));
    (lo <= hi && !beside).then(|| (part.cell(lo), part.cell(hi)))
}

/// The crossing's cells, one multiply-add a band, hold those computed band by band
/// afresh, and at most one more on either side: on lines of every slope (through
/// random robots, along a lattice's rows and diagonals, nearly along the run axis,
/// nearly across it), widened by a drift or not, in plain and nested parts, far from
/// the origin too.
#[test]
fn a_crossing_holds_the_cells_computed_afresh() {
    let mut rng = Stream::new(21, 0, 0, 0);
    let lattice = lattice_30();
    let (mut bands_checked, mut wider) = (0usize, 0usize);
    for (swarm, shift) in [
        (pinned_square(&mut rng), 0.0),
        (crowded_square(&mut rng), 0.0),
        (lattice, 0.0),
        (crowded_square(&mut rng), 1e6),
    ] {
        let pts: Vec<DVec2> = swarm.iter().map(|&p| p + DVec2::splat(shift)).collect();
        let grid = SegmentGrid::new(&pts);
        for t in 0..2000 {
            let p = pts[rng.below(pts.len())];
            let mut q = pts[rng.below(pts.len())];
            match t % 4 {
                // Nearly along an axis, or nearly across it.
                1 => q.y = p.y + (q.y - p.y) * 1e-9,
                2 => q.x = p.x + (q.x - p.x) * 1e-9,
                _ => {}
            }
            let d = q - p;
            if d == DVec2::ZERO {
                continue;
            }
            let g = if d.x.abs() >= d.y.abs() {
                &grid.rows
            } else {
                &grid.columns
            };
            let (a, b) = (g.run, 1 - g.run);
            let (pa, pb, da, db) = (p[a], p[b], d[a], d[b]);
            let tol = 1e-9 * d.length() * rng.uniform();
            // Widened across as a moving grid's drift widens it, on every third line.
            let drift = if t % 3 == 0 {
                grid.cell_size() * 2.0 * rng.uniform()
            } else {
                0.0
            };
            let tol_b = 2.0 * tol + drift * 1.5;
            let scale = pa
                .abs()
                .max((pa + da).abs())
                .max(pb.abs())
                .max((pb + db).abs())
                + d.length();
            let track = crossing::Track {
                pa,
                pb,
                inv_slope: da / db,
                tol_b,
                scale,
            };
            let steep = db.abs() * 1e12 >= da.abs();
            let extent = (pa.min(pa + da) - tol, pa.max(pa + da) + tol);
            for (k, part) in g.parts.iter().enumerate() {
                let (r0, r1) = (
                    part.band(pb.min(pb + db) - tol_b),
                    part.band(pb.max(pb + db) + tol_b),
                );
                let narrowed = r0 < r1 && steep;
                let crossing = crossing::Crossing::new(
                    part,
                    (r0, r1),
                    extent,
                    narrowed.then_some(&track),
                    k > 0,
                );
                for r in r0..=r1 {
                    let afresh = cells_afresh(part, &track, r, extent, narrowed, k > 0);
                    let found = crossing.cells::<true>(r);
                    assert_eq!(found, crossing.cells::<false>(r));
                    bands_checked += 1;
                    let Some((c0, c1)) = afresh else {
                        continue;
                    };
                    let (f0, f1) = found.unwrap_or_else(|| {
                        panic!("band {r} of part {k}: none, afresh {c0}..={c1}, {p} -> {q}")
                    });
                    assert!(
                        f0 <= c0 && c1 <= f1 && c0 - f0 <= 1 && f1 - c1 <= 1,
                        "band {r} of part {k}: {f0}..={f1}, afresh {c0}..={c1}, {p} -> {q}"
                    );
                    wider += usize::from((f0, f1) != (c0, c1));
                }
            }
        }
    }
    assert!(bands_checked > 20_000, "{bands_checked} bands");
    // Wider only where the crossing's extra room passes a cell's edge: rarely.
    assert!(
        wider * 1000 < bands_checked,
        "{wider} of {bands_checked} wider"
    );
}

/// Whether two layouts hold the same parts, cells, robots and stored points (bit for
/// bit, the padding's NaNs included) and reaches.
fn same_layout(a: &Bands, b: &Bands) -> bool {
    let bits = |g: &Bands| -> Vec<[u32; 2]> {
        g.coords
            .iter()
            .map(|c| [c[0].to_bits(), c[1].to_bits()])
            .collect()
    };
    let reach = |g: &Bands| -> Vec<u32> { g.reach.iter().map(|r| r.to_bits()).collect() };
    a.run == b.run
        && format!("{:?}", a.parts) == format!("{:?}", b.parts)
        && a.start == b.start
        && a.items == b.items
        && a.place == b.place
        && bits(a) == bits(b)
        && reach(a) == reach(b)
}

/// A moving grid made again in the arrays of one done with (of other robots, more or
/// fewer, with or without nested parts, with discs) is the grid made afresh: on
/// random, crowded, lattice and collinear swarms, in turn.
#[test]
fn a_grid_made_again_in_the_arrays_of_another_is_the_one_made_afresh() {
    let mut rng = Stream::new(17, 0, 0, 0);
    let lattice = lattice_30();
    let line: Vec<DVec2> = (0..300).map(|k| DVec2::splat(k as f64 * 0.25)).collect();
    let swarms = [
        crowded_square(&mut rng),
        pinned_square(&mut rng),
        lattice,
        crowded_square(&mut rng),
        line,
        pinned_square(&mut rng),
    ];
    let mut used: Option<SegmentGrid> = None;
    for (t, pts) in swarms.iter().enumerate() {
        let nested = t % 2 == 0;
        let fresh = SegmentGrid::moving(pts, nested);
        let mut grid = match used.take() {
            Some(old) => old.moving_again(pts, nested, false),
            None => SegmentGrid::moving(pts, nested),
        };
        assert!(grid.rows.reach.is_empty(), "swarm {t}: no disc yet");
        for (a, b) in [(&grid.rows, &fresh.rows), (&grid.columns, &fresh.columns)] {
            assert!(same_layout(a, b), "swarm {t}, run {}", a.run);
        }
        assert_eq!(
            (grid.lo, grid.hi, grid.rounding.to_bits(), grid.single),
            (fresh.lo, fresh.hi, fresh.rounding.to_bits(), fresh.single),
            "swarm {t}"
        );
        // Discs for some robots, to be emptied when the grid is made again.
        for k in (0..pts.len()).step_by(7) {
            grid.set_disc(k, [pts[k].x + 0.1, pts[k].y], 0.25);
        }
        assert_eq!(grid.rows.reach.len(), grid.rows.coords.len());
        used = Some(grid);
    }
}

/// A moving grid made again keeping its sizing has the parts of the grid before it
/// while every robot stays in its box, and answers lines of sight as the definition
/// does; it is sized afresh after [`KEEP_SIZING`] grids in a row, once a robot leaves
/// the box, and for the other kind of grid: on crowded, random and lattice swarms
/// shrinking towards their centres (so that sizing afresh would give other parts).
#[test]
fn a_grid_made_again_keeping_its_sizing_has_the_parts_before_until_it_must_not() {
    let v = VisionParams::default();
    let mut rng = Stream::new(23, 0, 0, 0);
    let swarms = [
        (crowded_square(&mut rng), true),
        (pinned_square(&mut rng), false),
        (lattice_30(), true),
    ];
    for (s, (swarm, nested)) in swarms.into_iter().enumerate() {
        let n = swarm.len();
        let shrink = |pts: &mut Vec<DVec2>| {
            let centre = pts.iter().sum::<DVec2>() / n as f64;
            for p in pts.iter_mut() {
                *p = centre + (*p - centre) * 0.97;
            }
        };
        let mut pts = swarm;
        let mut grid = SegmentGrid::moving(&pts, nested);
        let first = grid.levels();
        let mut differs = false;
        for t in 1..KEEP_SIZING {
            shrink(&mut pts);
            grid = grid.moving_again(&pts, nested, true);
            assert_eq!(grid.kept, t, "swarm {s}");
            let like = SegmentGrid::with_levels(None, &pts, &first, true);
            let fresh = SegmentGrid::moving(&pts, nested);
            for (a, b) in [(&grid.rows, &like.rows), (&grid.columns, &like.columns)] {
                assert!(same_layout(a, b), "swarm {s}, grid {t}, run {}", a.run);
            }
            differs |= !same_layout(&grid.rows, &fresh.rows);
            for _ in 0..40 {
                let (i, j) = (rng.below(n), rng.below(n));
                if i != j {
                    let expect = brute(&pts, i, j, &v);
                    let got = grid.blocked(pts.as_slice(), i, j, &v, 0.0);
                    assert_eq!(got, expect, "swarm {s}, grid {t}: {i} -> {j}");
                }
            }
        }
        assert!(differs, "swarm {s}: sizing afresh gives the same parts");
        let afresh = |grid: &SegmentGrid, pts: &[DVec2], nested: bool, what: &str| {
            let fresh = SegmentGrid::moving(pts, nested);
            assert_eq!(grid.kept, 0, "swarm {s}: {what}");
            for (a, b) in [(&grid.rows, &fresh.rows), (&grid.columns, &fresh.columns)] {
                assert!(same_layout(a, b), "swarm {s}: {what}, run {}", a.run);
            }
        };
        // The sixteenth in a row.
        shrink(&mut pts);
        grid = grid.moving_again(&pts, nested, true);
        afresh(&grid, &pts, nested, "after 16 in a row");
        // A robot outside the box.
        grid = grid.moving_again(&pts, nested, true);
        assert_eq!(grid.kept, 1, "swarm {s}");
        pts[7] = DVec2::new(grid.hi[0] + 0.5, pts[7].y);
        grid = grid.moving_again(&pts, nested, true);
        afresh(&grid, &pts, nested, "a robot outside");
        // The other kind, and without keeping.
        grid = grid.moving_again(&pts, !nested, true);
        afresh(&grid, &pts, !nested, "the other kind");
        grid = grid.moving_again(&pts, !nested, false);
        afresh(&grid, &pts, !nested, "not kept");
    }
}

/// Every robot is filed in the cell its own band and cell give in each layout, computed
/// for that layout alone (the two layouts' cells are found together, a band from the
/// other layout's cell halved): on random, crowded (nested parts), lattice, collinear
/// and far-off swarms, with robots on cell and band edges and on the box's far edges.
#[test]
fn each_robot_is_filed_in_the_cell_of_its_own_band_and_cell() {
    let mut rng = Stream::new(29, 0, 0, 0);
    let far = DVec2::new(-3.0e9, 7.0e11);
    let mut edges: Vec<DVec2> = (0..30)
        .flat_map(|i| (0..30).map(move |j| DVec2::new(i as f64 * 0.5, j as f64 * 1.5)))
        .collect();
    edges.push(DVec2::new(14.5, 43.5));
    let swarms = [
        pinned_square(&mut rng),
        crowded_square(&mut rng),
        lattice_30(),
        (0..300).map(|k| DVec2::splat(k as f64 * 0.25)).collect(),
        (0..500)
            .map(|_| far + DVec2::new(rng.uniform(), rng.uniform()) * 1e3)
            .collect(),
        edges,
    ];
    for (s, pts) in swarms.iter().enumerate() {
        let box_of = |g: &SegmentGrid| (g.lo, g.hi);
        let (lo, hi) = box_of(&SegmentGrid::new(pts));
        // Cells of 0.5 and 0.1 (edges on the lattice's points; not a binary fraction).
        let grids = [
            SegmentGrid::new(pts),
            SegmentGrid::moving(pts, false),
            SegmentGrid::with_spacing(pts, 0.5, lo, hi, false),
            SegmentGrid::with_spacing(pts, 0.1, lo, hi, true),
        ];
        for grid in grids {
            for g in [&grid.rows, &grid.columns] {
                let across = 1 - g.run;
                for (k, p) in pts.iter().enumerate() {
                    let level = grid.levels()[1..]
                        .iter()
                        .rposition(|l| l.holds(p))
                        .map_or(0, |l| l + 1);
                    let part = &g.parts[level];
                    let cell = part.row(part.band(p.axis(across))) + part.cell(p.axis(g.run));
                    let at = g.place[k];
                    assert_eq!(g.items[at as usize], k as u32);
                    let (from, to) = (g.start[cell], g.start[cell + 1]);
                    assert!(
                        from <= at && at < to,
                        "swarm {s}, run {}: robot {k} at {p} not in cell {cell}",
                        g.run
                    );
                }
            }
        }
    }
}
