//! Algorithms: the [`Algorithm`] trait that every algorithm implements (the paper's six
//! below, and a user's in their own crate), what a robot senses in each model
//! ([`Observation`]), and [`activate`], the one entry point the engine calls: draw the
//! robot's frame, build its observation, run the algorithm, check the decision and map
//! it back to the global frame.

mod algorithm;
mod angle_bisector;
mod center_of_gravity;
mod converge_locality;
mod converge_quadrant;
mod median;
mod observation;
mod termination;
mod termination_bits;

pub use algorithm::{Algorithm, NoParams, StopCriterion};
pub use angle_bisector::AngleBisector;
pub use center_of_gravity::CenterOfGravity;
pub use converge_locality::ConvergeLocality;
pub use converge_quadrant::{ConvergeQuadrant, along, empty_sides};
pub use median::Median;
pub use observation::{
    Directions, Kept, Ld, LocalFrame, Model, Observation, Ola, Positions, Sensing,
};
pub use termination::ConvergeQuadrantTermination;
pub use termination_bits::TerminationBits;

use crate::errors::{ObservationErrors, Perception};
use crate::geometry::Point;
use crate::rng::Stream;
use crate::vision::Sight;
use observation::Looker;

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

/// Whether an activation of `robot` by `A` is sure to decide Stay and leave its state as
/// it is, from the bounding box alone: `A` promises it
/// ([`Algorithm::STAYS_WHEN_SURROUNDED`]) for an OLA robot with robots beyond it on both
/// sides of every axis, and the robot perceives without errors, unlimited and through
/// point robots (else the box says nothing of what it sees). Its random stream is its
/// own, so skipping the activation changes nothing else. Most robots of a
/// ConvergeQuadrant run are such inner robots.
pub fn certainly_stays<A: Algorithm, P: Point, S: Sight<P> + ?Sized>(
    params: &ModelParams,
    sight: &S,
    robot: usize,
) -> bool {
    if !(A::STAYS_WHEN_SURROUNDED && <A::Sensing as Sensing>::MODEL == Model::Ola) {
        return false;
    }
    let v = sight.vision();
    if params.errors.any() || v.limited() || v.fat() {
        return false;
    }
    let eps = v.eps_axis;
    let p = sight.position(robot);
    let (lo, hi) = sight.bounds();
    // The tests of `OlaObservation::side_occupied`, for both sides of every axis.
    (0..P::DIM).all(|a| hi.axis(a) > p.axis(a) + eps && lo.axis(a) < p.axis(a) - eps)
}

/// Whether `A` keeps a state (and its robots a frame) between activations.
pub const fn keeps_state<A: Algorithm>() -> bool {
    std::mem::size_of::<A::State>() != 0
}

/// A decision that breaks the model (a step along a direction that is not a unit vector
/// or not finite, or a step bounded by a distance from an algorithm that senses none),
/// or an algorithm that panicked.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{algorithm}: {problem}")]
pub struct BadDecision {
    /// The algorithm's name.
    pub algorithm: &'static str,
    /// What is wrong.
    pub problem: String,
}

thread_local! {
    static DECIDING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether this thread is inside an algorithm's [`Algorithm::decide`]: a panic hook can
/// tell an algorithm's panic (which [`activate`] turns into a failed run) from a bug.
pub fn in_algorithm() -> bool {
    DECIDING.with(std::cell::Cell::get)
}

/// Marks this thread as deciding until dropped (also when `decide` unwinds).
struct Deciding;

impl Deciding {
    fn start() -> Self {
        DECIDING.with(|d| d.set(true));
        Deciding
    }
}

impl Drop for Deciding {
    fn drop(&mut self) {
        DECIDING.with(|d| d.set(false));
    }
}

/// The message of a panic's payload.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".into())
}

/// How far from 1 a step's direction may be in length.
pub const UNIT_TOLERANCE: f64 = 1e-6;

/// One activation of robot `robot` by `algorithm`: its global displacement, or `None`
/// to stay.
///
/// `kept` is the robot's frame and state when `A` keeps a state ([`keeps_state`]);
/// otherwise `None`, and the frame is drawn from `stream` first (a rotation and
/// chirality, or the agreed axes' order and orientation for [`Ola`]), then the
/// perception's errors, then whatever the algorithm draws.
pub fn activate<A: Algorithm, P: Point, S: Sight<P> + ?Sized>(
    algorithm: &A,
    params: &ModelParams,
    sight: &S,
    robot: usize,
    kept: Option<&mut Kept<P, A::State>>,
    stream: &mut Stream,
) -> Result<Option<P>, BadDecision> {
    let model = <A::Sensing as Sensing>::MODEL;
    let mut fresh = A::State::default();
    let (frame, state) = match kept {
        Some(k) => (k.frame, &mut k.state),
        None => (LocalFrame::draw(model, stream), &mut fresh),
    };
    let perception = Perception::new(params.errors, stream);
    let looker = Looker::new(model, sight, robot, frame, params, perception);
    let bad = |problem: String| BadDecision {
        algorithm: A::NAME,
        problem,
    };
    let decision = {
        let _deciding = Deciding::start();
        let obs = Observation::new(&looker);
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            algorithm.decide(&obs, state, stream)
        }))
        .map_err(|payload| bad(format!("panicked: {}", panic_message(&*payload))))?
    };
    let unit = |dir: P| {
        let length = dir.length();
        if (length - 1.0).abs() <= UNIT_TOLERANCE {
            Ok(looker.to_global(&frame, dir))
        } else {
            Err(bad(format!(
                "decided a step along {dir:?}, of length {length}: a direction must be a unit vector"
            )))
        }
    };
    match decision {
        Decision::Stay => Ok(None),
        Decision::Step(dir) => Ok(Some(unit(dir)? * params.step)),
        Decision::StepAtMost(_, _) if model != Model::Positions => Err(bad(format!(
            "decided a step bounded by a distance, but it senses {}, which gives no distance (only positions do)",
            model.name()
        ))),
        Decision::StepAtMost(_, dist) if dist.is_nan() || dist < 0.0 => Err(bad(format!(
            "decided a step of at most {dist}: the bound must be a distance, at least 0"
        ))),
        Decision::StepAtMost(dir, dist) => Ok(Some(unit(dir)? * params.step.min(dist))),
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
