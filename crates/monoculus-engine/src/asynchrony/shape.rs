//! [`KeptShape`]: the shape of the swarm at each tick, from the robots that can be on
//! its hull.

use bevy_ecs::prelude::*;

use super::Timing;
use super::kept_hull::{InnerBoxes, KeptHull};
use super::roster::Roster;
use crate::IndexPoint;
use crate::resources::Shape;

/// What the shape of the swarm at a tick (hull, diameter, extents) is computed from,
/// kept across ticks: the hull of the robots at rest ([`KeptHull`]), and the robots in
/// mid-move whose segment is not certainly strictly inside it (those inside its core
/// are set aside until the core changes, those between the core and the hull are looked
/// at again whenever the hull shrinks). Every other robot lies strictly inside a hull of robots
/// of the swarm, so it is no vertex of the swarm's hull: the hull over these points has
/// the vertices of the hull over all robots, and the measures (all taken from the
/// vertices, extents included) are the same to the bit (checked against the full
/// computation at every tick in debug builds, so in every test).
///
/// In space the shape is taken over all robots.
#[derive(Resource, Clone, Debug)]
pub struct KeptShape<P: IndexPoint> {
    /// The robots at rest, by robot.
    rest: KeptHull<P>,
    /// Movers whose segment may leave the hull of `rest`: robot, start point, clock.
    outside: Roster<(P, Timing<P>)>,
    /// Movers whose segment was strictly inside the hull of `rest`, not its core.
    between: Roster<(P, Timing<P>)>,
    /// The core and the shrinks of `rest` the movers were sorted against.
    seen: (u64, u64),
}

impl<P: IndexPoint> Default for KeptShape<P> {
    fn default() -> Self {
        Self::new()
    }
}

impl<P: IndexPoint> KeptShape<P> {
    /// For a swarm at rest.
    pub fn new() -> Self {
        KeptShape {
            rest: KeptHull::new(),
            outside: Roster::sparse(),
            between: Roster::sparse(),
            seen: (0, 0),
        }
    }

    /// Whether the whole segment of a mover, and every point within the rounding of
    /// an interpolation along it, lies strictly inside the polygon (`inside` its exact
    /// test): the corners of the boxes of that size around both ends do.
    ///
    /// `boxes` are closed boxes inside the polygon: where one holds every tested point
    /// (the box of both ends, widened by the room, rounded as the points are), no point
    /// is tested alone.
    fn certainly_inside(from: P, to: P, boxes: &InnerBoxes<P>, inside: impl Fn(P) -> bool) -> bool {
        let e = Self::room(from, to);
        let (x, y) = ((from.axis(0), to.axis(0)), (from.axis(1), to.axis(1)));
        // (In space there are no boxes. A NaN coordinate, which `min` and `max` would
        // drop, is left to the points' own tests.)
        if !(x.0.is_nan() | x.1.is_nan() | y.0.is_nan() | y.1.is_nan()) {
            // Each tested point's coordinate is an end's plus or minus the room, rounded:
            // rounding is monotone, so these bound every one of them.
            let (x0, x1) = (x.0.min(x.1) - e, x.0.max(x.1) + e);
            let (y0, y1) = (y.0.min(y.1) - e, y.0.max(y.1) + e);
            let held = boxes.iter().flatten().any(|(lo, hi)| {
                (x0 >= lo.axis(0)) & (x1 <= hi.axis(0)) & (y0 >= lo.axis(1)) & (y1 <= hi.axis(1))
            });
            if held {
                return true;
            }
        }
        [from, to].into_iter().all(|p| {
            (0..1usize << P::DIM).all(|corner| {
                let q = (0..P::DIM).fold(p, |q, a| {
                    let sign = if corner >> a & 1 == 1 { e } else { -e };
                    q + P::unit_axis(a) * sign
                });
                inside(q)
            })
        })
    }

    /// How far around both ends of a mover's segment [`Self::certainly_inside`] tests.
    fn room(from: P, to: P) -> f64 {
        let scale = (0..P::DIM)
            .map(|a| from.axis(a).abs().max(to.axis(a).abs()))
            .fold(0.0, f64::max);
        16.0 * f64::EPSILON * scale + f64::MIN_POSITIVE
    }

