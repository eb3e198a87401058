use bevy_ecs::prelude::*;

use crate::IndexPoint;
use crate::resources::{Clock, Positions, Shape, Tally};

/// Relative tolerance for "the hull grew": moving inside the hull changes its area only
/// by rounding.
pub const HULL_GROWTH_TOLERANCE: f64 = 1e-9;

/// Measures the configuration after the moves: hull size, diameter, extents; counts the
/// round if the hull grew.
pub fn measure_shape<P: IndexPoint>(
    positions: Res<Positions<P>>,
    mut shape: ResMut<Shape>,
    mut tally: ResMut<Tally>,
) {
    if tally.round_moves == 0 {
        return;
    }
    let measured = Shape::of(&positions.points);
    if measured.hull > shape.hull * (1.0 + HULL_GROWTH_TOLERANCE) + 1e-12 {
        tally.hull_growth_rounds += 1;
    }
    *shape = measured;
}

/// Advances the round counter.
pub fn advance_clock(mut clock: ResMut<Clock>) {
    clock.round += 1;
}

impl Shape {
    /// Measures a configuration.
    pub fn of<P: IndexPoint>(points: &[P]) -> Shape {
        let e = monoculus_core::metrics::extents(points);
        Shape {
            hull: P::hull_measure(points),
            diameter: P::diameter(points),
            extents: (0..P::DIM).map(|a| e.axis(a)).collect(),
        }
    }
}
