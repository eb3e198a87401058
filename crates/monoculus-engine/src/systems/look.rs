use bevy_ecs::prelude::*;
use monoculus_core::vision::ExactSight;

use crate::IndexPoint;
use crate::IndexedSight;
use crate::resources::{HullVertices, Params, Positions, SightBackend, Snapshot, SnapshotSight};

/// A sight over `points` with the configured backend. Fat robots (SPEC 9.3) are seen
/// through the R-tree in the plane too: its tube queries widen by the radius, while the
/// band grid's walks and angular sweep are for points.
pub fn build_sight<P: IndexPoint>(params: &Params, points: Vec<P>) -> SnapshotSight<P> {
    match params.backend {
        SightBackend::Index if params.vision.fat() => {
            SnapshotSight::Rtree(IndexedSight::with_index(points, params.vision))
        }
        SightBackend::Index => SnapshotSight::Index(IndexedSight::new(points, params.vision)),
        SightBackend::Exact => SnapshotSight::Exact(ExactSight::new(points, params.vision)),
        SightBackend::Rtree => {
            SnapshotSight::Rtree(IndexedSight::with_index(points, params.vision))
        }
    }
}

/// Takes a new snapshot unless the current one still reflects `positions`. The hull
/// measured after the last moves is the snapshot's where every robot is correct (the
/// hull is the correct robots') and nothing moved since it was taken.
fn update<P: IndexPoint>(
    params: &Params,
    positions: &Positions<P>,
    hull: &HullVertices<P>,
    snapshot: &mut Snapshot<P>,
) {
    if snapshot.sight.is_some() && snapshot.generation == positions.generation {
        return;
    }
    let points = positions.points.clone();
    snapshot.sight = Some(match snapshot.sight.take() {
        // Keeps the index if few robots moved (same answers).
        Some(SnapshotSight::Index(previous)) => {
            SnapshotSight::Index(IndexedSight::after(previous, points, params.vision))
        }
        _ => build_sight(params, points),
    });
    snapshot.generation = positions.generation;
    if params.faults.is_none() && hull.generation == positions.generation {
        match snapshot.sight.as_ref() {
            Some(SnapshotSight::Index(s)) => s.know_hull(&hull.vertices),
            Some(SnapshotSight::Rtree(s)) => s.know_hull(&hull.vertices),
            _ => {}
        }
    }
}

/// The Look: takes a snapshot of the configuration (and builds its index) unless the
/// current one is still valid (nothing moved since).
pub fn take_snapshot<P: IndexPoint>(
    params: Res<Params>,
    positions: Res<Positions<P>>,
    hull: Res<HullVertices<P>>,
    mut snapshot: ResMut<Snapshot<P>>,
) {
    update(&params, &positions, &hull, &mut snapshot);
}

/// [`take_snapshot`] outside the schedule (for the quiescence check).
pub fn refresh_snapshot<P: IndexPoint>(world: &mut World) {
    let params = world.resource::<Params>().clone();
    world.resource_scope(|world, mut snapshot: Mut<Snapshot<P>>| {
        update(
            &params,
            world.resource::<Positions<P>>(),
            world.resource::<HullVertices<P>>(),
            &mut snapshot,
        );
    });
}
