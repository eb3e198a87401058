//! The bins a walk reads in each band.

use super::*;

/// The bins a walk reads in a band, computed afresh in coordinates (both widened
/// edges, their room for rounding, then `Part::bin`): what [`Crossing`] must contain.
fn bins_afresh(
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
    (lo <= hi && !beside).then(|| (part.bin(lo), part.bin(hi)))
}

/// The crossing's bins, one multiply-add a band, hold those computed band by band
/// afresh, and at most one more on either side: on lines of every slope (through
/// random robots, along a lattice's rows and diagonals, nearly along the run axis,
/// nearly across it), widened by a drift or not, in plain and nested parts, far from
/// the origin too.
#[test]
fn a_crossing_holds_the_bins_computed_afresh() {
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
                grid.bin_size() * 2.0 * rng.uniform()
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
                    let afresh = bins_afresh(part, &track, r, extent, narrowed, k > 0);
                    let found = crossing.bins::<true>(r);
                    assert_eq!(found, crossing.bins::<false>(r));
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
    // Wider only where the crossing's extra room passes a bin's edge: rarely.
    assert!(
        wider * 1000 < bands_checked,
        "{wider} of {bands_checked} wider"
    );
}
