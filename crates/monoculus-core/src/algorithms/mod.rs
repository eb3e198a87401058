//! Algorithms: the [`Algorithm`] trait that every algorithm implements (the paper's six
//! below, and a user's in their own crate), what a robot senses in each model
//! ([`Observation`]), and [`activate`], the one entry point the engine calls: draw the
//! robot's frame, build its observation, run the algorithm, check the decision and map
//! it back to the global frame.

mod activation;
mod algorithm;
mod angle_bisector;
mod center_of_gravity;
mod converge_locality;
mod converge_quadrant;
mod goal;
mod median;
mod observation;
mod termination;
mod termination_bits;

pub use activation::{
    BadDecision, Pending, UNIT_TOLERANCE, activate, activate_lit, activate_together,
    certainly_stays, in_algorithm,
};
pub use algorithm::{Algorithm, MAX_LIGHTS, NoParams, StopCriterion};
pub use angle_bisector::AngleBisector;
pub use center_of_gravity::CenterOfGravity;
pub use converge_locality::ConvergeLocality;
pub use converge_quadrant::{ConvergeQuadrant, along, empty_sides};
pub use goal::Goal;
pub use median::Median;
pub use observation::{
    Directions, Kept, Ld, Lit, LocalFrame, Model, Observation, Ola, Positions, Sensing,
};
pub use termination::ConvergeQuadrantTermination;
pub use termination_bits::TerminationBits;

use crate::errors::ObservationErrors;

/// What an algorithm decides, in the robot's local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Decision<P> {
    /// Do not move.
    Stay,
    /// Move exactly the step length b along this unit direction (a rigid move).
    Step(P),
    /// Move along this unit direction by min(b, the given distance): for algorithms
    /// that sense [`Positions`] (the others know no distance).
    StepAtMost(P, f64),
}

/// The paper's algorithms, by name: a convenience for choosing one of them in code
/// (`AlgorithmKind::ConvergeLocality.name()`, or as an engine's algorithm). The engine
/// knows none of them: each is an [`Algorithm`] like any other.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AlgorithmKind {
    /// [`ConvergeLocality`] (LD), SPEC 4.1.
    ConvergeLocality,
    /// [`ConvergeQuadrant`] (OLA), SPEC 4.2.
    ConvergeQuadrant,
    /// [`ConvergeQuadrantTermination`] (OLA + 2 bits per axis), SPEC 4.3.
    ConvergeQuadrantTermination,
    /// [`CenterOfGravity`] (sees positions), SPEC 4.4.
    CenterOfGravity,
    /// [`Median`], SPEC 4.4.
    Median,
    /// [`AngleBisector`], SPEC 4.4.
    AngleBisector,
}

impl AlgorithmKind {
    /// Every one of them.
    pub const ALL: [AlgorithmKind; 6] = [
        AlgorithmKind::ConvergeLocality,
        AlgorithmKind::ConvergeQuadrant,
        AlgorithmKind::ConvergeQuadrantTermination,
        AlgorithmKind::CenterOfGravity,
        AlgorithmKind::Median,
        AlgorithmKind::AngleBisector,
    ];

    /// The config name ([`Algorithm::NAME`]).
    pub fn name(self) -> &'static str {
        match self {
            AlgorithmKind::ConvergeLocality => ConvergeLocality::NAME,
            AlgorithmKind::ConvergeQuadrant => ConvergeQuadrant::NAME,
            AlgorithmKind::ConvergeQuadrantTermination => ConvergeQuadrantTermination::NAME,
            AlgorithmKind::CenterOfGravity => CenterOfGravity::NAME,
            AlgorithmKind::Median => Median::NAME,
            AlgorithmKind::AngleBisector => AngleBisector::NAME,
        }
    }
}

/// How "choose any" draws (config `algorithm.target`). Both are uniform over the
/// eligible visible points; they differ only in how they use the random stream, so the
/// same seed gives different (equally distributed) runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TargetPolicy {
    /// Draw robots uniformly until one is eligible and visible (32 draws, then 256 more
    /// for the far points of LD); then draw among the robots that may be eligible (the
    /// robots farther than c, found by a range query) until one is eligible and visible,
    /// and list them all only after 32 more misses. The late rounds of a large
    /// ConvergeLocality run, where most robots see few far robots, then cost one line
    /// of sight per robot instead of one per far robot. Called `random_rejection`
    /// before it became the default (that name still selects it).
    #[default]
    #[serde(alias = "random_rejection")]
    Random,
    /// The reference procedure, the default before version 0.2: the same first 32
    /// draws, then list every eligible visible point and draw one of them. Exact but
    /// quadratic in the late rounds of large ConvergeLocality runs; kept for exact
    /// comparisons with earlier results.
    RandomListing,
}

