//! The algorithms of SPEC section 4 and the one entry point the engine calls,
//! [`activate`]: draw the robot's frame, build its observation, run the algorithm,
//! map the decision back to the global frame.

mod angle_bisector;
mod center_of_gravity;
mod converge_locality;
mod converge_quadrant;
mod median;
mod memory;
mod termination;

pub use memory::RobotMemory;

use crate::errors::{ObservationErrors, Perception};
use crate::geometry::{AxisFrame, Point};
use crate::observe::{LdObservation, OlaObservation, PositionObservation};
use crate::rng::Stream;
use crate::vision::Sight;

/// What an algorithm decides, in the robot's local frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Decision<P> {
    /// Do not move.
    Stay,
    /// Move exactly the step length b along this unit direction (a rigid move).
    Step(P),
    /// Move along this unit direction by min(b, the given distance) (baselines that
    /// know distances).
    StepAtMost(P, f64),
}

/// The algorithms (config `algorithm.name`, in snake case as [`AlgorithmKind::name`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AlgorithmKind {
    /// ConvergeLocality (LD), SPEC 4.1.
    ConvergeLocality,
    /// ConvergeQuadrant (OLA), SPEC 4.2.
    ConvergeQuadrant,
    /// ConvergeQuadrantTermination (OLA + 2 bits per axis), SPEC 4.3.
    ConvergeQuadrantTermination,
    /// Move toward the centroid of the visible points (sees positions), SPEC 4.4.
    CenterOfGravity,
    /// Boundary robots move toward the median visible point, SPEC 4.4.
    Median,
    /// Boundary robots move along the bisector of their visible angle, SPEC 4.4.
    AngleBisector,
}

/// The sensing model an algorithm runs in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// Locality Detection: directions and far bits.
    Ld,
    /// Orthogonal Line Agreement: directions in agreed axes.
    Ola,
    /// Positions of visible robots (baselines).
    Positions,
}

impl AlgorithmKind {
    /// Every algorithm.
    pub const ALL: [AlgorithmKind; 6] = [
        AlgorithmKind::ConvergeLocality,
        AlgorithmKind::ConvergeQuadrant,
        AlgorithmKind::ConvergeQuadrantTermination,
        AlgorithmKind::CenterOfGravity,
        AlgorithmKind::Median,
        AlgorithmKind::AngleBisector,
    ];

    /// The config name.
    pub fn name(self) -> &'static str {
        match self {
            AlgorithmKind::ConvergeLocality => "converge_locality",
            AlgorithmKind::ConvergeQuadrant => "converge_quadrant",
            AlgorithmKind::ConvergeQuadrantTermination => "converge_quadrant_termination",
            AlgorithmKind::CenterOfGravity => "center_of_gravity",
            AlgorithmKind::Median => "median",
            AlgorithmKind::AngleBisector => "angle_bisector",
        }
    }

    /// The sensing model.
    pub fn model(self) -> Model {
        match self {
            AlgorithmKind::ConvergeLocality
            | AlgorithmKind::Median
            | AlgorithmKind::AngleBisector => Model::Ld,
            AlgorithmKind::ConvergeQuadrant | AlgorithmKind::ConvergeQuadrantTermination => {
                Model::Ola
            }
            AlgorithmKind::CenterOfGravity => Model::Positions,
        }
    }

    /// Whether robots keep state between activations (the termination bits).
    pub fn has_memory(self) -> bool {
        self == AlgorithmKind::ConvergeQuadrantTermination
    }

    /// Whether the paper's guarantees assume c >= 2b for this algorithm.
    pub fn needs_locality_at_least_twice_step(self) -> bool {
        matches!(
            self,
            AlgorithmKind::ConvergeLocality
                | AlgorithmKind::ConvergeQuadrant
                | AlgorithmKind::ConvergeQuadrantTermination
        )
    }
}

/// How "choose any" draws (config `algorithm.target`). Both are uniform over the
/// eligible visible points; they differ only in how they use the random stream, so the
/// same seed gives different (equally distributed) runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TargetPolicy {
    /// Draw robots uniformly until one is eligible and visible (32 draws, then 256 more
    /// for ConvergeLocality); then draw among the robots that may be eligible (the
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

/// Parameters every activation needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlgorithmParams {
    /// Which algorithm.
    pub kind: AlgorithmKind,
    /// Step length b.
    pub step: f64,
    /// Locality constant c.
    pub locality: f64,
    /// Observation errors (off: [`ObservationErrors::NONE`]).
    pub errors: ObservationErrors,
    /// How "choose any" draws.
    pub target: TargetPolicy,
}

impl AlgorithmParams {
    /// Error-free parameters.
    pub fn new(kind: AlgorithmKind, step: f64, locality: f64) -> Self {
        AlgorithmParams {
            kind,
            step,
            locality,
            errors: ObservationErrors::NONE,
            target: TargetPolicy::Random,
        }
    }
}

