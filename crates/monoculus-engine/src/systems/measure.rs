use bevy_ecs::prelude::*;

use crate::IndexPoint;
use crate::components::{Activated, Intent, Robot};
use crate::resources::{Clock, HullVertices, Params, Positions, Shape, Tally};

/// Relative tolerance for "the hull grew": moving inside the hull changes its area only
/// by rounding.
pub const HULL_GROWTH_TOLERANCE: f64 = 1e-9;

/// Whether a hull of size `now` grew from one of size `before`: the one rule every
/// scheduler counts hull growth by (relative tolerance [`HULL_GROWTH_TOLERANCE`], and
/// an absolute 1e-12 for hulls of no area).
pub fn hull_grew(before: f64, now: f64) -> bool {
    now > before * (1.0 + HULL_GROWTH_TOLERANCE) + 1e-12
}

/// Counts one round (ASYNC: tick) in which the hull of the positions went from `shape`'s
/// to `measured`'s, and keeps the largest hull so far.
pub fn record_hull(tally: &mut Tally, shape: &Shape, measured: &mut Shape) {
    if hull_grew(shape.hull, measured.hull) {
        tally.hull_growth_rounds += 1;
        tally.hull_growth_max = tally.hull_growth_max.max(measured.hull / shape.hull - 1.0);
    }
    measured.hull_max = shape.hull_max.max(measured.hull);
}

/// Measures the configuration of the correct robots after the moves: hull size,
/// diameter, extents; counts the round if the hull grew.
pub fn measure_shape<P: IndexPoint>(
    params: Res<Params>,
    positions: Res<Positions<P>>,
    mut shape: ResMut<Shape>,
    mut hull: ResMut<HullVertices<P>>,
    mut tally: ResMut<Tally>,
) {
    shape_after_moves(&params, &positions, &mut shape, &mut hull, &mut tally);
}

/// The Measure phase as the round's schedule runs it: [`measure_shape`], then
/// [`advance_clock`], in one system (each system a round runs costs its dispatch and
/// its resources' fetching again, a sizeable part of a round of a few robots).
pub(crate) fn measure_round<P: IndexPoint>(
    params: Res<Params>,
    positions: Res<Positions<P>>,
    (mut shape, mut hull): (ResMut<Shape>, ResMut<HullVertices<P>>),
    mut tally: ResMut<Tally>,
    mut clock: ResMut<Clock>,
) {
    shape_after_moves(&params, &positions, &mut shape, &mut hull, &mut tally);
    clock.round += 1;
}

fn shape_after_moves<P: IndexPoint>(
    params: &Params,
    positions: &Positions<P>,
    shape: &mut Shape,
    hull: &mut HullVertices<P>,
    tally: &mut Tally,
) {
    if tally.round_moves == 0 {
        return;
    }
    let correct = params.correct(&positions.points);
    hull.vertices = P::hull_vertices(&correct);
    hull.generation = positions.generation;
    let mut measured = Shape::of_hull(&correct, &hull.vertices);
    record_hull(tally, shape, &mut measured);
    *shape = measured;
}

/// Before the moves: counts the round if a decided destination lies outside the hull of
/// the current positions (the hull of positions and destinations grows). Lemma 2 says
/// this never happens under ConvergeLocality; under ASYNC it is the hull that Lemma 2
/// bounds, and this keeps the two schedulers' counts comparable.
pub fn measure_committed<P: IndexPoint>(
    params: Res<Params>,
    positions: Res<Positions<P>>,
    shape: Res<Shape>,
    hull: Res<HullVertices<P>>,
    mut tally: ResMut<Tally>,
    robots: Query<(&Robot, &Activated, &Intent<P>)>,
    mut pts: Local<Vec<P>>,
) {
    if committed_grew((&params, &positions), (&shape, &hull), &robots, &mut pts) {
        tally.committed_hull_growth += 1;
    }
}

