//! [`Simulation`]: one run, a `World` of robot entities stepped by a `Schedule`.

mod build;
mod run;
mod view;
mod wiring;

pub use view::{Activity, RobotView};

use bevy_ecs::prelude::*;
use monoculus_core::algorithms::{Algorithm, Kept, LocalFrame, ModelParams, Sensing};
use monoculus_core::errors::MovementErrors;
use monoculus_core::metrics;
use monoculus_core::rng::{Purpose, Stream};
use monoculus_core::vision::{Sight, VisionParams};
use rayon::prelude::*;

use crate::algorithm::{AlgorithmBox, Rule, Setup};
use crate::asynchrony::{
    self, AsyncClock, AsyncSet, Clocks, Phase, RobotEntities, START, duration,
};
use crate::components::{Activated, Intent, Memory, Robot, Waiting};
use crate::resources::{
    Clock, HullVertices, Params, Positions, ScheduleState, Shape, SightBackend, Snapshot,
    SnapshotSight, Tally,
};
use crate::systems::{
    KeptBy, MemoryOf, RoundSet, activate_robots, compute_intents, decide_one, measure_round,
    move_round, refresh_snapshot, take_snapshot,
};
use crate::{
    AsyncStart, EngineError, Goal, IndexPoint, MAX_MAGNITUDE, MAX_ROBOTS, SchedulerSpec,
    StopCriterion, StopSpec, StoppedBy,
};

/// Everything that defines a run besides the initial positions.
#[derive(Clone, Debug)]
pub struct SimConfig {
    /// The algorithm (with its parameters).
    pub algorithm: AlgorithmBox,
    /// Step b, locality c, observation errors, target policy.
    pub model: ModelParams,
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
    /// Faulty robots (SPEC 9.1), if any.
    pub faults: Option<crate::FaultSpec>,
}

impl SimConfig {
    /// The paper's setting for `algorithm`: b = 1, c = 2, FSYNC, its default stop
    /// criterion and goal with a cap of `max_rounds`, the index backend, no errors.
    pub fn paper(algorithm: impl Into<AlgorithmBox>, seed: u64, max_rounds: u64) -> Self {
        let algorithm = algorithm.into();
        SimConfig {
            stop: StopSpec {
                criterion: algorithm.default_stop(),
                goal: algorithm.goal(),
                max_rounds,
            },
            algorithm,
            model: ModelParams::new(1.0, 2.0),
            vision: VisionParams::for_step(1.0),
            backend: SightBackend::Index,
            scheduler: SchedulerSpec::Fsync,
            seed,
            movement: MovementErrors::NONE,
            faults: None,
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
    world: &'a World,
    shown_lights: fn(&World) -> Vec<u8>,
}

impl<P> RoundReport<'_, P> {
    /// The colour each robot shows, by robot ([`Simulation::lights_now`]; empty when
    /// the algorithm has no lights).
    pub fn lights(&self) -> Vec<u8> {
        (self.shown_lights)(self.world)
    }

    /// The robots activated in this round, ascending (round schedulers; empty for
    /// round 0 and under ASYNC, whose epochs are not rounds of activations).
    pub fn activated_robots(&self) -> Vec<u32> {
        if self.round == 0 || self.world.contains_resource::<AsyncClock>() {
            return Vec::new();
        }
        let mut q = self
            .world
            .try_query::<(&Robot, &Activated)>()
            .expect("robots carry Activated");
        let mut robots: Vec<u32> = q
            .iter(self.world)
            .filter(|(_, a)| a.0)
            .map(|(r, _)| r.index)
            .collect();
        robots.sort_unstable();
        robots
    }
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
    /// Whether the run converged: its stop criterion ended it (not the cap, a
    /// schedule's end, a failure or an interruption) and its goal holds at the end.
    pub converged: bool,
    /// What ended the run.
    pub stopped_by: StoppedBy,
    /// The goal the run was judged by ([`StopSpec::goal`]).
    pub goal: Goal,
    /// Whether the goal holds for the configuration the run ended with.
    pub goal_met: bool,
    /// The radius of the smallest disc (ball in space) holding every correct robot at
    /// the end.
    pub final_radius: f64,
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
    /// Why the run stopped early, if its algorithm failed (a step along a direction that
    /// is not a unit vector, a panic): the run is then not converged.
    pub failure: Option<crate::resources::RunFailure>,
    /// The number of faulty robots (SPEC 9.1); the metrics above are the correct robots'.
    pub faulty: u64,
}

impl RunOutcome {
    /// Whether the run is stuck: it fell quiescent (no robot would move) without its
    /// goal, so it would never reach it.
    pub fn stuck(&self) -> bool {
        self.stopped_by == StoppedBy::Quiescent && !self.goal_met
    }

