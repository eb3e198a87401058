//! Engine errors.

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
