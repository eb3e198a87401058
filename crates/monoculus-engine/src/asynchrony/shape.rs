//! [`KeptShape`]: the shape of the swarm at each tick, from the robots that can be on
//! its hull.

use bevy_ecs::prelude::*;

use super::Timing;
use super::roster::Roster;
use crate::IndexPoint;
use crate::resources::Shape;

/// What the shape of the swarm at a tick (hull, diameter, extents) is computed from,
/// kept across ticks: the hull of the robots at rest, and the robots in mid-move
/// whose segment is not certainly strictly inside it. Every other robot lies strictly
/// inside a hull of robots of the swarm, so it is no vertex of the swarm's hull: the
/// hull over these points has the vertices of the hull over all robots, and the
/// measures (all taken from the vertices, extents included) are the same to the bit
/// (checked against the full computation at every tick in debug builds, so in every
/// test). A move that starts at a vertex of the robots at rest makes their hull be taken
/// again over all robots (about once per cycle per vertex).
///
/// In space, and while the robots at rest have fewer than three hull vertices, the
/// shape is taken over all robots.
#[derive(Resource, Clone, Debug)]
pub struct KeptShape<P: IndexPoint> {
    /// The hull of the robots at rest (valid while `kept`).
    rest: Vec<P>,
    /// A disc certainly inside `rest`, as centre and radius: the cheap first test.
    disc: (P, f64),
    kept: bool,
    /// Whether a robot that may be a vertex of `rest` started to move.
    stale: bool,
    /// Movers whose segment may leave `rest`: robot, start point, clock.
    outside: Roster<(P, Timing<P>)>,
    /// Shapes asked for since the hull at rest was last taken over all robots.
    since_rebuild: u32,
    /// Shapes still to take over all robots, keeping nothing: where the hull at rest
    /// must be taken again within a few ticks (short cycles), keeping it costs more
    /// than it saves.
    plain: u32,
    /// Hulls at rest in a row that lasted fewer than [`SHORT_LIVED`] shapes.
    short: u32,
}

/// A hull at rest that lasts fewer shapes than this, [`STRIKES`] times in a row...
const SHORT_LIVED: u32 = 4;
/// (once is chance: a fine time resolution with two vertices leaving close together)...
const STRIKES: u32 = 3;
/// ...makes this many shapes be taken over all robots before trying again.
const PLAIN: u32 = 64;

impl<P: IndexPoint> KeptShape<P> {
    /// For a swarm at rest at `initial`.
    pub fn new(initial: &[P]) -> Self {
        let rest = P::hull_vertices(initial);
        KeptShape {
            kept: rest.len() >= 3,
            disc: inner_disc(&rest),
            rest,
            stale: false,
            outside: Roster::new(initial.len()),
            since_rebuild: 0,
            plain: 0,
            short: 0,
        }
    }

    /// Whether the whole segment of a mover, and every point within the rounding of
    /// an interpolation along it, lies strictly inside the hull at rest: the corners of
    /// the boxes of that size around both ends are.
    fn certainly_inside(&self, from: P, to: P) -> bool {
        let scale = (0..P::DIM)
            .map(|a| from.axis(a).abs().max(to.axis(a).abs()))
            .fold(0.0, f64::max);
        let e = 16.0 * f64::EPSILON * scale + f64::MIN_POSITIVE;
        // The disc is convex: both ends well inside it put the segment inside.
        let (centre, radius) = self.disc;
        let room = radius - e - 1e-9 * (scale + radius);
        if [from, to].iter().all(|&p| (p - centre).length() < room) {
            return true;
        }
        [from, to].into_iter().all(|p| {
            (0..1usize << P::DIM).all(|corner| {
                let q = (0..P::DIM).fold(p, |q, a| {
                    let sign = if corner >> a & 1 == 1 { e } else { -e };
                    q + P::unit_axis(a) * sign
                });
                P::strictly_inside(&self.rest, q)
            })
        })
    }

