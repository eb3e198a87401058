//! Experiment configs: TOML files whose scalar fields may be lists (the experiment is
//! the cartesian product of all lists: its cells), with `--set` overrides and one-line
//! errors naming the file, line and key.

mod locate;
mod spec;

use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

use monoculus_core::algorithms::{AlgorithmKind, AlgorithmParams};
use monoculus_core::errors::{FactorDist, MovementErrors, ObservationErrors};
use monoculus_core::geometry::Point;
use monoculus_core::init::{InitShape, generate};
use monoculus_core::vision::VisionParams;
use monoculus_engine::{
    AsyncSpec, AsyncStart, MAX_MAGNITUDE, SchedulerSpec, SequentialOrder, SightBackend, SimConfig,
    StopCriterion, StopSpec, TickDist,
};

pub use locate::{key_at_line, line_of, line_of_offset};
pub use spec::*;

use crate::positions::{PositionsFile, read_positions};

/// A bad config: where, which key, what is wrong. Displays as one line:
/// `FILE:LINE: KEY: MESSAGE`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct ConfigError {
    /// The config file (or `--set` for an override).
    pub file: String,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// Dotted key, when known.
    pub key: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", crate::one_line(&self.file))?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if let Some(key) = &self.key {
            write!(f, ": {}", crate::one_line(key))?;
        }
        write!(f, ": {}", crate::one_line(&self.message))
    }
}

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

struct Source<'a> {
    label: String,
    text: &'a str,
    overridden: Vec<String>,
}

impl Source<'_> {
    fn error(&self, key: &str, message: impl Into<String>) -> ConfigError {
        let message = message.into();
        // The override's own key, a key inside it, or a table the config does not have
        // that only the override names (`--set bogus.x=5`).
        if self.overridden.iter().any(|o| {
            key == o
                || key.starts_with(&format!("{o}."))
                || (!key.is_empty()
                    && o.starts_with(&format!("{key}."))
                    && line_of(self.text, key).is_none())
        }) {
            return ConfigError {
                file: "--set".into(),
                line: None,
                key: Some(key.to_string()),
                message,
            };
        }
        ConfigError {
            file: self.label.clone(),
            line: if key.is_empty() {
                None
            } else {
                line_of(self.text, key)
            },
            key: (!key.is_empty()).then(|| key.to_string()),
            message,
        }
    }
}

/// Applies one `KEY=VALUE` override to a table. VALUE is read as a TOML value
/// (`3`, `[1, 2]`, `"x"`), or else as a bare string.
pub fn apply_override(table: &mut toml::Table, assignment: &str) -> Result<String, ConfigError> {
    let bad = |m: String| ConfigError {
        file: "--set".into(),
        line: None,
        key: None,
        message: m,
    };
    let (key, value) = assignment
        .split_once('=')
        .ok_or_else(|| bad(format!("expected KEY=VALUE, got `{assignment}`")))?;
    let key = key.trim();
    if key.is_empty() || key.split('.').any(str::is_empty) {
        return Err(bad(format!("bad key `{key}`")));
    }
    let value = match toml::from_str::<toml::Table>(&format!("v = {}", value.trim())) {
        Ok(mut t) => t.remove("v").expect("parsed v"),
        Err(_) => toml::Value::String(value.trim().to_string()),
    };
    let parts: Vec<&str> = key.split('.').collect();
    let mut t = table;
    for part in &parts[..parts.len() - 1] {
        let entry = t
            .entry(part.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        t = entry.as_table_mut().ok_or_else(|| ConfigError {
            file: "--set".into(),
            line: None,
            key: Some(key.to_string()),
            message: format!("`{part}` is not a table"),
        })?;
    }
    t.insert(parts[parts.len() - 1].to_string(), value);
    Ok(key.to_string())
}

fn collect_axes(table: &toml::Table, prefix: &str, out: &mut Vec<Axis>) {
    for (k, v) in table {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(t) => collect_axes(t, &path, out),
            toml::Value::Array(a) if path != "seeds" => out.push(Axis {
                path,
                values: a.clone(),
            }),
            _ => {}
        }
    }
}

fn set_path(table: &mut toml::Table, path: &str, value: toml::Value) {
    let parts: Vec<&str> = path.split('.').collect();
    let mut t = table;
    for part in &parts[..parts.len() - 1] {
        t = t
            .get_mut(*part)
            .and_then(toml::Value::as_table_mut)
            .expect("axis path exists");
    }
    t.insert(parts[parts.len() - 1].to_string(), value);
}

