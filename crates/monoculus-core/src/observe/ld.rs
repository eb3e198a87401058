//! [`LdObservation`]: the Locality Detection model.

use super::{Candidates, count_visible_up_to, direction, sample_visible_point, sole_visible};
use crate::algorithms::TargetPolicy;
use crate::errors::Perception;
use crate::geometry::Point;
use crate::rng::Stream;
use crate::vision::Sight;

/// One visible point as an LD robot senses it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seen<P> {
    /// Unit direction in the robot's local frame.
    pub direction: P,
    /// Whether the point is farther than the locality constant c.
    pub far: bool,
}

/// What an LD robot senses in one activation: directions in a local frame (random
/// rotation and chirality) and one far/near bit per visible point.
pub struct LdObservation<'a, P: Point, S: Sight<P> + ?Sized> {
    sight: &'a S,
    me: usize,
    frame: P::Frame,
    locality: f64,
    perception: Perception,
    target: TargetPolicy,
}

impl<'a, P: Point, S: Sight<P> + ?Sized> LdObservation<'a, P, S> {
    /// The view of robot `me` in the local `frame`, with locality constant `locality`,
    /// perceived without errors.
    pub fn new(sight: &'a S, me: usize, frame: P::Frame, locality: f64) -> Self {
        Self::with_perception(sight, me, frame, locality, Perception::EXACT)
    }

    /// The same, perceived with observation errors.
    pub fn with_perception(
        sight: &'a S,
        me: usize,
        frame: P::Frame,
        locality: f64,
        perception: Perception,
    ) -> Self {
        LdObservation {
            sight,
            me,
            frame,
            locality,
            perception,
            target: TargetPolicy::Random,
        }
    }

    /// The same observation, drawing random targets with `target`.
    pub fn with_target(mut self, target: TargetPolicy) -> Self {
        self.target = target;
        self
    }

    /// The direction of robot `j` in the local frame, as perceived.
    pub(crate) fn local(&self, j: usize) -> P {
        P::to_local(
            &self.frame,
            self.perception
                .direction(j, direction(self.sight, self.me, j)),
        )
    }

    fn is_far(&self, j: usize) -> bool {
        let (p, q) = (self.sight.position(self.me), self.sight.position(j));
        self.perception.far(j, (q - p).length(), self.locality)
    }

    /// The number of visible points, counted up to `limit`.
    pub fn count_visible_up_to(&self, limit: usize) -> usize {
        count_visible_up_to(self.sight, self.me, limit).0
    }

    /// If exactly one point is visible, its direction.
    pub fn sole_visible(&self) -> Option<P> {
        sole_visible(self.sight, self.me).map(|j| self.local(j))
    }

    /// The direction of a uniformly random visible far point, if any.
    pub fn random_far(&self, stream: &mut Stream) -> Option<P> {
        let n = self.sight.len();
        let far = |j: usize| self.is_far(j);
        // Robots at the threshold or closer are never perceived far.
        let threshold = self.perception.far_threshold(self.locality);
        // Nobody is farther than the threshold iff the farthest robot is not: decided
        // from the farthest distance unless rounding could matter, then by counting.
        let nobody = || {
            let farthest = self.sight.farthest(self.me);
            let guard = 1e-12 * (farthest + threshold);
            if farthest > threshold + guard {
                false
            } else if farthest + guard <= threshold {
                true
            } else {
                self.sight.count_within(self.me, threshold) + 1 >= n
            }
        };
        let beyond = |f: &mut dyn FnMut(usize)| self.sight.for_each_beyond(self.me, threshold, f);
        let candidates = Candidates {
            list: &beyond,
            redraw: self.target == TargetPolicy::Random,
        };
        sample_visible_point(self.sight, self.me, &far, &nobody, Some(candidates), stream)
            .map(|j| self.local(j))
    }

    /// The direction of a uniformly random visible point, if any.
    pub fn random_visible(&self, stream: &mut Stream) -> Option<P> {
        sample_visible_point(self.sight, self.me, &|_| true, &|| false, None, stream)
            .map(|j| self.local(j))
    }

    /// Every visible point, in unspecified order. Costs a full look (O(n log n)).
    pub fn all(&self) -> Vec<Seen<P>> {
        self.sight
            .visible_points(self.me)
            .into_iter()
            .map(|j| Seen {
                direction: self.local(j),
                far: self.is_far(j),
            })
            .collect()
    }
}
