//! Nested parts over a crowded core.

use super::*;

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
    assert_eq!(grid.bin_size(), grid.levels().last().unwrap().spacing);
    // Every robot is held once, in the innermost part whose box holds it.
    for layout in [&grid.rows, &grid.columns] {
        let mut seen = vec![0; pts.len()];
        for (x, part) in layout.parts.iter().enumerate() {
            for r in 0..part.bands {
                for s in layout.bins_range(part, r, 0, part.bins - 1) {
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
/// outer part, whose bins are sized for the few robots outside the nested box over
/// the whole swarm: tens of robots to a bin, tested by every line through the
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
/// be crowded only if the first bins were made for 16 times the quartile box's area
/// per robot) never leaves out a part: the levels are those found without it, for
/// both limits on the bins, on a square of 100 robots whose core of 4000 more shrinks
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
        for most in [MOST_BINS, MOST_MOVING_BINS] {
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
