//! Running: stepping until the stop criterion holds, quiescence, the outcome.

use super::*;

/// Whether no correct robot would move if activated now, nor change the light it shows
/// (the robots' states copied: nothing is changed). A robot that would only change its
/// light is not quiescent: the others may act on it.
pub(super) fn quiescent<P: IndexPoint, A: Algorithm>(world: &mut World) -> bool {
    refresh_snapshot::<P>(world);
    let params = world.resource::<Params>().clone();
    let mut q = world.query::<(&Robot, Option<&MemoryOf<P, A>>)>();
    // The colours shown: ASYNC keeps them (a robot shows its new colour once its
    // Compute ends); the others show their states'.
    let lights = match world.get_resource::<crate::asynchrony::Lights>() {
        // A colour set by a Compute that has not ended yet is a change to come.
        Some(l) if l.shown != l.set => return false,
        Some(l) => l.shown.clone(),
        None => lights::<P, A>(world),
    };
    let robots: Vec<(usize, Option<KeptBy<P, A>>)> = q
        .iter(world)
        .filter(|(r, _)| params.is_correct(r.index as usize))
        .map(|(r, m)| (r.index as usize, m.map(|m| m.0.clone())))
        .collect();
    let algorithm = world.resource::<Rule<A>>().0.clone();
    let snapshot = world.resource::<Snapshot<P>>();
    fn any_moves<P: IndexPoint, S: Sight<P>, A: Algorithm>(
        (params, algorithm): (&Params, &A),
        view: (&S, &[u8]),
        robots: &[(usize, Option<KeptBy<P, A>>)],
    ) -> bool {
        if algorithm.decides_together() {
            let mut items: Vec<crate::systems::Item<P, A>> = robots
                .iter()
                .map(|(i, m)| (*i, u64::MAX, m.clone()))
                .collect();
            let decided = crate::systems::decide_items(params, algorithm, view, &mut items);
            return decided.iter().any(Option::is_some)
                || items
                    .iter()
                    .zip(robots)
                    .any(|((.., after), (_, before))| relit::<P, A>(algorithm, before, after));
        }
        robots.par_iter().with_min_len(32).any(|(i, before)| {
            let mut after = before.clone();
            decide_one(params, algorithm, view, *i, u64::MAX, after.as_mut()).is_some()
                || relit::<P, A>(algorithm, before, &after)
        })
    }
    /// Whether an activation changed the robot's light.
    fn relit<P: IndexPoint, A: Algorithm>(
        algorithm: &A,
        before: &Option<KeptBy<P, A>>,
        after: &Option<KeptBy<P, A>>,
    ) -> bool {
        let light = |m: &Option<KeptBy<P, A>>| m.as_ref().map(|m| A::light(&m.state));
        algorithm.light_names().len() > 0 && light(before) != light(after)
    }
    let rule = (&params, &*algorithm);
    let quiet = match snapshot.sight.as_ref().expect("snapshot refreshed") {
        SnapshotSight::Index(s) => !any_moves(rule, (s, &lights), &robots),
        SnapshotSight::Exact(s) => !any_moves(rule, (s, &lights), &robots),
        SnapshotSight::Rtree(s) => !any_moves(rule, (s, &lights), &robots),
    };
    if matches!(params.scheduler, SchedulerSpec::Async(_)) {
        // ASYNC's Looks see through their own sight: the snapshot taken for this
        // check would only hold a copy of the swarm and a grid until the next one.
        world.resource_mut::<Snapshot<P>>().sight = None;
    }
    quiet
}

