//! Experiment configs: TOML files whose scalar fields may be lists (the experiment is
//! the cartesian product of all lists: its cells), with `--set` overrides and one-line
//! errors naming the file, line and key.

mod error;
mod hunt_spec;
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

use monoculus_core::algorithms::ModelParams;
use monoculus_core::errors::{FactorDist, MovementErrors, ObservationErrors};
use monoculus_core::geometry::Point;
use monoculus_core::init::{InitShape, generate};
use monoculus_core::vision::VisionParams;
use monoculus_engine::{
    AlgorithmBox, AsyncSpec, ByzantineRule, CrashAt, FaultCount, FaultKind, FaultSpec, Goal,
    MAX_MAGNITUDE, SchedulerSpec, SimConfig, StopCriterion, StopSpec, TickDist,
};

pub use error::ConfigError;
use error::Source;
pub use hunt_spec::*;
pub use locate::{key_at_line, line_of, line_of_offset};
pub use overrides::apply_override;
pub use spec::*;
use sweep::render;
use typed::typed;
use validate::{validate, validate_axes, validate_run_count};

use crate::Registry;
use crate::durations::{DurationsFile, parse_durations};
use crate::positions::{PositionsError, PositionsFile, parse_positions};
use crate::schedule::{ScheduleFile, parse_schedule};

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
    /// The typed configuration (`algorithm.params` in full, defaults filled in).
    pub spec: RunSpec,
    /// The algorithm, with its parameters.
    pub algorithm: AlgorithmBox,
    /// Positions read from `swarm.file`, if `init = "file"`.
    pub file_positions: Option<PositionsFile>,
    /// The schedule read from `scheduler.file`, if `scheduler.kind = "file"`.
    pub schedule: Option<std::sync::Arc<monoculus_engine::ActivationList>>,
    /// The durations read from `scheduler.durations` (ASYNC), if given.
    pub durations: Option<std::sync::Arc<monoculus_engine::asynchrony::Durations>>,
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
    /// The files it reads, whose contents are part of its identity (`resolved` records
    /// their hashes, so [`Experiment::hash`] covers them).
    pub inputs: Vec<InputFile>,
}

impl Experiment {
    /// When `resolved` (a `config.toml` written earlier) differs from this experiment's
    /// only in the contents of a file both read: which file, and how. One line.
    pub fn changed_input(&self, resolved: &str) -> Option<String> {
        let then = InputFile::records(resolved);
        let strip = |text: &str| -> String {
            text.lines()
                .filter(|l| !l.starts_with("# input "))
                .collect::<Vec<_>>()
                .join("\n")
        };
        if strip(resolved) != strip(&self.resolved) {
            return None;
        }
        self.inputs.iter().find_map(|f| {
            let (_, _, old) = then
                .iter()
                .find(|(k, w, _)| *k == f.key && *w == format!("{:?}", f.written))?;
            (*old != f.hash).then(|| {
                format!(
                    "{} {} has changed since (contents hash {old} then, {} now): results are never continued or merged across a change to an input",
                    f.key,
                    crate::one_line(&f.path.display().to_string()),
                    f.hash
                )
            })
        })
    }
}

/// A file an experiment reads (`swarm.file`, `scheduler.file`, `scheduler.durations`): its contents belong to
/// the experiment's identity, so that results are never continued or merged across a
/// change to it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InputFile {
    /// The config key naming it.
    pub key: String,
    /// The path as the config writes it (relative to the config's folder).
    pub written: String,
    /// The path it was read from.
    pub path: PathBuf,
    /// [`crate::results::config_hash`] of its contents.
    pub hash: String,
}

impl InputFile {
    /// The line of `config.toml` that records it (a comment, so that `config.toml`
    /// stays a config).
    fn record(&self) -> String {
        format!("# input {} {:?} {}", self.key, self.written, self.hash)
    }

    /// Reads back the records of a resolved config: (key, written path, hash).
    fn records(resolved: &str) -> Vec<(String, String, String)> {
        resolved
            .lines()
            .filter_map(|l| {
                let rest = l.strip_prefix("# input ")?;
                let (key, rest) = rest.split_once(' ')?;
                let (written, hash) = rest.rsplit_once(' ')?;
                Some((key.to_string(), written.to_string(), hash.to_string()))
            })
            .collect()
    }
}

/// One run of an experiment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RunId {
    /// Cell index.
    pub cell: usize,
    /// Seed.
    pub seed: u64,
}
