//! Proposals (random starts, local moves), evaluation (one run, scored for the property)
//! and the search loop.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use glam::{DVec2, DVec3};
use monoculus_core::geometry::Point;
use monoculus_core::rng::Stream;
use monoculus_engine::systems::hull_grew;
use monoculus_engine::{AsyncStart, IndexPoint, SchedulerSpec, Simulation};
use rayon::prelude::*;

use super::*;

/// The random streams of the hunt (keyed by candidate and generation).
const HUNT_STREAM: u64 = 0x4855_4e54;

/// Seeds of runs are drawn below this (they stay readable, and TOML integers).
const SEED_RANGE: u64 = 1 << 31;

impl Hunt {
    /// A new random start: n uniform in [n_min, n_max], positions as `[swarm]` draws them
    /// (or the file's, perturbed; candidate 0's first start is the file as it is).
    pub(super) fn random_start(&self, first: bool, rng: &mut Stream) -> Candidate {
        let n = self.n_min + rng.below(self.n_max - self.n_min + 1);
        let dim = self.cell.dim();
        let points = match &self.cell.file_positions {
            Some(f) => {
                let mut rows = f.rows.clone();
                while rows.len() > n {
                    rows.remove(rng.below(rows.len()));
                }
                if !first {
                    for r in &mut rows {
                        for x in r.iter_mut().take(dim) {
                            *x += rng.normal() * self.perturb;
                        }
                    }
                }
                rows
            }
            None => {
                let seed = rng.next_u64();
                if dim == 3 {
                    rows_of(&self.cell.generated_positions::<DVec3>(n, seed))
                } else {
                    rows_of(&self.cell.generated_positions::<DVec2>(n, seed))
                }
            }
        };
        let seed = rng.next_u64() % SEED_RANGE;
        let schedule = if self.subsets {
            let p = self.cell.spec.scheduler.p;
            Some(
                (0..self.max_rounds)
                    .map(|_| random_mask(n, p, rng))
                    .collect(),
            )
        } else {
            self.cell
                .schedule
                .as_ref()
                .map(|list| masks_of(list, list.rounds()))
        };
        let durations = self.cell.durations.as_ref().map_or(Vec::new(), |d| {
            d.iter().filter(|g| (g.robot as usize) < n).collect()
        });
        Candidate {
            points,
            seed,
            schedule,
            durations,
        }
    }

    /// One local move from `c` (whose run was `run`): a robot moved (or all of them a
    /// little), added or removed, the run's seed drawn again, (subsets searched)
    /// activations flipped in the rounds the run reached, or (durations searched) one
    /// phase duration given, changed or taken back.
    pub(super) fn mutate(&self, c: &Candidate, run: &Evaluation, rng: &mut Stream) -> Candidate {
        let mut c = c.clone();
        let n = c.len();
        let rounds = run.rounds;
        if self.durations && rng.uniform() < 0.3 {
            self.mutate_durations(&mut c, run, rng);
            return c;
        }
        let dim = self.cell.dim();
        let scale = self.perturb * 10f64.powf(-2.0 * rng.uniform());
        if self.subsets && rng.uniform() < 0.3 {
            let schedule = c.schedule.as_mut().expect("subsets are searched");
            let reached = (rounds as usize + 1).min(schedule.len()).max(1);
            for _ in 0..1 + rng.below(3) {
                let k = rng.below(reached);
                let bit = 1u64 << rng.below(n);
                schedule[k] ^= bit;
                if schedule[k] == 0 {
                    schedule[k] = 1 << rng.below(n);
                }
            }
            return c;
        }
        let r = rng.uniform();
        if r < 0.55 || (r < 0.9 && n == 1) {
            let i = rng.below(n);
            for x in c.points[i].iter_mut().take(dim) {
                *x += rng.normal() * scale;
            }
        } else if r < 0.7 {
            for p in &mut c.points {
                for x in p.iter_mut().take(dim) {
                    *x += rng.normal() * scale * 0.25;
                }
            }
        } else if r < 0.8 && n < self.n_max {
            let (lo, hi) = bounds(&c.points, dim);
            let mut p = [0.0; 3];
            for a in 0..dim {
                p[a] = rng.uniform_in(lo[a] - self.perturb, hi[a] + self.perturb);
            }
            c.points.push(p);
            if let Some(s) = c.schedule.as_mut().filter(|_| self.subsets) {
                let prob = self.cell.spec.scheduler.p;
                for m in s.iter_mut() {
                    if rng.bernoulli(prob) {
                        *m |= 1 << n;
                    }
                }
            }
        } else if r < 0.9 && n > self.n_min {
            let i = rng.below(n);
            c = self.without_robot(&c, i, rng);
        } else {
            c.seed = rng.next_u64() % SEED_RANGE;
        }
        // Drawn starts lie in [0, side] on every axis, and so do the moved ones: the
        // search space is the region `[swarm]` draws from (a start from a file is free).
        if self.cell.file_positions.is_none() {
            let side = self.cell.spec.swarm.side;
            for p in &mut c.points {
                for x in p.iter_mut().take(dim) {
                    *x = x.clamp(0.0, side);
                }
            }
        }
        c
    }

