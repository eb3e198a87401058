//! The typed form of one cell of an experiment: every field a single value.

use monoculus_core::errors::FactorDist;
use monoculus_engine::{
    AsyncStart, ByzantineRule, Objective, SequentialOrder, SightBackend, TickDist,
};
use serde::{Deserialize, Serialize};

use super::HuntSpec;

/// Which seeds every cell runs: `seeds = 100` (0..99) or `seeds = [3, 7]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Seeds {
    /// Seeds 0..count.
    Count(u64),
    /// These seeds.
    List(Vec<u64>),
}

const SEEDS_EXPECTED: &str =
    "a count of seeds (a whole number, at least 1) or a list of seeds (whole numbers, at least 0)";

impl<'de> Deserialize<'de> for Seeds {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Seeds;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(SEEDS_EXPECTED)
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Seeds, E> {
                Ok(Seeds::Count(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Seeds, E> {
                u64::try_from(v)
                    .map(Seeds::Count)
                    .map_err(|_| E::custom(format!("expected {SEEDS_EXPECTED}, got {v}")))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Seeds, E> {
                Err(E::custom(format!("expected {SEEDS_EXPECTED}, got {v}")))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Seeds, E> {
                Err(E::custom(format!("expected {SEEDS_EXPECTED}, got \"{v}\"")))
            }
            fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<Seeds, E> {
                Err(E::custom(format!("expected {SEEDS_EXPECTED}, got {v}")))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Seeds, A::Error> {
                let mut v = Vec::new();
                let mut k = 0;
                while let Some(x) = seq.next_element::<toml::Value>()? {
                    match x.as_integer().and_then(|i| u64::try_from(i).ok()) {
                        Some(s) => v.push(s),
                        None => {
                            return Err(serde::de::Error::custom(format!(
                                "seed {k} of the list is {x}: seeds are whole numbers, at least 0"
                            )));
                        }
                    }
                    k += 1;
                }
                Ok(Seeds::List(v))
            }
        }
        d.deserialize_any(V)
    }
}

impl Default for Seeds {
    fn default() -> Self {
        Seeds::Count(1)
    }
}

impl Seeds {
    /// The seeds, in order.
    pub fn to_vec(&self) -> Vec<u64> {
        match self {
            Seeds::Count(n) => (0..*n).collect(),
            Seeds::List(v) => v.clone(),
        }
    }
}

/// One run's configuration (one cell of a sweep), as in the TOML file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// Experiment name.
    pub name: String,
    /// Seeds of every cell. Default: one seed, 0.
    #[serde(default)]
    pub seeds: Seeds,
    /// The robots.
    pub swarm: SwarmSpec,
    /// The algorithm.
    pub algorithm: AlgorithmSpec,
    /// Visibility tolerances.
    #[serde(default)]
    pub vision: VisionSpec,
    /// The scheduler.
    #[serde(default)]
    pub scheduler: SchedulerConfig,
    /// When to stop.
    #[serde(default)]
    pub stop: StopConfig,
    /// Observation and movement errors (all off by default).
    #[serde(default)]
    pub errors: ErrorsConfig,
    /// Faulty robots (SPEC 9.1). Default: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub faults: Option<FaultsConfig>,
    /// `[hunt]`: what `monoculus hunt` searches for (ignored by the other commands).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hunt: Option<HuntSpec>,
}

/// What faulty robots do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FaultKindName {
    /// They stop forever.
    Crash,
    /// They move by a rule of their own.
    Byzantine,
}

/// `at = "random"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RandomRound {
    /// A uniform round in [0, `until`].
    Random,
}

/// `at`: a round, or `"random"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(untagged)]
pub enum CrashAtConfig {
    /// From this round (0: the start).
    Round(u64),
    /// A uniform round in [0, `until`], per crashed robot.
    Random(RandomRound),
}

const AT_EXPECTED: &str = "a round (a whole number, at least 0) or \"random\"";

impl<'de> Deserialize<'de> for CrashAtConfig {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl serde::de::Visitor<'_> for V {
            type Value = CrashAtConfig;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(AT_EXPECTED)
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<CrashAtConfig, E> {
                Ok(CrashAtConfig::Round(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<CrashAtConfig, E> {
                u64::try_from(v)
                    .map(CrashAtConfig::Round)
                    .map_err(|_| E::custom(format!("expected {AT_EXPECTED}, got {v}")))
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<CrashAtConfig, E> {
                Err(E::custom(format!("expected {AT_EXPECTED}, got {v}")))
            }
            fn visit_bool<E: serde::de::Error>(self, v: bool) -> Result<CrashAtConfig, E> {
                Err(E::custom(format!("expected {AT_EXPECTED}, got {v}")))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<CrashAtConfig, E> {
                match v {
                    "random" => Ok(CrashAtConfig::Random(RandomRound::Random)),
                    _ => Err(E::custom(format!(
                        "expected {AT_EXPECTED}, got {}",
                        crate::shown(v)
                    ))),
                }
            }
        }
        d.deserialize_any(V)
    }
}

/// `[faults]` (SPEC 9.1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FaultsConfig {
    /// `crash` or `byzantine`.
    pub kind: FaultKindName,
    /// This many faulty robots...
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub count: Option<u64>,
    /// ... or this share of them, rounded down.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fraction: Option<f64>,
    /// Crash: the first round without moves (0, the default: from the start), or
    /// `"random"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<CrashAtConfig>,
    /// Crash with `at = "random"`: the last round a crash may start.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until: Option<u64>,
    /// Byzantine: `random` (the default), `away` or `farthest`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rule: Option<ByzantineRule>,
}

/// Initial shape names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InitKind {
    /// Uniform in a square of side `side`.
    Square,
    /// Uniform in a disc of diameter `side`.
    Disc,
    /// Uniform on a segment of length `side`.
    Line,
    /// A grid filling a square of side `side`.
    Lattice,
    /// Gaussian clusters.
    Clusters,
    /// Positions from the CSV file `file`.
    File,
}

fn default_dim() -> usize {
    2
}
fn default_side() -> f64 {
    20.0
}
fn default_clusters() -> usize {
    4
}

/// `[swarm]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SwarmSpec {
    /// Number of robots (optional with `init = "file"`, where the file decides).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub n: Option<usize>,
    /// Dimension (2).
    #[serde(default = "default_dim")]
    pub dim: usize,
    /// Initial shape.
    pub init: InitKind,
    /// Side length L of the square (diameter of the disc, length of the line). Default 20.
    #[serde(default = "default_side")]
    pub side: f64,
    /// `clusters`: number of clusters. Default 4.
    #[serde(default = "default_clusters")]
    pub clusters: usize,
    /// `clusters`: standard deviation of each cluster. Default side / 20.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spread: Option<f64>,
    /// `file`: CSV of positions (header `x,y`), relative to the config file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
}

pub use monoculus_core::algorithms::TargetPolicy;

fn default_step() -> f64 {
    1.0
}
fn default_locality() -> f64 {
    2.0
}

/// `[algorithm]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AlgorithmSpec {
    /// Which algorithm: a name the binary registers (see [`crate::Registry`]).
    pub name: String,
    /// Step length b. Default 1.
    #[serde(default = "default_step")]
    pub step: f64,
    /// Locality constant c. Default 2.
    #[serde(default = "default_locality")]
    pub locality: f64,
    /// Target policy. Default random.
    #[serde(default)]
    pub target: TargetPolicy,
    /// `[algorithm.params]`: the algorithm's own parameters (read by its type).
    #[serde(default, skip_serializing_if = "toml::Table::is_empty")]
    pub params: toml::Table,
}

