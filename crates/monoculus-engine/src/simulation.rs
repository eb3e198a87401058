//! [`Simulation`]: one run, a `World` of robot entities stepped by a `Schedule`.

use bevy_ecs::prelude::*;
use monoculus_core::algorithms::{AlgorithmParams, RobotMemory};
use monoculus_core::errors::MovementErrors;
use monoculus_core::geometry::AxisFrame;
use monoculus_core::metrics;
use monoculus_core::rng::{Purpose, Stream};
use monoculus_core::vision::{Sight, VisionParams};
use rayon::prelude::*;

use crate::asynchrony::{
    self, AsyncClock, AsyncSet, Phase, RobotEntities, START, Timing, duration,
};
use crate::components::{Activated, Intent, Memory, Robot, Waiting};
use crate::resources::{
    Clock, HullVertices, Params, Positions, ScheduleState, Shape, SightBackend, Snapshot,
    SnapshotSight, Tally,
};
use crate::systems::{
    RoundSet, activate_robots, advance_clock, apply_moves, compute_intents, decide_one,
    measure_committed, measure_shape, refresh_snapshot, take_snapshot,
};
use crate::{
    AsyncStart, EngineError, IndexPoint, MAX_MAGNITUDE, MAX_ROBOTS, SchedulerSpec, StopCriterion,
    StopSpec,
};

/// Everything that defines a run besides the initial positions.
#[derive(Clone, Copy, Debug)]
pub struct SimConfig {
    /// Algorithm, step b, locality c.
    pub algorithm: AlgorithmParams,
    /// Visibility tolerances.
    pub vision: VisionParams,
    /// Visibility backend (the spatial index, or brute force).
    pub backend: SightBackend,
    /// Scheduler.
    pub scheduler: SchedulerSpec,
    /// Stop criterion and round cap.
    pub stop: StopSpec,
    /// The seed of every random stream of the run.
    pub seed: u64,
    /// Movement errors (step-length factor, non-rigid moves).
    pub movement: MovementErrors,
}

impl SimConfig {
    /// The paper's setting for `kind`: b = 1, c = 2, FSYNC, the default stop criterion
    /// with a cap of `max_rounds`, the index backend, no errors.
    pub fn paper(
        kind: monoculus_core::algorithms::AlgorithmKind,
        seed: u64,
        max_rounds: u64,
    ) -> Self {
        SimConfig {
            algorithm: AlgorithmParams::new(kind, 1.0, 2.0),
            vision: VisionParams::for_step(1.0),
            backend: SightBackend::Index,
            scheduler: SchedulerSpec::Fsync,
            stop: StopSpec {
                criterion: StopCriterion::default_for(kind),
                max_rounds,
            },
            seed,
            movement: MovementErrors::NONE,
        }
    }
}

/// The state after a round, for traces.
#[derive(Debug)]
pub struct RoundReport<'a, P> {
    /// Rounds completed (0: the start configuration).
    pub round: u64,
    /// Robots activated in this round.
    pub activated: u64,
    /// Robots that moved in this round.
    pub moving: u64,
    /// Hull area (d = 2) or volume (d = 3).
    pub hull: f64,
    /// Diameter.
    pub diameter: f64,
    /// Bounding-box extents.
    pub extents: &'a [f64],
    /// Positions by robot index.
    pub positions: &'a [P],
}

/// The metrics of a finished run (SPEC section 6).
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutcome {
    /// Rounds completed when the stop criterion was first found to hold (or the cap).
    pub rounds: u64,
    /// Activations.
    pub activations: u64,
    /// Activations that moved.
    pub moves: u64,
    /// Total distance travelled (moves * b for rigid moves).
    pub distance: f64,
    /// Whether the stop criterion was reached before the cap.
    pub converged: bool,
    /// Sum over robots of max(0, d_i - c/2), d_i the distance to the initial centroid.
    pub d_opt: f64,
    /// Largest d_i.
    pub d_max: f64,
    /// Diameter at the end.
    pub final_diameter: f64,
    /// Bounding-box extents at the end.
    pub final_extents: Vec<f64>,
    /// Hull area (volume) at the start.
    pub hull_initial: f64,
    /// Hull area (volume) at the end.
    pub hull_final: f64,
    /// The largest hull area (volume) measured during the run.
    pub hull_max: f64,
    /// The largest relative growth of the hull in one round (ASYNC: tick), 0 if none.
    pub hull_growth_max: f64,
    /// Rounds (ASYNC: ticks) in which the area of the hull of the positions grew.
    pub hull_growth_rounds: u64,
    /// Rounds (ASYNC: ticks) in which the hull of the positions and the destinations
    /// of decided moves grew (for the round schedulers: rounds in which a destination
    /// lay outside the hull of the positions). Under ASYNC this is the hull that
    /// Lemma 2 bounds; the hull of the positions alone can grow.
    pub committed_hull_growth: u64,
    /// Termination algorithm: robots with all 2d bits set at the end.
    pub terminated: Option<u64>,
    /// ASYNC: the tick at which the run stopped.
    pub ticks: Option<u64>,
}

