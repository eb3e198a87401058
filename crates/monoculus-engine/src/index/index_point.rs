//! [`IndexPoint`]: a point the engine can index: its rstar point type, and the spatial
//! index of its dimension.

use glam::{DVec2, DVec3};
use monoculus_core::geometry::HullGeometry;

use super::{PlaneIndex, SpaceIndex, SpatialIndex};

/// A [`HullGeometry`] point that the spatial index can store (d = 2: the band grid; d = 3:
/// the R-tree).
pub trait IndexPoint: HullGeometry {
    /// rstar's point type of the same dimension.
    type Array: rstar::Point<Scalar = f64> + Copy + Send + Sync;
    /// Converts to rstar's point.
    fn to_array(self) -> Self::Array;
    /// The index of this dimension: the band grid in the plane, the R-tree in space.
    type Index: SpatialIndex<Self>;
}

impl IndexPoint for DVec2 {
    type Array = [f64; 2];
    type Index = PlaneIndex;
    fn to_array(self) -> [f64; 2] {
        [self.x, self.y]
    }
}

impl IndexPoint for DVec3 {
    type Array = [f64; 3];
    type Index = SpaceIndex<DVec3>;
    fn to_array(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
}
