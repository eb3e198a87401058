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

    /// Asks for what [`Locate::at`] reads of robot `k` once what [`Locate::prefetch`]
    /// asked for has arrived, where one read leads to the next (a robot in mid-move's
    /// entry in a roster; a hint, no effect on results).
    fn prefetch_next(&self, _k: usize) {}
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
    fn prefetch_next(&self, k: usize) {
        (**self).prefetch_next(k)
    }
}
