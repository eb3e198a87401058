//! The naive "median" strategy of the paper's Figure 1 (SPEC 4.4).

use super::{Algorithm, Decision, Ld, NoParams, Observation, StopCriterion};
use crate::geometry::Point;
use crate::rng::Stream;

/// Why the naive strategies need the plane.
pub(crate) const ANGULAR_ORDER: &str =
    "is defined by angular order in the plane (the paper's Figure 1)";

/// Directions of the visible points in angular order, starting just after the widest
/// angular gap, when that gap is at least pi (the robot is a boundary robot: all
/// visible points lie in a closed half-plane). `None` for inner robots and robots that
/// see nothing. Planar: the angle is taken in the first two local coordinates.
pub(crate) fn boundary_fan<P: Point>(dirs: &[P]) -> Option<Vec<(f64, P)>> {
    if dirs.is_empty() {
        return None;
    }
    let mut fan: Vec<(f64, P)> = dirs
        .iter()
        .map(|&d| (d.axis(1).atan2(d.axis(0)), d))
        .collect();
    fan.sort_by(|a, b| a.0.total_cmp(&b.0));
    let m = fan.len();
    let (mut widest, mut after) = (0.0, 0);
    for i in 0..m {
        let next = (i + 1) % m;
        let mut gap = fan[next].0 - fan[i].0;
        if next <= i {
            gap += std::f64::consts::TAU;
        }
        if gap > widest {
            widest = gap;
            after = next;
        }
    }
    if widest < std::f64::consts::PI - 1e-12 {
        return None;
    }
    fan.rotate_left(after);
    Some(fan)
}

/// The naive "median" strategy of the paper's Figure 1 (SPEC 4.4): a boundary robot
/// moves b toward the median visible point in angular order (the lower median for an
/// even count, in the robot's own chirality); others stay. It can grow the hull.
#[derive(Clone, Copy, Debug, Default)]
pub struct Median;

impl Algorithm for Median {
    const NAME: &'static str = "median";
    type Sensing = Ld;
    type Params = NoParams;
    type State = ();
    const STOP: StopCriterion = StopCriterion::Diameter;
    const PLANE_ONLY: Option<&'static str> = Some(ANGULAR_ORDER);

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(Median)
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Ld, V>,
        _: &mut (),
        _: &mut Stream,
    ) -> Decision<V> {
        match boundary_fan(&obs.directions()) {
            Some(fan) => Decision::Step(fan[(fan.len() - 1) / 2].1),
            None => Decision::Stay,
        }
    }
}