fn default_eps_ang() -> f64 {
    1e-9
}

/// `[vision]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VisionSpec {
    /// Co-location tolerance. Default 1e-9 * step.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eps_pos: Option<f64>,
    /// Angular tolerance in radians. Default 1e-9.
    #[serde(default = "default_eps_ang")]
    pub eps_ang: f64,
    /// OLA side tolerance. Default 1e-9 * step.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eps_axis: Option<f64>,
    /// `index` (band grid in the plane, R-tree in space; default) or `exact` (brute force).
    #[serde(default)]
    pub backend: SightBackend,
    /// Visibility range V (SPEC 9.2; `inf`: unlimited, the default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<f64>,
    /// Fat robots (SPEC 9.3): the radius of every robot's opaque disc (ball). Default 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub robot_radius: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl Default for VisionSpec {
    fn default() -> Self {
        VisionSpec {
            eps_pos: None,
            eps_ang: default_eps_ang(),
            eps_axis: None,
            backend: SightBackend::Index,
            range: None,
            robot_radius: 0.0,
        }
    }
}

/// Scheduler names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SchedulerKind {
    /// Fully synchronous.
    #[default]
    Fsync,
    /// Semi-synchronous.
    Ssync,
    /// One robot per round.
    Sequential,
    /// Continuous time (ticks), per-robot cycles.
    Async,
    /// The rounds and robots of a CSV file (`scheduler.file`).
    File,
    /// Activates the robots its objective prefers, k-fairly (`scheduler.objective`).
    Adversary,
}

fn one_tick() -> TickDist {
    TickDist::ONE
}

fn default_p() -> f64 {
    0.5
}

