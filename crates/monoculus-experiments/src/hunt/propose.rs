//! Proposals: a new random start, and one local move from a candidate (a robot moved,
//! added or removed, the run's seed drawn again, SSYNC activations flipped, an ASYNC
//! phase duration given, changed or taken back).

use glam::{DVec2, DVec3};
use monoculus_core::geometry::Point;
use monoculus_core::rng::Stream;
use monoculus_engine::AsyncStart;

use super::*;

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
}

/// Gives `g` in `durations` (sorted by key): in place of the same phase's, or inserted.
pub(super) fn give(durations: &mut Vec<GivenDuration>, g: GivenDuration) {
    match durations.binary_search_by_key(&g.key(), GivenDuration::key) {
        Ok(i) => durations[i] = g,
        Err(i) => durations.insert(i, g),
    }
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
