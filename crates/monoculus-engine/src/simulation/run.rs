//! Running: stepping until the stop criterion holds, quiescence, the outcome.

use super::*;

impl<P: IndexPoint> Simulation<P> {
    fn memories(&mut self) -> Vec<(Entity, RobotMemory)> {
        let mut q = self.world.query::<(Entity, &Memory)>();
        q.iter(&self.world).map(|(e, m)| (e, m.0)).collect()
    }

    /// Whether no correct robot would move if activated now.
    pub fn is_quiescent(&mut self) -> bool {
        refresh_snapshot::<P>(&mut self.world);
        let mut q = self.world.query::<(&Robot, Option<&Memory>)>();
        let params = self.world.resource::<Params>().clone();
        let robots: Vec<(usize, Option<RobotMemory>)> = q
            .iter(&self.world)
            .filter(|(r, _)| params.is_correct(r.index as usize))
            .map(|(r, m)| (r.index as usize, m.map(|m| m.0)))
            .collect();
        let snapshot = self.world.resource::<Snapshot<P>>();
        fn any_moves<P: IndexPoint, S: Sight<P>>(
            params: &Params,
            sight: &S,
            robots: &[(usize, Option<RobotMemory>)],
        ) -> bool {
            robots.par_iter().with_min_len(32).any(|&(i, memory)| {
                let mut memory = memory;
                decide_one(params, sight, i, u64::MAX, memory.as_mut()).is_some()
            })
        }
        let quiet = match snapshot.sight.as_ref().expect("snapshot refreshed") {
            SnapshotSight::Index(s) => !any_moves(&params, s, &robots),
            SnapshotSight::Exact(s) => !any_moves(&params, s, &robots),
            SnapshotSight::Rtree(s) => !any_moves(&params, s, &robots),
        };
        if matches!(params.scheduler, SchedulerSpec::Async(_)) {
            // ASYNC's Looks see through their own sight: the snapshot taken for this
            // check would only hold a copy of the swarm and a grid until the next one.
            self.world.resource_mut::<Snapshot<P>>().sight = None;
        }
        quiet
    }

    fn criterion_holds(&mut self) -> bool {
        let c = self.config.algorithm.locality;
        let b = self.config.algorithm.step;
        let shape = self.world.resource::<Shape>();
        let (diameter_ok, box_ok) = (
            shape.diameter <= c,
            shape.extents.iter().all(|&e| e <= 2.0 * b),
        );
        let fsync = self.config.scheduler == SchedulerSpec::Fsync;
        match self.config.stop.criterion {
            StopCriterion::Diameter => diameter_ok,
            StopCriterion::Box => box_ok,
            StopCriterion::QuiescentOrDiameter if diameter_ok => true,
            // Under FSYNC quiescence shows as a round in which nobody moves (see `run_with`).
            StopCriterion::Quiescent | StopCriterion::QuiescentOrDiameter if fsync => false,
            StopCriterion::Quiescent | StopCriterion::QuiescentOrDiameter => {
                // Under ASYNC the configuration is still only while nobody is moving or
                // about to move.
                if self
                    .world
                    .get_resource::<AsyncClock>()
                    .is_some_and(|c| c.in_motion > 0)
                {
                    return false;
                }
                let key = (
                    self.world.resource::<Positions<P>>().generation,
                    if self.config.algorithm.kind.has_memory() {
                        self.world.resource::<Tally>().activations
                    } else {
                        0
                    },
                );
                if self.last_quiescence_check == Some(key) {
                    return false;
                }
                let quiet = self.is_quiescent();
                if !quiet {
                    self.last_quiescence_check = Some(key);
                }
                quiet
            }
        }
    }

    /// Runs to the stop criterion (or the round cap).
    pub fn run(&mut self) -> RunOutcome {
        self.run_with(|_| {})
    }

