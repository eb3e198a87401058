//! A cell as the engine's types: its simulation config and its start positions.

use super::*;

impl Cell {
    /// The algorithm (with its parameters).
    pub fn algorithm(&self) -> &AlgorithmBox {
        &self.algorithm
    }

    /// Number of robots.
    pub fn n(&self) -> usize {
        self.file_positions
            .as_ref()
            .map_or_else(|| self.spec.swarm.n.unwrap_or(0), PositionsFile::len)
    }

    /// The stop criterion in force.
    pub fn criterion(&self) -> StopCriterion {
        match self.spec.stop.criterion {
            CriterionName::Default => self.algorithm.default_stop(),
            CriterionName::Quiescent => StopCriterion::Quiescent,
            CriterionName::Diameter => StopCriterion::Diameter,
            CriterionName::QuiescentOrDiameter => StopCriterion::QuiescentOrDiameter,
            CriterionName::Box => StopCriterion::Box,
        }
    }

    /// The goal in force: what convergence means for the cell's runs.
    pub fn goal(&self) -> Goal {
        match self.spec.stop.goal {
            GoalName::Default => self.algorithm.goal(),
            GoalName::Diameter => Goal::Diameter,
            GoalName::Disc => Goal::Disc,
            GoalName::Box => Goal::Box,
        }
    }

    /// The engine configuration for `seed`.
    pub fn sim_config(&self, seed: u64) -> SimConfig {
        let a = &self.spec.algorithm;
        let v = &self.spec.vision;
        let defaults = VisionParams::for_step(a.step);
        let sc = &self.spec.scheduler;
        SimConfig {
            algorithm: self.algorithm.clone(),
            model: ModelParams {
                step: a.step,
                locality: a.locality,
                errors: ObservationErrors {
                    flip_p: self.spec.errors.flip_p,
                    flip_window: self.spec.errors.flip_window,
                    angle_sigma: self.spec.errors.angle_sigma,
                },
                target: a.target,
            },
            vision: VisionParams {
                eps_pos: v.eps_pos.unwrap_or(defaults.eps_pos),
                eps_ang: v.eps_ang,
                eps_axis: v.eps_axis.unwrap_or(defaults.eps_axis),
                range: v.range.unwrap_or(f64::INFINITY),
                robot_radius: v.robot_radius,
            },
            backend: v.backend,
            scheduler: match sc.kind {
                SchedulerKind::Fsync => SchedulerSpec::Fsync,
                SchedulerKind::Ssync => SchedulerSpec::Ssync {
                    p: sc.p,
                    fairness: sc.fairness,
                },
                SchedulerKind::Async => SchedulerSpec::Async(AsyncSpec {
                    idle: sc.idle,
                    compute: sc.compute,
                    motion: sc.motion,
                    start: sc.start,
                    durations: self.durations.clone(),
                }),
                SchedulerKind::Sequential => SchedulerSpec::Sequential { order: sc.order },
                SchedulerKind::Adversary => SchedulerSpec::Adversary {
                    objective: sc.objective,
                    fairness: sc.fairness,
                },
                SchedulerKind::File => SchedulerSpec::File(
                    self.schedule
                        .clone()
                        .expect("the schedule file is read at validation"),
                ),
            },
            stop: StopSpec {
                criterion: self.criterion(),
                goal: self.goal(),
                max_rounds: self.spec.stop.max_rounds,
            },
            seed,
            faults: self.spec.faults.as_ref().map(|f| FaultSpec {
                count: match (f.count, f.fraction) {
                    (_, Some(x)) => FaultCount::Fraction(x),
                    (c, None) => FaultCount::Robots(c.unwrap_or(0) as usize),
                },
                kind: match f.kind {
                    FaultKindName::Crash => FaultKind::Crash(match (f.at, f.until) {
                        (Some(CrashAtConfig::Random(_)), until) => CrashAt::Random {
                            until: until.unwrap_or(0),
                        },
                        (Some(CrashAtConfig::Round(r)), _) => CrashAt::Round(r),
                        (None, _) => CrashAt::Round(0),
                    }),
                    FaultKindName::Byzantine => {
                        FaultKind::Byzantine(f.rule.unwrap_or(ByzantineRule::Random))
                    }
                },
            }),
            movement: MovementErrors {
                step_factor: self.spec.errors.step_factor,
                non_rigid: self.spec.errors.non_rigid.map(|n| n.delta_min),
            },
        }
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.spec.swarm.dim
    }

    /// The initial positions for `seed`, in dimension `P::DIM` (= [`Cell::dim`]).
    pub fn initial_positions<P: Point>(&self, seed: u64) -> Vec<P> {
        if let Some(p) = &self.file_positions {
            return p.points();
        }
        self.generated_positions(self.n(), seed)
    }

    /// `n` positions drawn as `[swarm]` describes them (`init`, `side`, ...) for `seed`
    /// (`init = "file"` has no such draw: the file's positions, all of them).
    pub fn generated_positions<P: Point>(&self, n: usize, seed: u64) -> Vec<P> {
        if let Some(p) = &self.file_positions {
            return p.points();
        }
        let s = &self.spec.swarm;
        let side = s.side;
        let shape = match s.init {
            InitKind::Square => InitShape::Square { side },
            InitKind::Disc => InitShape::Disc { side },
            InitKind::Line => InitShape::Line { side },
            InitKind::Lattice => InitShape::Lattice { side },
            InitKind::Clusters => InitShape::Clusters {
                side,
                clusters: s.clusters,
                spread: s.spread.unwrap_or(side / 20.0),
            },
            InitKind::File => unreachable!("file positions are loaded at validation"),
        };
        generate(&shape, n, seed)
    }
}
