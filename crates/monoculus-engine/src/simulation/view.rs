//! Watching a run from outside (the replay): every round, or under ASYNC every event
//! tick, with each robot's position at that moment and what it is doing.

use super::*;

/// What a robot is doing, as a viewer shows it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Activity {
    /// Not activated (round schedulers), or waiting for its next Look (ASYNC).
    Idle,
    /// Has looked and decided to stay (ASYNC: its Move phase is spent in place).
    Staying,
    /// ASYNC: has looked and is computing.
    Computing,
    /// Moving (round schedulers: it moved in the last round).
    Moving,
}

/// One robot as a viewer sees it after a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RobotView<P> {
    /// What it is doing.
    pub activity: Activity,
    /// Whether it looked in the last step (round schedulers: it was activated; ASYNC: it
    /// looked at the current tick).
    pub looked: bool,
    /// The displacement it decided at its last Look (`None`: stay, or no Look yet).
    pub decision: Option<P>,
    /// The byte of its state a replay shows (the termination algorithm: its bits).
    pub bits: Option<u8>,
    /// The colour it shows, an index into its algorithm's lights (`None`: the algorithm
    /// has none). Under ASYNC the colour the others see: set by a Compute that has
    /// ended.
    pub light: Option<u8>,
}

impl<P: IndexPoint> Simulation<P> {
    /// The time of the state: rounds completed, or under ASYNC the current tick.
    pub fn time(&self) -> u64 {
        match self.world.get_resource::<AsyncClock>() {
            Some(clock) => clock.tick,
            None => self.world.resource::<Clock>().round,
        }
    }

    /// Positions by robot index at the current time: under ASYNC the movers where they
    /// are on their segments (what a Look now would see), otherwise [`Self::positions`].
    pub fn positions_now(&self) -> Vec<P> {
        let settled = self.positions();
        let Some(clock) = self.world.get_resource::<AsyncClock>() else {
            return settled.to_vec();
        };
        let clocks = self.world.resource::<Clocks<P>>();
        asynchrony::positions_now(clock.tick, settled, clocks.with_points(settled))
    }

    /// Every robot's [`RobotView`], by robot index.
    pub fn robot_views(&self) -> Vec<RobotView<P>> {
        let n = self.positions().len();
        let mut views = vec![
            RobotView {
                activity: Activity::Idle,
                looked: false,
                decision: None,
                bits: None,
                light: None,
            };
            n
        ];
        if let Some(clock) = self.world.get_resource::<AsyncClock>() {
            for (r, t) in self.world.resource::<Clocks<P>>().0.iter().enumerate() {
                let looked = t.phase == Phase::Compute && t.looked == clock.tick;
                let started = t.cycle > 0;
                views[r] = RobotView {
                    activity: match (t.phase, t.pending()) {
                        (Phase::Idle, _) => Activity::Idle,
                        (Phase::Compute, _) => Activity::Computing,
                        (Phase::Move, Some(_)) => Activity::Moving,
                        (Phase::Move, None) => Activity::Staying,
                    },
                    looked,
                    decision: if started { t.pending() } else { None },
                    bits: None,
                    light: None,
                };
            }
        } else {
            let rounds = self.world.resource::<Clock>().round > 0;
            let mut q = self
                .world
                .try_query::<(&Robot, &Activated, &Intent<P>)>()
                .expect("robots carry an Intent");
            for (r, a, intent) in q.iter(&self.world) {
                let looked = rounds && a.0;
                views[r.index as usize] = RobotView {
                    activity: match (looked, intent.0) {
                        (false, _) => Activity::Idle,
                        (true, Some(_)) => Activity::Moving,
                        (true, None) => Activity::Staying,
                    },
                    looked,
                    decision: if looked { intent.0 } else { None },
                    bits: None,
                    light: None,
                };
            }
        }
        for (r, bits) in (self.hooks.shown_bits)(&self.world) {
            views[r as usize].bits = Some(bits);
        }
        for (view, light) in views.iter_mut().zip(self.lights_now()) {
            view.light = Some(light);
        }
        views
    }

    /// The colour each robot shows now, by robot: an index into the algorithm's lights
    /// ([`AlgorithmBox::lights`](crate::AlgorithmBox::lights)); empty when it has none.
    /// Under ASYNC a robot shows the colour its last ended Compute set.
    pub fn lights_now(&self) -> Vec<u8> {
        (self.hooks.shown_lights)(&self.world)
    }

    /// Runs to the stop criterion like [`Self::run`], calling `on_step` with the start
    /// and after every counted round, or under ASYNC after every event tick.
    pub fn run_observed(&mut self, mut on_step: impl FnMut(&Self)) -> RunOutcome {
        on_step(self);
        if matches!(self.config.scheduler, SchedulerSpec::Async(_)) {
            return self.run_async_with(|sim, _| on_step(sim));
        }
        self.run_rounds_with(|sim, _| on_step(sim))
    }
}

/// The colour each robot shows, by robot (empty when the algorithm has no lights).
pub(super) fn shown_lights<P: IndexPoint, A: Algorithm>(world: &World) -> Vec<u8> {
    let algorithm = &world.resource::<Rule<A>>().0;
    if algorithm.light_names().len() == 0 {
        return Vec::new();
    }
    if let Some(l) = world.get_resource::<asynchrony::Lights>() {
        return l.shown.clone();
    }
    let n = world.resource::<Positions<P>>().points.len();
    match world.try_query::<(&Robot, &MemoryOf<P, A>)>() {
        Some(mut q) => crate::systems::lights_of::<A>(
            algorithm,
            n,
            q.iter(world).map(|(r, m)| (r.index as usize, &m.0.state)),
        ),
        None => crate::systems::lights_of::<A>(algorithm, n, std::iter::empty()),
    }
}

/// The byte of each robot's state a replay shows ([`Algorithm::shown_bits`]), by robot.
pub(super) fn shown_bits<P: IndexPoint, A: Algorithm>(world: &World) -> Vec<(u32, u8)> {
    if A::shown_bits(&A::State::default()).is_none() {
        return Vec::new();
    }
    // Only the robots of an algorithm with a state carry one (and register it).
    let Some(mut q) = world.try_query::<(&Robot, &MemoryOf<P, A>)>() else {
        return Vec::new();
    };
    q.iter(world)
        .filter_map(|(r, m)| A::shown_bits(&m.0.state).map(|b| (r.index, b)))
        .collect()
}
