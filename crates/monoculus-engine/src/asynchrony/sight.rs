//! [`LookSight`]: what ASYNC Looks see, kept from one tick to the next.

use bevy_ecs::prelude::*;
use monoculus_core::vision::Sight;

use super::Timing;
use super::components::interpolate;
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
    movers: Vec<Mover<P>>,
    /// Where each robot is in `movers` (`u32::MAX`: not there).
    slot: Vec<u32>,
    /// Robots whose move ended since the sight was last brought up to date.
    arrived: Vec<u32>,
    /// Grids built (for the performance page's figures).
    builds: u64,
}

const ABSENT: u32 = u32::MAX;

/// A robot in mid-move, as [`Timing::position_at`] reads it.
#[derive(Clone, Copy, Debug)]
struct Mover<P> {
    robot: u32,
    from: P,
    to: P,
    since: u64,
    until: u64,
}

impl<P: IndexPoint> Mover<P> {
    fn at(&self, tick: u64) -> P {
        if self.until <= self.since {
            self.from
        } else {
            interpolate(self.from, self.to, self.since, self.until, tick)
        }
    }
}

impl<P: IndexPoint> LookSight<P> {
    /// For a swarm of `n` robots, all at rest.
    pub fn new(n: usize) -> Self {
        LookSight {
            sight: None,
            movers: Vec::new(),
            slot: vec![ABSENT; n],
            arrived: Vec::new(),
            builds: 0,
        }
    }

    /// Robot `robot` starts a move from `from` (its clock says where to and when).
    pub fn depart(&mut self, robot: u32, from: P, timing: Timing<P>) {
        debug_assert_eq!(self.slot[robot as usize], ABSENT);
        debug_assert!(timing.pending.is_some() && timing.phase == super::Phase::Move);
        self.slot[robot as usize] = self.movers.len() as u32;
        self.movers.push(Mover {
            robot,
            from,
            to: timing.target,
            since: timing.since,
            until: timing.until,
        });
    }

    /// Robot `robot` ended its move, and is at rest at its target.
    pub fn arrive(&mut self, robot: u32) {
        let at = std::mem::replace(&mut self.slot[robot as usize], ABSENT);
        if at != ABSENT {
            self.movers.swap_remove(at as usize);
            if let Some(moved) = self.movers.get(at as usize) {
                self.slot[moved.robot as usize] = at;
            }
            self.arrived.push(robot);
        }
    }

    /// How many times a sight or grid was made afresh.
    pub fn builds(&self) -> u64 {
        self.builds
    }

    /// The sight at `tick`: robots at rest at their points in `settled`, movers on
    /// their segments.
    pub fn at(&mut self, params: &Params, tick: u64, settled: &[P]) -> &SnapshotSight<P> {
        let changes = self
            .arrived
            .drain(..)
            .map(|r| (r, settled[r as usize]))
            .chain(self.movers.iter().map(|m| (m.robot, m.at(tick))));
        let followed = matches!(params.backend, SightBackend::Index) && !params.vision.fat();
        self.sight = Some(match self.sight.take() {
            Some(SnapshotSight::Index(mut s)) if followed => {
                if !s.advance(changes) {
                    self.builds += 1;
                }
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
                self.builds += 1;
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