/// `[scheduler]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SchedulerConfig {
    /// `fsync` (default), `ssync`, `sequential`, `async`, `file`, `adversary`.
    #[serde(default)]
    pub kind: SchedulerKind,
    /// `file`: CSV with header `round,robot`, relative to the config file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// ASYNC: CSV with header `robot,cycle,phase,ticks`, relative to the config file:
    /// phase lengths given for single cycles of single robots, in place of draws.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub durations: Option<String>,
    /// SSYNC activation probability. Default 0.5.
    #[serde(default = "default_p")]
    pub p: f64,
    /// SSYNC k-fairness: no robot waits more than this many rounds. Default: none.
    /// Adversary: every robot is activated at least once every k rounds. Default n.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fairness: Option<u32>,
    /// Adversary: `slow` (default) or `grow`.
    #[serde(default)]
    pub objective: Objective,
    /// Sequential order: `round_robin` (default) or `random`.
    #[serde(default)]
    pub order: SequentialOrder,
    /// ASYNC: Idle durations. Default fixed 1 tick.
    #[serde(default = "one_tick")]
    pub idle: TickDist,
    /// ASYNC: Compute durations (Look to start of Move). Default fixed 1 tick.
    #[serde(default = "one_tick")]
    pub compute: TickDist,
    /// ASYNC: Move durations. Default fixed 1 tick.
    #[serde(default = "one_tick", rename = "move")]
    pub motion: TickDist,
    /// ASYNC: `together` (default: everybody Looks at tick 0) or `random` (everybody
    /// starts Idle for one idle draw).
    #[serde(default)]
    pub start: AsyncStart,
}

/// `non_rigid = { delta_min = 0.5 }`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NonRigidConfig {
    /// The adversary stops a move after at least this distance.
    pub delta_min: f64,
}

fn default_flip_window() -> f64 {
    0.1
}

/// `[errors]` (SPEC section 7).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ErrorsConfig {
    /// Probability that a far/near bit is wrong within the window. Default 0.
    #[serde(default)]
    pub flip_p: f64,
    /// Relative half-width w of the window [c(1 - w), c(1 + w)]. Default 0.1.
    #[serde(default = "default_flip_window")]
    pub flip_window: f64,
    /// Standard deviation (radians) of the angular noise on directions (and of the
    /// tilt of the agreed axes for OLA). Default 0.
    #[serde(default)]
    pub angle_sigma: f64,
    /// Factor on every move's length. Default fixed 1.
    #[serde(default)]
    pub step_factor: FactorDist,
    /// Non-rigid moves. Default: rigid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub non_rigid: Option<NonRigidConfig>,
}

impl Default for ErrorsConfig {
    fn default() -> Self {
        ErrorsConfig {
            flip_p: 0.0,
            flip_window: default_flip_window(),
            angle_sigma: 0.0,
            step_factor: FactorDist::default(),
            non_rigid: None,
        }
    }
}

impl Default for SchedulerConfig {
    fn default() -> Self {
        SchedulerConfig {
            kind: SchedulerKind::Fsync,
            file: None,
            durations: None,
            objective: Objective::Slow,
            p: default_p(),
            fairness: None,
            order: SequentialOrder::RoundRobin,
            idle: TickDist::ONE,
            compute: TickDist::ONE,
            motion: TickDist::ONE,
            start: AsyncStart::Together,
        }
    }
}

/// Stop criterion names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CriterionName {
    /// The algorithm's default (SPEC section 6).
    #[default]
    Default,
    /// No robot would move.
    Quiescent,
    /// Diameter <= c.
    Diameter,
    /// Either.
    QuiescentOrDiameter,
    /// Bounding box <= 2b on every axis.
    Box,
}

/// Goal names (`stop.goal`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GoalName {
    /// The algorithm's own (SPEC section 11).
    #[default]
    Default,
    /// Diameter <= c.
    Diameter,
    /// Every robot within a disc (ball) of radius c.
    Disc,
    /// Bounding box <= 2b on every axis.
    Box,
}

fn default_max_rounds() -> u64 {
    100_000
}

/// `[stop]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopConfig {
    /// Criterion. Default: the algorithm's.
    #[serde(default)]
    pub criterion: CriterionName,
    /// What convergence means. Default: the algorithm's goal.
    #[serde(default)]
    pub goal: GoalName,
    /// Round cap. Default 100000.
    #[serde(default = "default_max_rounds")]
    pub max_rounds: u64,
}

impl Default for StopConfig {
    fn default() -> Self {
        StopConfig {
            criterion: CriterionName::Default,
            goal: GoalName::Default,
            max_rounds: default_max_rounds(),
        }
    }
}