/// Whether an activation of `robot` is sure to decide Stay and leave its memory as it
/// is, from the bounding box alone: an OLA robot (perceiving without errors) with robots
/// beyond it on both sides of every axis is an inner robot: E is empty, no termination
/// bit is set, and it sees at least two points (SPEC 4.2, 4.3). Its random stream is
/// its own, so skipping the activation changes nothing else. Most robots of a
/// ConvergeQuadrant run are inner robots.
pub fn certainly_stays<P: Point, S: Sight<P> + ?Sized>(
    params: &AlgorithmParams,
    sight: &S,
    robot: usize,
) -> bool {
    // With a limited range or fat robots the bounding box says nothing about what a
    // robot sees.
    let v = sight.vision();
    if params.kind.model() != Model::Ola || params.errors.any() || v.limited() || v.fat() {
        return false;
    }
    let eps = sight.vision().eps_axis;
    let p = sight.position(robot);
    let (lo, hi) = sight.bounds();
    // The tests of `OlaObservation::side_occupied`, for both sides of every axis.
    (0..P::DIM).all(|a| hi.axis(a) > p.axis(a) + eps && lo.axis(a) < p.axis(a) - eps)
}

/// One activation of robot `robot`: returns its global displacement, or `None` to stay.
///
/// `memory` is the robot's persistent state (termination algorithm only; `None` for
/// the others). `stream` is the robot's random stream for this activation; its frame
/// (for memoryless algorithms) is drawn from it first.
pub fn activate<P: Point, S: Sight<P> + ?Sized>(
    params: &AlgorithmParams,
    sight: &S,
    robot: usize,
    memory: Option<&mut RobotMemory>,
    stream: &mut Stream,
) -> Option<P> {
    let b = params.step;
    match params.kind.model() {
        Model::Ld | Model::Positions => {
            let frame = P::random_frame(stream);
            let perception = Perception::new(params.errors, stream);
            let ld = || {
                LdObservation::with_perception(sight, robot, frame, params.locality, perception)
                    .with_target(params.target)
            };
            let decision = match params.kind {
                AlgorithmKind::ConvergeLocality => converge_locality::decide(&ld(), stream),
                AlgorithmKind::Median => median::decide(&ld()),
                AlgorithmKind::AngleBisector => angle_bisector::decide(&ld()),
                AlgorithmKind::CenterOfGravity => {
                    center_of_gravity::decide(&PositionObservation::new(sight, robot, frame))
                }
                _ => unreachable!("model dispatch"),
            };
            to_global(decision, b, |v| P::to_global(&frame, v))
        }
        Model::Ola => {
            let (frame, memory) = match memory {
                Some(m) if params.kind.has_memory() => (m.frame, Some(m)),
                _ => (AxisFrame::random(P::DIM, stream), None),
            };
            let obs = OlaObservation::with_perception(
                sight,
                robot,
                frame,
                Perception::new(params.errors, stream),
            );
            let decision = match (params.kind, memory) {
                (AlgorithmKind::ConvergeQuadrant, _) => converge_quadrant::decide(&obs, stream),
                (AlgorithmKind::ConvergeQuadrantTermination, Some(memory)) => {
                    termination::decide(&obs, memory, stream)
                }
                (AlgorithmKind::ConvergeQuadrantTermination, None) => {
                    panic!("the termination algorithm needs robot memory")
                }
                _ => unreachable!("model dispatch"),
            };
            to_global(decision, b, |v| obs.to_global(v))
        }
    }
}

fn to_global<P: Point>(decision: Decision<P>, step: f64, map: impl Fn(P) -> P) -> Option<P> {
    match decision {
        Decision::Stay => None,
        Decision::Step(dir) => Some(map(dir) * step),
        Decision::StepAtMost(dir, dist) => Some(map(dir) * step.min(dist)),
    }
}

#[cfg(test)]
mod tests {
    use super::AlgorithmKind;

    #[derive(serde::Deserialize)]
    struct Named {
        name: AlgorithmKind,
    }

    #[test]
    fn config_names_are_the_display_names() {
        for kind in AlgorithmKind::ALL {
            let parsed: Named = toml_like(kind.name());
            assert_eq!(parsed.name, kind);
        }
    }

    /// With a limited range a robot beyond it neither occupies a side nor lets the
    /// bounding box vouch that a robot stays.
    #[test]
    fn a_limited_range_hides_the_sides_beyond_it() {
        use crate::algorithms::{AlgorithmParams, certainly_stays};
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
        let params = AlgorithmParams::new(AlgorithmKind::ConvergeQuadrant, 1.0, 2.0);
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
        assert!(certainly_stays(&params, &unlimited, 1));
        assert!(!certainly_stays(&params, &limited, 1));
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
        use crate::algorithms::{AlgorithmParams, certainly_stays};
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
        let params = AlgorithmParams::new(AlgorithmKind::ConvergeQuadrant, 1.0, 2.0);
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
        assert!(certainly_stays(&params, &points, 0));
        assert!(!certainly_stays(&params, &fat, 0));
    }

    /// Deserialises `{ name = "<name>" }` through serde's value deserializer.
    fn toml_like(name: &str) -> Named {
        use serde::de::IntoDeserializer;
        use serde::de::value::{Error, MapDeserializer};
        let map = MapDeserializer::<_, Error>::new(std::iter::once(("name", name)));
        serde::Deserialize::deserialize(map.into_deserializer()).unwrap()
    }
}
