//! What the schema cannot say: ranges, sizes the machine can hold, names, files.

use super::*;

/// Checks the swept keys (each list non-empty, with distinct values; `name` not swept)
/// and returns the number of cells, refused past [`crate::limits::MAX_CELLS`].
pub(super) fn validate_axes(axes: &[Axis], src: &Source<'_>) -> Result<usize, ConfigError> {
    if let Some(empty) = axes.iter().find(|a| a.values.is_empty()) {
        return Err(src.error(
            &empty.path,
            "empty list: a swept key needs at least one value",
        ));
    }
    if let Some(name) = axes.iter().find(|a| a.path == "name") {
        return Err(src.error(&name.path, "one plain name for the experiment, not a list"));
    }
    for axis in axes {
        // Values compared by their TOML text (`1` and `1.0` differ, as toml::Value's
        // equality has them), in one pass.
        let mut seen = std::collections::HashSet::with_capacity(axis.values.len());
        if let Some(v) = axis.values.iter().find(|v| !seen.insert(v.to_string())) {
            return Err(src.error(
                &axis.path,
                format!("the list has {} twice: every cell must differ", render(v)),
            ));
        }
    }
    axes.iter()
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
        })
}

/// Refuses more than [`crate::limits::MAX_RUNS`] runs (cells x seeds), before the seeds
/// are listed.
pub(super) fn validate_run_count(
    seeds: &Seeds,
    cells: usize,
    src: &Source<'_>,
) -> Result<(), ConfigError> {
    let seed_count = match seeds {
        Seeds::Count(c) => *c,
        Seeds::List(v) => v.len() as u64,
    };
    let runs = seed_count.saturating_mul(cells as u64);
    if runs > crate::limits::MAX_RUNS {
        return Err(src.error(
            "seeds",
            format!(
                "{seed_count} seeds x {cells} cells: at most {} runs in one experiment (split it into several)",
                crate::limits::MAX_RUNS
            ),
        ));
    }
    crate::limits::check_results(runs).map_err(|m| src.error("seeds", m))
}