    /// Whether a point [`Self::certainly_inside`] tests for a mover's segment may lie
    /// in one of the closed boxes `lost`: the box of both ends, widened by twice the
    /// room (each tested point is an end moved by the room on every axis, rounded),
    /// meets one of them.
    fn may_meet(lost: &[(P, P)], from: P, to: P) -> bool {
        let e = 2.0 * Self::room(from, to);
        lost.iter().any(|(lo, hi)| {
            (0..P::DIM).all(|a| {
                let (x, y) = (from.axis(a), to.axis(a));
                (x.min(y) - e <= hi.axis(a)) & (x.max(y) + e >= lo.axis(a))
            })
        })
    }

    /// Sorts a mover: set aside inside the core, between the core and the hull, or
    /// outside.
    fn track(&mut self, robot: u32, from: P, timing: Timing<P>) {
        let to = timing.target(from);
        if !self.rest.core().is_empty()
            && Self::certainly_inside(from, to, self.rest.core_boxes(), |q| self.rest.in_core(q))
        {
            return;
        }
        self.track_beyond_core(robot, from, timing);
    }

    /// Sorts a mover whose segment is not certainly inside the core: between the core
    /// and the hull, or outside.
    fn track_beyond_core(&mut self, robot: u32, from: P, timing: Timing<P>) {
        let to = timing.target(from);
        if Self::certainly_inside(from, to, self.rest.hull_boxes(), |q| self.rest.in_hull(q)) {
            self.between.insert(robot, (from, timing));
        } else {
            self.outside.insert(robot, (from, timing));
        }
    }

    /// Robot `robot` starts a move from `from` (its clock says where to and when).
    pub fn depart(&mut self, robot: u32, from: P, timing: Timing<P>) {
        self.rest.remove(robot);
        self.track(robot, from, timing);
    }

    /// Robot `robot` ended its move at `at`, and is at rest there.
    pub fn arrive(&mut self, robot: u32, at: P) {
        self.outside.remove(robot);
        self.between.remove(robot);
        self.rest.insert(robot, at);
    }

    /// Brings what is kept up to date with the tick's events (in the plane). `robots`
    /// lists every robot's start point and clock (a pass made as often as needed): it
    /// is read only when the hull at rest must be taken again over all robots, or the
    /// movers sorted again against a new core.
    pub fn refresh<I: Iterator<Item = (u32, P, Timing<P>)>>(&mut self, robots: impl Fn() -> I) {
        if P::DIM != 2 {
            return;
        }
        let moving = |t: &Timing<P>| t.phase == super::Phase::Move && t.pending().is_some();
        self.rest.vertices(|| {
            robots()
                .filter(|(_, _, timing)| !moving(timing))
                .map(|(robot, from, _)| (robot, from))
        });
        if self.rest.generation() != self.seen.0 {
            // A new core: the movers are sorted against it.
            self.outside.clear();
            self.between.clear();
            for (robot, from, timing) in robots().filter(|(_, _, timing)| moving(timing)) {
                self.track(robot, from, timing);
            }
        } else if self.rest.shrinks() != self.seen.1 {
            // A smaller hull: the movers that were inside it where it lost ground are
            // looked at again (against the same core, which they were not certainly
            // inside); the others are still strictly inside it (`KeptHull::lost`).
            let lost = self.rest.lost();
            let again: Vec<u32> = self
                .between
                .iter()
                .filter(|&&(_, (from, timing))| Self::may_meet(lost, from, timing.target(from)))
                .map(|&(robot, _)| robot)
                .collect();
            for robot in again {
                if let Some((from, timing)) = self.between.take(robot) {
                    self.track_beyond_core(robot, from, timing);
                }
            }
        }
        self.seen = (self.rest.generation(), self.rest.shrinks());
    }

    /// Of a [refreshed](KeptShape::refresh) shape in the plane: points at `tick` whose
    /// hull is the swarm's (every vertex of the swarm's hull is among them, and every
    /// other point is one of the swarm's): the vertices at rest and the movers that may
    /// be outside them.
    pub fn points(&self, tick: u64) -> Vec<P> {
        let mut points = self.rest.hull().to_vec();
        points.extend(
            self.outside
                .iter()
                .map(|&(_, (from, timing))| timing.position_at(from, tick)),
        );
        points
    }

