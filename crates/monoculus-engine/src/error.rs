//! Engine errors.

/// The most robots one simulation takes (robots are indexed by `u32` in the spatial
/// index).
pub const MAX_ROBOTS: usize = u32::MAX as usize - 1;
/// The largest magnitude of a coordinate, a step or a locality constant: squares and sums
/// of squares of such values stay far from overflow.
pub const MAX_MAGNITUDE: f64 = 1e100;

/// Why a simulation cannot be built.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum EngineError {
    /// No robots.
    #[error("the swarm is empty")]
    EmptySwarm,
    /// A parameter out of range.
    #[error("{0}")]
    Invalid(String),
}