    /// Whether the run was stopped from outside ([`Simulation::set_interrupt`]) before
    /// its criterion or its cap: its metrics are those of where it stopped.
    pub fn interrupted(&self) -> bool {
        self.stopped_by == StoppedBy::Interrupted
    }

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
    hooks: Hooks<P>,
    d_opt: f64,
    d_max: f64,
    hull_initial: f64,
    /// The (position generation, activations) at which quiescence was last found false.
    last_quiescence_check: Option<(u64, u64)>,
    /// Set from outside to stop the run at the end of the current round (tick).
    interrupt: Option<std::sync::Arc<std::sync::atomic::AtomicBool>>,
    _point: std::marker::PhantomData<fn() -> P>,
}

impl<P: IndexPoint> Simulation<P> {
    /// A simulation of `initial` (robot i starts at `initial[i]`).
    pub fn new(config: SimConfig, initial: Vec<P>) -> Result<Self, EngineError> {
        build::validate(&config, &initial)?;
        let mut world = World::new();
        let (params, measures) = prepare(&mut world, &config, &initial);
        let mut schedule = Schedule::default();
        let hooks = config.algorithm.for_points::<P>().install(Setup {
            world: &mut world,
            schedule: &mut schedule,
            config: &config,
            params: &params,
            initial: &initial,
        });
        Ok(Simulation {
            world,
            schedule,
            hooks,
            d_opt: measures.d_opt,
            d_max: measures.d_max,
            hull_initial: measures.hull_initial,
            config,
            last_quiescence_check: None,
            interrupt: None,
            _point: std::marker::PhantomData,
        })
    }

