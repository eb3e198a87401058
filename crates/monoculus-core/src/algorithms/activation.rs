//! [`activate`]: one activation of any algorithm, the one entry point the engine calls
//! (and [`activate_together`] for algorithms that decide a round's activations in one
//! call); and what the engine may skip ([`certainly_stays`]).

use super::observation::Scene;
use super::{Algorithm, Decision, Kept, LocalFrame, Model, ModelParams, Observation, Sensing};
use crate::errors::Perception;
use crate::geometry::Point;
use crate::rng::Stream;
use crate::vision::Sight;

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

/// A decision that breaks the model (a step along a direction that is not a unit vector
/// or not finite, or a step bounded by a distance from an algorithm that senses none),
/// or an algorithm that panicked.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{algorithm}: {problem}")]
pub struct BadDecision {
    /// The algorithm's name.
    pub algorithm: String,
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
/// `kept` is the robot's frame and state when `A` keeps a state ([`Algorithm::keeps_state`]);
/// otherwise `None`, and the frame is drawn from `stream` first (a rotation and
/// chirality, or the agreed axes' order and orientation for OLA), then the perception's
/// errors, then whatever the algorithm draws. Every robot shows colour 0 (see
/// [`activate_lit`] for algorithms with lights).
pub fn activate<A: Algorithm, P: Point, S: Sight<P> + ?Sized>(
    algorithm: &A,
    params: &ModelParams,
    sight: &S,
    robot: usize,
    kept: Option<&mut Kept<P, A::State>>,
    stream: &mut Stream,
) -> Result<Option<P>, BadDecision> {
    activate_lit(algorithm, params, (sight, &[]), robot, kept, stream)
}

/// [`activate`] with the colour each robot shows (`lights[j]` for robot `j`, an index
/// into [`Algorithm::LIGHTS`]; robots beyond the slice show 0). The robot's light after
/// the activation ([`Algorithm::light`] of its state) must be in the palette.
///
/// ```
/// use glam::DVec2;
/// use monoculus_core::algorithms::{ModelParams, Median, activate_lit};
/// use monoculus_core::rng::Stream;
/// use monoculus_core::vision::{ExactSight, VisionParams};
///
/// let pts = vec![DVec2::ZERO, DVec2::X, DVec2::new(0.0, 1.0)];
/// let sight = ExactSight::new(pts, VisionParams::default());
/// let mut stream = Stream::new(7, 0, 0, 0);
/// // Median has no lights: the colours are there, and nothing asks for them.
/// let step = activate_lit(&Median, &ModelParams::new(1.0, 2.0), (&sight, &[0, 0, 0]), 0, None, &mut stream);
/// assert!(step.unwrap().is_some());
/// ```
pub fn activate_lit<A: Algorithm, P: Point, S: Sight<P> + ?Sized>(
    algorithm: &A,
    params: &ModelParams,
    (sight, lights): (&S, &[u8]),
    robot: usize,
    kept: Option<&mut Kept<P, A::State>>,
    stream: &mut Stream,
) -> Result<Option<P>, BadDecision> {
    let mut fresh = A::State::default();
    let (frame, state) = frame_and_state::<A, P>(kept, &mut fresh, stream);
    let perception = Perception::new(params.errors, stream);
    let scene = Scene::new(
        model_of::<A>(),
        (sight, lights),
        robot,
        frame,
        params,
        perception,
    );
    let decision = {
        let _deciding = Deciding::start();
        let obs = Observation::new(&scene);
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            algorithm.decide(&obs, state, stream)
        }))
        .map_err(|payload| panicked(algorithm, &*payload))?
    };
    check_light(algorithm, state)?;
    to_global(algorithm, params, &scene, &frame, decision)
}

/// An activation to decide: the robot, what it keeps (if its algorithm keeps a state),
/// its stream.
pub type Pending<'a, P, T> = (usize, Option<&'a mut Kept<P, T>>, Stream);

