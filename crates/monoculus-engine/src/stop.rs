//! Stop criteria (SPEC section 6).

use monoculus_core::algorithms::AlgorithmKind;

/// When a run has converged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopCriterion {
    /// No robot would move if activated.
    Quiescent,
    /// Every pair of robots is within the locality constant c.
    Diameter,
    /// Either of the two above (ConvergeLocality's default: on a line the two end robots
    /// keep stepping forever while staying within c).
    QuiescentOrDiameter,
    /// The bounding box extends at most 2b on every axis.
    Box,
}

impl StopCriterion {
    /// The default for an algorithm.
    pub fn default_for(kind: AlgorithmKind) -> Self {
        match kind {
            AlgorithmKind::ConvergeLocality => StopCriterion::QuiescentOrDiameter,
            AlgorithmKind::ConvergeQuadrant => StopCriterion::Box,
            AlgorithmKind::ConvergeQuadrantTermination => StopCriterion::Quiescent,
            AlgorithmKind::CenterOfGravity
            | AlgorithmKind::Median
            | AlgorithmKind::AngleBisector => StopCriterion::Diameter,
        }
    }

    /// The config name.
    pub fn name(self) -> &'static str {
        match self {
            StopCriterion::Quiescent => "quiescent",
            StopCriterion::Diameter => "diameter",
            StopCriterion::QuiescentOrDiameter => "quiescent_or_diameter",
            StopCriterion::Box => "box",
        }
    }

    /// Whether quiescence is part of the criterion.
    pub fn checks_quiescence(self) -> bool {
        matches!(
            self,
            StopCriterion::Quiescent | StopCriterion::QuiescentOrDiameter
        )
    }
}

/// The stop criterion and the cap on rounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopSpec {
    /// The criterion.
    pub criterion: StopCriterion,
    /// Runs that reach this many rounds stop unconverged.
    pub max_rounds: u64,
}
