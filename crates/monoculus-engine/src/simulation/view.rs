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

    /// ASYNC: every phase duration the run has used so far (drawn, or given by
    /// [`AsyncSpec::durations`](crate::AsyncSpec::durations)), by robot, cycle and phase,
    /// in the form `scheduler.durations` gives them: a run given all of them replays
    /// this one whatever its distributions. Empty for the round schedulers.
    ///
    /// ```
    /// use glam::DVec2;
    /// use monoculus_core::algorithms::ConvergeLocality;
    /// use monoculus_engine::prelude::*;
    ///
    /// let async_spec = AsyncSpec { idle: TickDist::Uniform { min: 1, max: 5 }, ..AsyncSpec::default() };
    /// let config = SimConfig {
    ///     scheduler: SchedulerSpec::Async(async_spec),
    ///     ..SimConfig::paper(AlgorithmBox::new(ConvergeLocality), 1, 100)
    /// };
    /// let mut sim = Simulation::new(config, vec![DVec2::ZERO, DVec2::new(5.0, 0.0)]).unwrap();
    /// sim.run();
    /// let used = sim.drawn_durations();
    /// assert!(used.iter().any(|g| g.cycle == 0 && g.robot == 1));
    /// ```
    pub fn drawn_durations(&self) -> Vec<asynchrony::GivenDuration> {
        use asynchrony::{COMPUTE, GivenDuration, IDLE, MOVE};
        let SchedulerSpec::Async(spec) = &self.config.scheduler else {
            return Vec::new();
        };
        let params = self.world.resource::<Params>();
        let clocks = &self.world.resource::<Clocks<P>>().0;
        let mut out = Vec::new();
        for (r, t) in clocks.iter().enumerate() {
            let r32 = r as u32;
            let draw = |cycle: u64, tag: u64, dist: crate::TickDist| {
                duration(params, r32, cycle, tag, dist)
            };
            let give = |cycle: u64, phase: Phase, ticks: u64| GivenDuration {
                robot: r32,
                cycle,
                phase,
                ticks,
            };
            if spec.start == AsyncStart::Random {
                out.push(give(0, Phase::Idle, draw(0, START, spec.idle)));
            }
            // After k Looks: the Computes of cycles 0..k; the Move of cycle u once its
            // Compute ended, and the Idle of cycle u + 1 once that Move ended.
            let k = t.cycle;
            for u in 0..k {
                out.push(give(u, Phase::Compute, draw(u, COMPUTE, spec.compute)));
                let last = u + 1 == k;
                if !last || t.phase != Phase::Compute {
                    out.push(give(u, Phase::Move, draw(u + 1, MOVE, spec.motion)));
                }
                if !last || t.phase == Phase::Idle {
                    out.push(give(u + 1, Phase::Idle, draw(u + 1, IDLE, spec.idle)));
                }
            }
        }
        out
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
