//! [`TerminationBits`]: the termination algorithm's state.

use crate::observe::Side;

/// The only memory in the paper: 2 bits per axis of the robot's own frame ("this side
/// of this axis has been seen empty"); bit `2 * axis + (side == High)`. The robot's
/// frame, fixed for the whole run, is kept beside it by the engine.
///
/// ```
/// use monoculus_core::algorithms::TerminationBits;
/// use monoculus_core::observe::Side;
///
/// let mut bits = TerminationBits::default();
/// bits.set(0, Side::Low);
/// bits.set(0, Side::High);
/// assert!(bits.axis_done(0) && !bits.terminated(2));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TerminationBits(pub u8);

impl TerminationBits {
    fn bit(axis: usize, side: Side) -> u8 {
        1 << (2 * axis + usize::from(side == Side::High))
    }

    /// Sets the bit of (`axis`, `side`).
    pub fn set(&mut self, axis: usize, side: Side) {
        self.0 |= Self::bit(axis, side);
    }

    /// Whether the bit of (`axis`, `side`) is set.
    pub fn get(&self, axis: usize, side: Side) -> bool {
        self.0 & Self::bit(axis, side) != 0
    }

    /// Whether both bits of `axis` are set.
    pub fn axis_done(&self, axis: usize) -> bool {
        self.get(axis, Side::Low) && self.get(axis, Side::High)
    }

    /// Whether all 2 `dim` bits are set: the robot has terminated.
    pub fn terminated(&self, dim: usize) -> bool {
        (0..dim).all(|k| self.axis_done(k))
    }
}
