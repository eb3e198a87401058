//! Experiment configs: TOML files whose scalar fields may be lists (the experiment is
//! the cartesian product of all lists: its cells), with `--set` overrides and one-line
//! errors naming the file, line and key.

mod error;
mod locate;
mod overrides;
mod spec;
mod sweep;
mod to_engine;
mod typed;
mod validate;

use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

use monoculus_core::algorithms::{AlgorithmKind, AlgorithmParams};
use monoculus_core::errors::{FactorDist, MovementErrors, ObservationErrors};
use monoculus_core::geometry::Point;
use monoculus_core::init::{InitShape, generate};
use monoculus_core::vision::VisionParams;
use monoculus_engine::{
    AsyncSpec, ByzantineRule, CrashAt, FaultCount, FaultKind, FaultSpec, MAX_MAGNITUDE,
    SchedulerSpec, SimConfig, StopCriterion, StopSpec, TickDist,
};

pub use error::ConfigError;
use error::Source;
pub use locate::{key_at_line, line_of, line_of_offset};
pub use overrides::apply_override;
pub use spec::*;
use sweep::render;
use typed::typed;
use validate::{validate, validate_axes, validate_run_count};

use crate::positions::{PositionsFile, read_positions};
use crate::schedule::{ScheduleFile, read_schedule};

/// One swept key and its values.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// Dotted key.
    pub path: String,
    /// Its values, in order.
    pub values: Vec<toml::Value>,
}

/// One cell: a single value for every key.
#[derive(Clone, Debug)]
pub struct Cell {
    /// Position in the experiment (first axis varies slowest).
    pub index: usize,
    /// Stable identity: `key=value` for every axis, joined by `;` (empty without axes).
    pub key: String,
    /// The value of each axis in this cell, rendered.
    pub values: Vec<(String, String)>,
    /// The typed configuration.
    pub spec: RunSpec,
    /// Positions read from `swarm.file`, if `init = "file"`.
    pub file_positions: Option<PositionsFile>,
    /// The schedule read from `scheduler.file`, if `scheduler.kind = "file"`.
    pub schedule: Option<std::sync::Arc<monoculus_engine::ActivationList>>,
}

/// A loaded, validated experiment.
#[derive(Clone, Debug)]
pub struct Experiment {
    /// `name`.
    pub name: String,
    /// The seeds every cell runs.
    pub seeds: Vec<u64>,
    /// Swept keys.
    pub axes: Vec<Axis>,
    /// The cells.
    pub cells: Vec<Cell>,
    /// The config as resolved (defaults filled in, overrides applied), as TOML.
    pub resolved: String,
    /// Non-fatal findings (e.g. c < 2b).
    pub warnings: Vec<String>,
    /// [`crate::results::config_hash`] of `resolved`: written in every row.
    pub hash: String,
    /// The folder relative paths in the config (`swarm.file`) are read from.
    pub base: PathBuf,
    /// The config's text as given.
    pub source: String,
    /// The `--set` overrides applied to it.
    pub overrides: Vec<String>,
}

/// One run of an experiment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RunId {
    /// Cell index.
    pub cell: usize,
    /// Seed.
    pub seed: u64,
}
