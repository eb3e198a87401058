//! [`CommittedHull`]: the hull of the committed points, kept from one tick to the next.

use bevy_ecs::prelude::*;

use super::kept_hull::KeptHull;
use crate::IndexPoint;

/// The hull of the committed points (every robot's position at the start of its phase
/// and the destination of every decided move, the points whose hull Lemma 2 bounds),
/// kept across ticks ([`KeptHull`]): a tick changes that set only by its events (a
/// Look adds a destination, the end of a move removes where the move began, the
/// destination becoming the robot's position), so the hull is taken again only over
/// the points outside its core when a point that may be a vertex is removed, and over
/// every committed point only when the core leaves that hull. The vertex sequence is
/// that of the chain over every committed point, so the measure is the same to the bit
/// (checked against the full computation at every tick in debug builds, so in every
/// test).
///
/// Point ids: `2 r` is robot r's position at the start of its phase, `2 r + 1` its
/// destination. In space the hull is taken over all committed points at every tick.
#[derive(Resource, Clone, Debug)]
pub struct CommittedHull<P: IndexPoint> {
    kept: KeptHull<P>,
    measure: f64,
    /// The hull's count of times taken when `measure` was (in the plane): while it
    /// stays, the vertices and so the measure do.
    measured: Option<u64>,
}

impl<P: IndexPoint> CommittedHull<P> {
    /// No move decided yet, the hull's measure `measure`.
    pub fn new(measure: f64) -> Self {
        CommittedHull {
            kept: KeptHull::new(),
            measure,
            measured: None,
        }
    }

    /// The measure last taken (at the start, that of the initial positions).
    pub fn last(&self) -> f64 {
        self.measure
    }

    /// A Look decided robot `robot`'s move to `p`.
    pub fn decide(&mut self, robot: u32, p: P) {
        self.kept.insert(2 * robot + 1, p);
    }

    /// Robot `robot`'s move ended: where it began leaves the set, and its destination is
    /// its position.
    pub fn arrive(&mut self, robot: u32) {
        self.kept.remove(2 * robot);
        self.kept.rekey(2 * robot + 1, 2 * robot);
    }

    /// The measure of the hull after this tick's events; `all` lists every committed
    /// point with its id (a pass made as often as needed), read only when the hull must
    /// be taken over all of them.
    pub fn measure<I: Iterator<Item = (u32, P)>>(&mut self, all: impl Fn() -> I) -> f64 {
        if P::DIM != 2 {
            self.measure = P::hull_measure(&P::hull_candidates_of(|| all().map(|(_, p)| p)));
            return self.measure;
        }
        self.kept.vertices(all);
        let taken = Some(self.kept.taken());
        if taken != self.measured {
            self.measured = taken;
            self.measure = P::hull_measure(self.kept.hull());
        }
        self.measure
    }
}
