//! Faulty robots (SPEC 9.1): a set drawn once per run from the seed, either crashed
//! (never moving again from some round) or Byzantine (moving b by a rule of their own at
//! every activation). Faulty robots are seen and block like any other; the metrics and the
//! stop criteria are those of the correct robots.

use bevy_ecs::prelude::*;
use monoculus_core::geometry::Point;
use monoculus_core::rng::{Purpose, Stream};

/// How many robots are faulty.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FaultCount {
    /// Exactly this many (at most n).
    Robots(usize),
    /// This share of the robots, rounded down (in [0, 1]).
    Fraction(f64),
}

/// When a crashed robot stops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CrashAt {
    /// From this round (0: from the start).
    Round(u64),
    /// From a round drawn uniformly in [0, until], for each crashed robot.
    Random {
        /// The last round a crash may start.
        until: u64,
    },
}

/// A Byzantine robot's rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ByzantineRule {
    /// A uniformly random direction at every activation.
    Random,
    /// Away from the centroid of all robots.
    Away,
    /// Toward the robot farthest from it (the lowest index among equals).
    Farthest,
}

/// What the faulty robots do.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FaultKind {
    /// They stop forever.
    Crash(CrashAt),
    /// They move by their own rule.
    Byzantine(ByzantineRule),
}

/// The faults of a run: how many robots, and what they do.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaultSpec {
    /// How many.
    pub count: FaultCount,
    /// What they do.
    pub kind: FaultKind,
}

/// One robot's part in a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// Runs the algorithm.
    Correct,
    /// Runs the algorithm until round `from`, then never moves again.
    Crashed {
        /// The first round in which it does not move.
        from: u64,
    },
    /// Moves by its rule at every activation.
    Byzantine(ByzantineRule),
}

/// Every robot's role in one run, drawn from the seed.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct FaultPlan {
    roles: Vec<Role>,
    faulty: usize,
}

impl FaultSpec {
    /// The number of faulty robots among `n`.
    pub fn faulty(&self, n: usize) -> usize {
        match self.count {
            FaultCount::Robots(f) => f.min(n),
            FaultCount::Fraction(x) => ((x * n as f64).floor() as usize).min(n),
        }
    }
}

impl FaultPlan {
    /// Draws the faulty robots of a run of `n` robots: a uniform subset of
    /// [`FaultSpec::faulty`] robots (a partial Fisher-Yates shuffle of one stream), and
    /// for random crashes each one's round from its own stream.
    pub fn draw(spec: &FaultSpec, n: usize, seed: u64) -> Self {
        let f = spec.faulty(n);
        let mut roles = vec![Role::Correct; n];
        let mut pick = Stream::keyed(seed, Purpose::Fault, u64::MAX, 0);
        let mut order: Vec<u32> = (0..n as u32).collect();
        for k in 0..f {
            let j = k + pick.below(n - k);
            order.swap(k, j);
            let robot = order[k];
            roles[robot as usize] = match spec.kind {
                FaultKind::Crash(CrashAt::Round(from)) => Role::Crashed { from },
                FaultKind::Crash(CrashAt::Random { until }) => {
                    let mut s = Stream::keyed(seed, Purpose::Fault, robot as u64, 1);
                    Role::Crashed {
                        from: s.below(until.saturating_add(1).min(usize::MAX as u64) as usize)
                            as u64,
                    }
                }
                FaultKind::Byzantine(rule) => Role::Byzantine(rule),
            };
        }
        FaultPlan { roles, faulty: f }
    }

    /// Robot `i`'s role.
    pub fn role(&self, i: usize) -> Role {
        self.roles[i]
    }

    /// Whether robot `i` is correct.
    pub fn is_correct(&self, i: usize) -> bool {
        self.roles[i] == Role::Correct
    }

    /// The number of faulty robots.
    pub fn faulty(&self) -> usize {
        self.faulty
    }

    /// The positions of the correct robots, in index order.
    pub fn correct<P: Copy>(&self, points: &[P]) -> Vec<P> {
        points
            .iter()
            .zip(&self.roles)
            .filter(|(_, r)| **r == Role::Correct)
            .map(|(p, _)| *p)
            .collect()
    }
}

/// A Byzantine robot's displacement in an activation: b along its rule, or `None` where
/// the rule names no direction (at the centroid, or every robot at its own position).
pub fn byzantine_move<P: Point>(
    rule: ByzantineRule,
    positions: &[P],
    robot: usize,
    step: f64,
    stream: &mut Stream,
) -> Option<P> {
    let p = positions[robot];
    let direction = match rule {
        ByzantineRule::Random => P::to_global(&P::random_frame(stream), P::unit_axis(0)),
        ByzantineRule::Away => {
            let sum = positions.iter().fold(P::zero(), |a, &q| a + q);
            p - sum * (1.0 / positions.len() as f64)
        }
        ByzantineRule::Farthest => {
            let mut best = (0.0, robot);
            for (k, &q) in positions.iter().enumerate() {
                let d = q.distance(p);
                if d > best.0 {
                    best = (d, k);
                }
            }
            positions[best.1] - p
        }
    };
    let length = direction.length();
    (length > 1e-12 * step.max(1.0)).then(|| direction * (step / length))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn draws_the_stated_number_uniformly_and_by_seed() {
        let spec = FaultSpec {
            count: FaultCount::Fraction(0.25),
            kind: FaultKind::Crash(CrashAt::Random { until: 9 }),
        };
        let plan = FaultPlan::draw(&spec, 41, 5);
        assert_eq!(plan.faulty(), 10);
        assert_eq!((0..41).filter(|&i| !plan.is_correct(i)).count(), 10);
        assert_eq!(plan, FaultPlan::draw(&spec, 41, 5));
        assert_ne!(plan, FaultPlan::draw(&spec, 41, 6));
        for i in 0..41 {
            if let Role::Crashed { from } = plan.role(i) {
                assert!(from <= 9);
            }
        }
        // Every robot is drawn about equally often over many seeds.
        let mut hits = [0u32; 8];
        let one = FaultSpec {
            count: FaultCount::Robots(1),
            kind: FaultKind::Byzantine(ByzantineRule::Away),
        };
        for seed in 0..8000 {
            let plan = FaultPlan::draw(&one, 8, seed);
            hits[(0..8).find(|&i| !plan.is_correct(i)).unwrap()] += 1;
        }
        assert!(hits.iter().all(|&h| (850..1150).contains(&h)), "{hits:?}");
    }

    #[test]
    fn byzantine_rules_point_where_they_say() {
        let pts = [
            DVec2::new(0.0, 0.0),
            DVec2::new(4.0, 0.0),
            DVec2::new(0.0, 2.0),
            DVec2::new(1.0, 1.0),
        ];
        let mut s = Stream::new(1, 2, 3, 4);
        let far = byzantine_move(ByzantineRule::Farthest, &pts, 2, 0.5, &mut s).unwrap();
        assert!((far - (pts[1] - pts[2]).normalize() * 0.5).length() < 1e-12);
        let away = byzantine_move(ByzantineRule::Away, &pts, 0, 1.0, &mut s).unwrap();
        let centroid = DVec2::new(1.25, 0.75);
        assert!((away - (pts[0] - centroid).normalize()).length() < 1e-12);
        let random = byzantine_move(ByzantineRule::Random, &pts, 0, 2.0, &mut s).unwrap();
        assert!((random.length() - 2.0).abs() < 1e-12);
        let still = [DVec2::ONE, DVec2::ONE];
        assert_eq!(
            byzantine_move(ByzantineRule::Away, &still, 0, 1.0, &mut s),
            None
        );
    }
}