    /// The shape at `tick`. `robots` lists every robot's start point and clock (a pass
    /// made as often as needed): it is read only when the hull at rest must be taken
    /// again over all robots, or in space.
    pub fn shape<I: Iterator<Item = (u32, P, Timing<P>)>>(
        &mut self,
        tick: u64,
        robots: impl Fn() -> I,
    ) -> Shape {
        if P::DIM != 2 {
            return Shape::of(&P::hull_candidates_of(|| {
                robots().map(|(_, from, timing)| timing.position_at(from, tick))
            }));
        }
        self.refresh(robots);
        Shape::of(&self.points(tick))
    }
}

/// What the farthest robot from a point is taken from at the ticks after a
/// [refreshed](KeptShape::refresh) shape's, for Looks decided ahead
/// ([`KeptShape::ahead`]): the vertices of the hull at rest, each with the tick from
/// which it may no longer be a robot's (a robot at rest there leaves), and the segments
/// that may leave that hull.
#[derive(Clone, Debug, Default)]
pub(crate) struct AheadShape<P> {
    /// A vertex of the hull at rest, and the tick at which a robot at rest there starts
    /// a move, so that it is elsewhere at every later tick (`u64::MAX`: none does).
    vertices: Vec<(P, u64)>,
    /// Segments that may leave the hull at rest: from, to, the ticks of the move.
    movers: Vec<(P, P, u64, u64)>,
}

impl<P: IndexPoint> AheadShape<P> {
    /// The distance from `p` to the farthest robot at `tick`, if these points tell it:
    /// `None` where the farthest of them is a vertex whose robot has left by then.
    pub(crate) fn farthest(&self, p: P, tick: u64) -> Option<f64> {
        if self.vertices.is_empty() {
            return None;
        }
        let (mut real, mut left) = (0.0f64, 0.0f64);
        for &(v, leaves) in &self.vertices {
            let d = (v - p).length();
            if leaves < tick {
                left = left.max(d);
            } else {
                real = real.max(d);
            }
        }
        for &(from, to, since, until) in &self.movers {
            let at = super::components::on_move(from, to, since, until, tick);
            real = real.max((at - p).length());
        }
        (left <= real).then_some(real)
    }
}

impl<P: IndexPoint> KeptShape<P> {
    /// The points the farthest robot from any point is found among at the ticks after
    /// the one this shape was [refreshed](KeptShape::refresh) at (in the plane), where
    /// `departing` (robot at rest, from, its move's clock) start their moves in
    /// between: the vertices at rest, the movers that may leave their hull, and those
    /// of `departing` whose segment is not certainly strictly inside it. Any other robot
    /// lies strictly inside the hull at rest, nearer than one of its vertices.
    pub(crate) fn ahead(&self, departing: impl Iterator<Item = (P, Timing<P>)>) -> AheadShape<P> {
        let mut vertices: Vec<(P, u64)> = self.rest.hull().iter().map(|&v| (v, u64::MAX)).collect();
        let mut movers: Vec<(P, P, u64, u64)> = self
            .outside
            .iter()
            .map(|&(_, (from, t))| (from, t.target(from), t.since, t.until))
            .collect();
        for (from, t) in departing {
            for (v, leaves) in vertices.iter_mut() {
                if *v == from {
                    *leaves = (*leaves).min(t.since);
                }
            }
            let to = t.target(from);
            if !Self::certainly_inside(from, to, self.rest.hull_boxes(), |q| self.rest.in_hull(q)) {
                movers.push((from, to, t.since, t.until));
            }
        }
        AheadShape { vertices, movers }
    }
}

