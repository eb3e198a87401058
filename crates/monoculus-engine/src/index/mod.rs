//! The spatial index answering the engine's visibility questions: a band grid for lines
//! of sight in the plane ([`SegmentGrid`]; measured faster than rstar there, see
//! docs/performance.md), an rstar R-tree in space.

mod index_point;
mod indexed_sight;
mod locate;
mod plane_index;
mod segment_grid;
mod space_index;
mod spatial_index;
mod tube;

pub use index_point::IndexPoint;
pub use indexed_sight::{FEW_ROBOTS, IndexedSight};
pub use locate::Locate;
pub use plane_index::PlaneIndex;
pub(crate) use segment_grid::prefetch;
pub use segment_grid::{SegmentGrid, Stale};
pub use space_index::SpaceIndex;
pub use spatial_index::{SpatialIndex, SpatialOrder};
pub use tube::Tube;
