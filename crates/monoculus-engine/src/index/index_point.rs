//! [`IndexPoint`]: the bridge from [`Point`] to rstar's point type.

use glam::{DVec2, DVec3};
use monoculus_core::geometry::HullGeometry;

/// A [`HullGeometry`] point that the spatial index can store (d = 2: the band grid; d = 3:
/// the R-tree).
pub trait IndexPoint: HullGeometry {
    /// rstar's point type of the same dimension.
    type Array: rstar::Point<Scalar = f64> + Copy + Send + Sync;
    /// Converts to rstar's point.
    fn to_array(self) -> Self::Array;
}

impl IndexPoint for DVec2 {
    type Array = [f64; 2];
    fn to_array(self) -> [f64; 2] {
        [self.x, self.y]
    }
}

impl IndexPoint for DVec3 {
    type Array = [f64; 3];
    fn to_array(self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }
}
