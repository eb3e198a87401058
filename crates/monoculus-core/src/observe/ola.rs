//! [`OlaObservation`]: the Orthogonal Line Agreement model.

use super::{count_visible_up_to, direction, sample_visible_point, sole_visible};
use crate::errors::Perception;
use crate::geometry::{AxisFrame, Point};
use crate::rng::Stream;
use crate::vision::{Sight, distinct};

/// One of the two sides of an agreed axis, in the robot's local orientation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// Toward negative local coordinates.
    Low,
    /// Toward positive local coordinates.
    High,
}

impl Side {
    /// The other side.
    pub fn opposite(self) -> Side {
        match self {
            Side::Low => Side::High,
            Side::High => Side::Low,
        }
    }

    /// -1 for `Low`, +1 for `High`.
    pub fn sign(self) -> f64 {
        match self {
            Side::Low => -1.0,
            Side::High => 1.0,
        }
    }

    /// Both sides.
    pub const BOTH: [Side; 2] = [Side::Low, Side::High];
}

/// What an OLA robot senses in one activation: directions in a local frame whose axes
/// are the agreed lines in unknown order and orientation, and which open half-spaces
/// beyond the hyperplanes through the robot hold robots.
pub struct OlaObservation<'a, P: Point, S: Sight<P> + ?Sized> {
    sight: &'a S,
    me: usize,
    frame: AxisFrame,
    perception: Perception,
    /// The perceived tilt of the agreed axes (observation errors), if any.
    tilt: Option<P::Frame>,
}

impl<'a, P: Point, S: Sight<P> + ?Sized> OlaObservation<'a, P, S> {
    /// The view of robot `me` in the local axis `frame`, perceived without errors.
    pub fn new(sight: &'a S, me: usize, frame: AxisFrame) -> Self {
        Self::with_perception(sight, me, frame, Perception::EXACT)
    }

    /// The same, perceived with observation errors: noisy directions and tilted axes.
    pub fn with_perception(
        sight: &'a S,
        me: usize,
        frame: AxisFrame,
        perception: Perception,
    ) -> Self {
        OlaObservation {
            sight,
            me,
            frame,
            perception,
            tilt: perception.tilt::<P>(),
        }
    }

    /// Maps a global vector into the robot's perceived (tilted) agreed axes.
    fn perceived(&self, v: P) -> P {
        match &self.tilt {
            Some(t) => P::to_local(t, v),
            None => v,
        }
    }

    /// Maps a local decision back to the global frame (through the tilt, if any).
    pub fn to_global(&self, local: P) -> P {
        let v = self.frame.to_global(local);
        match &self.tilt {
            Some(t) => P::to_global(t, v),
            None => v,
        }
    }

    /// The dimension (number of agreed axes).
    pub fn dim(&self) -> usize {
        P::DIM
    }

    /// The direction of robot `j` in the local axes, as perceived.
    pub(crate) fn local(&self, j: usize) -> P {
        let dir = self
            .perception
            .direction(j, direction(self.sight, self.me, j));
        self.frame.to_local(self.perceived(dir))
    }

    /// Whether a robot lies beyond the hyperplane through this robot normal to local
    /// axis `axis`, on `side`, by more than `eps_axis`. A robot in that open half-space
    /// has a visible robot there too (its nearest blocker lies on the same side), so
    /// this is what the robot sees; it is read off the swarm's bounding box in O(1).
    /// With a limited visibility range V only robots within V count (a blocker of one
    /// is within V too), found among the robots within V.
    ///
    /// With fat robots a robot in the half-space may be hidden by robots outside it: the
    /// visible points are listed (O(n) lines of sight).
    ///
    /// With tilted axes the half-space is no longer axis-aligned and the robots are
    /// scanned (O(n)).
    pub fn side_occupied(&self, axis: usize, side: Side) -> bool {
        let eps = self.sight.vision().eps_axis;
        let global =
            P::unit_axis(self.frame.global_axis(axis)) * (self.frame.sign(axis) * side.sign());
        let normal = match &self.tilt {
            Some(t) => P::to_global(t, global),
            None => global,
        };
        let at = |k: usize| self.sight.position(k);
        let p = at(self.me);
        let vision = *self.sight.vision();
        if vision.fat() {
            let seen = self.sight.visible_points(self.me);
            return seen.iter().any(|&k| (at(k) - p).dot(normal) > eps);
        }
        if vision.limited() {
            let mut occupied = false;
            self.sight.for_each_within(self.me, vision.range, &mut |k| {
                let q = at(k);
                occupied |= distinct(p, q, &vision) && (q - p).dot(normal) > eps;
            });
            return occupied;
        }
        if self.tilt.is_some() {
            return self
                .sight
                .positions()
                .iter()
                .any(|&q| (q - p).dot(normal) > eps);
        }
        let a = self.frame.global_axis(axis);
        let dir = side.sign() * self.frame.sign(axis); // +1: toward larger global coordinate
        let p = p.axis(a);
        let (lo, hi) = self.sight.bounds();
        if dir > 0.0 {
            hi.axis(a) > p + eps
        } else {
            lo.axis(a) < p - eps
        }
    }

    /// The number of visible points, counted up to `limit`.
    pub fn count_visible_up_to(&self, limit: usize) -> usize {
        count_visible_up_to(self.sight, self.me, limit).0
    }

    /// If exactly one point is visible, its direction.
    pub fn sole_visible(&self) -> Option<P> {
        sole_visible(self.sight, self.me).map(|j| self.local(j))
    }

    /// The direction of a uniformly random visible point in the closed orthant given by
    /// `constraints` (each: a local axis and the side the point must lie on, with
    /// tolerance `eps_axis`), if any.
    pub fn random_in_orthant(
        &self,
        constraints: &[(usize, Side)],
        stream: &mut Stream,
    ) -> Option<P> {
        let p = self.sight.position(self.me);
        let eps = self.sight.vision().eps_axis;
        let inside = |j: usize| {
            let d = self.perceived(self.sight.position(j) - p);
            constraints
                .iter()
                .all(|&(k, side)| side.sign() * self.frame.local_coord(d, k) >= -eps)
        };
        sample_visible_point(self.sight, self.me, &inside, &|| false, None, stream)
            .map(|j| self.local(j))
    }

    /// Every visible point's local direction, in unspecified order (a full look).
    pub fn all(&self) -> Vec<P> {
        self.sight
            .visible_points(self.me)
            .into_iter()
            .map(|j| self.local(j))
            .collect()
    }
}