/// A disc inside the convex polygon `hull` (counter-clockwise, at least three
/// vertices; else an empty disc): around the mean of the vertices, with the smallest
/// distance from it to an edge's line, shrunk by a millionth for rounding.
pub(crate) fn inner_disc<P: IndexPoint>(hull: &[P]) -> (P, f64) {
    if hull.len() < 3 || P::DIM != 2 {
        return (P::zero(), f64::NEG_INFINITY);
    }
    let centre = hull.iter().fold(P::zero(), |c, &v| c + v) * (1.0 / hull.len() as f64);
    let radius = (0..hull.len())
        .map(|k| {
            let (a, b) = (hull[k], hull[(k + 1) % hull.len()]);
            let (e, r) = (b - a, centre - a);
            // The distance from `centre` to the line through a and b.
            (e.axis(0) * r.axis(1) - e.axis(1) * r.axis(0)).abs() / e.length()
        })
        .fold(f64::INFINITY, f64::min);
    (
        centre,
        if radius.is_finite() {
            radius * (1.0 - 1e-6)
        } else {
            f64::NEG_INFINITY
        },
    )
}

/// Whether `p` is certainly strictly inside the polygon whose [`inner_disc`] is `disc`:
/// well inside the disc, with room for rounding.
pub(crate) fn in_disc<P: IndexPoint>((centre, radius): (P, f64), p: P) -> bool {
    let scale = (0..P::DIM)
        .map(|a| p.axis(a).abs().max(centre.axis(a).abs()))
        .fold(0.0, f64::max);
    let room = radius - 16.0 * f64::EPSILON * scale - 1e-9 * (scale + radius);
    (p - centre).length() < room
}

#[cfg(test)]
mod tests {
    use glam::DVec2;
    use monoculus_core::geometry::HullGeometry;
    use monoculus_core::rng::Stream;

    use super::KeptShape;
    use crate::asynchrony::boxes::{in_boxes, inner_boxes};
    use crate::asynchrony::kept_hull::tests::polygons;
    use crate::asynchrony::{Phase, Timing};

    /// For Looks decided ahead: the farthest robot found from the hull at rest, the
    /// movers that may leave it and the robots that start moving after the shape's tick
    /// is, where told, the farthest of all robots at each later tick, to the bit; it is
    /// not told exactly where the farthest of those points is a vertex whose robot left
    /// (robots leave from hull vertices too, some outward).
    #[test]
    fn the_farthest_robot_ahead_is_the_farthest_of_all() {
        let mut rng = Stream::new(16, 0, 0, 0);
        let (mut told, mut untold) = (0, 0);
        for trial in 0..40 {
            let n = 20 + 10 * (trial % 5);
            let now = 100;
            let mut robots: Vec<(u32, DVec2, Timing<DVec2>)> = (0..n as u32)
                .map(|r| {
                    let from = DVec2::new(rng.uniform_in(-5.0, 5.0), rng.uniform_in(-5.0, 5.0));
                    let d = DVec2::new(rng.uniform_in(-3.0, 3.0), rng.uniform_in(-3.0, 3.0));
                    let timing = if rng.below(3) == 0 {
                        let since = now - rng.below(20) as u64;
                        Timing::new(
                            Phase::Move,
                            since,
                            now + 1 + rng.below(30) as u64,
                            1,
                            0,
                            Some(d),
                        )
                    } else {
                        Timing::new(Phase::Idle, 0, now + 50, 0, 0, None)
                    };
                    (r, from, timing)
                })
                .collect();
            let mut shape = KeptShape::<DVec2>::new();
            shape.refresh(|| robots.clone().into_iter());
            // Robots at rest that start moving after `now`: hull vertices first.
            let hull = shape.rest.hull().to_vec();
            let mut departing = Vec::new();
            for (_, from, timing) in robots.iter_mut() {
                let vertex = hull.contains(from);
                if timing.phase == Phase::Idle && (vertex || rng.below(4) == 0) && rng.below(2) == 0
                {
                    let d = DVec2::new(rng.uniform_in(-3.0, 3.0), rng.uniform_in(-3.0, 3.0));
                    let since = now + 1 + rng.below(20) as u64;
                    *timing = Timing::new(
                        Phase::Move,
                        since,
                        since + 1 + rng.below(30) as u64,
                        1,
                        0,
                        Some(d),
                    );
                    departing.push((*from, *timing));
                }
            }
            let ahead = shape.ahead(departing.iter().copied());
            for tick in now + 1..now + 60 {
                let at: Vec<DVec2> = robots
                    .iter()
                    .map(|&(_, from, t)| match t.phase {
                        Phase::Move if tick >= t.until => t.target(from),
                        Phase::Move if tick > t.since => t.position_at(from, tick),
                        _ => from,
                    })
                    .collect();
                for k in 0..8 {
                    let p = if k < 4 {
                        at[rng.below(n)]
                    } else {
                        DVec2::new(rng.uniform_in(-9.0, 9.0), rng.uniform_in(-9.0, 9.0))
                    };
                    let all = at.iter().map(|&q| (q - p).length()).fold(0.0, f64::max);
                    match ahead.farthest(p, tick) {
                        Some(far) => {
                            assert_eq!(
                                far.to_bits(),
                                all.to_bits(),
                                "trial {trial} tick {tick} from {p}"
                            );
                            told += 1;
                        }
                        None => untold += 1,
                    }
                }
            }
        }
        assert!(
            told > 20 * untold && untold > 0,
            "told {told}, not told {untold}"
        );
    }

