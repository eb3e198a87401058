//! The search loop: candidates side by side, each improved by local moves
//! (`propose.rs`) and scored by its run (`evaluate.rs`), the best kept.

use std::sync::atomic::Ordering;
use std::time::Instant;

use monoculus_core::rng::Stream;
use rayon::prelude::*;

use super::*;

/// The random streams of the hunt (keyed by candidate and generation).
const HUNT_STREAM: u64 = 0x4855_4e54;

/// The running hunt: its counts and its best candidate.
pub(super) struct State<'a> {
    pub(super) hunt: &'a Hunt,
    options: &'a HuntOptions<'a>,
    start: Instant,
    pub(super) best: Option<Found>,
    pub(super) evaluations: u64,
    pub(super) shrink_evaluations: u64,
    generations: u64,
    failures: u64,
    first_failure: Option<String>,
    pub(super) shrunk: bool,
}

/// One chain of the search: its candidate, the candidate's run, moves since it improved.
struct Chain {
    candidate: Candidate,
    evaluation: Evaluation,
    stale: u32,
}

impl<'a> State<'a> {
    pub(super) fn new(hunt: &'a Hunt, options: &'a HuntOptions<'a>, start: Instant) -> Self {
        State {
            hunt,
            options,
            start,
            best: None,
            evaluations: 0,
            shrink_evaluations: 0,
            generations: 0,
            failures: 0,
            first_failure: None,
            shrunk: false,
        }
    }

    /// Whether the hunt was stopped from outside.
    pub(super) fn stopped(&self) -> bool {
        self.options
            .interrupt
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
    }

    /// Evaluates candidates in parallel (results in their order), counting them and
    /// the failed runs.
    pub(super) fn evaluate_all(&mut self, candidates: &[Candidate]) -> Vec<Evaluation> {
        let hunt = self.hunt;
        let out: Vec<Evaluation> = candidates.par_iter().map(|c| hunt.evaluate(c)).collect();
        self.evaluations += out.len() as u64;
        for e in &out {
            if let Some(f) = &e.failure {
                self.failures += 1;
                self.first_failure.get_or_insert_with(|| f.clone());
            }
        }
        out
    }

    pub(super) fn progress(&self, phase: &'static str) {
        if let Some(f) = self.options.on_progress {
            f(&Progress {
                phase,
                evaluations: self.evaluations,
                best: self.best.as_ref().map(|b| b.evaluation.score),
                found: self.best.as_ref().is_some_and(|b| b.evaluation.violated),
                seconds: self.start.elapsed().as_secs_f64(),
            });
        }
    }

    /// Random restarts and local search until a counterexample, the budget or a stop.
    pub(super) fn search(&mut self) {
        let hunt = self.hunt;
        let spec = &hunt.spec;
        let budget = spec.evaluations.unwrap_or(u64::MAX);
        let mut chains: Vec<Option<Chain>> = (0..spec.population).map(|_| None).collect();
        loop {
            let out_of_time = spec
                .seconds
                .is_some_and(|s| self.start.elapsed().as_secs_f64() >= s);
            if self.stopped() || self.evaluations >= budget || out_of_time {
                break;
            }
            let k = (budget - self.evaluations).min(spec.population as u64) as usize;
            let g = self.generations;
            let proposals: Vec<Candidate> = (0..k)
                .into_par_iter()
                .map(|i| {
                    let mut rng = Stream::new(spec.seed, HUNT_STREAM, i as u64, g);
                    match &chains[i] {
                        Some(ch) if ch.stale < spec.restart => {
                            hunt.mutate(&ch.candidate, &ch.evaluation, &mut rng)
                        }
                        _ => hunt.random_start(i == 0 && g == 0, &mut rng),
                    }
                })
                .collect();
            let evaluations = self.evaluate_all(&proposals);
            let mut improved = false;
            for (i, (candidate, evaluation)) in proposals.into_iter().zip(evaluations).enumerate() {
                if better(&evaluation, self.best.as_ref().map(|b| &b.evaluation)) {
                    self.best = Some(Found {
                        candidate: candidate.clone(),
                        evaluation: evaluation.clone(),
                    });
                    improved = true;
                }
                let chain = &mut chains[i];
                match chain {
                    Some(ch) if ch.stale < spec.restart => {
                        if evaluation.score >= ch.evaluation.score {
                            ch.stale = if evaluation.score > ch.evaluation.score {
                                0
                            } else {
                                ch.stale + 1
                            };
                            ch.candidate = candidate;
                            ch.evaluation = evaluation;
                        } else {
                            ch.stale += 1;
                        }
                    }
                    _ => {
                        *chain = Some(Chain {
                            candidate,
                            evaluation,
                            stale: 0,
                        })
                    }
                }
            }
            self.generations += 1;
            self.progress("search");
            let found = self.best.as_ref().is_some_and(|b| b.evaluation.violated);
            if found {
                break;
            }
            if improved {
                self.notify_best();
            }
        }
    }

    /// Tells `on_best` of the best so far.
    pub(super) fn notify_best(&self) {
        if let Some(f) = self.options.on_best {
            f(&self.snapshot());
        }
    }

    /// The hunt so far, as a report (not shrunk).
    fn snapshot(&self) -> HuntReport {
        HuntReport {
            property: self.hunt.property(),
            // `slow` is never broken: its best is the slowest run found.
            found: self.best.as_ref().is_some_and(|b| b.evaluation.violated),
            shrunk: false,
            best: self.best.clone().map(|b| self.hunt.as_reproduced(b)),
            evaluations: self.evaluations,
            shrink_evaluations: self.shrink_evaluations,
            generations: self.generations,
            failures: self.failures,
            first_failure: self.first_failure.clone(),
            seconds: self.start.elapsed().as_secs_f64(),
            interrupted: self.stopped(),
        }
    }

    /// The finished hunt.
    pub(super) fn report(self) -> HuntReport {
        HuntReport {
            shrunk: self.shrunk,
            ..self.snapshot()
        }
    }
}

/// Whether `e` beats the best so far: a violation beats none, then the higher score.
fn better(e: &Evaluation, best: Option<&Evaluation>) -> bool {
    if e.failure.is_some() || e.score == f64::NEG_INFINITY {
        return best.is_none() && e.failure.is_none() && e.score > f64::NEG_INFINITY;
    }
    match best {
        None => true,
        Some(b) => (e.violated && !b.violated) || (e.violated == b.violated && e.score > b.score),
    }
}