    /// Keeps a mover among those that may leave the hull at rest unless it certainly
    /// does not (by the disc, then by the exact test of its ends: the disc alone left
    /// a third of the movers of fine-grained runs to be taken at every tick).
    fn track(&mut self, robot: u32, from: P, timing: Timing<P>) {
        if self.certainly_inside(from, timing.target(from)) {
            return;
        }
        // A robot departs only once its last move ended, which untracked it.
        self.outside.insert(robot, (from, timing));
    }

    /// Robot `robot` starts a move from `from` (its clock says where to and when).
    pub fn depart(&mut self, robot: u32, from: P, timing: Timing<P>) {
        if !self.kept || self.stale {
            return;
        }
        if !P::strictly_inside(&self.rest, from) {
            self.stale = true;
            return;
        }
        self.track(robot, from, timing);
    }

    /// Robot `robot` ended its move at `at`, and is at rest there.
    pub fn arrive(&mut self, robot: u32, at: P) {
        self.outside.remove(robot);
        if !self.kept || self.stale || P::strictly_inside(&self.rest, at) {
            return;
        }
        let mut points = std::mem::take(&mut self.rest);
        points.push(at);
        self.rest = P::hull_vertices(&points);
        self.kept = self.rest.len() >= 3;
        // The hull grew: the old disc is still inside it.
    }

    /// The shape at `tick`. `robots` lists every robot's start point and clock (a pass
    /// made as often as needed): it is read only when the hull at rest must be taken
    /// again over all robots, or where nothing is kept.
    pub fn shape<I: Iterator<Item = (u32, P, Timing<P>)>>(
        &mut self,
        tick: u64,
        robots: impl Fn() -> I,
    ) -> Shape {
        // Every robot's position at `tick`, down to those that may be on the hull.
        let all = || {
            Shape::of(&P::hull_candidates_of(|| {
                robots().map(|(_, from, timing)| timing.position_at(from, tick))
            }))
        };
        if P::DIM != 2 {
            return all();
        }
        if self.plain > 0 {
            self.plain -= 1;
            return all();
        }
        if self.stale {
            self.short = if self.since_rebuild < SHORT_LIVED {
                self.short + 1
            } else {
                0
            };
        }
        if self.stale && self.short >= STRIKES {
            self.short = 0;
            self.kept = false;
            self.plain = PLAIN;
            // Taken again over all robots once the plain shapes are done.
            self.since_rebuild = SHORT_LIVED;
            return all();
        }
        if self.stale || !self.kept {
            self.rebuild(&robots);
            self.since_rebuild = 0;
            if !self.kept {
                // Fewer than three vertices at rest (a line of robots): nothing to keep.
                self.plain = PLAIN;
                self.since_rebuild = SHORT_LIVED;
                return all();
            }
        }
        self.since_rebuild = self.since_rebuild.saturating_add(1);
        let mut points = self.rest.clone();
        points.extend(
            self.outside
                .iter()
                .map(|&(_, (from, timing))| timing.position_at(from, tick)),
        );
        Shape::of(&points)
    }

    fn rebuild<I: Iterator<Item = (u32, P, Timing<P>)>>(&mut self, robots: &impl Fn() -> I) {
        let moving = |t: &Timing<P>| t.phase == super::Phase::Move && t.pending.is_some();
        let at_rest = P::hull_candidates_of(|| {
            robots()
                .filter(|(_, _, timing)| !moving(timing))
                .map(|(_, from, _)| from)
        });
        self.rest = P::hull_vertices(&at_rest);
        self.kept = self.rest.len() >= 3;
        self.disc = inner_disc(&self.rest);
        self.stale = false;
        self.outside.clear();
        if self.kept {
            for (robot, from, timing) in robots().filter(|(_, _, timing)| moving(timing)) {
                self.track(robot, from, timing);
            }
        }
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
