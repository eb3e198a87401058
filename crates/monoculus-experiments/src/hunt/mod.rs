//! `monoculus hunt`: a search for starts (and schedules) that break a property of an
//! algorithm — the hull grows, the diameter grows, the run does not converge or is stuck
//! short of its goal, two robots collide — or that make it slow; a counterexample found is shrunk and written as a
//! config that `monoculus run` replays.
//!
//! The search keeps `hunt.population` candidates side by side. Each generation every
//! candidate proposes one change (a robot moved, added or removed, the run's seed drawn
//! again, activations of an SSYNC round flipped) or, after `hunt.restart` moves without
//! improvement, a new random start; a change is kept when it scores at least as high.
//! Each proposal draws from its own random stream keyed by (hunt seed, candidate,
//! generation) and the generation's results are reduced in candidate order, so the
//! result of an evaluations budget is the same whatever the thread count.
//!
//! ```
//! use monoculus_experiments::hunt::{Hunt, HuntOptions};
//! use monoculus_experiments::{Experiment, Registry};
//!
//! let config = r#"
//! name = "median-hull"
//! [swarm]
//! n = 4
//! init = "square"
//! side = 3.0
//! [algorithm]
//! name = "median"
//! [stop]
//! max_rounds = 10
//! [hunt]
//! property = "hull_grows"
//! n_min = 3
//! n_max = 6
//! evaluations = 4000
//! "#;
//! let exp = Experiment::parse(config, "median.toml", ".".as_ref(), &[], &Registry::builtin())?;
//! let hunt = Hunt::new(&exp, &exp.cells[0], "median.toml")?;
//! let report = hunt.run(&HuntOptions::default());
//! assert!(report.found); // the paper's Figure 1: Median can grow the hull
//! assert!(report.best.as_ref().unwrap().candidate.len() <= 6);
//! # Ok::<(), monoculus_experiments::ConfigError>(())
//! ```

mod search;
mod shrink;
mod write;

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

pub use write::{FILES, FolderWriter, HtmlWriter, summary_json, write_found};

use monoculus_engine::asynchrony::{Durations, GivenDuration, Phase};
use monoculus_engine::{AsyncSpec, TickDist};

use crate::config::{HuntSpec, Property, SchedulerKind};
use crate::{Cell, ConfigError, Experiment};
use monoculus_engine::asynchrony::MAX_PHASE_TICKS;

/// The largest swarm whose SSYNC activation subsets are searched (one bit per robot).
pub const MAX_SUBSET_ROBOTS: usize = 64;

/// One point of the search: a start, the run's seed, (SSYNC with subsets searched, or a
/// schedule file) the robots activated in each round and (ASYNC) the phase durations
/// given in place of draws.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    /// The start: one row per robot (x, y, z; z = 0 in the plane).
    pub points: Vec<[f64; 3]>,
    /// The run's seed (the robots' frames, random choices, durations).
    pub seed: u64,
    /// Round k + 1's activated robots as a bit set (bit i: robot i), when the schedule is
    /// part of the candidate.
    pub schedule: Option<Vec<u64>>,
    /// ASYNC: phase durations given in place of draws (searched, or the config's
    /// `scheduler.durations`), by robot, cycle and phase, each phase once.
    pub durations: Vec<GivenDuration>,
}

impl Candidate {
    /// The number of robots.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether it has no robots.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

/// What one candidate's run showed.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// How close it came to breaking the property, or (`slow`) how slow it was: higher
    /// is worse for the algorithm.
    pub score: f64,
    /// Whether it breaks the property (never for `slow`).
    pub violated: bool,
    /// The round (ASYNC: epoch) the property broke in, or the rounds the run took.
    pub round: u64,
    /// The rounds (epochs) run.
    pub rounds: u64,
    /// Epochs (`slow` under SSYNC with its subsets searched: spans in which every robot
    /// was activated), else equal to `rounds`.
    pub epochs: u64,
    /// Whether the run converged.
    pub converged: bool,
    /// Whether the run fell quiescent short of its goal.
    pub stuck: bool,
    /// What ended the run (`None` for a candidate that could not run).
    pub stopped_by: Option<monoculus_engine::StoppedBy>,
    /// Looks made by all the robots.
    pub activations: u64,
    /// Why the run failed (the algorithm panicked or returned a bad direction), if it did.
    pub failure: Option<String>,
}

