//! The spatial index: an rstar R-tree answering the engine's visibility questions.

mod index_point;
mod indexed_sight;
mod segment_grid;
mod tube;

pub use index_point::IndexPoint;
pub use indexed_sight::IndexedSight;
pub use segment_grid::SegmentGrid;
pub use tube::Tube;