/// What robot `robot` would decide if activated now: its global displacement (`None`:
/// it stays), from a copy of its state, as a Look now would see the swarm (ASYNC: the
/// movers where they are). Nothing changes: an algorithm's failure is returned, not
/// recorded as the run's.
pub(super) fn decide_now<P: IndexPoint, A: Algorithm>(
    world: &mut World,
    robot: usize,
) -> Result<Option<P>, crate::resources::RunFailure> {
    refresh_snapshot::<P>(world);
    let mut params = world.resource::<Params>().clone();
    params.failure = crate::resources::Failure::default();
    let lights = match world.get_resource::<crate::asynchrony::Lights>() {
        Some(l) => l.shown.clone(),
        None => lights::<P, A>(world),
    };
    let mut q = world.query::<(&Robot, Option<&MemoryOf<P, A>>)>();
    let kept: Option<KeptBy<P, A>> = q
        .iter(world)
        .find(|(r, _)| r.index as usize == robot)
        .and_then(|(_, m)| m.map(|m| m.0.clone()));
    let algorithm = world.resource::<Rule<A>>().0.clone();
    // The random stream of its next activation: the next round's, or (ASYNC) its cycle's.
    let round = match world.get_resource::<Clocks<P>>() {
        Some(clocks) if world.contains_resource::<AsyncClock>() => clocks.0[robot].cycle,
        _ => world.resource::<Clock>().round,
    };
    fn one<P: IndexPoint, S: Sight<P>, A: Algorithm>(
        (params, algorithm): (&Params, &A),
        view: (&S, &[u8]),
        (robot, round): (usize, u64),
        kept: Option<KeptBy<P, A>>,
    ) -> Option<P> {
        if algorithm.decides_together() {
            let mut items: Vec<crate::systems::Item<P, A>> = vec![(robot, round, kept)];
            return crate::systems::decide_items(params, algorithm, view, &mut items)[0];
        }
        let mut kept = kept;
        decide_one(params, algorithm, view, robot, round, kept.as_mut())
    }
    let rule = (&params, &*algorithm);
    let who = (robot, round);
    let snapshot = world.resource::<Snapshot<P>>();
    let decided = match snapshot.sight.as_ref().expect("snapshot refreshed") {
        SnapshotSight::Index(s) => one(rule, (s, &lights), who, kept),
        SnapshotSight::Exact(s) => one(rule, (s, &lights), who, kept),
        SnapshotSight::Rtree(s) => one(rule, (s, &lights), who, kept),
    };
    if matches!(params.scheduler, SchedulerSpec::Async(_)) {
        world.resource_mut::<Snapshot<P>>().sight = None;
    }
    match params.failure.get() {
        Some(failure) => Err(failure),
        None => Ok(decided),
    }
}

/// The colour each robot's state shows (empty when `A` has no lights).
pub(super) fn lights<P: IndexPoint, A: Algorithm>(world: &mut World) -> Vec<u8> {
    let algorithm = world.resource::<Rule<A>>().0.clone();
    if algorithm.light_names().len() == 0 {
        return Vec::new();
    }
    let mut q = world.query::<(&Robot, Option<&MemoryOf<P, A>>)>();
    crate::systems::lights_of::<A>(
        &*algorithm,
        q.iter(world).count(),
        q.iter(world)
            .filter_map(|(r, m)| Some((r.index as usize, &m?.0.state))),
    )
}

type Saved<P, A> = Vec<(Entity, KeptBy<P, A>)>;

/// The robots' kept states, if the algorithm keeps any.
pub(super) fn save_states<P: IndexPoint, A: Algorithm>(
    world: &mut World,
) -> Option<Box<dyn std::any::Any + Send>> {
    if !world.resource::<Rule<A>>().0.keeps_state() {
        return None;
    }
    let mut q = world.query::<(Entity, &MemoryOf<P, A>)>();
    let saved: Saved<P, A> = q.iter(world).map(|(e, m)| (e, m.0.clone())).collect();
    Some(Box::new(saved))
}

/// Puts back what [`save_states`] took.
pub(super) fn restore_states<P: IndexPoint, A: Algorithm>(
    world: &mut World,
    saved: Box<dyn std::any::Any + Send>,
) {
    let saved = saved
        .downcast::<Saved<P, A>>()
        .expect("the states this run saved");
    for (e, m) in *saved {
        world.entity_mut(e).insert(Memory(m));
    }
}

/// How many robots have terminated, for algorithms that say ([`Algorithm::terminated`]).
pub(super) fn terminated<P: IndexPoint, A: Algorithm>(world: &mut World) -> Option<u64> {
    A::terminated(&A::State::default(), P::DIM)?;
    let mut q = world.query::<&MemoryOf<P, A>>();
    Some(
        q.iter(world)
            .filter(|m| A::terminated(&m.0.state, P::DIM) == Some(true))
            .count() as u64,
    )
}

impl<P: IndexPoint> Simulation<P> {
    /// Whether no correct robot would move if activated now.
    pub fn is_quiescent(&mut self) -> bool {
        (self.hooks.quiescent)(&mut self.world)
    }