fn render(value: &toml::Value) -> String {
    match value {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

fn typed(table: toml::Table, src: &Source<'_>) -> Result<RunSpec, ConfigError> {
    serde_path_to_error::deserialize::<_, RunSpec>(toml::Value::Table(table)).map_err(|e| {
        let mut key = e.path().to_string();
        if key == "." {
            key.clear();
        }
        let message = e.inner().message().to_string();
        for marker in ["unknown field `", "missing field `"] {
            if let Some(rest) = message.split(marker).nth(1)
                && let Some(field) = rest.split('`').next()
            {
                let parent = key
                    .strip_suffix(&format!(".{field}"))
                    .unwrap_or(&key)
                    .to_string();
                let parent = if parent == field {
                    String::new()
                } else {
                    parent
                };
                key = if parent.is_empty() {
                    field.to_string()
                } else {
                    format!("{parent}.{field}")
                };
            }
        }
        let message = message.replace(", expected one of", "; expected one of");
        src.error(&key, message)
    })
}

impl Experiment {
    /// Loads and validates the config at `path`, with `--set` overrides.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Experiment, ConfigError> {
        let label = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| ConfigError {
            file: label.clone(),
            line: None,
            key: None,
            message: format!("cannot read: {e}"),
        })?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::parse(&text, &label, &base, overrides)
    }

    /// Parses a config from its text; `label` names it in errors, `base` resolves
    /// relative file paths.
    pub fn parse(
        text: &str,
        label: &str,
        base: &Path,
        overrides: &[String],
    ) -> Result<Experiment, ConfigError> {
        let mut table: toml::Table = toml::from_str(text).map_err(|e| {
            let line = e.span().map(|s| line_of_offset(text, s.start));
            let mut message = e.message().trim().to_string();
            if message.contains("as i128") || message.contains("number too large") {
                message = "integer too large: TOML integers are 64-bit".into();
            }
            if message == "duplicate key"
                && let Some(span) = e.span()
                && let Some(k) = text.get(span)
            {
                message = format!("duplicate key `{}`", k.trim().trim_matches('"'));
            }
            ConfigError {
                file: label.to_string(),
                line,
                key: line.and_then(|l| key_at_line(text, l)),
                message,
            }
        })?;
        let mut src = Source {
            label: label.to_string(),
            text,
            overridden: Vec::new(),
        };
        for o in overrides {
            src.overridden.push(apply_override(&mut table, o)?);
        }
        let mut axes = Vec::new();
        collect_axes(&table, "", &mut axes);
        if let Some(empty) = axes.iter().find(|a| a.values.is_empty()) {
            return Err(src.error(
                &empty.path,
                "empty list: a swept key needs at least one value",
            ));
        }
        if let Some(name) = axes.iter().find(|a| a.path == "name") {
            return Err(src.error(&name.path, "one plain name for the experiment, not a list"));
        }
        for axis in &axes {
            for (k, v) in axis.values.iter().enumerate() {
                if axis.values[..k].contains(v) {
                    return Err(src.error(
                        &axis.path,
                        format!("the list has {} twice: every cell must differ", render(v)),
                    ));
                }
            }
        }
        let count = axes
            .iter()
            .try_fold(1usize, |c, a| c.checked_mul(a.values.len()))
            .filter(|&c| c <= crate::limits::MAX_CELLS)
            .ok_or_else(|| {
                src.error(
                    &axes[0].path,
                    format!(
                        "the sweep has more than {} cells (the product of the lists' lengths)",
                        crate::limits::MAX_CELLS
                    ),
                )
            })?;
        let mut cells = Vec::with_capacity(count);
        let mut warnings = Vec::new();
        let mut files: HashMap<PathBuf, PositionsFile> = HashMap::new();
        for index in 0..count {
            let mut rest = index;
            let mut chosen = vec![0; axes.len()];
            for (a, axis) in axes.iter().enumerate().rev() {
                chosen[a] = rest % axis.values.len();
                rest /= axis.values.len();
            }
            let mut cell_table = table.clone();
            let mut values = Vec::with_capacity(axes.len());
            for (axis, &c) in axes.iter().zip(&chosen) {
                set_path(&mut cell_table, &axis.path, axis.values[c].clone());
                values.push((axis.path.clone(), render(&axis.values[c])));
            }
            let spec = typed(cell_table, &src)?;
            let file_positions = validate(&spec, &src, base, &mut files, &mut warnings)?;
            let key = values
                .iter()
                .map(|(k, v)| format!("{k}={v}"))
                .collect::<Vec<_>>()
                .join(";");
            cells.push(Cell {
                index,
                key,
                values,
                spec,
                file_positions,
            });
        }
        let first = &cells[0].spec;
        let seed_count = match &first.seeds {
            Seeds::Count(c) => *c,
            Seeds::List(v) => v.len() as u64,
        };
        if seed_count.saturating_mul(count as u64) > crate::limits::MAX_RUNS {
            return Err(src.error(
                "seeds",
                format!(
                    "{seed_count} seeds x {count} cells: at most {} runs in one experiment",
                    crate::limits::MAX_RUNS
                ),
            ));
        }
        let seeds = first.seeds.to_vec();
        let mut resolved = toml::Table::try_from(first).expect("a RunSpec serialises");
        for axis in &axes {
            set_path(
                &mut resolved,
                &axis.path,
                toml::Value::Array(axis.values.clone()),
            );
        }
        warnings.sort();
        warnings.dedup();
        let resolved = toml::to_string(&resolved).expect("a table serialises");
        Ok(Experiment {
            name: first.name.clone(),
            seeds,
            axes,
            cells,
            hash: crate::results::config_hash(&resolved),
            resolved,
            warnings,
            base: std::path::absolute(if base.as_os_str().is_empty() {
                Path::new(".")
            } else {
                base
            })
            .unwrap_or_else(|_| base.to_path_buf()),
            source: text.to_string(),
            overrides: overrides.to_vec(),
        })
    }

    /// Every run, cell-major then by seed.
    pub fn runs(&self) -> Vec<RunId> {
        self.cells
            .iter()
            .flat_map(|c| {
                self.seeds.iter().map(move |&seed| RunId {
                    cell: c.index,
                    seed,
                })
            })
            .collect()
    }
}

