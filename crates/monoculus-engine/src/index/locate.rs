//! [`Locate`]: where each robot is, for the index's queries.

/// Where each robot is, read one robot at a time: the positions of one snapshot (a
/// slice), or, under ASYNC, robots at rest at their points and robots in mid-move placed
/// on their segments when asked ([`crate::asynchrony::TickSight`]).
pub trait Locate<P>: Sync {
    /// The position of robot `k`.
    fn at(&self, k: usize) -> P;

    /// Every position as one slice, where they are stored so (what an index built on
    /// first use is built over).
    fn as_slice(&self) -> Option<&[P]> {
        None
    }

    /// Asks for what [`Locate::at`] reads of robot `k` (a hint, no effect on results).
    fn prefetch(&self, _k: usize) {}

    /// The tick the positions are those of, where robots in mid-move are placed on
    /// [paths](super::Path) a moving index was told of ([`SpatialIndex::follow`]):
    /// its queries may then place them there themselves to rule them out.
    ///
    /// [`SpatialIndex::follow`]: super::SpatialIndex::follow
    fn tick(&self) -> Option<u64> {
        None
    }
}

/// Positions given whole, at a tick: those of robots in mid-move on the paths a moving
/// index was told of at that tick (for tests and benchmarks).
#[derive(Clone, Copy, Debug)]
pub struct AtTick<'a, P> {
    /// Every robot's position.
    pub positions: &'a [P],
    /// The tick.
    pub tick: u64,
}

impl<P: Copy + Sync> Locate<P> for AtTick<'_, P> {
    #[inline(always)]
    fn at(&self, k: usize) -> P {
        self.positions[k]
    }

    fn as_slice(&self) -> Option<&[P]> {
        Some(self.positions)
    }

    #[inline(always)]
    fn prefetch(&self, k: usize) {
        self.positions.prefetch(k)
    }

    fn tick(&self) -> Option<u64> {
        Some(self.tick)
    }
}

impl<P: Copy + Sync> Locate<P> for [P] {
    #[inline(always)]
    fn at(&self, k: usize) -> P {
        self[k]
    }

    fn as_slice(&self) -> Option<&[P]> {
        Some(self)
    }

    #[inline(always)]
    fn prefetch(&self, k: usize) {
        if let Some(p) = self.get(k) {
            super::prefetch(p);
        }
    }
}

impl<P, T: Locate<P> + ?Sized> Locate<P> for &T {
    #[inline(always)]
    fn at(&self, k: usize) -> P {
        (**self).at(k)
    }

    fn as_slice(&self) -> Option<&[P]> {
        (**self).as_slice()
    }

    #[inline(always)]
    fn prefetch(&self, k: usize) {
        (**self).prefetch(k)
    }

    #[inline(always)]
    fn tick(&self) -> Option<u64> {
        (**self).tick()
    }
}
