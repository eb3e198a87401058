//! [`Path`]: a robot's move, where it is at each tick.

use super::IndexPoint;

/// A move from `from` to `to`, started at tick `since` and ending at `until`: the
/// robot goes along the segment at constant speed (ASYNC's Move phase).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Path<P> {
    /// Where the move starts.
    pub from: P,
    /// Where it ends.
    pub to: P,
    /// The tick it starts at.
    pub since: u64,
    /// The tick it ends at.
    pub until: u64,
}

impl<P: IndexPoint> Path<P> {
    /// Where the robot is at `tick` (at or after the start): the fraction of the move's
    /// ticks elapsed along the segment, and `from` for a move of no ticks.
    #[inline]
    pub fn at(&self, tick: u64) -> P {
        if self.until <= self.since {
            return self.from;
        }
        let f = (tick.min(self.until) - self.since) as f64 / (self.until - self.since) as f64;
        self.from + (self.to - self.from) * f
    }
}
