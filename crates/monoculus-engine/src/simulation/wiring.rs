//! The two schedules: the systems of a synchronous round in [`RoundSet`] order, and the
//! ASYNC tick's in [`AsyncSet`] order (with each robot's first Idle phase drawn).

use super::*;

/// The ASYNC scheduler's resources, inserted before the robots are spawned (see
/// [`build::insert_resources`]); the clock's first phases and the entities are filled
/// in by [`wire_async`].
pub(super) fn insert_async_resources<P: IndexPoint>(
    world: &mut World,
    initial: &[P],
    hull_initial: f64,
) {
    build::put(world, AsyncClock::new(initial.len()));
    build::put(world, asynchrony::CommittedHull::<P>::new(hull_initial));
    build::put(world, asynchrony::KeptShape::<P>::new());
    build::put(world, asynchrony::LookSight::<P>::new(initial.len()));
    build::put(world, RobotEntities(Vec::new()));
    build::put(world, Clocks::<P>::new(initial.len()));
    build::put(world, asynchrony::Lights::default());
}

/// Starts the ASYNC scheduler over the robots spawned as `entities` (by index): every
/// robot's first phase, the clock, the lights.
pub(super) fn start_async<P: IndexPoint, A: Algorithm>(
    world: &mut World,
    params: &Params,
    spec: &crate::AsyncSpec,
    entities: Vec<Entity>,
) {
    let mut clock = std::mem::take(&mut *world.resource_mut::<AsyncClock>());
    let mut clocks = world.resource_mut::<Clocks<P>>();
    for (i, timing) in clocks.0.iter_mut().enumerate() {
        let i = i as u32;
        let until = match spec.start {
            AsyncStart::Together => 0,
            AsyncStart::Random => duration(params, i, 0, START, spec.idle),
        };
        timing.until = until;
        clock.schedule(until, i);
    }
    *world.resource_mut::<AsyncClock>() = clock;
    let algorithm = world.resource::<Rule<A>>().0.clone();
    let lights = crate::systems::lights_of::<A>(&*algorithm, entities.len(), std::iter::empty());
    *world.resource_mut::<asynchrony::Lights>() = asynchrony::Lights {
        shown: lights.clone(),
        set: lights,
    };
    world.resource_mut::<RobotEntities>().0 = entities;
}

/// Wires the ASYNC tick's systems.
pub(super) fn wire_async<P: IndexPoint, A: Algorithm>(schedule: &mut Schedule) {
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
    // Each phase's system runs at the ticks where that phase ends, Account where there
    // is something to account for: the systems change nothing otherwise.
    schedule.add_systems((
        asynchrony::advance::<P>.in_set(AsyncSet::Advance),
        asynchrony::finish_moves::<P>
            .in_set(AsyncSet::FinishMoves)
            .run_if(asynchrony::phase_ends(Phase::Move)),
        asynchrony::finish_computes::<P>
            .in_set(AsyncSet::FinishComputes)
            .run_if(asynchrony::phase_ends(Phase::Compute)),
        asynchrony::look::<P, A>
            .in_set(AsyncSet::Look)
            .run_if(asynchrony::phase_ends(Phase::Idle)),
        asynchrony::account::<P>
            .in_set(AsyncSet::Account)
            .run_if(asynchrony::to_account),
    ));
}

/// Wires a synchronous round (FSYNC, SSYNC, sequential, file, adversary: the adversary
/// chooses after the Look, from the robots' decisions on the snapshot).
pub(super) fn wire_rounds<P: IndexPoint, A: Algorithm>(schedule: &mut Schedule, adversary: bool) {
    if adversary {
        schedule.add_systems(
            crate::systems::choose_adversarially::<P, A>
                .after(take_snapshot::<P>)
                .in_set(RoundSet::Look),
        );
    }
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
        compute_intents::<P, A>.in_set(RoundSet::Compute),
        move_round::<P>.in_set(RoundSet::Move),
        measure_round::<P>.in_set(RoundSet::Measure),
    ));
}
