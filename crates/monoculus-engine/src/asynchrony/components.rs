//! The ASYNC scheduler's per-robot state and shared resources.

use bevy_ecs::prelude::*;

use super::agenda::Agenda;
use crate::IndexPoint;

/// Where a robot is in its cycle. The Look is instantaneous: it happens at the tick
/// the Idle phase ends. Phases order as a cycle runs them: Idle, Compute, Move.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Phase {
    /// Waiting; Looks when the phase ends.
    Idle,
    /// Has looked; starts its move (or goes idle) when the phase ends.
    Compute,
    /// Moving linearly from its `Position` to `target`.
    Move,
}

/// A robot's ASYNC clock.
///
/// The decided displacement is held as a point and a flag ([`Timing::pending`]) rather
/// than an `Option`, which would take 8 more bytes a robot (56 instead of 64 in the
/// plane: 8 MB at 10^6 robots).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing<P: IndexPoint> {
    /// The current phase.
    pub phase: Phase,
    /// The tick at which it began.
    pub since: u64,
    /// The tick at which it ends.
    pub until: u64,
    /// Looks so far: the key of the robot's decision stream, like the round in FSYNC.
    pub cycle: u64,
    /// The tick of the last Look.
    pub looked: u64,
    /// Whether a move was decided: [`Timing::pending`].
    decided: bool,
    /// The displacement decided, if `decided` (else zero).
    displacement: P,
}

impl<P: IndexPoint> Timing<P> {
    /// A clock in `phase` from tick `since` to `until`, after `cycle` Looks, the last
    /// at tick `looked`, with the displacement `pending` decided there.
    pub fn new(
        phase: Phase,
        since: u64,
        until: u64,
        cycle: u64,
        looked: u64,
        pending: Option<P>,
    ) -> Self {
        let mut timing = Timing {
            phase,
            since,
            until,
            cycle,
            looked,
            decided: false,
            displacement: P::default(),
        };
        timing.set_pending(pending);
        timing
    }

    /// Compute and Move: the displacement decided at the Look (`None`: stay; the Move
    /// phase is then spent in place).
    #[inline]
    pub fn pending(&self) -> Option<P> {
        self.decided.then_some(self.displacement)
    }

    /// Sets what [`Timing::pending`] gives.
    #[inline]
    pub fn set_pending(&mut self, pending: Option<P>) {
        self.decided = pending.is_some();
        self.displacement = pending.unwrap_or_default();
    }

    /// The position at `tick` of a robot whose phase started at `from`.
    pub fn position_at(&self, from: P, tick: u64) -> P {
        if self.phase != Phase::Move || !self.decided {
            return from;
        }
        interpolate(from, self.target(from), self.since, self.until, tick)
    }

    /// Where the move decided at the Look ends, for a robot whose phase started at
    /// `from` (`from` itself where it decided to stay).
    #[inline]
    pub fn target(&self, from: P) -> P {
        match self.pending() {
            Some(d) => from + d,
            None => from,
        }
    }
}

/// Where a move from `from` to `to` over the ticks `since..until` is at `tick`, at any
/// tick: at `from` until it starts (a move filed ahead of its start), at `to` itself
/// once it has ended (as its arrival settles it), on its segment between.
#[inline]
pub(crate) fn on_move<P: IndexPoint>(from: P, to: P, since: u64, until: u64, tick: u64) -> P {
    if tick <= since {
        from
    } else if tick >= until {
        to
    } else {
        interpolate(from, to, since, until, tick)
    }
}

/// Where a move from `from` to `to` over the ticks `since..until` is at `tick` (at or
/// after `since`): `from` for a move of no ticks.
#[inline]
pub(crate) fn interpolate<P: IndexPoint>(from: P, to: P, since: u64, until: u64, tick: u64) -> P {
    if until <= since {
        return from;
    }
    let f = (tick.min(until) - since) as f64 / (until - since) as f64;
    from + (to - from) * f
}

