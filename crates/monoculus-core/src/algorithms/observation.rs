//! [`Observation`]: what an algorithm is given in one activation, with the queries of
//! its sensing model only, and the models themselves ([`Sensing`]).

use std::marker::PhantomData;

use super::ModelParams;
use crate::errors::Perception;
use crate::geometry::{AxisFrame, Point};
use crate::observe::{
    LdObservation, OlaObservation, PositionObservation, Seen, Side, sample_visible_point,
};
use crate::rng::Stream;
use crate::vision::Sight;

/// The sensing models, as values (configs, replays, tools).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Model {
    /// Unit directions only.
    Directions,
    /// Locality Detection: directions and far bits.
    Ld,
    /// Orthogonal Line Agreement: directions in agreed axes, the sides occupied.
    Ola,
    /// Positions of visible robots (baselines).
    Positions,
}

impl Model {
    /// The name in configs and replays: `directions`, `ld`, `ola`, `positions`.
    pub fn name(self) -> &'static str {
        match self {
            Model::Directions => "directions",
            Model::Ld => "ld",
            Model::Ola => "ola",
            Model::Positions => "positions",
        }
    }
}

mod sealed {
    pub trait Sealed {}
}

/// A sensing model, as a type: what an [`Observation`] of it can answer. Implemented by
/// [`Directions`], [`Ld`], [`Ola`] and [`Positions`] only.
pub trait Sensing: sealed::Sealed + Send + Sync + 'static {
    /// The model.
    const MODEL: Model;
}

/// Unit directions to the visible points, nothing else: the setting of the paper's
/// impossibility result (no algorithm in it converges from every start).
pub struct Directions;
/// Locality Detection: directions, and for each whether it is farther than c.
pub struct Ld;
/// Orthogonal Line Agreement: directions in a frame of the agreed axes (in an unknown
/// order and orientation), and which sides of each axis hold robots.
pub struct Ola;
/// Positions of the visible robots relative to the robot (baselines only: not a
/// monoculus model).
pub struct Positions;

macro_rules! sensing {
    ($($t:ident => $m:ident),*) => {$(
        impl sealed::Sealed for $t {}
        impl Sensing for $t {
            const MODEL: Model = Model::$m;
        }
    )*};
}
sensing!(Directions => Directions, Ld => Ld, Ola => Ola, Positions => Positions);

/// A robot's local frame: a rotation and chirality (directions, LD, positions), or the
/// agreed axes in an order and orientation of its own (OLA).
#[derive(Clone, Copy, Debug)]
pub enum LocalFrame<P: Point> {
    /// A rotation (with a mirror) of the global frame.
    Rotation(P::Frame),
    /// The agreed axes, permuted and signed.
    Axes(AxisFrame),
}

impl<P: Point> PartialEq for LocalFrame<P> {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (LocalFrame::Rotation(a), LocalFrame::Rotation(b)) => a == b,
            (LocalFrame::Axes(a), LocalFrame::Axes(b)) => a == b,
            _ => false,
        }
    }
}

impl<P: Point> LocalFrame<P> {
    /// A frame of `model` drawn from `stream`: uniform rotation and chirality, or a
    /// uniform order and orientation of the axes.
    pub fn draw(model: Model, stream: &mut Stream) -> Self {
        match model {
            Model::Ola => LocalFrame::Axes(AxisFrame::random(P::DIM, stream)),
            _ => LocalFrame::Rotation(P::random_frame(stream)),
        }
    }
}

/// What a robot keeps between activations when its algorithm has a state: its frame,
/// fixed for the run, and the state.
#[derive(Clone, Debug)]
pub struct Kept<P: Point, T> {
    /// The robot's local frame.
    pub frame: LocalFrame<P>,
    /// The algorithm's state.
    pub state: T,
}

impl<P: Point, T: PartialEq> PartialEq for Kept<P, T> {
    fn eq(&self, other: &Self) -> bool {
        self.frame == other.frame && self.state == other.state
    }
}

