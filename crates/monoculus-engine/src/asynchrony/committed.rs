//! [`CommittedHull`]: the hull of the committed points, kept from one tick to the next.

use bevy_ecs::prelude::*;

use super::shape::{in_disc, inner_disc};
use crate::IndexPoint;

/// The hull of the committed points (every robot's position at the start of its phase
/// and the destination of every decided move, the points whose hull Lemma 2 bounds),
/// kept across ticks: a tick changes that set only by its events (a Look adds a
/// destination, the end of a move removes where the move began), so the hull is taken
/// again over all robots only when a point that may be one of its vertices is removed.
/// Otherwise the points added outside the hull are joined to its vertices. Either way
/// the vertex sequence is that of the chain over every committed point (every other
/// point lies inside), so the measure is the same to the bit (checked against the full
/// computation at every tick in debug builds, so in every test).
///
/// In space, and for hulls of fewer than three vertices, it is taken over all robots
/// at every tick.
#[derive(Resource, Clone, Debug)]
pub struct CommittedHull<P: IndexPoint> {
    vertices: Vec<P>,
    measure: f64,
    /// Whether `vertices` is a polygon the exact inside test works on.
    kept: bool,
    /// A disc inside it: the cheap first test.
    disc: (P, f64),
    added: Vec<P>,
    removed: Vec<P>,
}

impl<P: IndexPoint> CommittedHull<P> {
    /// The hull of `initial` (no move decided yet), whose measure is `measure`.
    pub fn new(initial: &[P], measure: f64) -> Self {
        let vertices = P::hull_vertices(initial);
        CommittedHull {
            kept: vertices.len() >= 3,
            disc: inner_disc(&vertices),
            vertices,
            measure,
            added: Vec::new(),
            removed: Vec::new(),
        }
    }

    /// The measure last taken (at the start, that of the initial positions).
    pub fn last(&self) -> f64 {
        self.measure
    }

    /// A Look decided a move to `p`.
    pub fn add(&mut self, p: P) {
        self.added.push(p);
    }

    /// A move that began at `p` ended.
    pub fn remove(&mut self, p: P) {
        self.removed.push(p);
    }

    /// The measure of the hull after this tick's events; `all` lists every committed
    /// point (a pass made twice), asked for only when the hull must be taken over all
    /// of them.
    pub fn measure<I: Iterator<Item = P>>(&mut self, all: impl Fn() -> I) -> f64 {
        let disc = self.disc;
        let inside = |hull: &[P], p: &P| in_disc(disc, *p) || P::strictly_inside(hull, *p);
        if self.kept && self.removed.iter().all(|p| inside(&self.vertices, p)) {
            let outside: Vec<P> = self
                .added
                .iter()
                .filter(|p| !inside(&self.vertices, p))
                .copied()
                .collect();
            if !outside.is_empty() {
                let mut points = std::mem::take(&mut self.vertices);
                points.extend(outside);
                self.vertices = P::hull_vertices(&points);
                self.measure = P::hull_measure(&self.vertices);
                self.kept = self.vertices.len() >= 3;
                // The hull grew: the old disc is still inside it.
            }
        } else {
            // Only the points that may be vertices: the hull is that of all of them.
            let points = P::hull_candidates_of(all);
            self.measure = P::hull_measure(&points);
            self.vertices = P::hull_vertices(&points);
            self.kept = self.vertices.len() >= 3;
            self.disc = inner_disc(&self.vertices);
        }
        self.added.clear();
        self.removed.clear();
        self.measure
    }
}