    /// Runs to the stop criterion, calling `on_round` with the start configuration
    /// (round 0) and after every counted round (ASYNC: every completed epoch).
    pub fn run_with(&mut self, mut on_round: impl FnMut(&RoundReport<'_, P>)) -> RunOutcome {
        on_round(&self.report(0));
        if matches!(self.config.scheduler, SchedulerSpec::Async(_)) {
            return self.run_async_with(|sim, epoch_ended| {
                if epoch_ended {
                    let epochs = sim.world.resource::<AsyncClock>().epochs;
                    on_round(&sim.report(epochs));
                }
            });
        }
        self.run_rounds_with(|sim, round| on_round(&sim.report(round)))
    }

    /// The round schedulers' loop: `after` is called after every counted round.
    pub(super) fn run_rounds_with(&mut self, mut after: impl FnMut(&Self, u64)) -> RunOutcome {
        let fsync = self.config.scheduler == SchedulerSpec::Fsync;
        let quiescence = self.config.stop.criterion.checks_quiescence();
        let mut rounds = 0u64;
        let converged = loop {
            if self.criterion_holds() {
                break true;
            }
            if rounds >= self.config.stop.max_rounds
                || self
                    .config
                    .scheduler
                    .last_round()
                    .is_some_and(|last| rounds >= last)
            {
                break false;
            }
            let before = *self.world.resource::<Tally>();
            let check = fsync && quiescence;
            let memories = if check && self.config.algorithm.kind.has_memory() {
                self.memories()
            } else {
                Vec::new()
            };
            self.step();
            if check && self.world.resource::<Tally>().round_moves == 0 {
                // Nobody moved with everybody activated: the configuration before this
                // round was quiescent. The round was the check, not a round of the run:
                // its activations and the bits it set are undone.
                *self.world.resource_mut::<Tally>() = before;
                for (e, m) in memories {
                    self.world.entity_mut(e).insert(Memory(m));
                }
                break true;
            }
            rounds += 1;
            after(self, rounds);
        };
        self.outcome(rounds, converged)
    }

    /// ASYNC: event tick by event tick; the criterion is checked at the start, after
    /// every tick at which a move ended, and (for quiescence) whenever nobody moves.
    /// `after` is called after every tick, with whether it completed an epoch.
    pub(super) fn run_async_with(&mut self, mut after: impl FnMut(&Self, bool)) -> RunOutcome {
        let converged = loop {
            if self.criterion_holds() {
                break true;
            }
            if self.world.resource::<AsyncClock>().epochs >= self.config.stop.max_rounds {
                break false;
            }
            self.step();
            let epoch_ended = self.world.resource::<AsyncClock>().epoch_ended;
            after(self, epoch_ended);
        };
        let epochs = self.world.resource::<AsyncClock>().epochs;
        self.outcome(epochs, converged)
    }

    fn outcome(&mut self, rounds: u64, converged: bool) -> RunOutcome {
        let tally = *self.world.resource::<Tally>();
        let shape = self.world.resource::<Shape>().clone();
        let terminated = if self.config.algorithm.kind.has_memory() {
            let mut q = self.world.query::<&Memory>();
            Some(q.iter(&self.world).filter(|m| m.0.terminated()).count() as u64)
        } else {
            None
        };
        RunOutcome {
            rounds,
            activations: tally.activations,
            moves: tally.moves,
            distance: tally.distance,
            converged,
            d_opt: self.d_opt,
            d_max: self.d_max,
            final_diameter: shape.diameter,
            final_extents: shape.extents,
            hull_initial: self.hull_initial,
            hull_final: shape.hull,
            hull_max: shape.hull_max,
            hull_growth_max: tally.hull_growth_max,
            hull_growth_rounds: tally.hull_growth_rounds,
            committed_hull_growth: tally.committed_hull_growth,
            terminated,
            ticks: self.world.get_resource::<AsyncClock>().map(|c| c.tick),
            faulty: self
                .world
                .resource::<Params>()
                .faults
                .as_ref()
                .map_or(0, |f| f.faulty() as u64),
        }
    }
}
