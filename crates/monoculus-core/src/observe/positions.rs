//! [`PositionObservation`]: the classical model with positions (baselines only).

use crate::geometry::Point;
use crate::vision::Sight;

/// Relative positions of the visible points in a local frame. This is the model of the
/// centre-of-gravity baseline (Cohen and Peleg), not of monoculus robots.
pub struct PositionObservation<'a, P: Point, S: Sight<P> + ?Sized> {
    sight: &'a S,
    me: usize,
    frame: P::Frame,
}

impl<'a, P: Point, S: Sight<P> + ?Sized> PositionObservation<'a, P, S> {
    /// The view of robot `me` in the local `frame`.
    pub fn new(sight: &'a S, me: usize, frame: P::Frame) -> Self {
        PositionObservation { sight, me, frame }
    }

    /// The visible points relative to the robot, in its local frame.
    pub fn relative_positions(&self) -> Vec<P> {
        let pos = self.sight.positions();
        let p = pos[self.me];
        self.sight
            .visible_points(self.me)
            .into_iter()
            .map(|j| P::to_local(&self.frame, pos[j] - p))
            .collect()
    }
}
