//! How robots are filed: grids made again, kept bins, each robot's bin.

use super::*;

/// Whether two layouts hold the same parts, bins, robots and stored points (bit for
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

/// Every robot is filed in the bin its own band and bin give in each layout, computed
/// for that layout alone (the two layouts' bins are found together, a band from the
/// other layout's bin halved): on random, crowded (nested parts), lattice, collinear
/// and far-off swarms, with robots on bin and band edges and on the box's far edges.
#[test]
fn each_robot_is_filed_in_the_bin_of_its_own_band_and_bin() {
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
        let first = SegmentGrid::new(pts);
        let (lo, hi) = (first.lo, first.hi);
        // Bins of 0.5 and 0.1 (edges on the lattice's points; not a binary fraction).
        let grids = [
            first,
            SegmentGrid::moving(pts, false),
            SegmentGrid::with_spacing(pts, 0.5, lo, hi, false),
            SegmentGrid::with_spacing(pts, 0.1, lo, hi, true),
        ];
        for grid in grids {
            let levels = grid.levels();
            for g in [&grid.rows, &grid.columns] {
                let across = 1 - g.run;
                for (k, p) in pts.iter().enumerate() {
                    let level = levels[1..]
                        .iter()
                        .rposition(|l| l.holds(p))
                        .map_or(0, |l| l + 1);
                    let part = &g.parts[level];
                    let bin = part.row(part.band(p.axis(across))) + part.bin(p.axis(g.run));
                    let at = g.place[k];
                    assert_eq!(g.items[at as usize], k as u32);
                    let (from, to) = (g.start[bin], g.start[bin + 1]);
                    assert!(
                        from <= at && at < to,
                        "swarm {s}, run {}: robot {k} at {p} not in bin {bin}",
                        g.run
                    );
                }
            }
        }
    }
}
