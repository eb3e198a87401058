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

mod evaluate;
mod propose;
mod search;
mod shrink;
mod validate;
mod write;

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

pub use write::{FILES, FolderWriter, HtmlWriter, summary_json, write_found};

use monoculus_engine::asynchrony::{Durations, GivenDuration, Phase};

use crate::config::{HuntSpec, Property, SchedulerKind};
use crate::{Cell, Experiment};

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
        let report = state.report();
        crate::runner::drop_kept();
        report
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

    /// A best that comes within [`FolderWriter::EVERY`] of the last write is kept back,
    /// and written by the next progress once that much time has passed: the folder is
    /// never more than about that much behind the hunt.
    #[test]
    fn the_folder_follows_the_best_within_its_interval() {
        let h = hunt("[hunt]\nproperty = \"hull_grows\"\nn_min = 3\nevaluations = 64");
        let registry = Registry::builtin();
        let dir = tempfile::tempdir().unwrap();
        let writer = FolderWriter::new(dir.path(), &h, &registry, None);
        let report = h.run(&HuntOptions::default());
        let with_score = |score: f64, evaluations: u64| {
            let mut r = report.clone();
            let best = r.best.as_mut().unwrap();
            best.evaluation.violated = false;
            best.evaluation.score = score;
            r.found = false;
            r.evaluations = evaluations;
            r
        };
        let summary = || std::fs::read_to_string(dir.path().join("summary.json")).unwrap();
        writer.on_best(&with_score(0.1, 10));
        assert!(summary().contains("\"evaluations\": 10,"), "{}", summary());
        writer.on_best(&with_score(0.2, 20));
        writer.on_progress();
        assert!(
            summary().contains("\"evaluations\": 10,"),
            "kept back: {}",
            summary()
        );
        std::thread::sleep(FolderWriter::EVERY);
        writer.on_progress();
        assert!(
            summary().contains("\"evaluations\": 20,"),
            "written: {}",
            summary()
        );
        // A counterexample is written at once, whenever it comes.
        let mut broken = with_score(0.3, 30);
        broken.best.as_mut().unwrap().evaluation.violated = true;
        broken.found = true;
        writer.on_best(&broken);
        assert!(summary().contains("\"found\": true"), "{}", summary());
        writer.finish(&broken).unwrap();
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
        assert_eq!(evaluate::epochs(&s, 3, 6), 2);
        assert_eq!(evaluate::epochs(&s, 3, 4), 1);
        assert_eq!(evaluate::epochs(&s, 3, 0), 0);
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
