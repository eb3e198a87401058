//! [`Stale`]: the robots that moved since a grid was built.

/// Robots that moved since a grid was built (to points it [covers](SegmentGrid::covers)):
/// their bins are out of date, so queries skip them in the bins, where that matters,
/// and test them one by one at their current positions. A set of robot indices: a
/// list, and a bit per robot.
#[derive(Debug, Default)]
pub struct Stale {
    list: Vec<u32>,
    bits: Vec<u64>,
}

impl Stale {
    /// No robot, for a swarm of `n`.
    pub fn none(n: usize) -> Self {
        Stale {
            list: Vec::new(),
            bits: vec![0; n.div_ceil(64)],
        }
    }

    /// Empties the set, now for a swarm of `n`, in the memory it has.
    pub fn empty(&mut self, n: usize) {
        for &k in &self.list {
            if let Some(w) = self.bits.get_mut(k as usize / 64) {
                *w = 0;
            }
        }
        self.list.clear();
        self.bits.resize(n.div_ceil(64), 0);
    }

    /// Whether robot `k` is in the set.
    #[inline]
    pub fn contains(&self, k: usize) -> bool {
        self.bits
            .get(k / 64)
            .is_some_and(|w| w & (1u64 << (k % 64)) != 0)
    }

    /// Adds robot `k` (which must be below the swarm size given to [`Stale::none`]).
    pub fn insert(&mut self, k: usize) {
        if !self.contains(k) {
            self.bits[k / 64] |= 1u64 << (k % 64);
            self.list.push(k as u32);
        }
    }

    /// How many robots are in the set.
    pub fn len(&self) -> usize {
        self.list.len()
    }

    /// Whether the set is empty.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// The robots, in the order they were added.
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.list.iter().map(|&k| k as usize)
    }
}
