//! The impossibility construction: why robots that perceive only directions cannot be
//! guaranteed to converge (the paper's Theorem 1), and why the far bit of Locality
//! Detection is what breaks it.
//!
//! Robot 0 sits at the origin; the others lie along the same directions, at distance
//! `near` in one configuration and `far` in the other. Robot 0 sees the same directions
//! in both, so a rule that reads only directions makes the same decision in both. If it
//! moves b along u, and 2 * near < b, the move leaves the hull of the near configuration
//! (its hull has diameter at most 2 * near), whatever u is; if it stays, it stays in the
//! far configuration as well, where it is a hull vertex far from everybody. With c
//! between `near` and `far`, Locality Detection tells the two apart: every point is near
//! in one and far in the other.

use glam::DVec2;

use crate::geometry::{HullGeometry, convex_hull_2d};

/// The two configurations, robot 0 at the origin in both.
#[derive(Clone, Debug, PartialEq)]
pub struct Indistinguishable {
    /// The others at distance `near` along the directions.
    pub near: Vec<DVec2>,
    /// The others at distance `far` along the same directions.
    pub far: Vec<DVec2>,
}

/// Builds the two configurations for the directions at `angles` (radians).
pub fn construction(angles: &[f64], near: f64, far: f64) -> Indistinguishable {
    let place = |d: f64| {
        std::iter::once(DVec2::ZERO)
            .chain(angles.iter().map(|a| DVec2::new(a.cos(), a.sin()) * d))
            .collect()
    };
    Indistinguishable {
        near: place(near),
        far: place(far),
    }
}

/// The unit directions robot 0 sees in `config` (every other robot, in order).
pub fn directions(config: &[DVec2]) -> Vec<DVec2> {
    config[1..]
        .iter()
        .map(|q| (*q - config[0]).normalize())
        .collect()
}

/// Whether robot 0's move by `step` along the unit vector `u` ends outside the convex
/// hull of `config` (the hull grows).
pub fn leaves_hull(config: &[DVec2], step: f64, u: DVec2) -> bool {
    let to = config[0] + u * step;
    let hull = convex_hull_2d(config);
    let mut moved = config.to_vec();
    moved.push(to);
    // Outside iff adding the destination changes the hull.
    let before = DVec2::hull_measure(config);
    let after = DVec2::hull_measure(&moved);
    after > before * (1.0 + 1e-12) + 1e-15 || (hull.len() < 3 && !on_hull(&hull, to))
}

/// For hulls of fewer than three vertices: whether `p` lies on the point or segment.
fn on_hull(hull: &[DVec2], p: DVec2) -> bool {
    match hull {
        [] => false,
        [a] => a.distance(p) < 1e-12,
        [a, b, ..] => {
            let (ab, ap) = (*b - *a, p - *a);
            ab.perp_dot(ap).abs() < 1e-12 * ab.length()
                && ab.dot(ap) >= 0.0
                && ap.length() <= ab.length()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_view_is_the_same_and_every_move_leaves_a_hull() {
        let angles = [20f64.to_radians(), 50f64.to_radians(), 80f64.to_radians()];
        let c = construction(&angles, 0.2, 6.0);
        let (dn, df) = (directions(&c.near), directions(&c.far));
        for (a, b) in dn.iter().zip(&df) {
            assert!((*a - *b).length() < 1e-12);
        }
        let mut inside_far = 0;
        for k in 0..360 {
            let u = DVec2::from_angle(f64::from(k).to_radians());
            // 2 * near < b: every move leaves the near hull.
            assert!(leaves_hull(&c.near, 1.0, u), "{k} degrees");
            // Moves into the cone of the others stay inside the far hull.
            if !leaves_hull(&c.far, 1.0, u) {
                inside_far += 1;
                assert!((20..=80).contains(&k), "{k} degrees");
            }
        }
        assert!(inside_far > 40, "{inside_far}");
        // A short move toward the near robots stays inside: the rule is b, not the hull.
        assert!(!leaves_hull(
            &c.near,
            0.05,
            DVec2::from_angle(50f64.to_radians())
        ));
    }
}
