//! Stop criteria (SPEC section 6).

pub use monoculus_core::algorithms::StopCriterion;

/// The stop criterion and the cap on rounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopSpec {
    /// The criterion.
    pub criterion: StopCriterion,
    /// Runs that reach this many rounds stop unconverged.
    pub max_rounds: u64,
}