/// The queries of one activation, behind [`Observation`]: one call per query, each
/// answered for the concrete sight (its lines of sight inlined).
pub(crate) trait Probe<V> {
    fn sole_visible(&self) -> Option<V>;
    fn count_visible_up_to(&self, limit: usize) -> usize;
    fn random_visible(&self, stream: &mut Stream) -> Option<V>;
    fn random_far(&self, stream: &mut Stream) -> Option<V>;
    fn side_occupied(&self, axis: usize, side: Side) -> bool;
    fn random_in_orthant(&self, constraints: &[(usize, Side)], stream: &mut Stream) -> Option<V>;
    fn seen(&self) -> Vec<Seen<V>>;
    fn relative_positions(&self) -> Vec<V>;
    fn lit(&self) -> Vec<Lit<V>>;
    fn random_lit(&self, light: usize, stream: &mut Stream) -> Option<V>;
    fn sees_light(&self, light: usize) -> bool;
}

/// A visible point and the colour its robot shows (the luminous-robot model).
///
/// ```
/// use monoculus_core::algorithms::Lit;
/// use glam::DVec2;
///
/// let seen = Lit { direction: DVec2::X, light: 1 };
/// assert_eq!(seen.light, 1);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lit<V> {
    /// Unit direction in the robot's local frame.
    pub direction: V,
    /// The colour its robot shows: an index into the algorithm's
    /// [`Algorithm::LIGHTS`](super::Algorithm::LIGHTS) (0 for robots without lights).
    /// Robots sharing a point are one visible point, showing the colour of the one with
    /// the lowest index.
    pub light: usize,
}

/// The observation of one model over a concrete sight.
pub(crate) enum Looker<'a, P: Point, S: Sight<P> + ?Sized> {
    /// Directions and LD (directions ignore the far bits).
    Ld(LdObservation<'a, P, S>),
    /// OLA.
    Ola(OlaObservation<'a, P, S>),
    /// Positions (the LD observation answers the shared queries).
    Positions(LdObservation<'a, P, S>, PositionObservation<'a, P, S>),
}

impl<'a, P: Point, S: Sight<P> + ?Sized> Looker<'a, P, S> {
    /// Robot `me`'s observation in `model` through `frame`.
    pub(crate) fn new(
        model: Model,
        sight: &'a S,
        me: usize,
        frame: LocalFrame<P>,
        params: &ModelParams,
        perception: Perception,
    ) -> Self {
        let ld = |f| {
            LdObservation::with_perception(sight, me, f, params.locality, perception)
                .with_target(params.target)
        };
        match (model, frame) {
            (Model::Ola, LocalFrame::Axes(f)) => {
                Looker::Ola(OlaObservation::with_perception(sight, me, f, perception))
            }
            (Model::Positions, LocalFrame::Rotation(f)) => {
                Looker::Positions(ld(f), PositionObservation::new(sight, me, f))
            }
            (_, LocalFrame::Rotation(f)) => Looker::Ld(ld(f)),
            (_, LocalFrame::Axes(_)) => unreachable!("axes are OLA's frame"),
        }
    }

    /// A local decision's direction in the global frame.
    pub(crate) fn to_global(&self, frame: &LocalFrame<P>, v: P) -> P {
        match (self, frame) {
            (Looker::Ola(o), _) => o.to_global(v),
            (_, LocalFrame::Rotation(f)) => P::to_global(f, v),
            (_, LocalFrame::Axes(a)) => a.to_global(v),
        }
    }

    /// Robot `j`'s direction in the robot's local frame, as perceived.
    fn direction_of(&self, j: usize) -> P {
        match self {
            Looker::Ola(o) => o.local(j),
            _ => self.ld().local(j),
        }
    }

    fn ld(&self) -> &LdObservation<'a, P, S> {
        match self {
            Looker::Ld(o) | Looker::Positions(o, _) => o,
            Looker::Ola(_) => unreachable!("an LD query of an OLA observation"),
        }
    }

    fn ola(&self) -> &OlaObservation<'a, P, S> {
        match self {
            Looker::Ola(o) => o,
            _ => unreachable!("an OLA query of another model's observation"),
        }
    }
}

/// One robot's observation with the colours the robots show: what an [`Observation`]
/// asks.
pub(crate) struct Scene<'a, P: Point, S: Sight<P> + ?Sized> {
    /// The observation of the robot's model.
    pub(crate) looker: Looker<'a, P, S>,
    sight: &'a S,
    me: usize,
    /// Each robot's colour (empty: every robot shows colour 0).
    lights: &'a [u8],
}