    /// What robot `robot` would decide if activated now: its displacement (`None`: it
    /// stays), from a copy of its state (memory, light), as a Look now would see the
    /// swarm (ASYNC: movers where they are on their segments), before movement errors,
    /// with the random draws of its next activation (the next round's; ASYNC, its
    /// cycle's): under FSYNC, the move the next step makes, bar movement errors.
    /// Nothing changes: the run goes on as if this was never asked, and a bad decision
    /// of the algorithm is returned rather than failing the run.
    ///
    /// ```
    /// use glam::DVec2;
    /// use monoculus_core::algorithms::ConvergeLocality;
    /// use monoculus_engine::prelude::*;
    ///
    /// let config = SimConfig::paper(AlgorithmBox::new(ConvergeLocality), 1, 100);
    /// let mut sim = Simulation::new(config, vec![DVec2::ZERO, DVec2::new(5.0, 0.0)]).unwrap();
    /// let d = sim.decide_now(0).unwrap().expect("robot 0 moves toward robot 1");
    /// assert!(d.x > 0.0 && d.y == 0.0);
    /// sim.step();
    /// assert!((sim.positions()[0] - d).length() < 1e-12);
    /// ```
    ///
    /// # Panics
    /// If `robot` is not a robot of the run.
    pub fn decide_now(&mut self, robot: usize) -> Result<Option<P>, crate::resources::RunFailure> {
        assert!(
            robot < self.positions().len(),
            "robot {robot}: no such robot"
        );
        (self.hooks.decide_now)(&mut self.world, robot)
    }

    /// A flag that, once set (from any thread: a signal handler, a binding's Ctrl-C),
    /// stops [`Simulation::run`] at the end of the round (ASYNC: tick) it is in; the
    /// outcome then says `interrupted`.
    pub fn set_interrupt(&mut self, flag: std::sync::Arc<std::sync::atomic::AtomicBool>) {
        self.interrupt = Some(flag);
    }

    fn interrupted(&self) -> bool {
        self.interrupt
            .as_ref()
            .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
    }

    /// Sets the cap on rounds (ASYNC: epochs) of the runs to come.
    pub fn set_max_rounds(&mut self, max_rounds: u64) {
        self.config.stop.max_rounds = max_rounds;
    }

    /// Whether the stop criterion holds now (quiescence is checked on a copy: nothing
    /// changes).
    pub fn criterion_holds_now(&mut self) -> bool {
        self.criterion_met_now().is_some()
    }

    /// Which part of the stop criterion holds now, if any: what would end a run here
    /// (the diameter or the box before quiescence, which is checked on a copy, under
    /// FSYNC too).
    pub fn criterion_met_now(&mut self) -> Option<StoppedBy> {
        self.criterion_met(false)
    }

    /// Whether the goal ([`StopSpec::goal`]) holds for the correct robots now.
    pub fn goal_holds_now(&self) -> bool {
        let model = &self.config.model;
        self.goal_measure().0 <= self.config.stop.goal.bound(model.step, model.locality)
    }

    /// The radius of the smallest disc (ball in space) holding every correct robot now
    /// (ASYNC: movers where they are, as the shape is measured).
    pub fn enclosing_radius(&self) -> f64 {
        let now = self.positions_now();
        let correct = self.world.resource::<Params>().correct(&now);
        monoculus_core::geometry::enclosing_radius(&correct)
    }

    /// The goal's measure now and the enclosing radius.
    fn goal_measure(&self) -> (f64, f64) {
        let shape = self.world.resource::<Shape>();
        let radius = self.enclosing_radius();
        (
            self.config
                .stop
                .goal
                .measure(shape.diameter, radius, &shape.extents),
            radius,
        )
    }

    /// Rounds completed (ASYNC: epochs).
    pub fn rounds_done(&self) -> u64 {
        match self.world.get_resource::<AsyncClock>() {
            Some(c) => c.epochs,
            None => self.world.resource::<Clock>().round,
        }
    }

    /// The shape now: (hull area or volume, diameter).
    pub fn shape(&self) -> (f64, f64) {
        let s = self.world.resource::<Shape>();
        (s.hull, s.diameter)
    }

    /// Why the run has failed, if its algorithm made a bad decision or panicked.
    pub fn failure(&self) -> Option<crate::resources::RunFailure> {
        self.world.resource::<Params>().failure.get()
    }