    /// One move of `c`'s given durations: one taken back, one made longer or shorter
    /// (by a factor of 2), or a phase of a robot's cycle that `run` reached given a
    /// length drawn log-uniformly from 1 to `max_ticks`.
    fn mutate_durations(&self, c: &mut Candidate, run: &Evaluation, rng: &mut Stream) {
        let given = c.durations.len();
        let r = rng.uniform();
        if given > 0 && r < 0.2 {
            c.durations.remove(rng.below(given));
            return;
        }
        if given > 0 && r < 0.45 {
            let g = &mut c.durations[rng.below(given)];
            let t = if rng.bernoulli(0.5) {
                g.ticks.saturating_mul(2)
            } else {
                g.ticks / 2
            };
            g.ticks = t.clamp(1, self.max_ticks);
            return;
        }
        let n = c.len().max(1);
        // A robot's share of the Looks, twice over: some robots cycle faster.
        let reached = (2 * run.activations / n as u64 + 1) as usize;
        let robot = rng.below(n) as u32;
        let cycle = rng.below(reached.max(1)) as u64;
        let starts_idle = self.cell.spec.scheduler.start == AsyncStart::Random;
        let phases: &[Phase] = if cycle > 0 || starts_idle {
            &[Phase::Idle, Phase::Compute, Phase::Move]
        } else {
            &[Phase::Compute, Phase::Move]
        };
        let phase = phases[rng.below(phases.len())];
        let ticks = ((self.max_ticks as f64).ln() * rng.uniform()).exp().round() as u64;
        give(
            &mut c.durations,
            GivenDuration {
                robot,
                cycle,
                phase,
                ticks: ticks.clamp(1, self.max_ticks),
            },
        );
    }

    /// `c` without robot `i` (its schedule's and durations' robots above i renumbered; a
    /// searched round left with nobody gets a robot drawn from `rng`).
    pub(super) fn without_robot(&self, c: &Candidate, i: usize, rng: &mut Stream) -> Candidate {
        let mut c = c.clone();
        c.points.remove(i);
        let i32 = i as u32;
        c.durations.retain(|g| g.robot != i32);
        for g in &mut c.durations {
            if g.robot > i32 {
                g.robot -= 1;
            }
        }
        let n = c.len();
        if let Some(s) = c.schedule.as_mut() {
            for m in s.iter_mut() {
                let low = *m & ((1u64 << i) - 1);
                let high = if i + 1 < 64 { *m >> (i + 1) << i } else { 0 };
                *m = low | high;
                if *m == 0 && self.subsets && n > 0 {
                    *m = 1 << rng.below(n);
                }
            }
        }
        c
    }

    /// Runs `c` and scores it for the property.
    pub fn evaluate(&self, c: &Candidate) -> Evaluation {
        if self.cell.dim() == 3 {
            self.evaluate_in::<DVec3>(c)
        } else {
            self.evaluate_in::<DVec2>(c)
        }
    }

    fn evaluate_in<P: IndexPoint>(&self, c: &Candidate) -> Evaluation {
        let mut config = self.cell.sim_config(c.seed);
        if let Some(rounds) = &c.schedule {
            config.scheduler = SchedulerSpec::File(Arc::new(activation_list(rounds)));
        }
        if let SchedulerSpec::Async(spec) = &mut config.scheduler {
            spec.durations = durations_of(&c.durations);
        }
        let eps_pos = config.vision.eps_pos;
        let points: Vec<P> = c.points.iter().map(|r| P::from_slice(r)).collect();
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
        let Ok(mut sim) = Simulation::new(config, points) else {
            return invalid;
        };
        let stop = Arc::new(AtomicBool::new(false));
        sim.set_interrupt(stop.clone());
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
        let outcome = sim.run_with(|r| {
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
        });
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

/// Gives `g` in `durations` (sorted by key): in place of the same phase's, or inserted.
pub(super) fn give(durations: &mut Vec<GivenDuration>, g: GivenDuration) {
    match durations.binary_search_by_key(&g.key(), GivenDuration::key) {
        Ok(i) => durations[i] = g,
        Err(i) => durations.insert(i, g),
    }
}

/// The engine's durations of a candidate (`None` when none is given).
pub(super) fn durations_of(given: &[GivenDuration]) -> Option<Arc<Durations>> {
    (!given.is_empty()).then(|| {
        Arc::new(Durations::new(given.iter().copied()).expect("each phase once, in range"))
    })
}

/// Rows (x, y, z) of points.
fn rows_of<P: Point>(points: &[P]) -> Vec<[f64; 3]> {
    points
        .iter()
        .map(|p| {
            let mut r = [0.0; 3];
            for (a, x) in r.iter_mut().enumerate().take(P::DIM) {
                *x = p.axis(a);
            }
            r
        })
        .collect()
}

/// The smallest and largest coordinate on each axis.
fn bounds(points: &[[f64; 3]], dim: usize) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for a in 0..dim {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
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

/// Each of `n` robots with probability `p`, and at least one.
fn random_mask(n: usize, p: f64, rng: &mut Stream) -> u64 {
    let mut m = 0u64;
    for i in 0..n {
        if rng.bernoulli(p) {
            m |= 1 << i;
        }
    }
    if m == 0 {
        m = 1 << rng.below(n);
    }
    m
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
            found: self
                .best
                .as_ref()
                .is_some_and(|b| b.evaluation.violated || self.hunt.property() == Property::Slow),
            shrunk: false,
            best: self.best.clone(),
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
