//! [`Roster`]: a set of robots with an item each, listed densely.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use crate::index::prefetch;

const ABSENT: u32 = u32::MAX;

/// Robots with an item each (the robots in mid-move, say): insertion, removal by robot
/// and iteration, each O(1) per robot, over one dense list. Where each robot is in the
/// list is kept in an array over the swarm ([`Roster::new`]: the fastest to look up,
/// 4 bytes a robot), or, for rosters that stay small, in a map ([`Roster::sparse`]).
#[derive(Clone, Debug)]
pub(crate) struct Roster<T> {
    items: Vec<(u32, T)>,
    slot: Slots,
}

/// Where each robot is in a roster's list.
#[derive(Clone, Debug)]
enum Slots {
    /// By robot (`ABSENT`: not there).
    Dense(Vec<u32>),
    /// The robots there.
    Sparse(HashMap<u32, u32, BuildHasherDefault<IdHasher>>),
}

/// A hasher for robot ids: a multiplicative hash (ids are small integers, spread over
/// the table by the high bits of the product).
#[derive(Default)]
struct IdHasher(u64);

impl Hasher for IdHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0.rotate_left(8) ^ u64::from(b)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        }
    }

    fn write_u32(&mut self, i: u32) {
        self.0 = u64::from(i).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

impl Slots {
    #[inline]
    fn get(&self, robot: u32) -> u32 {
        match self {
            Slots::Dense(v) => v[robot as usize],
            Slots::Sparse(m) => m.get(&robot).copied().unwrap_or(ABSENT),
        }
    }

    #[inline]
    fn set(&mut self, robot: u32, at: u32) {
        match self {
            Slots::Dense(v) => v[robot as usize] = at,
            Slots::Sparse(m) => {
                if at == ABSENT {
                    m.remove(&robot);
                } else {
                    m.insert(robot, at);
                }
            }
        }
    }
}

impl<T> Roster<T> {
    /// No robot, for a swarm of `n`.
    pub(crate) fn new(n: usize) -> Self {
        Roster {
            items: Vec::new(),
            slot: Slots::Dense(vec![ABSENT; n]),
        }
    }

    /// No robot; the robots there are kept in a map, for a roster that holds few of
    /// the swarm's robots at a time.
    pub(crate) fn sparse() -> Self {
        Roster {
            items: Vec::new(),
            slot: Slots::Sparse(HashMap::default()),
        }
    }

    /// Adds `robot` (not there yet) with its item.
    pub(crate) fn insert(&mut self, robot: u32, item: T) {
        debug_assert_eq!(self.slot.get(robot), ABSENT);
        self.slot.set(robot, self.items.len() as u32);
        self.items.push((robot, item));
    }

    /// Gives `robot` its item, in place if it is there, else added.
    pub(crate) fn set(&mut self, robot: u32, item: T) {
        match self.slot.get(robot) {
            ABSENT => self.insert(robot, item),
            at => self.items[at as usize].1 = item,
        }
    }

    /// Removes `robot`; whether it was there.
    pub(crate) fn remove(&mut self, robot: u32) -> bool {
        self.take(robot).is_some()
    }

    /// Removes `robot`, giving back its item if it was there.
    pub(crate) fn take(&mut self, robot: u32) -> Option<T> {
        let at = self.slot.get(robot);
        if at == ABSENT {
            return None;
        }
        self.slot.set(robot, ABSENT);
        let (_, item) = self.items.swap_remove(at as usize);
        if let Some(&(moved, _)) = self.items.get(at as usize) {
            self.slot.set(moved, at);
        }
        Some(item)
    }

    /// The item of `robot`, if it is there.
    #[inline]
    pub(crate) fn get(&self, robot: u32) -> Option<&T> {
        match self.slot.get(robot) {
            ABSENT => None,
            at => Some(&self.items[at as usize].1),
        }
    }

    /// Asks for where `robot` is in the list (a hint, no effect on results; nothing for
    /// a roster kept in a map).
    #[inline]
    pub(crate) fn prefetch_slot(&self, robot: u32) {
        if let Slots::Dense(v) = &self.slot
            && let Some(at) = v.get(robot as usize)
        {
            prefetch(at);
        }
    }

    /// Asks for the item of `robot`, if it is there (a hint, no effect on results: reads
    /// where it is in the list, which [`Roster::prefetch_slot`] asks for).
    #[inline]
    pub(crate) fn prefetch_item(&self, robot: u32) {
        if let Slots::Dense(v) = &self.slot
            && let Some(item) = v
                .get(robot as usize)
                .and_then(|&at| self.items.get(at as usize))
        {
            prefetch(item);
        }
    }

    /// Removes every robot.
    pub(crate) fn clear(&mut self) {
        match &mut self.slot {
            Slots::Dense(v) => {
                for &(robot, _) in &self.items {
                    v[robot as usize] = ABSENT;
                }
            }
            Slots::Sparse(m) => m.clear(),
        }
        self.items.clear();
    }

    /// The robots and their items, in no particular order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &(u32, T)> {
        self.items.iter()
    }

    /// The same, as a slice.
    pub(crate) fn as_slice(&self) -> &[(u32, T)] {
        &self.items
    }
}

#[cfg(test)]
mod tests {
    use super::Roster;

    #[test]
    fn robots_come_and_go() {
        for sparse in [false, true] {
            robots_come_and_go_in(if sparse {
                Roster::sparse()
            } else {
                Roster::new(5)
            });
        }
    }

    fn robots_come_and_go_in(mut r: Roster<char>) {
        r.insert(3, 'a');
        r.insert(1, 'b');
        r.insert(4, 'c');
        assert!(r.remove(3));
        assert!(!r.remove(3));
        r.insert(0, 'd');
        let mut now: Vec<_> = r.iter().copied().collect();
        now.sort_unstable();
        assert_eq!(now, vec![(0, 'd'), (1, 'b'), (4, 'c')]);
        assert!(r.remove(4) && r.remove(0) && r.remove(1));
        r.clear();
        assert_eq!(r.iter().count(), 0);
        r.insert(1, 'e');
        assert_eq!(r.iter().count(), 1);
        // Set: in place where there, else added.
        r.set(1, 'f');
        r.set(2, 'g');
        let mut now: Vec<_> = r.iter().copied().collect();
        now.sort_unstable();
        assert_eq!(now, vec![(1, 'f'), (2, 'g')]);
        assert_eq!(r.get(1), Some(&'f'));
    }
}