/// A number as a person writes it: plain, or with an exponent when very large or small.
fn show(x: f64) -> String {
    if x != 0.0 && !(1e-6..1e16).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// What is wrong with a length: not positive (not negative, with `zero_ok`), or so large
/// that its square could overflow.
fn bounded(x: f64, zero_ok: bool) -> Option<String> {
    if !(x > 0.0 || zero_ok && x == 0.0) {
        let what = if zero_ok { "non-negative" } else { "positive" };
        Some(format!("must be {what}, got {}", show(x)))
    } else if x.is_nan() || x > MAX_MAGNITUDE {
        Some(format!(
            "must be at most {MAX_MAGNITUDE:e} (so that squares cannot overflow), got {}",
            show(x)
        ))
    } else {
        None
    }
}

/// Why `name` cannot name a results folder (`results/<name>`), if it cannot: it must be a
/// plain file name.
fn name_problem(name: &str) -> Option<String> {
    let problem = if name.is_empty() {
        "is empty"
    } else if name == "." || name == ".." || name.contains(['/', '\\']) {
        "names a path; it must be a plain file name (the default results folder is results/<name>)"
    } else if name.starts_with('.') {
        "starts with a dot; it must be a plain, visible file name"
    } else if name.chars().any(char::is_control) {
        "contains a control character"
    } else if name.len() > 200 {
        "is longer than 200 bytes"
    } else {
        return None;
    };
    Some(format!("{name:?} {problem}"))
}

fn validate(
    spec: &RunSpec,
    src: &Source<'_>,
    base: &Path,
    files: &mut HashMap<PathBuf, PositionsFile>,
    warnings: &mut Vec<String>,
) -> Result<Option<PositionsFile>, ConfigError> {
    let err = |key: &str, m: String| Err(src.error(key, m));
    match &spec.seeds {
        Seeds::Count(0) => return err("seeds", "must be at least 1".into()),
        Seeds::List(v) if v.is_empty() => return err("seeds", "the list of seeds is empty".into()),
        Seeds::List(v) => {
            let mut seen = std::collections::HashSet::new();
            if let Some(d) = v.iter().find(|s| !seen.insert(**s)) {
                return err(
                    "seeds",
                    format!("seed {d} is listed twice: every run must differ"),
                );
            }
        }
        _ => {}
    }
    if let Some(problem) = name_problem(&spec.name) {
        return err("name", problem);
    }
    let s = &spec.swarm;
    if s.dim == 3
        && matches!(
            spec.algorithm.name,
            AlgorithmKind::Median | AlgorithmKind::AngleBisector
        )
    {
        return err(
            "algorithm.name",
            format!(
                "{} is defined by angular order in the plane (the paper's Figure 1): dim must be 2",
                spec.algorithm.name.name()
            ),
        );
    }
    if s.dim != 2 && s.dim != 3 {
        return err("swarm.dim", format!("must be 2 or 3, got {}", s.dim));
    }
    if let Some(m) = bounded(s.side, false) {
        return err("swarm.side", m);
    }
    if s.clusters == 0 {
        return err("swarm.clusters", "must be at least 1".into());
    }
    if let Some(m) = s.spread.and_then(|sp| bounded(sp, true)) {
        return err("swarm.spread", m);
    }
    let mut file_positions = None;
    if s.init == InitKind::File {
        let Some(file) = &s.file else {
            return err(
                "swarm.file",
                "init = \"file\" needs swarm.file, a CSV of positions".into(),
            );
        };
        let path = base.join(file);
        let pts = match files.get(&path) {
            Some(p) => p.clone(),
            None => {
                let p =
                    read_positions(&path).map_err(|e| src.error("swarm.file", e.to_string()))?;
                files.insert(path.clone(), p.clone());
                p
            }
        };
        if let Err(m) = crate::limits::check_robots(pts.len() as u64) {
            return err("swarm.file", m);
        }
        if s.dim == 3 && !pts.has_z {
            return err(
                "swarm.file",
                format!("dim = 3 needs a z column in {}", path.display()),
            );
        }
        if let Some(n) = s.n
            && n != pts.len()
        {
            return err(
                "swarm.n",
                format!("n = {n} but {} has {} robots", path.display(), pts.len()),
            );
        }
        file_positions = Some(pts);
    } else {
        match s.n {
            None => return err("swarm.n", "missing: the number of robots".into()),
            Some(0) => return err("swarm.n", "must be at least 1".into()),
            Some(n) => {
                if let Err(m) = crate::limits::check_robots(n as u64) {
                    return err("swarm.n", m);
                }
                if s.init == InitKind::Clusters && s.clusters > n {
                    return err(
                        "swarm.clusters",
                        format!(
                            "{} clusters for {n} robots: at most one cluster a robot",
                            s.clusters
                        ),
                    );
                }
            }
        }
    }
    let a = &spec.algorithm;
    if let Some(m) = bounded(a.step, false) {
        return err("algorithm.step", m);
    }
    if let Some(m) = bounded(a.locality, false) {
        return err("algorithm.locality", m);
    }
    let kind = a.name;
    if kind.needs_locality_at_least_twice_step() && a.locality < 2.0 * a.step {
        let line = line_of(src.text, "algorithm.locality")
            .map(|l| format!(":{l}"))
            .unwrap_or_default();
        warnings.push(format!(
            "{}{line}: algorithm.locality: c = {} < 2b = {}: the paper's convergence guarantees for {} need c >= 2b",
            src.label,
            a.locality,
            2.0 * a.step,
            kind.name()
        ));
    }
    let v = &spec.vision;
    for (key, value) in [
        ("vision.eps_pos", v.eps_pos),
        ("vision.eps_ang", Some(v.eps_ang)),
        ("vision.eps_axis", v.eps_axis),
    ] {
        if let Some(x) = value
            && !(x >= 0.0 && x.is_finite())
        {
            return err(key, format!("must be non-negative, got {x}"));
        }
    }
    let sc = &spec.scheduler;
    if !(sc.p > 0.0 && sc.p <= 1.0) {
        return err("scheduler.p", format!("must be in (0, 1], got {}", sc.p));
    }
    for (key, ticks) in [
        ("scheduler.idle", sc.idle),
        ("scheduler.compute", sc.compute),
        ("scheduler.move", sc.motion),
    ] {
        let problem = match ticks {
            TickDist::Fixed { ticks: 0 } => Some("ticks must be at least 1".to_string()),
            TickDist::Uniform { min, max } if min == 0 || max < min => Some(format!(
                "needs 1 <= min <= max, got min = {min}, max = {max}"
            )),
            TickDist::Exponential { mean } if !(mean > 0.0 && mean.is_finite()) => {
                Some(format!("mean must be positive, got {mean}"))
            }
            _ => None,
        };
        if let Some(m) = problem {
            return err(key, m);
        }
    }
    let e = &spec.errors;
    if !(0.0..=1.0).contains(&e.flip_p) {
        return err(
            "errors.flip_p",
            format!("must be in [0, 1], got {}", e.flip_p),
        );
    }
    if !(0.0..=1.0).contains(&e.flip_window) {
        return err(
            "errors.flip_window",
            format!("must be in [0, 1], got {}", e.flip_window),
        );
    }
    if !(e.angle_sigma >= 0.0 && e.angle_sigma.is_finite()) {
        return err(
            "errors.angle_sigma",
            format!("must be non-negative, got {}", e.angle_sigma),
        );
    }
    let factor_ok = match e.step_factor {
        FactorDist::Fixed { value } => value >= 0.0 && value.is_finite(),
        FactorDist::Uniform { min, max } => min >= 0.0 && min <= max && max.is_finite(),
        FactorDist::Normal { mean, sd } => mean.is_finite() && sd >= 0.0 && sd.is_finite(),
    };
    if !factor_ok {
        return err(
            "errors.step_factor",
            "factors must be finite and non-negative (min <= max, sd >= 0)".into(),
        );
    }
    if let Some(nr) = e.non_rigid
        && !(nr.delta_min >= 0.0 && nr.delta_min.is_finite())
    {
        return err(
            "errors.non_rigid",
            format!("delta_min must be non-negative, got {}", nr.delta_min),
        );
    }
    Ok(file_positions)
}

impl Cell {
    /// The algorithm.
    pub fn algorithm(&self) -> AlgorithmKind {
        self.spec.algorithm.name
    }

    /// Number of robots.
    pub fn n(&self) -> usize {
        self.file_positions
            .as_ref()
            .map_or_else(|| self.spec.swarm.n.unwrap_or(0), PositionsFile::len)
    }

    /// The stop criterion in force.
    pub fn criterion(&self) -> StopCriterion {
        match self.spec.stop.criterion {
            CriterionName::Default => StopCriterion::default_for(self.algorithm()),
            CriterionName::Quiescent => StopCriterion::Quiescent,
            CriterionName::Diameter => StopCriterion::Diameter,
            CriterionName::QuiescentOrDiameter => StopCriterion::QuiescentOrDiameter,
            CriterionName::Box => StopCriterion::Box,
        }
    }

    /// The engine configuration for `seed`.
    pub fn sim_config(&self, seed: u64) -> SimConfig {
        let a = &self.spec.algorithm;
        let v = &self.spec.vision;
        let defaults = VisionParams::for_step(a.step);
        let sc = &self.spec.scheduler;
        SimConfig {
            algorithm: AlgorithmParams {
                kind: self.algorithm(),
                step: a.step,
                locality: a.locality,
                errors: ObservationErrors {
                    flip_p: self.spec.errors.flip_p,
                    flip_window: self.spec.errors.flip_window,
                    angle_sigma: self.spec.errors.angle_sigma,
                },
                target: a.target,
            },
            vision: VisionParams {
                eps_pos: v.eps_pos.unwrap_or(defaults.eps_pos),
                eps_ang: v.eps_ang,
                eps_axis: v.eps_axis.unwrap_or(defaults.eps_axis),
            },
            backend: match v.backend {
                BackendName::Index => SightBackend::Index,
                BackendName::Exact => SightBackend::Exact,
            },
            scheduler: match sc.kind {
                SchedulerKind::Fsync => SchedulerSpec::Fsync,
                SchedulerKind::Ssync => SchedulerSpec::Ssync {
                    p: sc.p,
                    fairness: sc.fairness,
                },
                SchedulerKind::Async => SchedulerSpec::Async(AsyncSpec {
                    idle: sc.idle,
                    compute: sc.compute,
                    motion: sc.motion,
                    start: match sc.start {
                        StartName::Together => AsyncStart::Together,
                        StartName::Random => AsyncStart::Random,
                    },
                }),
                SchedulerKind::Sequential => SchedulerSpec::Sequential {
                    order: match sc.order {
                        OrderName::RoundRobin => SequentialOrder::RoundRobin,
                        OrderName::Random => SequentialOrder::Random,
                    },
                },
            },
            stop: StopSpec {
                criterion: self.criterion(),
                max_rounds: self.spec.stop.max_rounds,
            },
            seed,
            movement: MovementErrors {
                step_factor: self.spec.errors.step_factor,
                non_rigid: self.spec.errors.non_rigid.map(|n| n.delta_min),
            },
        }
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.spec.swarm.dim
    }

    /// The initial positions for `seed`, in dimension `P::DIM` (= [`Cell::dim`]).
    pub fn initial_positions<P: Point>(&self, seed: u64) -> Vec<P> {
        if let Some(p) = &self.file_positions {
            return p.points();
        }
        let s = &self.spec.swarm;
        let side = s.side;
        let shape = match s.init {
            InitKind::Square => InitShape::Square { side },
            InitKind::Disc => InitShape::Disc { side },
            InitKind::Line => InitShape::Line { side },
            InitKind::Lattice => InitShape::Lattice { side },
            InitKind::Clusters => InitShape::Clusters {
                side,
                clusters: s.clusters,
                spread: s.spread.unwrap_or(side / 20.0),
            },
            InitKind::File => unreachable!("file positions are loaded at validation"),
        };
        generate(&shape, self.n(), seed)
    }
}
