//! [`RobotMemory`]: the termination algorithm's persistent state.

use crate::geometry::AxisFrame;
use crate::observe::Side;

/// The only memory in the paper: 2 bits per axis ("this side of this axis has been seen
/// empty"), plus the robot's fixed local axis frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RobotMemory {
    /// The robot's local frame, fixed for the whole run.
    pub frame: AxisFrame,
    /// Bit `2 * axis + (side == High)`.
    pub bits: u8,
}

impl RobotMemory {
    /// Fresh memory (all bits 0) with a fixed frame.
    pub fn new(frame: AxisFrame) -> Self {
        RobotMemory { frame, bits: 0 }
    }

    fn bit(axis: usize, side: Side) -> u8 {
        1 << (2 * axis + usize::from(side == Side::High))
    }

    /// Sets the bit of (`axis`, `side`).
    pub fn set(&mut self, axis: usize, side: Side) {
        self.bits |= Self::bit(axis, side);
    }

    /// Whether the bit of (`axis`, `side`) is set.
    pub fn get(&self, axis: usize, side: Side) -> bool {
        self.bits & Self::bit(axis, side) != 0
    }

    /// Whether both bits of `axis` are set.
    pub fn axis_done(&self, axis: usize) -> bool {
        self.get(axis, Side::Low) && self.get(axis, Side::High)
    }

    /// Whether all 2d bits are set: the robot has terminated.
    pub fn terminated(&self) -> bool {
        (0..self.frame.dim()).all(|k| self.axis_done(k))
    }
}
