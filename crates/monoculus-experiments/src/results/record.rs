//! One row of `runs.csv`.

use monoculus_engine::RunOutcome;

use crate::config::{Cell, Experiment};

/// Parameter columns that every results file has, with the dotted config key each one
/// shows (a swept key listed here gets no extra column).
pub const PARAM_COLUMNS: [(&str, &str); 9] = [
    ("algorithm", "algorithm.name"),
    ("scheduler", "scheduler.kind"),
    ("init", "swarm.init"),
    ("n", "swarm.n"),
    ("dim", "swarm.dim"),
    ("side", "swarm.side"),
    ("step", "algorithm.step"),
    ("locality", "algorithm.locality"),
    ("max_rounds", "stop.max_rounds"),
];

/// Metric columns of `runs.csv`, after the parameters and the seed.
pub const METRIC_COLUMNS: [&str; 24] = [
    "rounds",
    "activations",
    "moves",
    "d_opt",
    "d_max",
    "rho",
    "tau",
    "converged",
    "final_diameter",
    "final_extent_x",
    "final_extent_y",
    "final_extent_z",
    "hull_area_initial",
    "hull_area_final",
    "hull_area_max",
    "hull_growth_rounds",
    "hull_grew",
    "hull_growth_max",
    "committed_hull_growth",
    "terminated",
    "distance",
    "stop_criterion",
    "ticks",
    "wall_ms",
];

/// The last column of `runs.csv`: the hash of the resolved config, so that every row
/// says which experiment it belongs to.
pub const CONFIG_HASH_COLUMN: &str = "config_hash";

/// Swept keys that are not among [`PARAM_COLUMNS`]: each gets a column named by its
/// dotted key.
pub fn extra_axes(exp: &Experiment) -> Vec<String> {
    exp.axes
        .iter()
        .map(|a| a.path.clone())
        .filter(|p| !PARAM_COLUMNS.iter().any(|(_, k)| k == p) && p != "name")
        .collect()
}

/// The parameter part of the header: name, cell, the fixed parameters, extra axes.
pub fn param_header(exp: &Experiment) -> Vec<String> {
    let mut h = vec!["name".to_string(), "cell".to_string()];
    h.extend(PARAM_COLUMNS.iter().map(|(c, _)| c.to_string()));
    h.extend(extra_axes(exp));
    h
}

/// The header of `runs.csv`.
pub fn runs_header(exp: &Experiment) -> Vec<String> {
    let mut h = param_header(exp);
    h.push("seed".into());
    h.extend(METRIC_COLUMNS.iter().map(|c| c.to_string()));
    h.push(CONFIG_HASH_COLUMN.into());
    h
}

/// A float as written to CSV: shortest round-trip form.
pub fn num(x: f64) -> String {
    format!("{x}")
}

/// The parameter values of a cell, matching [`param_header`].
pub fn param_values(exp: &Experiment, cell: &Cell) -> Vec<String> {
    let s = &cell.spec;
    let mut v = vec![
        s.name.clone(),
        cell.key.clone(),
        cell.algorithm().name().to_string(),
        cell.sim_config(0).scheduler.name().to_string(),
        serde_name(&s.swarm.init),
        cell.n().to_string(),
        s.swarm.dim.to_string(),
        num(s.swarm.side),
        num(s.algorithm.step),
        num(s.algorithm.locality),
        s.stop.max_rounds.to_string(),
    ];
    for path in extra_axes(exp) {
        let value = cell
            .values
            .iter()
            .find(|(k, _)| *k == path)
            .map(|(_, v)| v.clone())
            .unwrap_or_default();
        v.push(value);
    }
    v
}

fn serde_name<T: serde::Serialize>(value: &T) -> String {
    match toml::Value::try_from(value) {
        Ok(toml::Value::String(s)) => s,
        Ok(other) => other.to_string(),
        Err(_) => String::new(),
    }
}

/// The full row of one finished run.
pub fn run_row(
    exp: &Experiment,
    cell: &Cell,
    seed: u64,
    o: &RunOutcome,
    wall_ms: f64,
) -> Vec<String> {
    let step = cell.spec.algorithm.step;
    let mut v = param_values(exp, cell);
    v.push(seed.to_string());
    let ext = |k: usize| o.final_extents.get(k).copied().map(num).unwrap_or_default();
    v.extend([
        o.rounds.to_string(),
        o.activations.to_string(),
        o.moves.to_string(),
        num(o.d_opt),
        num(o.d_max),
        num(o.rho(step)),
        num(o.tau()),
        o.converged.to_string(),
        num(o.final_diameter),
        ext(0),
        ext(1),
        ext(2),
        num(o.hull_initial),
        num(o.hull_final),
        num(o.hull_max),
        o.hull_growth_rounds.to_string(),
        (o.hull_growth_rounds > 0).to_string(),
        num(o.hull_growth_max),
        o.committed_hull_growth.to_string(),
        o.terminated.map(|t| t.to_string()).unwrap_or_default(),
        num(o.distance),
        cell.criterion().name().to_string(),
        o.ticks.map(|t| t.to_string()).unwrap_or_default(),
        format!("{wall_ms:.3}"),
        exp.hash.clone(),
    ]);
    v
}