    /// Makes this simulation a new run, as [`Simulation::new`] would make it (the same
    /// steps, bit for bit), keeping its world and its schedule where the new run's
    /// algorithm has the same type and its scheduler the same systems: a small run then
    /// costs its activations, not the making of a world and a schedule. Otherwise it is
    /// made afresh.
    ///
    /// ```
    /// use glam::DVec2;
    /// use monoculus_core::algorithms::ConvergeLocality;
    /// use monoculus_engine::{AlgorithmBox, SimConfig, Simulation};
    ///
    /// let start = |k: f64| vec![DVec2::ZERO, DVec2::new(5.0 + k, 0.0), DVec2::new(0.0, 5.0)];
    /// let config = |seed| SimConfig::paper(AlgorithmBox::new(ConvergeLocality), seed, 1000);
    /// let mut sim = Simulation::new(config(0), start(0.0)).unwrap();
    /// sim.run();
    /// sim.restart(config(1), start(1.0)).unwrap();
    /// let again = sim.run();
    /// let fresh = Simulation::new(config(1), start(1.0)).unwrap().run();
    /// assert_eq!((again.rounds, again.moves), (fresh.rounds, fresh.moves));
    /// ```
    pub fn restart(&mut self, config: SimConfig, initial: Vec<P>) -> Result<(), EngineError> {
        let same_systems = systems_of(&config) == systems_of(&self.config)
            && config.algorithm.for_points::<P>().algorithm_type()
                == self.config.algorithm.for_points::<P>().algorithm_type();
        if !same_systems {
            *self = Simulation::new(config, initial)?;
            return Ok(());
        }
        build::validate(&config, &initial)?;
        // The robots before are set again in place or despawned as the new ones are
        // spawned (`build::spawn_robots`).
        let (params, measures) = prepare(&mut self.world, &config, &initial);
        config.algorithm.for_points::<P>().reinstall(Setup {
            world: &mut self.world,
            schedule: &mut self.schedule,
            config: &config,
            params: &params,
            initial: &initial,
        });
        self.d_opt = measures.d_opt;
        self.d_max = measures.d_max;
        self.hull_initial = measures.hull_initial;
        self.config = config;
        self.last_quiescence_check = None;
        self.interrupt = None;
        Ok(())
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

    /// Activations so far.
    pub fn activations(&self) -> u64 {
        self.world.resource::<Tally>().activations
    }

    /// Under ASYNC, the current tick and the epochs completed; `None` otherwise.
    pub fn async_progress(&self) -> Option<(u64, u64)> {
        self.world
            .get_resource::<AsyncClock>()
            .map(|c| (c.tick, c.epochs))
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
            world: &self.world,
            shown_lights: self.hooks.shown_lights,
        }
    }
}

/// What a run's loop asks of its algorithm, compiled for it when the run is built: plain
/// functions of the world, so that the loop itself is the same for every algorithm.
pub(crate) struct Hooks<P> {
    /// Whether no correct robot would move if activated now.
    pub(crate) quiescent: fn(&mut World) -> bool,
    /// The robots' kept states, to be put back (`None`: the algorithm keeps none).
    pub(crate) save: fn(&mut World) -> Option<Box<dyn std::any::Any + Send>>,
    /// Puts back what `save` took.
    pub(crate) restore: fn(&mut World, Box<dyn std::any::Any + Send>),
    /// How many robots have terminated, for algorithms that terminate.
    pub(crate) terminated: fn(&mut World) -> Option<u64>,
    /// The byte of each robot's state that a replay shows, by robot (empty if none).
    pub(crate) shown_bits: fn(&World) -> Vec<(u32, u8)>,
    /// The colour each robot's state shows, by robot (empty: the algorithm has no
    /// lights).
    pub(crate) lights: fn(&mut World) -> Vec<u8>,
    /// The colour each robot shows to the others now (ASYNC: set by an ended Compute),
    /// by robot (empty: the algorithm has no lights).
    pub(crate) shown_lights: fn(&World) -> Vec<u8>,
    /// What one robot would decide if activated now (states copied: nothing changes).
    pub(crate) decide_now: fn(&mut World, usize) -> Result<Option<P>, crate::resources::RunFailure>,
}

/// The measures of a run's start.
struct StartMeasures {
    d_opt: f64,
    d_max: f64,
    hull_initial: f64,
}

/// Inserts (or puts back) every resource of a run of `config` from `initial`: its
/// parameters, and the start's measures.
fn prepare<P: IndexPoint>(
    world: &mut World,
    config: &SimConfig,
    initial: &[P],
) -> (Params, StartMeasures) {
    let params = build::params(config, initial.len());
    let hull_initial = build::insert_resources(world, params.clone(), initial);
    if matches!(config.scheduler, SchedulerSpec::Async(_)) {
        wiring::insert_async_resources(world, initial, hull_initial);
    }
    let correct = params.correct(initial);
    let measures = StartMeasures {
        d_opt: metrics::d_opt(&correct, config.model.locality),
        d_max: metrics::d_max(&correct),
        hull_initial,
    };
    (params, measures)
}

/// Which systems a scheduler's schedule holds: what [`install`] wires, and what a run
/// started again must share with the last ([`Simulation::restart`]).
#[derive(PartialEq)]
enum Systems {
    Rounds { adversary: bool },
    Async,
}

fn systems_of(config: &SimConfig) -> Systems {
    match config.scheduler {
        SchedulerSpec::Async(_) => Systems::Async,
        SchedulerSpec::Adversary { .. } => Systems::Rounds { adversary: true },
        _ => Systems::Rounds { adversary: false },
    }
}

/// Installs `algorithm` into a run: its resource, the robots (with their kept frames and
/// states), the systems of the scheduler compiled for it; returns the loop's hooks.
pub(crate) fn install<P: IndexPoint, A: Algorithm>(
    algorithm: std::sync::Arc<A>,
    setup: Setup<'_, P>,
) -> Hooks<P> {
    let systems = systems_of(setup.config);
    let schedule = populate::<P, A>(algorithm, setup);
    match systems {
        Systems::Async => wiring::wire_async::<P, A>(schedule),
        Systems::Rounds { adversary } => wiring::wire_rounds::<P, A>(schedule, adversary),
    }
    Hooks {
        quiescent: run::quiescent::<P, A>,
        save: run::save_states::<P, A>,
        restore: run::restore_states::<P, A>,
        terminated: run::terminated::<P, A>,
        shown_bits: view::shown_bits::<P, A>,
        lights: run::lights::<P, A>,
        shown_lights: view::shown_lights::<P, A>,
        decide_now: run::decide_now::<P, A>,
    }
}

/// Inserts `algorithm` and spawns the robots (under ASYNC, with their first phases);
/// returns the schedule, for the systems.
pub(crate) fn populate<'a, P: IndexPoint, A: Algorithm>(
    algorithm: std::sync::Arc<A>,
    setup: Setup<'a, P>,
) -> &'a mut Schedule {
    let Setup {
        world,
        schedule,
        config,
        params,
        initial,
    } = setup;
    let keeps = algorithm.keeps_state();
    build::put(world, Rule(algorithm));
    let entities = build::spawn_robots::<P, A>(world, config, initial, keeps);
    if let SchedulerSpec::Async(spec) = &config.scheduler {
        wiring::start_async::<P, A>(world, params, spec, entities);
    }
    schedule
}
