//! Error models (SPEC section 7): what robots perceive wrongly and how moves go wrong.
//! All off by default.

use crate::geometry::Point;
use crate::rng::Stream;

/// Observation errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObservationErrors {
    /// Probability that a far/near bit is wrong when the distance lies in
    /// [c(1 - w), c(1 + w)].
    pub flip_p: f64,
    /// The relative half-width w of that window.
    pub flip_window: f64,
    /// Standard deviation (radians) of the angular noise on every perceived direction;
    /// OLA robots also see the agreed axes tilted by one such angle per activation.
    pub angle_sigma: f64,
}

impl ObservationErrors {
    /// No errors.
    pub const NONE: ObservationErrors = ObservationErrors {
        flip_p: 0.0,
        flip_window: 0.0,
        angle_sigma: 0.0,
    };

    /// Whether any error is on.
    pub fn any(&self) -> bool {
        self.flip_p > 0.0 || self.angle_sigma > 0.0
    }
}

impl Default for ObservationErrors {
    fn default() -> Self {
        Self::NONE
    }
}

/// What one activation perceives wrongly. Each perceived quantity draws from its own
/// stream keyed by the activation's key and the target robot, so the same target is
/// perceived the same way however often, and in whatever order, it is asked about.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Perception {
    errors: ObservationErrors,
    key: u64,
}

const FLIP: u64 = 1;
const DIRECTION: u64 = 2;
const TILT: u64 = 3;

impl Perception {
    /// Error-free perception.
    pub const EXACT: Perception = Perception {
        errors: ObservationErrors::NONE,
        key: 0,
    };

    /// Perception with `errors`, keyed by one draw from the activation's stream (no draw
    /// when errors are off, so error-free runs are unchanged).
    pub fn new(errors: ObservationErrors, stream: &mut Stream) -> Self {
        if errors.any() {
            Perception {
                errors,
                key: stream.next_u64(),
            }
        } else {
            Self::EXACT
        }
    }

    /// The perceived far bit of target `j` at true distance `distance`.
    pub fn far(&self, j: usize, distance: f64, locality: f64) -> bool {
        let far = distance > locality;
        let e = &self.errors;
        if e.flip_p > 0.0
            && distance > locality * (1.0 - e.flip_window)
            && distance <= locality * (1.0 + e.flip_window)
            && Stream::new(self.key, FLIP, j as u64, 0).bernoulli(e.flip_p)
        {
            !far
        } else {
            far
        }
    }

    /// Robots at this distance or closer are never perceived far.
    pub fn far_threshold(&self, locality: f64) -> f64 {
        if self.errors.flip_p > 0.0 {
            locality * (1.0 - self.errors.flip_window)
        } else {
            locality
        }
    }

    /// The perceived direction of target `j` (true unit direction `dir`).
    pub fn direction<P: Point>(&self, j: usize, dir: P) -> P {
        if self.errors.angle_sigma > 0.0 {
            P::perturb_direction(
                dir,
                self.errors.angle_sigma,
                &mut Stream::new(self.key, DIRECTION, j as u64, 0),
            )
        } else {
            dir
        }
    }

    /// The tilt of the agreed axes as this activation perceives them (a rotation).
    pub fn tilt<P: Point>(&self) -> Option<P::Frame> {
        (self.errors.angle_sigma > 0.0).then(|| {
            P::random_tilt(
                self.errors.angle_sigma,
                &mut Stream::new(self.key, TILT, 0, 0),
            )
        })
    }
}

/// A distribution of step-length factors; in configs `{ kind = "fixed", value = 1.0 }`,
/// `{ kind = "uniform", min = 0.8, max = 1.2 }` or `{ kind = "normal", mean = 1, sd = 0.1 }`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum FactorDist {
    /// Always this factor.
    Fixed {
        /// The factor.
        value: f64,
    },
    /// Uniform in [min, max].
    Uniform {
        /// Lower bound.
        min: f64,
        /// Upper bound.
        max: f64,
    },
    /// Normal, clamped at 0.
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation.
        sd: f64,
    },
}

impl Default for FactorDist {
    fn default() -> Self {
        FactorDist::Fixed { value: 1.0 }
    }
}