/// The constants of the model every activation needs, whatever the algorithm: the step
/// length b, the locality constant c, the observation errors and how random choices
/// draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelParams {
    /// Step length b.
    pub step: f64,
    /// Locality constant c.
    pub locality: f64,
    /// Observation errors (off: [`ObservationErrors::NONE`]).
    pub errors: ObservationErrors,
    /// How "choose any" draws.
    pub target: TargetPolicy,
}

impl ModelParams {
    /// Error-free constants with steps of `step` and locality `locality`.
    pub fn new(step: f64, locality: f64) -> Self {
        ModelParams {
            step,
            locality,
            errors: ObservationErrors::NONE,
            target: TargetPolicy::Random,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{AlgorithmKind, ConvergeQuadrant};

    #[test]
    fn names_are_unique() {
        let names: std::collections::HashSet<&str> =
            AlgorithmKind::ALL.iter().map(|k| k.name()).collect();
        assert_eq!(names.len(), AlgorithmKind::ALL.len());
    }

    /// With a limited range a robot beyond it neither occupies a side nor lets the
    /// bounding box vouch that a robot stays.
    #[test]
    fn a_limited_range_hides_the_sides_beyond_it() {
        use crate::algorithms::{ModelParams, certainly_stays};
        use crate::vision::{ExactSight, VisionParams};
        use glam::DVec2;
        // Robot 1 between robot 0 (1 to its left) and robot 2 (10 to its right, and 10 up
        // and down from robots 3 and 4).
        let pts = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(11.0, 0.0),
            DVec2::new(1.0, 10.0),
            DVec2::new(1.0, -10.0),
        ];
        let params = ModelParams::new(1.0, 2.0);
        let unlimited = ExactSight::new(pts.clone(), VisionParams::default());
        let limited = ExactSight::new(
            pts,
            VisionParams {
                range: 2.0,
                ..VisionParams::default()
            },
        );
        let occupied = |sight: &ExactSight<DVec2>| sides_occupied(sight, 1);
        assert_eq!(occupied(&unlimited), [true; 4]);
        assert_eq!(occupied(&limited), [true, false, false, false]);
        assert!(certainly_stays::<ConvergeQuadrant, _, _>(
            &params, &unlimited, 1
        ));
        assert!(!certainly_stays::<ConvergeQuadrant, _, _>(
            &params, &limited, 1
        ));
    }

    /// Whether robot `me` sees a robot on each side of each axis: x low, x high, y low,
    /// y high.
    fn sides_occupied(sight: &crate::vision::ExactSight<glam::DVec2>, me: usize) -> [bool; 4] {
        use crate::geometry::AxisFrame;
        use crate::observe::{OlaObservation, Side};
        let obs = OlaObservation::new(sight, me, AxisFrame::identity(2));
        [
            (0, Side::Low),
            (0, Side::High),
            (1, Side::Low),
            (1, Side::High),
        ]
        .map(|(a, s)| obs.side_occupied(a, s))
    }

    /// With fat robots a side is occupied only by what the robot sees there: a robot
    /// hidden behind a fat robot on the other side of the axis does not count, and the
    /// bounding box vouches for nothing.
    #[test]
    fn fat_robots_hide_a_side_behind_them() {
        use crate::algorithms::{ModelParams, certainly_stays};
        use crate::vision::{ExactSight, VisionParams};
        use glam::DVec2;
        // Robot 0 sees robot 1 just below the x axis, 1 ahead; robot 2 lies 5 ahead just
        // above it, hidden by robot 1's disc (radius 0.3); robots 3 and 4 occupy the
        // other sides.
        let pts = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, -0.1),
            DVec2::new(5.0, 0.2),
            DVec2::new(-3.0, -1.0),
            DVec2::new(-2.0, -4.0),
        ];
        let params = ModelParams::new(1.0, 2.0);
        let points = ExactSight::new(pts.clone(), VisionParams::default());
        let fat = ExactSight::new(
            pts,
            VisionParams {
                robot_radius: 0.3,
                ..VisionParams::default()
            },
        );
        let occupied = |sight: &ExactSight<DVec2>| sides_occupied(sight, 0);
        assert_eq!(occupied(&points), [true; 4]);
        assert_eq!(occupied(&fat), [true, true, true, false]);
        assert!(certainly_stays::<ConvergeQuadrant, _, _>(
            &params, &points, 0
        ));
        assert!(!certainly_stays::<ConvergeQuadrant, _, _>(&params, &fat, 0));
    }
}