/// The Move phase as the round's schedule runs it: [`measure_committed`], then
/// [`apply_moves`](super::apply_moves), in one system (see [`measure_round`]).
pub(crate) fn move_round<P: IndexPoint>(
    (params, shape, hull): (Res<Params>, Res<Shape>, Res<HullVertices<P>>),
    mut positions: ResMut<Positions<P>>,
    mut tally: ResMut<Tally>,
    robots: Query<(&Robot, &Activated, &Intent<P>)>,
    mut pts: Local<Vec<P>>,
) {
    if committed_grew((&params, &positions), (&shape, &hull), &robots, &mut pts) {
        tally.committed_hull_growth += 1;
    }
    super::movement::apply(&params, &robots, &mut positions, &mut tally);
}

/// Whether the hull of the correct robots' positions and decided destinations grew
/// from the hull measured before the moves (`pts` a buffer for the points).
fn committed_grew<P: IndexPoint>(
    (params, positions): (&Params, &Positions<P>),
    (shape, hull): (&Shape, &HullVertices<P>),
    robots: &Query<(&Robot, &Activated, &Intent<P>)>,
    pts: &mut Vec<P>,
) -> bool {
    pts.clear();
    for (robot, active, intent) in robots {
        if let (true, Some(d), true) = (active.0, intent.0, params.is_correct(robot.index as usize))
        {
            pts.push(positions.points[robot.index as usize] + d);
        }
    }
    // Destinations strictly inside the current hull leave it exactly as it is: the
    // common case, decided without recomputing the hull. Those are never vertices of
    // the hull of positions and destinations, nor are the positions inside the hull:
    // the hull is that of its vertices and the other destinations (the same vertex
    // sequence, so the same area to the bit; tested in `monoculus_core::geometry`).
    pts.retain(|&d| !P::strictly_inside(&hull.vertices, d));
    if pts.is_empty() {
        return false;
    }
    if hull.vertices.is_empty() {
        pts.extend_from_slice(&params.correct(&positions.points));
    } else {
        pts.extend_from_slice(&hull.vertices);
    }
    hull_grew(shape.hull, P::hull_measure(pts))
}

/// Advances the round counter.
pub fn advance_clock(mut clock: ResMut<Clock>) {
    clock.round += 1;
}

impl Shape {
    /// Measures a configuration.
    pub fn of<P: IndexPoint>(points: &[P]) -> Shape {
        Self::measured(points, P::hull_and_diameter(points))
    }

    /// Measures a configuration from the vertices of its hull, as
    /// [`HullGeometry::hull_vertices`](monoculus_core::geometry::HullGeometry) gives
    /// them (not empty): the same measures as [`Shape::of`] the configuration, to the
    /// bit, without taking their hull again.
    ///
    /// ```
    /// use glam::DVec2;
    /// use monoculus_core::geometry::HullGeometry;
    /// use monoculus_engine::resources::Shape;
    /// let pts = [DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::splat(0.25)];
    /// let vertices = DVec2::hull_vertices(&pts);
    /// assert_eq!(Shape::of_vertices(&vertices).hull, Shape::of(&pts).hull);
    /// ```
    pub fn of_vertices<P: IndexPoint>(vertices: &[P]) -> Shape {
        Self::measured(vertices, P::vertices_hull_and_diameter(vertices))
    }

    /// Measures a configuration, `points`, whose hull's vertices are `vertices` (empty
    /// in space, where there is no vertex list): [`Shape::of_vertices`] where there are
    /// vertices, else [`Shape::of`] the points.
    ///
    /// ```
    /// use glam::DVec2;
    /// use monoculus_core::geometry::HullGeometry;
    /// use monoculus_engine::resources::Shape;
    /// let pts = [DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::splat(0.25)];
    /// let shape = Shape::of_hull(&pts, &DVec2::hull_vertices(&pts));
    /// assert_eq!(shape.diameter, Shape::of(&pts).diameter);
    /// ```
    pub fn of_hull<P: IndexPoint>(points: &[P], vertices: &[P]) -> Shape {
        if vertices.is_empty() {
            Self::of(points)
        } else {
            Self::of_vertices(vertices)
        }
    }

    fn measured<P: IndexPoint>(points: &[P], (hull, diameter): (f64, f64)) -> Shape {
        let e = monoculus_core::metrics::extents(points);
        Shape {
            hull,
            hull_max: hull,
            diameter,
            extents: (0..P::DIM).map(|a| e.axis(a)).collect(),
        }
    }
}