/// The best candidate found, with its evaluation.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    /// The candidate.
    pub candidate: Candidate,
    /// Its run.
    pub evaluation: Evaluation,
}

/// How a hunt is run: when to stop from outside, and what to tell while it runs.
#[derive(Default)]
pub struct HuntOptions<'a> {
    /// Once set, the search stops at the end of its generation (and shrinking at the end
    /// of its batch); the report then says `interrupted`.
    pub interrupt: Option<Arc<AtomicBool>>,
    /// Called after every generation and shrinking batch.
    pub on_progress: Option<&'a (dyn Fn(&Progress) + Sync)>,
    /// Called whenever the best candidate changes, with the hunt so far (not shrunk): a
    /// caller writes it out, so that an interrupted hunt keeps it.
    pub on_best: Option<&'a (dyn Fn(&HuntReport) + Sync)>,
}

/// Where a hunt is.
#[derive(Clone, Debug, PartialEq)]
pub struct Progress {
    /// `search` or `shrink`.
    pub phase: &'static str,
    /// Candidates evaluated so far.
    pub evaluations: u64,
    /// The best score so far, if any candidate ran.
    pub best: Option<f64>,
    /// Whether a counterexample has been found.
    pub found: bool,
    /// Seconds since the start.
    pub seconds: f64,
}

/// What a hunt found.
#[derive(Clone, Debug, PartialEq)]
pub struct HuntReport {
    /// The property.
    pub property: Property,
    /// Whether a counterexample was found (`slow`: whether any run converged).
    pub found: bool,
    /// Whether the counterexample was shrunk to the end (false when interrupted).
    pub shrunk: bool,
    /// The best candidate: the counterexample, or the highest score seen.
    pub best: Option<Found>,
    /// Candidates evaluated (search and shrinking).
    pub evaluations: u64,
    /// Of which while shrinking.
    pub shrink_evaluations: u64,
    /// Generations of the search.
    pub generations: u64,
    /// Runs that failed (their algorithm panicked or returned a bad direction).
    pub failures: u64,
    /// The first such failure's message.
    pub first_failure: Option<String>,
    /// Seconds taken.
    pub seconds: f64,
    /// Whether it was stopped from outside.
    pub interrupted: bool,
}

/// A validated hunt: the cell it runs, its property, its search space and budget.
#[derive(Clone, Debug)]
pub struct Hunt {
    /// The cell whose algorithm, model, scheduler and stop are hunted.
    pub cell: Cell,
    /// `[hunt]`.
    pub spec: HuntSpec,
    /// Fewest robots.
    pub n_min: usize,
    /// Most robots.
    pub n_max: usize,
    /// Largest single move of the local search.
    pub perturb: f64,
    /// Whether SSYNC activation subsets are part of each candidate.
    pub subsets: bool,
    /// Whether ASYNC phase durations are searched.
    pub durations: bool,
    /// The longest duration the search gives a phase, ticks.
    pub max_ticks: u64,
    /// The rounds (epochs) of each run: `stop.max_rounds`.
    pub max_rounds: u64,
}

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

    /// The property.
    pub fn property(&self) -> Property {
        self.spec.property
    }

    /// Whether the counterexample's schedule is part of it (written to schedule.csv and
    /// replayed with `scheduler.kind = "file"`).
    pub fn schedule_matters(&self) -> bool {
        self.subsets || self.cell.spec.scheduler.kind == SchedulerKind::File
    }

    /// Searches, then shrinks what it found: see the module's documentation.
    pub fn run(&self, options: &HuntOptions<'_>) -> HuntReport {
        let start = std::time::Instant::now();
        let mut state = search::State::new(self, options, start);
        state.search();
        if let Some(best) = state.best.clone()
            && best.evaluation.violated
        {
            state.notify_best();
            if !state.stopped() {
                let shrunk = shrink::shrink(&mut state, best);
                state.best = Some(shrunk);
                state.shrunk = !state.stopped();
            }
        }
        state.report()
    }
}

/// The schedule of a candidate as the engine's list (rounds with nobody are left out).
fn activation_list(rounds: &[u64]) -> monoculus_engine::ActivationList {
    let rows = rounds
        .iter()
        .enumerate()
        .filter(|(_, m)| **m != 0)
        .map(|(k, &m)| (k as u64 + 1, robots_of(m)))
        .collect();
    monoculus_engine::ActivationList::new(rows).expect("rounds increase, robots once each")
}