/// The ASYNC clock, the agenda of phase ends, and epoch accounting.
#[derive(Resource, Clone, Debug, Default)]
pub struct AsyncClock {
    /// The current tick.
    pub tick: u64,
    /// Epochs completed: spans in which every robot completed a full cycle (a Look at
    /// or after the span's start, and the end of the Move or decision to stay).
    pub epochs: u64,
    epoch_start: u64,
    done: Vec<bool>,
    remaining: usize,
    /// The phase ends to come, by tick.
    agenda: Agenda,
    /// Robots whose phase ends at the current tick, ascending.
    pub due: Vec<u32>,
    /// The robots of `due` by the phase that ends (indexed by the phase), each list
    /// ascending: filled by [`AsyncClock::sort_due`].
    ending: [Vec<u32>; 3],
    /// (robot, tick of its Look) of the cycles completed at the current tick.
    pub completed: Vec<(u32, u64)>,
    /// Whether a move ended at the current tick.
    pub move_ended: bool,
    /// Whether the current tick completed an epoch.
    pub epoch_ended: bool,
    /// Robots moving or about to move (in Compute with a move decided).
    pub in_motion: usize,
    /// Looks in the current epoch.
    pub epoch_looks: u64,
    /// Moves started in the current epoch.
    pub epoch_moves: u64,
    /// Looks and moves of the epoch that ended last.
    pub last_epoch: (u64, u64),
    /// Whether a Look at the current tick decided a move.
    pub move_decided: bool,
    /// Looks decided so far ahead of their ticks, with the Looks of an earlier tick
    /// (their decisions are those of their own ticks; a diagnostic of the work's
    /// sharing, see docs/architecture.md).
    pub looks_ahead: u64,
    /// What the Looks cost so far, to share a tick's Looks between threads only where
    /// that pays.
    pub(crate) look_cost: super::parallel::LookCost,
}

impl AsyncClock {
    /// A clock for `n` robots.
    pub fn new(n: usize) -> Self {
        AsyncClock {
            done: vec![false; n],
            remaining: n,
            ..Default::default()
        }
    }

    /// Schedules robot `robot`'s next phase end, at `tick` (the current tick or later).
    pub fn schedule(&mut self, tick: u64, robot: u32) {
        self.agenda.schedule(self.tick, tick, robot);
    }

    /// Calls `f(tick, robot)` for each phase end scheduled after the current tick and
    /// at or before `last`, in no particular order (they stay scheduled).
    pub(crate) fn peek(&self, last: u64, f: impl FnMut(u64, u32)) {
        self.agenda.peek(self.tick, last, f);
    }

    /// Moves to the next tick with phase ends; `false` if nothing is scheduled.
    pub fn advance(&mut self) -> bool {
        self.due.clear();
        self.ending.iter_mut().for_each(Vec::clear);
        self.completed.clear();
        self.move_ended = false;
        self.move_decided = false;
        self.epoch_ended = false;
        match self
            .agenda
            .take_next(self.tick, self.done.len(), &mut self.due)
        {
            Some(tick) => {
                self.tick = tick;
                true
            }
            None => false,
        }
    }

    /// Sorts the robots of `due` by the phase that ends now: `ends(robot)` is that
    /// phase, `None` for a robot whose phase does not end now. Where there are
    /// `parallel_from` robots or more, they are asked in parallel (reading each
    /// robot's clock is a miss in the caches, and a crowded tick has thousands).
    pub fn sort_due(&mut self, parallel_from: usize, ends: impl Fn(u32) -> Option<Phase> + Sync) {
        use rayon::prelude::*;
        let ending = &mut self.ending;
        let mut place = |r: u32, phase: Option<Phase>| {
            if let Some(phase) = phase {
                ending[phase as usize].push(r);
            }
        };
        if self.due.len() < parallel_from {
            // Read and placed in one pass, with no list between (a fine-grained tick
            // has a robot or two).
            self.due.iter().for_each(|&r| place(r, ends(r)));
            return;
        }
        let phases: Vec<Option<Phase>> = self
            .due
            .par_iter()
            .with_min_len(64)
            .map(|&r| ends(r))
            .collect();
        self.due.iter().zip(phases).for_each(|(&r, p)| place(r, p));
    }

    /// Whether some robot's `phase` ends at the current tick.
    pub(crate) fn ends(&self, phase: Phase) -> bool {
        !self.ending[phase as usize].is_empty()
    }

    /// The robots whose `phase` ends at the current tick, ascending (taken out of
    /// the clock; give them back with [`AsyncClock::restore_ending`]).
    pub fn take_ending(&mut self, phase: Phase) -> Vec<u32> {
        std::mem::take(&mut self.ending[phase as usize])
    }

    /// Gives back a list [`AsyncClock::take_ending`] took.
    pub fn restore_ending(&mut self, phase: Phase, robots: Vec<u32>) {
        self.ending[phase as usize] = robots;
    }

