//! [`Roster`]: a set of robots with an item each, listed densely.

const ABSENT: u32 = u32::MAX;

/// Robots with an item each (the robots in mid-move, say): insertion, removal by robot
/// and iteration, each O(1) per robot, over one dense list.
#[derive(Clone, Debug)]
pub(crate) struct Roster<T> {
    items: Vec<(u32, T)>,
    /// Where each robot is in `items` (`ABSENT`: not there).
    slot: Vec<u32>,
}

impl<T> Roster<T> {
    /// No robot, for a swarm of `n`.
    pub(crate) fn new(n: usize) -> Self {
        Roster {
            items: Vec::new(),
            slot: vec![ABSENT; n],
        }
    }

    /// Adds `robot` (not there yet) with its item.
    pub(crate) fn insert(&mut self, robot: u32, item: T) {
        debug_assert_eq!(self.slot[robot as usize], ABSENT);
        self.slot[robot as usize] = self.items.len() as u32;
        self.items.push((robot, item));
    }

    /// Removes `robot`; whether it was there.
    pub(crate) fn remove(&mut self, robot: u32) -> bool {
        self.take(robot).is_some()
    }

    /// Removes `robot`, giving back its item if it was there.
    pub(crate) fn take(&mut self, robot: u32) -> Option<T> {
        let at = std::mem::replace(&mut self.slot[robot as usize], ABSENT);
        if at == ABSENT {
            return None;
        }
        let (_, item) = self.items.swap_remove(at as usize);
        if let Some(&(moved, _)) = self.items.get(at as usize) {
            self.slot[moved as usize] = at;
        }
        Some(item)
    }

    /// The item of `robot`, if it is there.
    #[inline]
    pub(crate) fn get(&self, robot: u32) -> Option<&T> {
        match self.slot[robot as usize] {
            ABSENT => None,
            at => Some(&self.items[at as usize].1),
        }
    }

    /// Removes every robot.
    pub(crate) fn clear(&mut self) {
        for &(robot, _) in &self.items {
            self.slot[robot as usize] = ABSENT;
        }
        self.items.clear();
    }

    /// The robots and their items, in no particular order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &(u32, T)> {
        self.items.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::Roster;

    #[test]
    fn robots_come_and_go() {
        let mut r = Roster::new(5);
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
    }
}
