//! ConvergeQuadrant with diagonal corners: the Remark of Pattanayak, Mondal, Mandal and
//! Schmid after their ConvergeQuadrant (OLA), that a corner robot could move diagonally.
//!
//! A robot sees the agreed axes in an order and orientation of its own. Let E be the
//! (axis, side) pairs whose side is empty while the opposite side is not. As in
//! ConvergeQuadrant: a robot that sees one point moves toward it; an inner robot (E
//! empty) stays; a boundary robot (|E| = 1) moves along that axis toward the robots.
//! A corner robot (|E| >= 2) moves along the diagonal of the axes of E toward the
//! robots (at pi/4 between the two axes in the plane; in space, between two axes, or
//! along the octant's diagonal) instead of toward a random visible point of that
//! quadrant.

use monoculus::prelude::*;

/// ConvergeQuadrant whose corner robots move diagonally.
pub struct DiagonalCorners;

impl Algorithm for DiagonalCorners {
    const NAME: &'static str = "diagonal_corners";
    type Sensing = Ola;
    type Params = NoParams;
    type State = ();
    const STOP: StopCriterion = StopCriterion::Box;
    const ASSUMES_C_AT_LEAST_2B: bool = true;
    // An inner robot stays, as in ConvergeQuadrant.
    const STAYS_WHEN_SURROUNDED: bool = true;

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(DiagonalCorners)
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Ola, V>,
        _: &mut (),
        _: &mut Stream,
    ) -> Decision<V> {
        let e = empty_sides(obs);
        if e.is_empty() {
            // An inner robot sees robots on both sides of some axis (or on none: then
            // it may see a single point).
            return match obs.sole_visible() {
                Some(toward) if obs.sides_occupied().iter().all(|s| s == &[false, false]) => {
                    Decision::Step(toward)
                }
                _ => Decision::Stay,
            };
        }
        if let Some(toward) = obs.sole_visible() {
            return Decision::Step(toward);
        }
        // Along each axis of E, toward the side that holds robots; their sum, made a
        // unit vector, is the diagonal.
        let sum = e.iter().fold(V::zero(), |acc, &(axis, empty)| {
            acc + along::<V>(axis, empty.opposite())
        });
        Decision::Step(sum.normalized())
    }
}