    /// Which part of the criterion holds. `by_round`: under FSYNC, quiescence is left to
    /// the run's loop, which finds it as a round in which nobody moves (see
    /// `run_rounds_with`); otherwise it is checked here.
    fn criterion_met(&mut self, by_round: bool) -> Option<StoppedBy> {
        let c = self.config.model.locality;
        let b = self.config.model.step;
        let shape = self.world.resource::<Shape>();
        let (diameter_ok, box_ok) = (
            shape.diameter <= c,
            shape.extents.iter().all(|&e| e <= 2.0 * b),
        );
        let fsync = by_round && self.config.scheduler == SchedulerSpec::Fsync;
        let quiet = match self.config.stop.criterion {
            StopCriterion::Diameter => return diameter_ok.then_some(StoppedBy::Diameter),
            StopCriterion::Box => return box_ok.then_some(StoppedBy::Box),
            StopCriterion::QuiescentOrDiameter if diameter_ok => return Some(StoppedBy::Diameter),
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
                    return None;
                }
                let key = (
                    self.world.resource::<Positions<P>>().generation,
                    if self.config.algorithm.keeps_state() {
                        self.world.resource::<Tally>().activations
                    } else {
                        0
                    },
                );
                if self.last_quiescence_check == Some(key) {
                    return None;
                }
                let quiet = self.is_quiescent();
                if !quiet {
                    self.last_quiescence_check = Some(key);
                }
                quiet
            }
        };
        quiet.then_some(StoppedBy::Quiescent)
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
        // Rounds already run (by `step`) count: a run continues where the steps left it.
        let mut rounds = self.world.resource::<Clock>().round;
        let stopped_by = loop {
            if let Some(cause) = self.stopped_from_outside() {
                break cause;
            }
            if let Some(met) = self.criterion_met(true) {
                break met;
            }
            if rounds >= self.config.stop.max_rounds {
                break StoppedBy::MaxRounds;
            }
            if self
                .config
                .scheduler
                .last_round()
                .is_some_and(|last| rounds >= last)
            {
                break StoppedBy::ScheduleEnd;
            }
            let before = *self.world.resource::<Tally>();
            let check = fsync && quiescence;
            let (saved, lit) = if check {
                let lit = (self.hooks.lights)(&mut self.world);
                ((self.hooks.save)(&mut self.world), lit)
            } else {
                (None, Vec::new())
            };
            self.step();
            if check
                && self.world.resource::<Tally>().round_moves == 0
                && self.failure().is_none()
                && (self.hooks.lights)(&mut self.world) == lit
            {
                // Nobody moved (nor changed its light) with everybody activated: the
                // configuration before this round was quiescent. The round was the
                // check, not a round of the run: its activations and the states it
                // changed are undone.
                *self.world.resource_mut::<Tally>() = before;
                if let Some(saved) = saved {
                    (self.hooks.restore)(&mut self.world, saved);
                }
                break StoppedBy::Quiescent;
            }
            rounds += 1;
            after(self, rounds);
        };
        self.outcome(rounds, stopped_by)
    }

    /// ASYNC: event tick by event tick; the criterion is checked at the start, after
    /// every tick at which a move ended, and (for quiescence) whenever nobody moves.
    /// `after` is called after every tick, with whether it completed an epoch.
    pub(super) fn run_async_with(&mut self, mut after: impl FnMut(&Self, bool)) -> RunOutcome {
        let stopped_by = loop {
            if let Some(cause) = self.stopped_from_outside() {
                break cause;
            }
            if let Some(met) = self.criterion_met(true) {
                break met;
            }
            if self.world.resource::<AsyncClock>().epochs >= self.config.stop.max_rounds {
                break StoppedBy::MaxRounds;
            }
            self.step();
            let epoch_ended = self.world.resource::<AsyncClock>().epoch_ended;
            after(self, epoch_ended);
        };
        let epochs = self.world.resource::<AsyncClock>().epochs;
        self.outcome(epochs, stopped_by)
    }

    /// A failure or an interruption, if the run has had one.
    fn stopped_from_outside(&self) -> Option<StoppedBy> {
        if self.failure().is_some() {
            Some(StoppedBy::Failure)
        } else if self.interrupted() {
            Some(StoppedBy::Interrupted)
        } else {
            None
        }
    }

    fn outcome(&mut self, rounds: u64, stopped_by: StoppedBy) -> RunOutcome {
        let tally = *self.world.resource::<Tally>();
        let shape = self.world.resource::<Shape>().clone();
        let terminated = (self.hooks.terminated)(&mut self.world);
        let (measure, final_radius) = self.goal_measure();
        let stop = self.config.stop;
        let goal_met = measure
            <= stop
                .goal
                .bound(self.config.model.step, self.config.model.locality);
        RunOutcome {
            rounds,
            activations: tally.activations,
            moves: tally.moves,
            distance: tally.distance,
            converged: stopped_by.by_criterion() && goal_met,
            stopped_by,
            goal: stop.goal,
            goal_met,
            final_radius,
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
            failure: self.failure(),
            faulty: self
                .world
                .resource::<Params>()
                .faults
                .as_ref()
                .map_or(0, |f| f.faulty() as u64),
        }
    }
}
