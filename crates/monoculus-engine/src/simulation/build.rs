//! Building a run: the parameters checked, the world's resources and robot entities.

use super::*;

/// Checks what the engine needs of a run (the experiments layer names the keys first).
pub(super) fn validate<P: IndexPoint>(
    config: &SimConfig,
    initial: &[P],
) -> Result<(), EngineError> {
    if initial.is_empty() {
        return Err(EngineError::EmptySwarm);
    }
    if initial.len() > MAX_ROBOTS {
        return Err(EngineError::Invalid(format!(
            "{} robots: at most {MAX_ROBOTS}",
            initial.len()
        )));
    }
    if let (Some(reason), 3) = (config.algorithm.plane_only(), P::DIM) {
        return Err(EngineError::Invalid(format!(
            "{} {reason}: the plane only (dim = 2)",
            config.algorithm.name()
        )));
    }
    let a = &config.model;
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
    if matches!(config.scheduler, SchedulerSpec::Adversary { .. }) && P::DIM != 2 {
        return Err(EngineError::Invalid(
            "the adversarial scheduler compares hull perimeters: the plane only (dim = 2)".into(),
        ));
    }
    if let SchedulerSpec::Adversary {
        fairness: Some(0), ..
    } = config.scheduler
    {
        return Err(EngineError::Invalid(
            "the adversary's fairness k must be at least 1".into(),
        ));
    }
    if let Some(spec) = &config.faults {
        match spec.count {
            crate::FaultCount::Robots(f) if f > initial.len() => {
                return Err(EngineError::Invalid(format!(
                    "{f} faulty robots of {}",
                    initial.len()
                )));
            }
            crate::FaultCount::Fraction(x) if !(0.0..=1.0).contains(&x) => {
                return Err(EngineError::Invalid(format!(
                    "the fraction of faulty robots must be in [0, 1], got {x}"
                )));
            }
            _ => {}
        }
        if spec.faulty(initial.len()) == initial.len() {
            return Err(EngineError::Invalid(
                "every robot is faulty: at least one must be correct".into(),
            ));
        }
    }
    if let SchedulerSpec::Async(spec) = &config.scheduler
        && let Err((_, message)) = spec.check(config.stop.max_rounds)
    {
        return Err(EngineError::Invalid(format!("ASYNC: {message}")));
    }
    if let Some((robot, what)) = match &config.scheduler {
        SchedulerSpec::File(list) => list.max_robot().map(|r| (r, "the schedule activates")),
        SchedulerSpec::Async(spec) => spec
            .durations
            .as_ref()
            .and_then(|d| d.max_robot())
            .map(|r| (r, "ASYNC: a duration is given to")),
        _ => None,
    } && robot as usize >= initial.len()
    {
        return Err(EngineError::Invalid(format!(
            "{what} robot {robot} of {} (robots are numbered from 0)",
            initial.len()
        )));
    }
    Ok(())
}

/// The parameters every system reads, with the faulty robots of a run of `n` drawn.
pub(super) fn params(config: &SimConfig, n: usize) -> Params {
    Params {
        faults: config
            .faults
            .map(|spec| std::sync::Arc::new(crate::FaultPlan::draw(&spec, n, config.seed))),
        model: config.model,
        vision: config.vision,
        backend: config.backend,
        scheduler: config.scheduler.clone(),
        seed: config.seed,
        movement: config.movement,
        failure: Default::default(),
    }
}

/// Inserts the resources of a run starting at `initial`; returns the initial hull.
/// Resources are entities too, and each carries a sparse index over every entity
/// before it (4 MB at 10^6 robots), so they are inserted before the robots are spawned
/// ([`spawn_robots`]).
pub(super) fn insert_resources<P: IndexPoint>(
    world: &mut World,
    params: Params,
    initial: &[P],
) -> f64 {
    let correct = params.correct(initial);
    let hull_vertices = P::hull_vertices(&correct);
    let shape = Shape::of_hull(&correct, &hull_vertices);
    let hull_initial = shape.hull;
    put(world, params);
    put(world, Clock::default());
    put(world, ScheduleState::default());
    put(world, Tally::default());
    put(world, shape);
    put(
        world,
        HullVertices {
            vertices: hull_vertices,
            generation: 0,
        },
    );
    put(
        world,
        Snapshot::<P> {
            sight: None,
            generation: 0,
        },
    );
    match world.get_resource_mut::<Positions<P>>() {
        // The positions' buffer kept from the run before.
        Some(mut positions) => {
            positions.points.clear();
            positions.points.extend_from_slice(initial);
            positions.generation = 0;
        }
        None => world.insert_resource(Positions {
            points: initial.to_vec(),
            generation: 0,
        }),
    }
    world.init_resource::<bevy_ecs::schedule::Schedules>();
    hull_initial
}

/// Sets the resource `R` to `value`: in place where the world holds one already (a run
/// started again, [`Simulation::restart`]), else inserted.
pub(super) fn put<R: Resource<Mutability = bevy_ecs::component::Mutable>>(
    world: &mut World,
    value: R,
) {
    if let Some(mut held) = world.get_resource_mut::<R>() {
        *held = value;
        return;
    }
    world.insert_resource(value);
}