    /// Counts the cycles completed at this tick toward the current epoch; ends the
    /// epoch when every robot has completed one.
    pub fn account(&mut self) {
        for &(r, looked) in &self.completed {
            let r = r as usize;
            if looked >= self.epoch_start && !self.done[r] {
                self.done[r] = true;
                self.remaining -= 1;
            }
        }
        if self.remaining == 0 {
            self.epochs += 1;
            self.epoch_start = self.tick;
            self.done.fill(false);
            self.remaining = self.done.len();
            self.epoch_ended = true;
            self.last_epoch = (self.epoch_looks, self.epoch_moves);
            self.epoch_looks = 0;
            self.epoch_moves = 0;
        }
    }
}

/// Every robot's ASYNC clock, by robot index. A table of its own rather than a
/// component of the robots' entities, like the positions: a tick reaches its robots by
/// index, scattered through the swarm, and through an entity each clock would be the
/// third of three dependent reads (the robot's entity, its place in its table, then
/// the clock), each a miss in the caches.
#[derive(Resource, Clone, Debug)]
pub struct Clocks<P: IndexPoint>(pub Vec<Timing<P>>);

/// The colours the robots show under ASYNC, for an algorithm with lights (both empty
/// otherwise): `shown[r]` is what the others see of robot `r`, `set[r]` what its last
/// decision set, shown from the end of that Compute on (SPEC section 10).
#[derive(Resource, Clone, Debug, Default)]
pub struct Lights {
    /// What each robot shows.
    pub shown: Vec<u8>,
    /// What each robot's last decision set.
    pub set: Vec<u8>,
}

impl<P: IndexPoint> Clocks<P> {
    /// `n` robots Idle from tick 0, their first phase end not yet drawn.
    pub fn new(n: usize) -> Self {
        Clocks(vec![Timing::new(Phase::Idle, 0, 0, 0, 0, None); n])
    }

    /// Each robot's index, settled point (from `points`, by robot index) and clock.
    pub fn with_points<'a>(
        &'a self,
        points: &'a [P],
    ) -> impl Iterator<Item = (u32, P, Timing<P>)> + 'a {
        self.0
            .iter()
            .zip(points)
            .enumerate()
            .map(|(r, (timing, &from))| (r as u32, from, *timing))
    }
}

/// Entities by robot index.
#[derive(Resource, Clone, Debug)]
pub struct RobotEntities(pub Vec<Entity>);

#[cfg(test)]
mod tests {
    use super::AsyncClock;

    /// A clock gives back the decision it was given, forgets it to the bit (two clocks
    /// that stay are equal whatever they held), and takes 56 bytes in the plane.
    #[test]
    fn a_clock_holds_its_decision_compactly() {
        use super::{Phase, Timing};
        use glam::{DVec2, DVec3};
        let d = DVec2::new(-0.0, 2.5);
        let mut t = Timing::new(Phase::Compute, 3, 7, 2, 3, Some(d));
        assert_eq!(
            t.pending().map(|p| p.to_array().map(f64::to_bits)),
            Some(d.to_array().map(f64::to_bits))
        );
        t.set_pending(None);
        assert_eq!(t.pending(), None);
        assert_eq!(t, Timing::new(Phase::Compute, 3, 7, 2, 3, None));
        t.set_pending(Some(DVec2::ZERO));
        assert_eq!(t.pending(), Some(DVec2::ZERO));
        assert_ne!(t, Timing::new(Phase::Compute, 3, 7, 2, 3, None));
        assert_eq!(std::mem::size_of::<Timing<DVec2>>(), 56);
        assert_eq!(std::mem::size_of::<Timing<DVec3>>(), 64);
    }

    #[test]
    fn the_robots_of_a_tick_are_sorted_by_the_phase_that_ends_serially_or_not() {
        use super::Phase;
        let phase = |r: u32| match r % 4 {
            0 => Some(Phase::Move),
            1 => Some(Phase::Idle),
            2 => Some(Phase::Compute),
            _ => None,
        };
        for parallel_from in [0, usize::MAX] {
            let mut clock = AsyncClock::new(1000);
            for r in (0..1000).rev() {
                clock.schedule(7, r);
            }
            assert!(clock.advance());
            clock.sort_due(parallel_from, phase);
            for (p, rest) in [(Phase::Move, 0), (Phase::Idle, 1), (Phase::Compute, 2)] {
                let ending = clock.take_ending(p);
                let expected: Vec<u32> = (0..1000).filter(|r| r % 4 == rest).collect();
                assert_eq!(ending, expected, "{p:?}, parallel from {parallel_from}");
                clock.restore_ending(p, ending);
            }
            clock.schedule(8, 3);
            assert!(clock.advance());
            assert!(
                clock.take_ending(Phase::Move).is_empty(),
                "emptied by advance"
            );
        }
    }
}