/// A number as a person writes it: plain, or with an exponent when very large or small.
pub(super) fn show(x: f64) -> String {
    if x != 0.0 && !(1e-6..1e16).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// What is wrong with a length: not positive (not negative, with `zero_ok`), or so large
/// that its square could overflow.
pub(super) fn bounded(x: f64, zero_ok: bool) -> Option<String> {
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
pub(super) fn name_problem(name: &str) -> Option<String> {
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

/// The files an experiment's cells read, each read once, with their contents' hashes.
#[derive(Default)]
pub(super) struct Files {
    positions: HashMap<PathBuf, PositionsFile>,
    schedules: HashMap<PathBuf, ScheduleFile>,
    durations: HashMap<PathBuf, DurationsFile>,
    /// Every file read, in the order first read.
    pub(super) read: Vec<InputFile>,
}

impl Files {
    /// The text of the file `written` (as the config names it under `key`), read once;
    /// its hash joins the experiment's identity.
    fn text(&mut self, key: &str, written: &str, path: &Path) -> Result<String, PositionsError> {
        let text = crate::positions::read_text(path)?;
        if !self.read.iter().any(|f| f.key == key && f.path == path) {
            self.read.push(InputFile {
                key: key.to_string(),
                written: written.to_string(),
                path: path.to_path_buf(),
                hash: crate::results::config_hash(&text),
            });
        }
        Ok(text)
    }
}

/// What a cell reads from files.
#[derive(Default)]
pub(super) struct Loaded {
    /// `swarm.file`.
    pub(super) positions: Option<PositionsFile>,
    /// `scheduler.file`.
    pub(super) schedule: Option<std::sync::Arc<monoculus_engine::ActivationList>>,
    /// `scheduler.durations`.
    pub(super) durations: Option<std::sync::Arc<monoculus_engine::asynchrony::Durations>>,
}

/// `[faults]`: one of count and fraction, at least one robot correct, the keys of the
/// kind only.
fn validate_faults(f: &FaultsConfig, n: usize, src: &Source<'_>) -> Result<(), ConfigError> {
    let err = |key: &str, m: String| Err(src.error(key, m));
    let faulty = match (f.count, f.fraction) {
        (Some(_), Some(_)) => {
            return err("faults.fraction", "give count or fraction, not both".into());
        }
        (None, None) => {
            return err(
                "faults.kind",
                "[faults] needs count (robots) or fraction (of the robots)".into(),
            );
        }
        (Some(c), None) => c,
        (None, Some(x)) => {
            if !(0.0..=1.0).contains(&x) {
                return err("faults.fraction", format!("must be in [0, 1], got {x}"));
            }
            (x * n as f64).floor() as u64
        }
    };
    if faulty >= n as u64 {
        let key = if f.count.is_some() {
            "faults.count"
        } else {
            "faults.fraction"
        };
        return err(
            key,
            format!("{faulty} faulty robots of {n}: at least one robot must be correct"),
        );
    }
    match f.kind {
        FaultKindName::Crash => {
            if f.rule.is_some() {
                return err(
                    "faults.rule",
                    "a rule is for byzantine robots; crashed robots stay".into(),
                );
            }
            match (f.at, f.until) {
                (Some(CrashAtConfig::Random(_)), None) => {
                    return err(
                        "faults.at",
                        "at = \"random\" needs until, the last round a crash may start".into(),
                    );
                }
                (Some(CrashAtConfig::Random(_)), Some(u)) if u > u64::from(u32::MAX) => {
                    return err(
                        "faults.until",
                        format!("must be at most {}, got {u}", u32::MAX),
                    );
                }
                (Some(CrashAtConfig::Random(_)), Some(_)) => {}
                (_, Some(_)) => {
                    return err(
                        "faults.until",
                        "until is read only with at = \"random\"".into(),
                    );
                }
                _ => {}
            }
        }
        FaultKindName::Byzantine => {
            for (key, given) in [
                ("faults.at", f.at.is_some()),
                ("faults.until", f.until.is_some()),
            ] {
                if given {
                    return err(
                        key,
                        "crash rounds are for crashed robots; byzantine robots move at every activation".into(),
                    );
                }
            }
        }
    }
    Ok(())
}

/// The cell's algorithm from the registry, with its parameters read from
/// `[algorithm.params]` (and written back in full): the name, the parameters' keys and
/// values, the dimension it runs in, and the paper's c >= 2b (a warning).
pub(super) fn algorithm(
    spec: &RunSpec,
    src: &Source<'_>,
    registry: &Registry,
    warnings: &mut Vec<String>,
) -> Result<(AlgorithmBox, toml::Table), ConfigError> {
    let a = &spec.algorithm;
    let Some(entry) = registry.get(&a.name) else {
        let names = registry.names();
        return Err(src.error(
            "algorithm.name",
            format!(
                "{} is not a registered algorithm; registered are {}",
                crate::shown(&a.name),
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            ),
        ));
    };
    let (algorithm, params) = entry.make(&a.params).map_err(|e| {
        let key = if e.key.is_empty() {
            "algorithm.params".to_string()
        } else {
            format!("algorithm.params.{}", e.key)
        };
        src.error(&key, e.message)
    })?;
    if let (Some(reason), 3) = (algorithm.plane_only(), spec.swarm.dim) {
        return Err(src.error(
            "algorithm.name",
            format!("{} {reason}: dim must be 2", algorithm.name()),
        ));
    }
    if algorithm.assumes_c_at_least_2b() && a.locality < 2.0 * a.step {
        let line = line_of(src.text, "algorithm.locality")
            .map(|l| format!(":{l}"))
            .unwrap_or_default();
        warnings.push(format!(
            "{}{line}: algorithm.locality: c = {} < 2b = {}: the paper's convergence guarantees for {} need c >= 2b",
            src.label,
            a.locality,
            2.0 * a.step,
            algorithm.name()
        ));
    }
    Ok((algorithm, params))
}

pub(super) fn validate(
    spec: &RunSpec,
    src: &Source<'_>,
    base: &Path,
    files: &mut Files,
) -> Result<Loaded, ConfigError> {
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
        let pts = match files.positions.get(&path) {
            Some(p) => p.clone(),
            None => {
                let p = files
                    .text("swarm.file", file, &path)
                    .and_then(|text| parse_positions(&text, &path.display().to_string()))
                    .map_err(|e| src.error("swarm.file", e.to_string()))?;
                files.positions.insert(path.clone(), p.clone());
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
        if s.dim == 2 && pts.has_z {
            return err(
                "swarm.file",
                format!(
                    "{} has a z column, but dim = 2: set swarm.dim = 3, or drop the column",
                    path.display()
                ),
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
    if let Some(range) = v.range
        && (range.is_nan() || range <= 0.0)
    {
        return err(
            "vision.range",
            format!("must be positive (inf: unlimited), got {range}"),
        );
    }
    if let Some(m) = bounded(v.robot_radius, true) {
        return err("vision.robot_radius", m);
    }
    let sc = &spec.scheduler;
    let schedule = match (sc.kind, &sc.file) {
        (SchedulerKind::File, None) => {
            return err(
                "scheduler.kind",
                "kind = \"file\" needs scheduler.file, a CSV with header round,robot".into(),
            );
        }
        (SchedulerKind::File, Some(file)) => {
            let path = base.join(file);
            let schedule = match files.schedules.get(&path) {
                Some(s) => s.clone(),
                None => {
                    let s = files
                        .text("scheduler.file", file, &path)
                        .and_then(|text| parse_schedule(&text, &path.display().to_string()))
                        .map_err(|e| src.error("scheduler.file", e.to_string()))?;
                    files.schedules.insert(path.clone(), s.clone());
                    s
                }
            };
            let n = file_positions
                .as_ref()
                .map_or(s.n.unwrap_or(0), PositionsFile::len);
            if let Err(m) = schedule.check_robots(n, &path.display().to_string()) {
                return err("scheduler.file", m);
            }
            Some(schedule.list)
        }
        (kind, Some(_)) => {
            return err(
                "scheduler.file",
                format!(
                    "a schedule file is read only with kind = \"file\", not {:?}",
                    format!("{kind:?}").to_lowercase()
                ),
            );
        }
        (_, None) => None,
    };
    let durations = match (&sc.durations, sc.kind) {
        (None, _) => None,
        (Some(_), kind) if kind != SchedulerKind::Async => {
            return err(
                "scheduler.durations",
                format!(
                    "durations are given only with kind = \"async\", not {:?}",
                    format!("{kind:?}").to_lowercase()
                ),
            );
        }
        (Some(file), _) => {
            let path = base.join(file);
            let given = match files.durations.get(&path) {
                Some(d) => d.clone(),
                None => {
                    let d = files
                        .text("scheduler.durations", file, &path)
                        .and_then(|text| parse_durations(&text, &path.display().to_string()))
                        .map_err(|e| src.error("scheduler.durations", e.to_string()))?;
                    files.durations.insert(path.clone(), d.clone());
                    d
                }
            };
            let n = file_positions
                .as_ref()
                .map_or(s.n.unwrap_or(0), PositionsFile::len);
            let together = sc.start == monoculus_engine::AsyncStart::Together;
            if let Err(m) = given.check(n, together, &path.display().to_string()) {
                return err("scheduler.durations", m);
            }
            Some(given.durations)
        }
    };
    if let Some(f) = &spec.faults {
        let n = file_positions
            .as_ref()
            .map_or(s.n.unwrap_or(0), PositionsFile::len);
        validate_faults(f, n, src)?;
    }
    if sc.kind == SchedulerKind::Adversary {
        if s.dim != 2 {
            return err(
                "scheduler.kind",
                "the adversary compares hull perimeters: the plane only (dim = 2)".into(),
            );
        }
        if sc.fairness == Some(0) {
            return err(
                "scheduler.fairness",
                "must be at least 1 (1: every robot every round)".into(),
            );
        }
    }
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
    if sc.kind == SchedulerKind::Async {
        let timing = AsyncSpec {
            idle: sc.idle,
            compute: sc.compute,
            motion: sc.motion,
            start: sc.start,
            durations: durations.clone(),
        };
        if let Err((phase, m)) = timing.check(spec.stop.max_rounds) {
            let key = match phase {
                "max_epochs" => "stop.max_rounds".to_string(),
                p => format!("scheduler.{p}"),
            };
            return err(&key, m);
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
    Ok(Loaded {
        positions: file_positions,
        schedule,
        durations,
    })
}