impl RunOutcome {
    /// work / d_opt, with work = moves * b.
    pub fn rho(&self, step: f64) -> f64 {
        self.moves as f64 * step / self.d_opt
    }

    /// rounds / d_max.
    pub fn tau(&self) -> f64 {
        self.rounds as f64 / self.d_max
    }
}

/// One simulation run. The caller owns the loop: [`Simulation::step`] runs one round
/// of the schedule; [`Simulation::run`] steps until the stop criterion holds.
pub struct Simulation<P: IndexPoint> {
    world: World,
    schedule: Schedule,
    config: SimConfig,
    d_opt: f64,
    d_max: f64,
    hull_initial: f64,
    /// The (position generation, activations) at which quiescence was last found false.
    last_quiescence_check: Option<(u64, u64)>,
    _point: std::marker::PhantomData<fn() -> P>,
}

impl<P: IndexPoint> Simulation<P> {
    /// A simulation of `initial` (robot i starts at `initial[i]`).
    pub fn new(config: SimConfig, initial: Vec<P>) -> Result<Self, EngineError> {
        if initial.is_empty() {
            return Err(EngineError::EmptySwarm);
        }
        if initial.len() > MAX_ROBOTS {
            return Err(EngineError::Invalid(format!(
                "{} robots: at most {MAX_ROBOTS}",
                initial.len()
            )));
        }
        let a = &config.algorithm;
        if !(a.step > 0.0 && a.step <= MAX_MAGNITUDE) {
            return Err(EngineError::Invalid(format!(
                "step must be positive and at most {MAX_MAGNITUDE:e}, got {}",
                a.step
            )));
        }
        if !(a.locality > 0.0 && a.locality <= MAX_MAGNITUDE) {
            return Err(EngineError::Invalid(format!(
                "locality must be positive and at most {MAX_MAGNITUDE:e}, got {}",
                a.locality
            )));
        }
        if initial
            .iter()
            .any(|p| (0..P::DIM).any(|k| p.axis(k).is_nan() || p.axis(k).abs() > MAX_MAGNITUDE))
        {
            return Err(EngineError::Invalid(format!(
                "initial positions must be finite and at most {MAX_MAGNITUDE:e} in magnitude"
            )));
        }
        let mut world = World::new();
        let params = Params {
            algorithm: config.algorithm,
            vision: config.vision,
            backend: config.backend,
            scheduler: config.scheduler,
            seed: config.seed,
            movement: config.movement,
        };
        let shape = Shape::of(&initial);
        let hull_initial = shape.hull;
        world.insert_resource(params);
        world.insert_resource(Clock::default());
        world.insert_resource(ScheduleState::default());
        world.insert_resource(Tally::default());
        world.insert_resource(shape);
        world.insert_resource(HullVertices(P::hull_vertices(&initial)));
        world.insert_resource(Snapshot::<P> {
            sight: None,
            generation: 0,
        });
        world.insert_resource(Positions {
            points: initial.clone(),
            generation: 0,
        });
        let has_memory = config.algorithm.kind.has_memory();
        let robots = (0..initial.len()).map(|i| {
            (
                Robot { index: i as u32 },
                Activated(false),
                Waiting(0),
                Intent::<P>(None),
            )
        });
        let entities: Vec<Entity> = world.spawn_batch(robots).collect();
        if has_memory {
            for (i, e) in entities.into_iter().enumerate() {
                let mut stream = Stream::keyed(config.seed, Purpose::RobotFrame, i as u64, 0);
                let frame = AxisFrame::random(P::DIM, &mut stream);
                world.entity_mut(e).insert(Memory(RobotMemory::new(frame)));
            }
        }
        let mut schedule = Schedule::default();
        if let SchedulerSpec::Async(spec) = config.scheduler {
            let entities: Vec<Entity> = {
                let mut q = world.query::<(Entity, &Robot)>();
                let mut v: Vec<(u32, Entity)> = q.iter(&world).map(|(e, r)| (r.index, e)).collect();
                v.sort_unstable_by_key(|&(i, _)| i);
                v.into_iter().map(|(_, e)| e).collect()
            };
            let mut clock = AsyncClock::new(initial.len());
            clock.committed_hull = hull_initial;
            for (i, &e) in entities.iter().enumerate() {
                let until = match spec.start {
                    AsyncStart::Together => 0,
                    AsyncStart::Random => duration(&params, i as u32, 0, START, spec.idle),
                };
                clock.schedule(until, i as u32);
                world.entity_mut(e).insert(Timing::<P> {
                    phase: Phase::Idle,
                    since: 0,
                    until,
                    cycle: 0,
                    looked: 0,
                    pending: None,
                    target: initial[i],
                });
            }
            world.insert_resource(clock);
            world.insert_resource(RobotEntities(entities));
            schedule.configure_sets(
                (
                    AsyncSet::Advance,
                    AsyncSet::FinishMoves,
                    AsyncSet::FinishComputes,
                    AsyncSet::Look,
                    AsyncSet::Account,
                )
                    .chain(),
            );
            schedule.add_systems((
                asynchrony::advance.in_set(AsyncSet::Advance),
                asynchrony::finish_moves::<P>.in_set(AsyncSet::FinishMoves),
                asynchrony::finish_computes::<P>.in_set(AsyncSet::FinishComputes),
                asynchrony::look::<P>.in_set(AsyncSet::Look),
                asynchrony::account::<P>.in_set(AsyncSet::Account),
            ));
        } else {
            schedule.configure_sets(
                (
                    RoundSet::Activate,
                    RoundSet::Look,
                    RoundSet::Compute,
                    RoundSet::Move,
                    RoundSet::Measure,
                )
                    .chain(),
            );
            schedule.add_systems((
                activate_robots.in_set(RoundSet::Activate),
                take_snapshot::<P>.in_set(RoundSet::Look),
                compute_intents::<P>.in_set(RoundSet::Compute),
                (measure_committed::<P>, apply_moves::<P>)
                    .chain()
                    .in_set(RoundSet::Move),
                (measure_shape::<P>, advance_clock)
                    .chain()
                    .in_set(RoundSet::Measure),
            ));
        }
        Ok(Simulation {
            world,
            schedule,
            d_opt: metrics::d_opt(&initial, config.algorithm.locality),
            d_max: metrics::d_max(&initial),
            hull_initial,
            config,
            last_quiescence_check: None,
            _point: std::marker::PhantomData,
        })
    }