impl FactorDist {
    /// One draw.
    pub fn sample(&self, stream: &mut Stream) -> f64 {
        match *self {
            FactorDist::Fixed { value } => value,
            FactorDist::Uniform { min, max } => stream.uniform_in(min, max),
            FactorDist::Normal { mean, sd } => (mean + sd * stream.normal()).max(0.0),
        }
    }
}

/// Movement errors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MovementErrors {
    /// Factor applied to the length of every move.
    pub step_factor: FactorDist,
    /// Non-rigid moves: the adversary stops a move after at least this distance
    /// (uniformly between it and the full length); `None`: rigid moves.
    pub non_rigid: Option<f64>,
}

impl MovementErrors {
    /// Rigid, exact moves.
    pub const NONE: MovementErrors = MovementErrors {
        step_factor: FactorDist::Fixed { value: 1.0 },
        non_rigid: None,
    };

    /// Whether any error is on.
    pub fn any(&self) -> bool {
        *self != Self::NONE
    }

    /// The displacement actually travelled for the intended displacement `d`.
    pub fn apply<P: Point>(&self, d: P, stream: &mut Stream) -> P {
        if !self.any() {
            return d;
        }
        let mut d = d * self.step_factor.sample(stream);
        if let Some(delta_min) = self.non_rigid {
            let len = d.length();
            if len > delta_min {
                d = d * (stream.uniform_in(delta_min, len) / len);
            }
        }
        d
    }
}

impl Default for MovementErrors {
    fn default() -> Self {
        Self::NONE
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn flips_only_inside_the_window() {
        let errors = ObservationErrors {
            flip_p: 1.0,
            flip_window: 0.1,
            angle_sigma: 0.0,
        };
        let p = Perception::new(errors, &mut Stream::new(1, 1, 1, 1));
        assert!(
            p.far(3, 1.9, 2.0),
            "near, inside the window: flipped to far"
        );
        assert!(
            !p.far(3, 2.1, 2.0),
            "far, inside the window: flipped to near"
        );
        assert!(!p.far(3, 1.7, 2.0) && p.far(3, 2.3, 2.0), "outside: exact");
        assert_eq!(p.far_threshold(2.0), 1.8);
    }

    #[test]
    fn perception_is_consistent_per_target_and_noise_has_the_right_size() {
        let errors = ObservationErrors {
            flip_p: 0.0,
            flip_window: 0.0,
            angle_sigma: 0.1,
        };
        let mut angles = vec![];
        for k in 0..2000 {
            let p = Perception::new(errors, &mut Stream::new(k, 1, 1, 1));
            let d = p.direction(7, DVec2::X);
            assert_eq!(d, p.direction(7, DVec2::X));
            assert!((d.length() - 1.0).abs() < 1e-12);
            angles.push(d.y.atan2(d.x));
        }
        let sd = (angles.iter().map(|a| a * a).sum::<f64>() / angles.len() as f64).sqrt();
        assert!((sd - 0.1).abs() < 0.01, "{sd}");
        assert_eq!(
            Perception::new(ObservationErrors::NONE, &mut Stream::new(0, 0, 0, 0)),
            Perception::EXACT
        );
    }

    #[test]
    fn non_rigid_moves_stop_between_delta_min_and_the_target() {
        let m = MovementErrors {
            step_factor: FactorDist::Fixed { value: 1.0 },
            non_rigid: Some(0.3),
        };
        let mut s = Stream::new(2, 2, 2, 2);
        for _ in 0..500 {
            let d = m.apply(DVec2::new(1.0, 0.0), &mut s);
            assert!(d.x >= 0.3 && d.x <= 1.0 && d.y == 0.0);
            assert_eq!(
                m.apply(DVec2::new(0.2, 0.0), &mut s),
                DVec2::new(0.2, 0.0),
                "short moves complete"
            );
        }
        let f = MovementErrors {
            step_factor: FactorDist::Uniform { min: 0.5, max: 1.5 },
            non_rigid: None,
        };
        let mean = (0..4000).map(|_| f.apply(DVec2::X, &mut s).x).sum::<f64>() / 4000.0;
        assert!((mean - 1.0).abs() < 0.03, "{mean}");
        assert_eq!(MovementErrors::NONE.apply(DVec2::X, &mut s), DVec2::X);
    }
}