impl<'a, P: Point, S: Sight<P> + ?Sized> Scene<'a, P, S> {
    /// Robot `me`'s observation in `model` through `frame`, with the robots showing
    /// `lights`.
    pub(crate) fn new(
        model: Model,
        (sight, lights): (&'a S, &'a [u8]),
        me: usize,
        frame: LocalFrame<P>,
        params: &ModelParams,
        perception: Perception,
    ) -> Self {
        Scene {
            looker: Looker::new(model, sight, me, frame, params, perception),
            sight,
            me,
            lights,
        }
    }

    fn light(&self, j: usize) -> usize {
        self.lights.get(j).map_or(0, |&l| l as usize)
    }
}

impl<P: Point, S: Sight<P> + ?Sized> Probe<P> for Scene<'_, P, S> {
    fn sole_visible(&self) -> Option<P> {
        self.looker.sole_visible()
    }

    fn count_visible_up_to(&self, limit: usize) -> usize {
        self.looker.count_visible_up_to(limit)
    }

    fn random_visible(&self, stream: &mut Stream) -> Option<P> {
        self.looker.random_visible(stream)
    }

    fn random_far(&self, stream: &mut Stream) -> Option<P> {
        self.looker.random_far(stream)
    }

    fn side_occupied(&self, axis: usize, side: Side) -> bool {
        self.looker.side_occupied(axis, side)
    }

    fn random_in_orthant(&self, constraints: &[(usize, Side)], stream: &mut Stream) -> Option<P> {
        self.looker.random_in_orthant(constraints, stream)
    }

    fn seen(&self) -> Vec<Seen<P>> {
        self.looker.seen()
    }

    fn relative_positions(&self) -> Vec<P> {
        self.looker.relative_positions()
    }

    fn lit(&self) -> Vec<Lit<P>> {
        self.sight
            .visible_points(self.me)
            .into_iter()
            .map(|j| Lit {
                direction: self.looker.direction_of(j),
                light: self.light(j),
            })
            .collect()
    }

    fn random_lit(&self, light: usize, stream: &mut Stream) -> Option<P> {
        let shows = |j: usize| self.light(j) == light;
        let nobody = || !(0..self.sight.len()).any(|j| j != self.me && shows(j));
        sample_visible_point(self.sight, self.me, &shows, &nobody, None, stream)
            .map(|j| self.looker.direction_of(j))
    }

    fn sees_light(&self, light: usize) -> bool {
        if self.lights.is_empty() {
            return light == 0 && self.looker.count_visible_up_to(1) > 0;
        }
        (0..self.sight.len()).any(|j| {
            j != self.me && self.light(j) == light && self.sight.is_visible_point(self.me, j)
        })
    }
}

impl<P: Point, S: Sight<P> + ?Sized> Looker<'_, P, S> {
    fn sole_visible(&self) -> Option<P> {
        match self {
            Looker::Ola(o) => o.sole_visible(),
            _ => self.ld().sole_visible(),
        }
    }

    fn count_visible_up_to(&self, limit: usize) -> usize {
        match self {
            Looker::Ola(o) => o.count_visible_up_to(limit),
            _ => self.ld().count_visible_up_to(limit),
        }
    }

    fn random_visible(&self, stream: &mut Stream) -> Option<P> {
        match self {
            Looker::Ola(o) => o.random_in_orthant(&[], stream),
            _ => self.ld().random_visible(stream),
        }
    }

    fn random_far(&self, stream: &mut Stream) -> Option<P> {
        self.ld().random_far(stream)
    }

    fn side_occupied(&self, axis: usize, side: Side) -> bool {
        self.ola().side_occupied(axis, side)
    }

    fn random_in_orthant(&self, constraints: &[(usize, Side)], stream: &mut Stream) -> Option<P> {
        self.ola().random_in_orthant(constraints, stream)
    }

    fn seen(&self) -> Vec<Seen<P>> {
        match self {
            Looker::Ola(o) => o
                .all()
                .into_iter()
                .map(|direction| Seen {
                    direction,
                    far: false,
                })
                .collect(),
            _ => self.ld().all(),
        }
    }

    fn relative_positions(&self) -> Vec<P> {
        match self {
            Looker::Positions(_, p) => p.relative_positions(),
            _ => unreachable!("positions of a model without them"),
        }
    }
}