/// Spawns the robots of a run starting at `initial` (with their frame and state, for an
/// algorithm that keeps one); under ASYNC, returns their entities by index.
pub(super) fn spawn_robots<P: IndexPoint, A: Algorithm>(
    world: &mut World,
    config: &SimConfig,
    initial: &[P],
    keeps_state: bool,
) -> Vec<Entity> {
    // Each robot is spawned with every component it will carry, so that nothing moves
    // it to another archetype later (at 10^6 robots, inserting a component one robot at
    // a time left two tables of the swarm behind: half the peak memory). Round
    // schedulers' robots carry their activation, wait and intent; ASYNC robots only
    // their index (their clocks are a table of their own, `Clocks`).
    let model = <A::Sensing as Sensing>::MODEL;
    let memory = |i: usize| {
        let mut stream = Stream::keyed(config.seed, Purpose::RobotFrame, i as u64, 0);
        Memory::<P, A::State>(Kept {
            frame: LocalFrame::draw(model, &mut stream),
            state: A::State::default(),
        })
    };
    let robot = |i: usize| Robot { index: i as u32 };
    let round = |i: usize| (robot(i), Activated(false), Waiting(0), Intent::<P>(None));
    let n = initial.len();
    let asynchronous = matches!(config.scheduler, SchedulerSpec::Async(_));
    if let Some(entities) =
        respawn_in_place::<P, A::State>(world, n, asynchronous, keeps_state.then_some(&memory))
    {
        return entities;
    }
    match (asynchronous, keeps_state) {
        (false, false) => world.spawn_batch((0..n).map(round)).for_each(drop),
        (false, true) => world
            .spawn_batch((0..n).map(|i| (round(i), memory(i))))
            .for_each(drop),
        (true, false) => return world.spawn_batch((0..n).map(robot)).collect(),
        (true, true) => {
            return world
                .spawn_batch((0..n).map(|i| (robot(i), memory(i))))
                .collect();
        }
    }
    Vec::new()
}

/// The queries [`respawn_in_place`] asks, kept in the world from run to run (a query
/// made anew costs more than setting ten robots again).
#[derive(Resource)]
struct Respawn<P: IndexPoint, S: Clone + PartialEq + Send + Sync + 'static> {
    robots: QueryState<RobotLayout<P, S>>,
    rounds: QueryState<RoundParts<P>>,
    kept: QueryState<(&'static Robot, &'static mut Memory<P, S>)>,
}

/// A robot, and which of the components that differ between runs it carries.
type RobotLayout<P, S> = (Entity, &'static Robot, Has<Activated>, Has<Memory<P, S>>);

/// What a round scheduler's robot carries besides its index.
type RoundParts<P> = (
    &'static mut Activated,
    &'static mut Waiting,
    &'static mut Intent<P>,
);

/// The robots of the run before, made the robots [`spawn_robots`] would spawn, where
/// there are `n` of them carrying the same components (the runs of a sweep, one after
/// the other): each robot's components set again, its index kept. Their table is in
/// index order, as they were spawned, and nothing moves a robot to another table, so
/// the systems meet them in the order new ones would come in. Otherwise the robots
/// before are despawned and `None` returned. Under ASYNC, the entities by index.
fn respawn_in_place<P: IndexPoint, S: Clone + PartialEq + Send + Sync + 'static>(
    world: &mut World,
    n: usize,
    asynchronous: bool,
    memory: Option<&dyn Fn(usize) -> Memory<P, S>>,
) -> Option<Vec<Entity>> {
    if !world.contains_resource::<Respawn<P, S>>() {
        let queries = Respawn::<P, S> {
            robots: world.query(),
            rounds: world.query(),
            kept: world.query(),
        };
        world.insert_resource(queries);
    }
    world.resource_scope(|world, mut queries: Mut<Respawn<P, S>>| {
        let mut entities = vec![Entity::PLACEHOLDER; n];
        let (mut same, mut count) = (true, 0);
        for (entity, robot, activated, remembers) in queries.robots.iter(world) {
            let i = robot.index as usize;
            count += 1;
            same &= i < n && activated != asynchronous && remembers == memory.is_some();
            if same {
                entities[i] = entity;
            }
        }
        if !same || count != n {
            let old: Vec<Entity> = queries.robots.iter(world).map(|(e, ..)| e).collect();
            for entity in old {
                world.despawn(entity);
            }
            return None;
        }
        if !asynchronous {
            for (mut activated, mut waiting, mut intent) in queries.rounds.iter_mut(world) {
                (activated.0, waiting.0, intent.0) = (false, 0, None);
            }
        }
        if let Some(memory) = memory {
            for (robot, mut m) in queries.kept.iter_mut(world) {
                *m = memory(robot.index as usize);
            }
        }
        Some(if asynchronous { entities } else { Vec::new() })
    })
}
