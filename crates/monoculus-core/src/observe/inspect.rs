//! What one robot senses, point by point, for tools that show it (`monoculus look`): the
//! directions and far bits an LD observation gives, and the sides an OLA observation
//! reads, computed by the same helpers, in the global frame and without errors, each with
//! the index of the robot that represents the visible point. Not for algorithms: an index
//! identifies a robot, which monoculus robots cannot do.

use super::direction;
use crate::errors::Perception;
use crate::geometry::Point;
use crate::vision::Sight;

/// One visible point as a tool shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct Looked<P> {
    /// The lowest index of the robots at the point.
    pub index: usize,
    /// Unit direction in the global frame.
    pub direction: P,
    /// LD: farther than the locality constant.
    pub far: bool,
    /// OLA: on which side of the observer the point lies on each axis, beyond the
    /// tolerance `eps_axis`: -1, 0 or 1.
    pub sides: Vec<i8>,
}

/// Every point robot `me` sees, in the order the sight lists them.
pub fn inspect<P: Point, S: Sight<P> + ?Sized>(
    sight: &S,
    me: usize,
    locality: f64,
) -> Vec<Looked<P>> {
    let pos = sight.positions();
    let eps = sight.vision().eps_axis;
    sight
        .visible_points(me)
        .into_iter()
        .map(|j| {
            let d = pos[j] - pos[me];
            Looked {
                index: j,
                direction: direction(sight, me, j),
                far: Perception::EXACT.far(j, d.length(), locality),
                sides: (0..P::DIM)
                    .map(|k| {
                        let c = d.axis(k);
                        if c > eps {
                            1
                        } else if c < -eps {
                            -1
                        } else {
                            0
                        }
                    })
                    .collect(),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vision::{ExactSight, VisionParams};
    use glam::DVec2;

    #[test]
    fn shows_what_the_robot_senses_and_nothing_hidden() {
        // Robot 2 hides behind robot 1; robot 3 is far, up and to the left.
        let pts = vec![
            DVec2::ZERO,
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(-3.0, 4.0),
        ];
        let sight = ExactSight::new(pts, VisionParams::default());
        let mut seen = inspect(&sight, 0, 2.0);
        seen.sort_by_key(|s| s.index);
        assert_eq!(seen.len(), 2);
        assert_eq!((seen[0].index, seen[0].far), (1, false));
        assert_eq!(seen[0].sides, vec![1, 0]);
        assert_eq!((seen[1].index, seen[1].far), (3, true));
        assert_eq!(seen[1].sides, vec![-1, 1]);
        assert!((seen[1].direction - DVec2::new(-0.6, 0.8)).length() < 1e-15);
    }
}
