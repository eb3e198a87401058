//! The naive "angle bisector" strategy of the paper's Figure 1 (SPEC 4.4).

use super::median::{ANGULAR_ORDER, boundary_fan};
use super::{Algorithm, Decision, Ld, NoParams, Observation, StopCriterion};
use crate::geometry::Point;
use crate::rng::Stream;

/// The naive "angle bisector" strategy of the paper's Figure 1 (SPEC 4.4): a boundary
/// robot moves b along the bisector of the angle spanned by its visible points; others
/// stay. Planar. It can grow the hull.
#[derive(Clone, Copy, Debug, Default)]
pub struct AngleBisector;

impl Algorithm for AngleBisector {
    const NAME: &'static str = "angle_bisector";
    type Sensing = Ld;
    type Params = NoParams;
    type State = ();
    const STOP: StopCriterion = StopCriterion::Diameter;
    const PLANE_ONLY: Option<&'static str> = Some(ANGULAR_ORDER);

    fn new(_: NoParams) -> Result<Self, String> {
        Ok(AngleBisector)
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, Ld, V>,
        _: &mut (),
        _: &mut Stream,
    ) -> Decision<V> {
        let Some(fan) = boundary_fan(&obs.directions()) else {
            return Decision::Stay;
        };
        let first = fan[0].0;
        let mut span = fan[fan.len() - 1].0 - first;
        if span < 0.0 {
            span += std::f64::consts::TAU;
        }
        let mid = first + span / 2.0;
        let mut c = [0.0; crate::geometry::MAX_DIM];
        c[0] = mid.cos();
        c[1] = mid.sin();
        Decision::Step(V::from_slice(&c))
    }
}
