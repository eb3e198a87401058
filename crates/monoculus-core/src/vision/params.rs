//! [`VisionParams`]: the tolerances of the Look phase.

/// Tolerances of what a robot sees (SPEC section 2). All lengths are absolute.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VisionParams {
    /// Robots closer than this are one point; a robot this close to the observer is not
    /// seen and does not block. Default `1e-9 * b`.
    pub eps_pos: f64,
    /// Largest angle (radians) between two rays that still counts as one ray, so that
    /// the nearer robot blocks the farther. Default `1e-9`.
    pub eps_ang: f64,
    /// OLA: a robot is on a side of an agreed axis only if it lies more than this beyond
    /// the hyperplane through the observer. Default `1e-9 * b`.
    pub eps_axis: f64,
    /// Visibility range V (SPEC 9.2): a robot farther than this is not seen. Default
    /// infinite (unlimited).
    pub range: f64,
    /// Fat robots (SPEC 9.3): every robot is an opaque disc (ball) of this radius that
    /// hides what lies behind it. Default 0 (points).
    pub robot_radius: f64,
}

impl VisionParams {
    /// The defaults of SPEC section 2 for step length `step`.
    pub fn for_step(step: f64) -> Self {
        VisionParams {
            eps_pos: 1e-9 * step,
            eps_ang: 1e-9,
            eps_axis: 1e-9 * step,
            range: f64::INFINITY,
            robot_radius: 0.0,
        }
    }
}

impl VisionParams {
    /// Whether the range is limited.
    pub fn limited(&self) -> bool {
        self.range.is_finite()
    }

    /// Whether robots are discs (balls) of positive radius.
    pub fn fat(&self) -> bool {
        self.robot_radius > 0.0
    }
}

impl Default for VisionParams {
    fn default() -> Self {
        Self::for_step(1.0)
    }
}
