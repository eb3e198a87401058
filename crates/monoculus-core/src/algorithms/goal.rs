//! [`Goal`]: what convergence means for an algorithm (SPEC section 11). The stop
//! criterion ([`StopCriterion`](super::StopCriterion)) decides when a run ends; the goal
//! decides whether the swarm it ended with has converged.

use crate::geometry::{Point, enclosing_radius};
use crate::metrics;

/// What an algorithm's convergence means: a run has converged when its stop criterion
/// ended it and its goal holds for the final configuration (config `stop.goal`;
/// [`Algorithm::GOAL`](super::Algorithm::GOAL)).
///
/// ```
/// use glam::DVec2;
/// use monoculus_core::algorithms::Goal;
///
/// // A 3 x 3 lattice of spacing 0.8 (b = 1, c = 2): its diameter, 2.26, exceeds c, but
/// // every robot lies within a disc of radius 1.13 <= c.
/// let lattice: Vec<DVec2> = (0..9)
///     .map(|k| DVec2::new((k % 3) as f64 * 0.8, (k / 3) as f64 * 0.8))
///     .collect();
/// assert!(!Goal::Diameter.holds(&lattice, 1.0, 2.0));
/// assert!(Goal::Disc.holds(&lattice, 1.0, 2.0));
/// assert!(!Goal::Box.holds(&lattice, 0.5, 2.0)); // extents 1.6 > 2b = 1
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Goal {
    /// Every pair of robots within the locality constant c (diameter <= c): the
    /// baselines' goal, and any algorithm's that declares none.
    Diameter,
    /// Every robot within a disc (a ball in space) of radius c: the smallest enclosing
    /// disc's radius at most c. ConvergeLocality's theorem; weaker than
    /// [`Goal::Diameter`].
    Disc,
    /// The bounding box's extent at most 2b on every axis: ConvergeQuadrant's and its
    /// termination variant's.
    Box,
}

impl Goal {
    /// Every goal, in the order of their names in messages.
    pub const ALL: [Goal; 3] = [Goal::Diameter, Goal::Disc, Goal::Box];

    /// The config name (`stop.goal`), as `runs.csv`'s column `goal` shows it.
    pub fn name(self) -> &'static str {
        match self {
            Goal::Diameter => "diameter",
            Goal::Disc => "disc",
            Goal::Box => "box",
        }
    }

    /// What it asks, in words, for messages and pages.
    ///
    /// ```
    /// assert_eq!(
    ///     monoculus_core::algorithms::Goal::Disc.describe(),
    ///     "every robot within a disc of radius c"
    /// );
    /// ```
    pub fn describe(self) -> &'static str {
        match self {
            Goal::Diameter => "every pair of robots within c",
            Goal::Disc => "every robot within a disc of radius c",
            Goal::Box => "a bounding box of extent at most 2b on every axis",
        }
    }

    /// The bound its measure must not exceed: c, c, 2b.
    pub fn bound(self, step: f64, locality: f64) -> f64 {
        match self {
            Goal::Diameter | Goal::Disc => locality,
            Goal::Box => 2.0 * step,
        }
    }

    /// Its measure of a configuration, from what the caller has measured already: the
    /// diameter, the smallest enclosing disc's (ball's) radius, or the largest extent of
    /// the bounding box.
    pub fn measure(self, diameter: f64, radius: f64, extents: &[f64]) -> f64 {
        match self {
            Goal::Diameter => diameter,
            Goal::Disc => radius,
            Goal::Box => extents.iter().copied().fold(0.0, f64::max),
        }
    }

    /// Whether it holds for `points` with step b = `step` and locality c = `locality`
    /// (computed here from the points; the engine measures once for every goal).
    pub fn holds<P: Point>(self, points: &[P], step: f64, locality: f64) -> bool {
        let measure = match self {
            Goal::Diameter => diameter(points),
            Goal::Disc => enclosing_radius(points),
            Goal::Box => {
                let e = metrics::extents(points);
                (0..P::DIM).map(|k| e.axis(k)).fold(0.0, f64::max)
            }
        };
        measure <= self.bound(step, locality)
    }
}

/// The largest distance between two of `points` (quadratic: for the few points
/// [`Goal::holds`] is asked about).
fn diameter<P: Point>(points: &[P]) -> f64 {
    let mut d = 0.0f64;
    for (i, &p) in points.iter().enumerate() {
        for &q in &points[i + 1..] {
            d = d.max(p.distance(q));
        }
    }
    d
}
