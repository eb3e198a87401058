//! [`LookSight`]: what ASYNC Looks see, kept from one tick to the next.

use bevy_ecs::prelude::*;
use monoculus_core::vision::Sight;

use super::Timing;
use super::components::interpolate;
use super::roster::Roster;
use crate::IndexPoint;
use crate::resources::{Params, SightBackend, SnapshotSight};
use crate::systems::build_sight;

/// The sight of the Looks of a tick, brought up to date at the next tick with Looks
/// rather than taken afresh: only the robots in mid-move and those whose move ended
/// since have other positions, and in the plane the band grid follows them (robots
/// that move a little widen its queries, the few that move farther are tested one by
/// one, and it is built again when too many did; see
/// [`SpatialIndex::follow`](crate::SpatialIndex::follow)). So a tick costs the movers,
/// not the swarm. Every answer is that of a sight taken afresh (tested).
#[derive(Resource)]
pub struct LookSight<P: IndexPoint> {
    sight: Option<SnapshotSight<P>>,
    /// Robots in mid-move.
    movers: Roster<Mover<P>>,
    /// Robots whose move ended since the sight was last brought up to date.
    arrived: Vec<u32>,
}

/// A robot in mid-move, as [`Timing::position_at`] reads it (where it started is its
/// settled position).
#[derive(Clone, Copy, Debug)]
struct Mover<P> {
    to: P,
    since: u64,
    until: u64,
}

impl<P: IndexPoint> Mover<P> {
    fn at(&self, from: P, tick: u64) -> P {
        if self.until <= self.since {
            from
        } else {
            interpolate(from, self.to, self.since, self.until, tick)
        }
    }
}

impl<P: IndexPoint> LookSight<P> {
    /// For a swarm of `n` robots, all at rest.
    pub fn new(n: usize) -> Self {
        LookSight {
            sight: None,
            movers: Roster::new(n),
            arrived: Vec::new(),
        }
    }

    /// Robot `robot` starts a move from `from` (its clock says where to and when).
    pub fn depart(&mut self, robot: u32, from: P, timing: Timing<P>) {
        debug_assert!(timing.pending.is_some() && timing.phase == super::Phase::Move);
        self.movers.insert(
            robot,
            Mover {
                to: timing.target(from),
                since: timing.since,
                until: timing.until,
            },
        );
    }

    /// Robot `robot` ended its move, and is at rest at its target.
    pub fn arrive(&mut self, robot: u32) {
        if self.movers.remove(robot) {
            self.arrived.push(robot);
        }
    }

    /// The sight at `tick`: robots at rest at their points in `settled`, movers on
    /// their segments.
    pub fn at(&mut self, params: &Params, tick: u64, settled: &[P]) -> &SnapshotSight<P> {
        let changes = self
            .arrived
            .drain(..)
            .map(|r| (r, settled[r as usize]))
            .chain(
                self.movers
                    .iter()
                    .map(|&(r, m)| (r, m.at(settled[r as usize], tick))),
            );
        let followed = matches!(params.backend, SightBackend::Index) && !params.vision.fat();
        self.sight = Some(match self.sight.take() {
            Some(SnapshotSight::Index(mut s)) if followed => {
                s.advance(changes);
                SnapshotSight::Index(s)
            }
            previous => {
                let mut now = match previous {
                    Some(SnapshotSight::Index(s)) => s.into_positions(),
                    Some(SnapshotSight::Rtree(s)) => s.into_positions(),
                    Some(SnapshotSight::Exact(s)) => s.positions().to_vec(),
                    None => settled.to_vec(),
                };
                for (r, p) in changes {
                    now[r as usize] = p;
                }
                if followed {
                    SnapshotSight::Index(crate::IndexedSight::following(now, params.vision))
                } else {
                    build_sight(params, now)
                }
            }
        });
        self.sight.as_ref().expect("just set")
    }
}