/// The activations of one round (ASYNC: one tick) of an algorithm that decides them
/// together ([`Algorithm::decides_together`]): each is (robot, its kept frame and state if `A`
/// keeps one, its stream), in the order given; each gets its frame and perception drawn
/// as in [`activate`], then [`Algorithm::decide_together`] decides them in one call. The
/// global displacements, in the same order (a panic fails every one). Robot `j` shows
/// colour `lights[j]` (see [`activate_lit`]).
pub fn activate_together<A: Algorithm, P: Point, S: Sight<P> + ?Sized>(
    algorithm: &A,
    params: &ModelParams,
    (sight, lights): (&S, &[u8]),
    activations: &mut [Pending<'_, P, A::State>],
) -> Vec<Result<Option<P>, BadDecision>> {
    let mut fresh: Vec<A::State> = (0..activations.len())
        .map(|_| A::State::default())
        .collect();
    let mut frames = Vec::with_capacity(activations.len());
    let mut states: Vec<&mut A::State> = Vec::with_capacity(activations.len());
    let mut scenes = Vec::with_capacity(activations.len());
    let mut streams: Vec<&mut Stream> = Vec::with_capacity(activations.len());
    for ((robot, kept, stream), spare) in activations.iter_mut().zip(fresh.iter_mut()) {
        let (frame, state) = frame_and_state::<A, P>(kept.as_deref_mut(), spare, stream);
        let perception = Perception::new(params.errors, stream);
        scenes.push(Scene::new(
            model_of::<A>(),
            (sight, lights),
            *robot,
            frame,
            params,
            perception,
        ));
        frames.push(frame);
        states.push(state);
        streams.push(stream);
    }
    let decided = {
        let _deciding = Deciding::start();
        let obs: Vec<Observation<'_, A::Sensing, P>> =
            scenes.iter().map(|l| Observation::new(l)).collect();
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            algorithm.decide_together(&obs, &mut states, &mut streams)
        }))
    };
    match decided {
        Err(payload) => {
            let bad = panicked(algorithm, &*payload);
            (0..scenes.len()).map(|_| Err(bad.clone())).collect()
        }
        Ok(decisions) if decisions.len() != scenes.len() => {
            let bad = BadDecision {
                algorithm: algorithm.name().to_string(),
                problem: format!(
                    "decided {} activations together, but there were {}",
                    decisions.len(),
                    scenes.len()
                ),
            };
            (0..scenes.len()).map(|_| Err(bad.clone())).collect()
        }
        Ok(decisions) => decisions
            .into_iter()
            .zip(scenes.iter().zip(&frames).zip(&states))
            .map(|(d, ((scene, frame), state))| {
                check_light(algorithm, state)?;
                to_global(algorithm, params, scene, frame, d)
            })
            .collect(),
    }
}

fn model_of<A: Algorithm>() -> Model {
    <A::Sensing as Sensing>::MODEL
}

/// The robot's frame and state: those it keeps, or a frame drawn now and `fresh`.
fn frame_and_state<'a, A: Algorithm, P: Point>(
    kept: Option<&'a mut Kept<P, A::State>>,
    fresh: &'a mut A::State,
    stream: &mut Stream,
) -> (LocalFrame<P>, &'a mut A::State) {
    match kept {
        Some(k) => (k.frame, &mut k.state),
        None => (LocalFrame::draw(model_of::<A>(), stream), fresh),
    }
}

/// The light a robot shows after its activation must be one of its algorithm's.
fn check_light<A: Algorithm>(algorithm: &A, state: &A::State) -> Result<(), BadDecision> {
    let light = A::light(state);
    let declared = algorithm.light_names().len();
    if light < declared.max(1) {
        return Ok(());
    }
    Err(BadDecision {
        algorithm: algorithm.name().to_string(),
        problem: format!(
            "shows light {light}, but declares {} (Algorithm::LIGHTS): a light is an index into them",
            match declared {
                0 => "no lights".to_string(),
                1 => "1 light".to_string(),
                k => format!("{k} lights"),
            }
        ),
    })
}

fn panicked<A: Algorithm>(algorithm: &A, payload: &(dyn std::any::Any + Send)) -> BadDecision {
    BadDecision {
        algorithm: algorithm.name().to_string(),
        problem: format!("panicked: {}", panic_message(payload)),
    }
}

/// A local decision checked (a unit direction; a bounded step only with positions) and
/// mapped to the global frame.
fn to_global<A: Algorithm, P: Point, S: Sight<P> + ?Sized>(
    algorithm: &A,
    params: &ModelParams,
    scene: &Scene<'_, P, S>,
    frame: &LocalFrame<P>,
    decision: Decision<P>,
) -> Result<Option<P>, BadDecision> {
    let model = model_of::<A>();
    let bad = |problem: String| BadDecision {
        algorithm: algorithm.name().to_string(),
        problem,
    };
    let unit = |dir: P| {
        let length = dir.length();
        if (length - 1.0).abs() <= UNIT_TOLERANCE {
            Ok(scene.looker.to_global(frame, dir))
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