    /// A segment held by one of the boxes inside a polygon is certainly inside it
    /// exactly when every point tested alone is, and every point tested lies in the
    /// boxes: segments at random around each polygon, and segments whose ends lie on
    /// the boxes' edges and corners or a rounding step beyond them, far from the origin
    /// as well as near it.
    #[test]
    fn the_boxes_answer_as_the_points_tested_alone() {
        let mut rng = Stream::new(15, 0, 0, 0);
        let mut held = 0;
        for (name, poly) in polygons(&mut rng) {
            for shift in [DVec2::ZERO, DVec2::new(1e6, -3e5)] {
                let poly: Vec<DVec2> = poly.iter().map(|&v| v + shift).collect();
                let poly = DVec2::hull_vertices(&poly);
                let boxes = inner_boxes(&poly);
                let inside = |q: DVec2| in_boxes(&boxes, q) || DVec2::strictly_inside(&poly, q);
                let mut ends: Vec<DVec2> = Vec::new();
                if !poly.is_empty() {
                    let (lo, hi) = monoculus_core::metrics::bounds(&poly);
                    let pad = (hi - lo) * 0.2 + 1.0;
                    ends.extend((0..200).map(|_| {
                        DVec2::new(
                            rng.uniform_in(lo.x - pad.x, hi.x + pad.x),
                            rng.uniform_in(lo.y - pad.y, hi.y + pad.y),
                        )
                    }));
                }
                for (lo, hi) in boxes.into_iter().flatten() {
                    for (x, y) in [(lo.x, lo.y), (hi.x, lo.y), (hi.x, hi.y), (lo.x, hi.y)] {
                        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (-1, -1), (1, 1), (2, -2)] {
                            let step = |v: f64, d: i32| match d {
                                0 => v,
                                d if d > 0 => (0..d).fold(v, |v, _| v.next_up()),
                                d => (0..-d).fold(v, |v, _| v.next_down()),
                            };
                            ends.push(DVec2::new(step(x, dx), step(y, dy)));
                        }
                        ends.push(DVec2::new(x, (lo.y + hi.y) / 2.0));
                        ends.push(DVec2::new((lo.x + hi.x) / 2.0, y));
                    }
                }
                for (k, &from) in ends.iter().enumerate() {
                    for &to in ends.iter().skip(k).step_by(7).take(40) {
                        let fast = KeptShape::<DVec2>::certainly_inside(from, to, &boxes, inside);
                        let alone =
                            KeptShape::<DVec2>::certainly_inside(from, to, &[None; 3], inside);
                        assert_eq!(fast, alone, "{name} {shift}: {from} -> {to}");
                        // Where a box holds the segment (the answer without any point
                        // tested alone), it holds every point tested.
                        let by_boxes =
                            KeptShape::<DVec2>::certainly_inside(from, to, &boxes, |_| false);
                        let boxes_only = |q: DVec2| in_boxes(&boxes, q);
                        assert!(
                            !by_boxes
                                || KeptShape::<DVec2>::certainly_inside(
                                    from, to, &[None; 3], boxes_only
                                ),
                            "{name} {shift}: {from} -> {to} held, a point outside the boxes"
                        );
                        held += usize::from(by_boxes);
                    }
                }
            }
        }
        assert!(held > 1000, "{held} segments held by a box");
    }
}
