//! `[hunt]`: the property `monoculus hunt` tries to break, its search space and budget
//! (read by `monoculus hunt` only; the other commands ignore the section).

use serde::{Deserialize, Serialize};

/// The property `monoculus hunt` tries to break (`hunt.property`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Property {
    /// The convex hull of the robots grows in some round (ASYNC: epoch).
    HullGrows,
    /// The diameter of the swarm grows in some round (ASYNC: epoch).
    DiameterGrows,
    /// The bounding box (in the global axes) grows on some axis in some round (ASYNC:
    /// epoch): what ConvergeQuadrant's argument forbids (with `hunt.above = 2b`: the
    /// box's extent, once at most 2b, stays at most 2b, and a wider box does not grow).
    BoxGrows,
    /// The run does not converge: the cap `stop.max_rounds` ends it, or it falls
    /// quiescent short of its goal (stuck).
    NoConvergence,
    /// The run falls quiescent short of its goal (SPEC section 11): no robot would move,
    /// and the goal does not hold.
    Stuck,
    /// Two robots that started apart reach one point (within `vision.eps_pos`).
    Collision,
    /// No violation: the start (and schedule) with the most rounds to converge (epochs
    /// under SSYNC and ASYNC).
    Slow,
}

impl Property {
    /// Whether a run is stopped at this property's violation, in the search and in
    /// reproduce.toml (`stop.max_rounds` the violation's round): the growths and
    /// collisions, judged round by round.
    ///
    /// ```
    /// use monoculus_experiments::config::Property;
    /// assert!(Property::HullGrows.cut_at_violation());
    /// assert!(!Property::Slow.cut_at_violation());
    /// ```
    pub fn cut_at_violation(self) -> bool {
        matches!(
            self,
            Property::HullGrows
                | Property::DiameterGrows
                | Property::BoxGrows
                | Property::Collision
        )
    }

    /// The config name.
    pub fn name(self) -> &'static str {
        match self {
            Property::HullGrows => "hull_grows",
            Property::DiameterGrows => "diameter_grows",
            Property::BoxGrows => "box_grows",
            Property::NoConvergence => "no_convergence",
            Property::Stuck => "stuck",
            Property::Collision => "collision",
            Property::Slow => "slow",
        }
    }
}

fn default_population() -> usize {
    32
}
fn default_restart() -> u32 {
    40
}

/// `[hunt]`: the property, the search space and the budget of `monoculus hunt`. The
/// starts are drawn as `[swarm]` describes them (`init`, `side`; `init = "file"`: the
/// file's positions perturbed), with n from `n_min` to `n_max`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HuntSpec {
    /// What to break.
    pub property: Property,
    /// Fewest robots searched (and the floor of shrinking). Default: `swarm.n` (the
    /// file's robots with `init = "file"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub n_min: Option<usize>,
    /// Most robots searched. Default: `swarm.n` (the file's robots).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub n_max: Option<usize>,
    /// Budget: runs of the search (shrinking a counterexample takes more).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub evaluations: Option<u64>,
    /// Budget: seconds of search (shrinking then runs to its end).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seconds: Option<f64>,
    /// The hunt's seed. Default 0.
    #[serde(default)]
    pub seed: u64,
    /// The largest move of one robot in the local search (and, with `init = "file"`, the
    /// spread of the perturbed starts). Default `swarm.side / 10`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub perturb: Option<f64>,
    /// Searches kept side by side (each a start improved by local moves). Default 32.
    #[serde(default = "default_population")]
    pub population: usize,
    /// A search that has not improved in this many of its moves restarts from a new
    /// random start. Default 40.
    #[serde(default = "default_restart")]
    pub restart: u32,
    /// SSYNC: search the activation subsets of each round (the counterexample then
    /// carries its schedule). Default true; false searches the scheduler's seed only.
    #[serde(default = "default_true")]
    pub subsets: bool,
    /// ASYNC: search single phase durations (the counterexample then carries them, as
    /// durations.csv). Default true; false searches the run's seed only.
    #[serde(default = "default_true")]
    pub durations: bool,
    /// Growth properties (`hull_grows`, `diameter_grows`, `box_grows`): a round counts
    /// only where the grown measure (area or volume, diameter, extent) exceeds this.
    /// Default 0: every growth counts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub above: Option<f64>,
    /// ASYNC: the longest duration the search gives a phase, ticks. Default 10 times the
    /// longest typical phase of the config (a fixed length, a uniform maximum, an
    /// exponential mean), and at least 10.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_ticks: Option<u64>,
}

fn default_true() -> bool {
    true
}
