//! Reading a `[hunt]` section: a property the cell can be judged on, a search space
//! that is not empty, a budget that is not zero.

use std::sync::Arc;

use monoculus_engine::asynchrony::{Durations, GivenDuration, MAX_PHASE_TICKS, Phase};
use monoculus_engine::{AsyncSpec, TickDist};

use super::{Hunt, MAX_SUBSET_ROBOTS};
use crate::config::{Property, SchedulerKind};
use crate::{Cell, ConfigError, Experiment};

impl Hunt {
    /// Reads and checks the `[hunt]` section of `cell` (`file` names the config in
    /// errors): a property the cell can be judged on, a search space that is not empty,
    /// a budget that is not zero.
    pub fn new(exp: &Experiment, cell: &Cell, file: &str) -> Result<Hunt, ConfigError> {
        let err = |key: &str, message: String| exp.error_at(file, key, message);
        let Some(spec) = cell.spec.hunt.clone() else {
            return Err(err(
                "",
                "no [hunt] section: give at least hunt.property and a budget (hunt.evaluations or hunt.seconds)".into(),
            ));
        };
        let swarm = &cell.spec.swarm;
        let default_n = cell.n();
        let n_min = spec.n_min.unwrap_or(default_n);
        let n_max = spec.n_max.unwrap_or(default_n.max(n_min));
        if n_min == 0 {
            return Err(err(
                if spec.n_min.is_some() {
                    "hunt.n_min"
                } else {
                    "swarm.n"
                },
                "the search needs at least one robot: give hunt.n_min (and hunt.n_max), or swarm.n"
                    .into(),
            ));
        }
        if n_min > n_max {
            return Err(err(
                "hunt.n_max",
                format!("{n_max} is below hunt.n_min = {n_min}: the search space is empty"),
            ));
        }
        if n_max > crate::limits::MAX_HUNT_ROBOTS {
            return Err(err(
                "hunt.n_max",
                format!(
                    "{n_max} robots: a hunt searches swarms of at most {} robots",
                    crate::limits::MAX_HUNT_ROBOTS
                ),
            ));
        }
        if let Some(f) = &cell.file_positions
            && (n_max > f.len() || spec.n_min.is_some_and(|m| m > f.len()))
        {
            return Err(err(
                "hunt.n_max",
                format!(
                    "{n_max}: the starts perturb the {} robots of swarm.file, and a hunt from a file searches at most that many",
                    f.len()
                ),
            ));
        }
        match (spec.evaluations, spec.seconds) {
            (None, None) => {
                return Err(err(
                    "hunt",
                    "no budget: give hunt.evaluations, hunt.seconds or both".into(),
                ));
            }
            (Some(0), _) => {
                return Err(err(
                    "hunt.evaluations",
                    "a budget of 0 evaluations searches nothing".into(),
                ));
            }
            (_, Some(s)) if !(s > 0.0 && s.is_finite()) => {
                return Err(err(
                    "hunt.seconds",
                    format!("{s}: a budget of seconds is a positive, finite number"),
                ));
            }
            _ => {}
        }
        if spec.population == 0 {
            return Err(err(
                "hunt.population",
                "0: the search keeps at least one candidate".into(),
            ));
        }
        if spec.population > crate::limits::MAX_HUNT_POPULATION {
            return Err(err(
                "hunt.population",
                format!("at most {}", crate::limits::MAX_HUNT_POPULATION),
            ));
        }
        let perturb = spec.perturb.unwrap_or(swarm.side / 10.0);
        if !(perturb > 0.0 && perturb.is_finite()) {
            return Err(err(
                "hunt.perturb",
                format!("{perturb}: the size of a move is a positive, finite number"),
            ));
        }
        let dim = cell.dim();
        let kind = cell.spec.scheduler.kind;
        match spec.property {
            Property::HullGrows if n_max <= dim => {
                return Err(err(
                    "hunt.property",
                    format!(
                        "hull_grows cannot be judged on at most {n_max} robots: their hull has no {} (give hunt.n_max >= {})",
                        if dim == 3 { "volume" } else { "area" },
                        dim + 1
                    ),
                ));
            }
            Property::Collision if cell.spec.vision.robot_radius > 0.0 => {
                return Err(err(
                    "hunt.property",
                    "collision cannot be judged on fat robots (vision.robot_radius > 0): the model keeps them apart".into(),
                ));
            }
            Property::Collision | Property::DiameterGrows | Property::BoxGrows if n_max < 2 => {
                return Err(err(
                    "hunt.property",
                    format!(
                        "{} needs two robots: give hunt.n_max >= 2",
                        spec.property.name()
                    ),
                ));
            }
            Property::Stuck if !cell.criterion().checks_quiescence() => {
                return Err(err(
                    "hunt.property",
                    format!(
                        "stuck is a run stopped by quiescence short of its goal, and stop.criterion = \"{}\" never stops a run for quiescence: use \"quiescent\" or \"quiescent_or_diameter\"",
                        cell.criterion().name()
                    ),
                ));
            }
            Property::Slow | Property::NoConvergence if cell.spec.faults.is_some() => {
                return Err(err(
                    "hunt.property",
                    format!(
                        "{} is judged by convergence, which faulty robots may forbid for every start: hunt it without [faults]",
                        spec.property.name()
                    ),
                ));
            }
            _ => {}
        }
        if kind == SchedulerKind::File
            && matches!(spec.property, Property::Slow | Property::NoConvergence)
        {
            return Err(err(
                "hunt.property",
                format!(
                    "{} is judged by convergence, and a run under scheduler.kind = \"file\" ends with its file: hunt it under ssync (its subsets searched)",
                    spec.property.name()
                ),
            ));
        }
        if let Some(above) = spec.above {
            if !matches!(
                spec.property,
                Property::HullGrows | Property::DiameterGrows | Property::BoxGrows
            ) {
                return Err(err(
                    "hunt.above",
                    format!(
                        "a threshold for growth: only with hull_grows, diameter_grows or box_grows, not {}",
                        spec.property.name()
                    ),
                ));
            }
            if !(above >= 0.0 && above.is_finite()) {
                return Err(err(
                    "hunt.above",
                    format!("{above}: a threshold is a finite number >= 0"),
                ));
            }
        }
        // An adversary choosing every round's robots can starve one robot for the whole
        // cap, which is not a failure to converge: no_convergence searches SSYNC's seed.
        let subsets = spec.subsets
            && kind == SchedulerKind::Ssync
            && spec.property != Property::NoConvergence;
        if subsets && n_max > MAX_SUBSET_ROBOTS {
            return Err(err(
                "hunt.n_max",
                format!(
                    "{n_max}: SSYNC activation subsets are searched for at most {MAX_SUBSET_ROBOTS} robots (or set hunt.subsets = false)"
                ),
            ));
        }
        if subsets && cell.spec.stop.max_rounds > crate::limits::MAX_HUNT_SCHEDULE {
            return Err(err(
                "stop.max_rounds",
                format!(
                    "{}: a hunt searching SSYNC subsets keeps a schedule of at most {} rounds (or set hunt.subsets = false)",
                    cell.spec.stop.max_rounds,
                    crate::limits::MAX_HUNT_SCHEDULE
                ),
            ));
        }
        if kind == SchedulerKind::File && n_max > MAX_SUBSET_ROBOTS {
            return Err(err(
                "hunt.n_max",
                format!(
                    "{n_max}: a hunt under a schedule file searches at most {MAX_SUBSET_ROBOTS} robots"
                ),
            ));
        }
        if let Some(list) = &cell.schedule
            && let Some(max) = list.max_robot()
            && max as usize >= n_min
        {
            return Err(err(
                "hunt.n_min",
                format!(
                    "{n_min}: scheduler.file activates robot {max}, so the hunt needs at least {} robots",
                    max + 1
                ),
            ));
        }
        if let Some(given) = &cell.durations
            && let Some(max) = given.max_robot()
            && max as usize >= n_min
        {
            return Err(err(
                "hunt.n_min",
                format!(
                    "{n_min}: scheduler.durations gives robot {max} a duration, so the hunt needs at least {} robots",
                    max + 1
                ),
            ));
        }
        let durations = spec.durations && kind == SchedulerKind::Async;
        let sc = &cell.spec.scheduler;
        let typical = [sc.idle, sc.compute, sc.motion]
            .iter()
            .map(|d| match *d {
                TickDist::Fixed { ticks } => ticks as f64,
                TickDist::Uniform { max, .. } => max as f64,
                TickDist::Exponential { mean } => mean.ceil(),
            })
            .fold(1.0, f64::max);
        let max_ticks = spec
            .max_ticks
            .unwrap_or((10.0 * typical).min(MAX_PHASE_TICKS as f64) as u64);
        if durations {
            if !(1..=MAX_PHASE_TICKS).contains(&max_ticks) {
                return Err(err(
                    "hunt.max_ticks",
                    format!("{max_ticks}: a phase lasts from 1 to 2^40 = {MAX_PHASE_TICKS} ticks"),
                ));
            }
            let longest = |phase| GivenDuration {
                robot: 0,
                cycle: 1,
                phase,
                ticks: max_ticks,
            };
            let widest = AsyncSpec {
                durations: Durations::new([
                    longest(Phase::Idle),
                    longest(Phase::Compute),
                    longest(Phase::Move),
                ])
                .ok()
                .map(Arc::new),
                ..AsyncSpec::default()
            };
            if let Err((_, m)) = widest.check(cell.spec.stop.max_rounds) {
                return Err(err("hunt.max_ticks", format!("{max_ticks}: {m}")));
            }
        }
        Ok(Hunt {
            cell: cell.clone(),
            spec,
            n_min,
            n_max,
            perturb,
            subsets,
            durations,
            max_ticks,
            max_rounds: cell.spec.stop.max_rounds,
        })
    }
}