    /// The run's configuration.
    pub fn config(&self) -> &SimConfig {
        &self.config
    }

    /// Positions by robot index.
    pub fn positions(&self) -> &[P] {
        &self.world.resource::<Positions<P>>().points
    }

    /// The ECS world (read-only), for inspection.
    pub fn world(&self) -> &World {
        &self.world
    }

    /// (robots that moved, robots activated) in the last round (ASYNC: in the last
    /// completed epoch).
    pub fn round_counts(&self) -> (u64, u64) {
        match self.world.get_resource::<AsyncClock>() {
            Some(clock) => (clock.last_epoch.1, clock.last_epoch.0),
            None => {
                let tally = self.world.resource::<Tally>();
                (tally.round_moves, tally.round_activations)
            }
        }
    }

    /// Runs one round (Activate, Look, Compute, Move, Measure), or under ASYNC one
    /// event tick (Advance, FinishMoves, FinishComputes, Look, Account).
    pub fn step(&mut self) {
        self.schedule.run(&mut self.world);
    }

    fn report(&self, round: u64) -> RoundReport<'_, P> {
        let tally = self.world.resource::<Tally>();
        let shape = self.world.resource::<Shape>();
        RoundReport {
            round,
            activated: if round == 0 {
                0
            } else {
                tally.round_activations
            },
            moving: if round == 0 { 0 } else { tally.round_moves },
            hull: shape.hull,
            diameter: shape.diameter,
            extents: &shape.extents,
            positions: self.positions(),
        }
    }

    fn memories(&mut self) -> Vec<(Entity, RobotMemory)> {
        let mut q = self.world.query::<(Entity, &Memory)>();
        q.iter(&self.world).map(|(e, m)| (e, m.0)).collect()
    }

    /// Whether no robot would move if activated now.
    pub fn is_quiescent(&mut self) -> bool {
        refresh_snapshot::<P>(&mut self.world);
        let mut q = self.world.query::<(&Robot, Option<&Memory>)>();
        let robots: Vec<(usize, Option<RobotMemory>)> = q
            .iter(&self.world)
            .map(|(r, m)| (r.index as usize, m.map(|m| m.0)))
            .collect();
        let params = *self.world.resource::<Params>();
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
        match snapshot.sight.as_ref().expect("snapshot refreshed") {
            SnapshotSight::Index(s) => !any_moves(&params, s, &robots),
            SnapshotSight::Exact(s) => !any_moves(&params, s, &robots),
        }
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
    /// (round 0) and after every counted round.
    pub fn run_with(&mut self, mut on_round: impl FnMut(&RoundReport<'_, P>)) -> RunOutcome {
        on_round(&self.report(0));
        if matches!(self.config.scheduler, SchedulerSpec::Async(_)) {
            return self.run_async(on_round);
        }
        let fsync = self.config.scheduler == SchedulerSpec::Fsync;
        let quiescence = self.config.stop.criterion.checks_quiescence();
        let mut rounds = 0u64;
        let converged = loop {
            if self.criterion_holds() {
                break true;
            }
            if rounds >= self.config.stop.max_rounds {
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
            on_round(&self.report(rounds));
        };
        self.outcome(rounds, converged)
    }

    /// ASYNC: event tick by event tick; the criterion is checked at the start, after
    /// every tick at which a move ended, and (for quiescence) whenever nobody moves.
    fn run_async(&mut self, mut on_round: impl FnMut(&RoundReport<'_, P>)) -> RunOutcome {
        let converged = loop {
            if self.criterion_holds() {
                break true;
            }
            if self.world.resource::<AsyncClock>().epochs >= self.config.stop.max_rounds {
                break false;
            }
            self.step();
            let clock = self.world.resource::<AsyncClock>();
            if clock.epoch_ended {
                let epochs = clock.epochs;
                on_round(&self.report(epochs));
            }
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
        }
    }
}