/// What a robot senses in one activation, in its local frame, with the queries of its
/// sensing model `M` only: every model answers [`Observation::sole_visible`],
/// [`Observation::random_visible`], [`Observation::count_visible_up_to`] and
/// [`Observation::directions`]; [`Ld`] adds the far bits, [`Ola`] the sides of the
/// agreed axes, [`Positions`] the relative positions. No query of a model without
/// positions can return a position or a distance, and no query names a robot.
///
/// The queries are lazy: each costs what it needs (the sole visible point, a random far
/// point by rejection sampling, ...); [`Observation::directions`] and the other full
/// listings cost a full look (O(n log n)). Random choices are uniform over the eligible
/// visible points, drawn from the robot's stream by the procedure every algorithm
/// shares (see `observe`), so that any two sights of a swarm choose alike.
pub struct Observation<'a, M: Sensing, V> {
    probe: &'a dyn Probe<V>,
    dim: usize,
    model: PhantomData<M>,
}

impl<'a, M: Sensing, V: Point> Observation<'a, M, V> {
    pub(crate) fn new(probe: &'a dyn Probe<V>) -> Self {
        Observation {
            probe,
            dim: V::DIM,
            model: PhantomData,
        }
    }

    /// The dimension (2 or 3).
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// If exactly one point is visible, its direction.
    pub fn sole_visible(&self) -> Option<V> {
        self.probe.sole_visible()
    }

    /// The number of visible points, counted up to `limit` (so that it costs no more
    /// than `limit` lines of sight when more are visible).
    pub fn count_visible_up_to(&self, limit: usize) -> usize {
        self.probe.count_visible_up_to(limit)
    }

    /// The direction of a uniformly random visible point, if any.
    pub fn random_visible(&self, rng: &mut Stream) -> Option<V> {
        self.probe.random_visible(rng)
    }

    /// The directions of every visible point, in unspecified order (a full look).
    pub fn directions(&self) -> Vec<V> {
        self.probe.seen().into_iter().map(|s| s.direction).collect()
    }

    /// Every visible point with the colour its robot shows (the luminous-robot model:
    /// [`Algorithm::LIGHTS`](super::Algorithm::LIGHTS)), in the order of
    /// [`Observation::directions`] (a full look). Without lights every colour is 0.
    pub fn lit(&self) -> Vec<Lit<V>> {
        self.probe.lit()
    }

    /// The direction of a uniformly random visible point whose robot shows colour
    /// `light`, if any (the shared sampling procedure, as [`Observation::random_visible`]).
    pub fn random_lit(&self, light: usize, rng: &mut Stream) -> Option<V> {
        self.probe.random_lit(light, rng)
    }

    /// Whether a visible point's robot shows colour `light` (it costs a line of sight
    /// for each robot showing it, until one is visible).
    pub fn sees_light(&self, light: usize) -> bool {
        self.probe.sees_light(light)
    }
}

impl<V: Point> Observation<'_, Ld, V> {
    /// The direction of a uniformly random visible point farther than c, if any.
    pub fn random_far(&self, rng: &mut Stream) -> Option<V> {
        self.probe.random_far(rng)
    }

    /// Every visible point, with its far bit, in unspecified order (a full look).
    pub fn seen(&self) -> Vec<Seen<V>> {
        self.probe.seen()
    }
}

impl<V: Point> Observation<'_, Ola, V> {
    /// Whether a visible robot lies beyond the line (plane) through the robot normal to
    /// local axis `axis`, on `side`.
    pub fn side_occupied(&self, axis: usize, side: Side) -> bool {
        self.probe.side_occupied(axis, side)
    }

    /// For each local axis, whether its low and its high side hold a visible robot.
    pub fn sides_occupied(&self) -> Vec<[bool; 2]> {
        (0..self.dim)
            .map(|k| Side::BOTH.map(|s| self.probe.side_occupied(k, s)))
            .collect()
    }

    /// The direction of a uniformly random visible point in the closed orthant given by
    /// `constraints` (each a local axis and the side the point must lie on, with the
    /// tolerance `eps_axis`), if any.
    pub fn random_in_orthant(&self, constraints: &[(usize, Side)], rng: &mut Stream) -> Option<V> {
        self.probe.random_in_orthant(constraints, rng)
    }
}

impl<V: Point> Observation<'_, Positions, V> {
    /// The visible points relative to the robot, in its local frame.
    pub fn relative_positions(&self) -> Vec<V> {
        self.probe.relative_positions()
    }
}
