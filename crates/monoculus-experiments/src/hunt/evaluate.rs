//! Evaluation: one candidate's run, scored for the hunt's property.

use std::sync::atomic::{AtomicBool, Ordering};

use glam::{DVec2, DVec3};
use monoculus_core::geometry::Point;
use monoculus_engine::systems::hull_grew;
use monoculus_engine::{IndexPoint, SchedulerSpec, SimConfig};

use super::*;

impl Hunt {
    /// Runs `c` and scores it for the property.
    pub fn evaluate(&self, c: &Candidate) -> Evaluation {
        if self.cell.dim() == 3 {
            self.evaluate_in::<DVec3>(c)
        } else {
            self.evaluate_in::<DVec2>(c)
        }
    }

    /// The run of `c`: its config (the cell's, with `c`'s seed, schedule and given
    /// durations) and its start.
    fn run_of<P: IndexPoint>(&self, c: &Candidate) -> (SimConfig, Vec<P>) {
        let mut config = self.cell.sim_config(c.seed);
        if let Some(rounds) = &c.schedule {
            config.scheduler = SchedulerSpec::File(Arc::new(activation_list(rounds)));
        }
        if let SchedulerSpec::Async(spec) = &mut config.scheduler {
            spec.durations = durations_of(&c.durations);
        }
        (config, c.points.iter().map(|r| P::from_slice(r)).collect())
    }

    /// `found` with the verdict (converged, stuck, stopped by) of its run as
    /// reproduce.toml replays it: a run stopped at its violation is cut there, with
    /// `stop.max_rounds` the violation's round, and the stop criterion may hold in that
    /// very round. The search stops such runs early and reads "interrupted"; this is
    /// asked only of what is reported.
    pub(super) fn as_reproduced(&self, mut found: Found) -> Found {
        if !(found.evaluation.violated && self.property().cut_at_violation()) {
            return found;
        }
        let cut = if self.cell.dim() == 3 {
            self.cut_run::<DVec3>(&found.candidate, found.evaluation.round)
        } else {
            self.cut_run::<DVec2>(&found.candidate, found.evaluation.round)
        };
        if let Ok(cut) = cut {
            let e = &mut found.evaluation;
            (e.converged, e.stuck, e.stopped_by) =
                (cut.converged, cut.stuck(), Some(cut.stopped_by));
        }
        found
    }

    fn cut_run<P: IndexPoint>(
        &self,
        c: &Candidate,
        round: u64,
    ) -> Result<monoculus_engine::RunOutcome, monoculus_engine::EngineError> {
        let (mut config, points) = self.run_of::<P>(c);
        config.stop.max_rounds = round.max(1);
        crate::runner::with_simulation::<P, _>(config, points, |sim| sim.run())
    }