/// The robots of a bit set, ascending.
fn robots_of(mask: u64) -> Vec<u32> {
    (0..64).filter(|i| mask >> i & 1 == 1).collect()
}

/// A schedule as bit sets per round, from the engine's list (rounds 1..=`len`).
fn masks_of(list: &monoculus_engine::ActivationList, len: u64) -> Vec<u64> {
    (1..=len)
        .map(|k| list.round(k).iter().fold(0u64, |m, &r| m | 1 << r))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Registry;

    fn hunt(extra: &str) -> Hunt {
        let text = format!(
            "name = \"t\"\n[swarm]\nn = 5\ninit = \"square\"\nside = 3.0\n[algorithm]\nname = \"median\"\n[stop]\nmax_rounds = 10\n{extra}\n"
        );
        let exp =
            Experiment::parse(&text, "t.toml", ".".as_ref(), &[], &Registry::builtin()).unwrap();
        Hunt::new(&exp, &exp.cells[0], "t.toml").unwrap()
    }

    #[test]
    fn a_hunt_stopped_at_its_first_counterexample_keeps_it_unshrunk() {
        let h =
            hunt("[hunt]\nproperty = \"hull_grows\"\nn_min = 3\nn_max = 8\nevaluations = 20000");
        let flag = Arc::new(AtomicBool::new(false));
        let seen = std::sync::Mutex::new(Vec::new());
        let on_best = |r: &HuntReport| {
            seen.lock().unwrap().push(r.clone());
            if r.best.as_ref().is_some_and(|b| b.evaluation.violated) {
                flag.store(true, std::sync::atomic::Ordering::Relaxed);
            }
        };
        let report = h.run(&HuntOptions {
            interrupt: Some(flag.clone()),
            on_progress: None,
            on_best: Some(&on_best),
        });
        assert!(report.found && !report.shrunk && report.interrupted);
        assert_eq!(report.shrink_evaluations, 0);
        let last = seen.lock().unwrap().last().cloned().unwrap();
        assert_eq!(last.best, report.best, "what was told is what is kept");
        assert!(summary_json(&h, &report).contains("\"shrunk\": false"));
        // Uninterrupted, the same search shrinks the same counterexample.
        let full = h.run(&HuntOptions::default());
        assert!(full.shrunk && full.found);
        assert!(full.best.unwrap().candidate.len() <= report.best.unwrap().candidate.len());
    }

    #[test]
    fn epochs_count_spans_in_which_every_robot_acted() {
        // Robots 0, 1, 2: {0}, {1, 2} is one epoch; {2}, {0}, {1} another; {0} unfinished.
        let s = [0b001, 0b110, 0b100, 0b001, 0b010, 0b001];
        assert_eq!(search::epochs(&s, 3, 6), 2);
        assert_eq!(search::epochs(&s, 3, 4), 1);
        assert_eq!(search::epochs(&s, 3, 0), 0);
    }

    #[test]
    fn leaving_a_robot_out_renumbers_the_schedule_and_durations_and_keeps_every_round_busy() {
        let h = hunt(
            "[scheduler]\nkind = \"ssync\"\n[hunt]\nproperty = \"hull_grows\"\nn_min = 2\nn_max = 4\nevaluations = 9",
        );
        assert!(h.subsets);
        let c = Candidate {
            points: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]],
            seed: 3,
            schedule: Some(vec![0b1011, 0b0010, 0b1100]),
            durations: [(0, Phase::Move), (1, Phase::Idle), (3, Phase::Compute)]
                .map(|(robot, phase)| GivenDuration {
                    robot,
                    cycle: 2,
                    phase,
                    ticks: 5,
                })
                .to_vec(),
        };
        let mut rng = monoculus_core::rng::Stream::new(0, 0, 0, 0);
        let d = h.without_robot(&c, 1, &mut rng);
        assert_eq!(d.points, vec![[0.0; 3], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]]);
        let s = d.schedule.unwrap();
        assert_eq!(s[0], 0b101);
        assert_ne!(
            s[1], 0,
            "robot 1 alone was activated: the round gets another"
        );
        assert!(s[1] < 0b1000);
        assert_eq!(s[2], 0b110);
        assert_eq!(activation_list(&s).round(3), &[1, 2]);
        // Its given durations go with it, and robot 3's become robot 2's.
        let robots: Vec<(u32, Phase)> = d.durations.iter().map(|g| (g.robot, g.phase)).collect();
        assert_eq!(robots, [(0, Phase::Move), (2, Phase::Compute)]);
    }
}
