//! The band grid against the definition: its parts (`parts`), its queries (`queries`),
//! the bins a walk reads in a band (`band_bins`), and how robots are filed
//! (`layout`); the swarms they share are here.

mod band_bins;
mod layout;
mod parts;
mod queries;

use super::*;
use glam::DVec2;
use monoculus_core::rng::Stream;
use monoculus_core::vision::{VisionParams, blocks};

pub(super) fn brute(points: &[DVec2], i: usize, j: usize, v: &VisionParams) -> bool {
    (0..points.len()).any(|k| k != i && k != j && blocks(points[i], points[k], points[j], v))
}

/// 404 robots in a square of side 20: the first four at its corners pin the bounds, so
/// that moving robots 4, 5 and 6 about inside keeps the grid's bins.
pub(super) fn pinned_square(rng: &mut Stream) -> Vec<DVec2> {
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
pub(super) fn crowded_square(rng: &mut Stream) -> Vec<DVec2> {
    let mut pts = pinned_square(rng);
    pts.extend(
        (0..3000).map(|_| DVec2::new(12.0 + 1.5 * rng.uniform(), 5.0 + 1.5 * rng.uniform())),
    );
    pts
}

/// 900 robots on the unit lattice, 30 by 30.
pub(super) fn lattice_30() -> Vec<DVec2> {
    (0..900)
        .map(|k| DVec2::new((k % 30) as f64, (k / 30) as f64))
        .collect()
}

/// A grid over `pts` with the parts of `like` (whose box must hold `pts`).
pub(super) fn grid_like(like: &SegmentGrid, pts: &[DVec2]) -> SegmentGrid {
    SegmentGrid::with_levels(None, pts, &like.levels(), false)
}
