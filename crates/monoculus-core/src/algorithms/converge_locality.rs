//! ConvergeLocality (SPEC 4.1).

use super::Decision;
use crate::geometry::Point;
use crate::observe::LdObservation;
use crate::rng::Stream;
use crate::vision::Sight;

/// 1. exactly one point visible: move toward it; 2. else toward a random far point;
/// 3. else stay.
pub fn decide<P: Point, S: Sight<P> + ?Sized>(
    obs: &LdObservation<'_, P, S>,
    stream: &mut Stream,
) -> Decision<P> {
    if let Some(dir) = obs.sole_visible() {
        return Decision::Step(dir);
    }
    match obs.random_far(stream) {
        Some(dir) => Decision::Step(dir),
        None => Decision::Stay,
    }
}
