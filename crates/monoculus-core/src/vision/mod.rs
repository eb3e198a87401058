//! What a robot sees (SPEC section 2): the opaque-point visibility predicate, the
//! [`Sight`] interface the engine implements, and exact oracles.

mod oracle;
mod params;
mod predicate;
mod sight;

pub use oracle::{
    ExactSight, beyond_brute, nearest_first_brute, representatives, seen_sweep_2d, sees_brute,
    visible_points_brute, visible_points_sweep_2d, within_brute,
};
pub use params::VisionParams;
pub use predicate::{blocks, distinct, in_range};
pub use sight::{NEIGHBOURS, Near, Sight};