    fn evaluate_in<P: IndexPoint>(&self, c: &Candidate) -> Evaluation {
        let (config, points) = self.run_of::<P>(c);
        let eps_pos = config.vision.eps_pos;
        let invalid = Evaluation {
            score: f64::NEG_INFINITY,
            violated: false,
            round: 0,
            rounds: 0,
            epochs: 0,
            converged: false,
            stuck: false,
            stopped_by: None,
            activations: 0,
            failure: None,
        };
        let min0 = min_distance(&points);
        let property = self.property();
        if property == Property::Collision && min0 <= eps_pos {
            // Robots that start together did not collide.
            return invalid;
        }
        let stop = Arc::new(AtomicBool::new(false));
        let mut score = match property {
            Property::HullGrows | Property::DiameterGrows | Property::BoxGrows => -1.0,
            _ => 0.0,
        };
        let mut violated_at = None;
        let mut previous: Option<(f64, f64)> = None;
        let mut extents: Vec<f64> = Vec::new();
        // A growth counts where the grown measure exceeds `above`; the score is the
        // growth against the larger of the measure before and `above` (so it nears 0
        // from below as a growth nears the threshold).
        let above = self.spec.above.unwrap_or(0.0);
        let run = crate::runner::with_simulation::<P, _>(config, points, |sim| {
            sim.set_interrupt(stop.clone());
            sim.run_with(|r| {
                let grew = |before: f64, now: f64, score: &mut f64| {
                    let base = before.max(above);
                    if base > 0.0 && now != before {
                        *score = f64::max(*score, now / base - 1.0);
                    }
                    hull_grew(before, now) && now > above
                };
                let broke = match (property, previous) {
                    (Property::HullGrows, Some((hull, _))) => grew(hull, r.hull, &mut score),
                    (Property::DiameterGrows, Some((_, diameter))) => {
                        grew(diameter, r.diameter, &mut score)
                    }
                    (Property::BoxGrows, Some(_)) => {
                        let mut any = false;
                        for (&before, &now) in extents.iter().zip(r.extents) {
                            any |= grew(before, now, &mut score);
                        }
                        any
                    }
                    (Property::Collision, Some(_)) => {
                        let d = min_distance(r.positions);
                        score = score.max(1.0 - d / min0);
                        d <= eps_pos
                    }
                    _ => false,
                };
                if broke && violated_at.is_none() {
                    violated_at = Some(r.round);
                    stop.store(true, Ordering::Relaxed);
                }
                previous = Some((r.hull, r.diameter));
                extents.clear();
                extents.extend_from_slice(r.extents);
            })
        });
        let Ok(outcome) = run else {
            return invalid;
        };
        if let Some(f) = &outcome.failure {
            return Evaluation {
                failure: Some(f.to_string()),
                rounds: outcome.rounds,
                ..invalid
            };
        }
        let epochs = match (&c.schedule, self.subsets) {
            (Some(s), true) => epochs(s, c.len(), outcome.rounds),
            _ => outcome.rounds,
        };
        let (violated, round) = match property {
            Property::NoConvergence => {
                score = outcome.rounds as f64 / self.max_rounds.max(1) as f64
                    + if outcome.converged { 0.0 } else { 1.0 };
                (!outcome.converged, outcome.rounds)
            }
            Property::Slow => {
                score = epochs as f64;
                (false, outcome.rounds)
            }
            Property::Stuck => {
                // How far from its goal the run fell quiescent (above 1: stuck); runs
                // that did not fall quiescent score 0.
                let a = &self.cell.spec.algorithm;
                let goal = outcome.goal;
                let measure = goal.measure(
                    outcome.final_diameter,
                    outcome.final_radius,
                    &outcome.final_extents,
                );
                score = if outcome.stopped_by == monoculus_engine::StoppedBy::Quiescent {
                    measure / goal.bound(a.step, a.locality)
                } else {
                    0.0
                };
                (outcome.stuck(), outcome.rounds)
            }
            _ => (violated_at.is_some(), violated_at.unwrap_or(outcome.rounds)),
        };
        if violated && property != Property::NoConvergence {
            score = score.max(0.0);
        }
        Evaluation {
            score,
            violated,
            round,
            rounds: outcome.rounds,
            epochs,
            converged: outcome.converged,
            stuck: outcome.stuck(),
            stopped_by: Some(outcome.stopped_by),
            activations: outcome.activations,
            failure: None,
        }
    }
}

/// The engine's durations of a candidate (`None` when none is given).
pub(super) fn durations_of(given: &[GivenDuration]) -> Option<Arc<Durations>> {
    (!given.is_empty()).then(|| {
        Arc::new(Durations::new(given.iter().copied()).expect("each phase once, in range"))
    })
}

/// The smallest distance between two robots (infinite for fewer than two).
fn min_distance<P: Point>(points: &[P]) -> f64 {
    let mut d = f64::INFINITY;
    for (i, &p) in points.iter().enumerate() {
        for &q in &points[i + 1..] {
            d = d.min(p.distance(q));
        }
    }
    d
}

/// Epochs completed in the first `rounds` rounds of `schedule` (an epoch: the shortest
/// span in which every robot was activated).
pub(super) fn epochs(schedule: &[u64], n: usize, rounds: u64) -> u64 {
    let all = if n >= 64 { u64::MAX } else { (1u64 << n) - 1 };
    let mut seen = 0u64;
    let mut epochs = 0;
    for &m in schedule.iter().take(rounds as usize) {
        seen |= m;
        if seen & all == all {
            epochs += 1;
            seen = 0;
        }
    }
    epochs
}
