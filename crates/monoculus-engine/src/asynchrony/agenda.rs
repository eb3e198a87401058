//! [`Agenda`]: the ASYNC phase ends to come, by tick.

use std::collections::BTreeMap;

/// The robots whose phase ends at each tick to come: the next ticks in a ring of slots,
/// later ones in a map. A tick's robots come out in ascending order.
#[derive(Clone, Debug)]
pub(super) struct Agenda {
    /// The first entry of each slot's list: the robots of the pending phase ends at
    /// ticks `now..now + span`, those of tick `t` in slot `t % span` (`span` =
    /// `heads.len()`, a power of two), or [`NONE`]. Scheduling one costs a push. The
    /// ring starts at [`NEAR`] slots when first needed and doubles, up to [`FAR`], when
    /// a phase ends beyond it, so that it spans the durations the run draws: a robot is
    /// scheduled three times a cycle, and a map's search each time was 2% of a coarse
    /// run and 4-5% of one at 1000 times the coarse durations.
    heads: Vec<u32>,
    /// The slots' lists, linked through one pool: (robot, next entry of its slot or
    /// [`NONE`]). At fine durations a slot holds a robot or two, and a list of its own
    /// per slot cost a read of its header and of its buffer, each a miss in the
    /// caches, at every robot scheduled and taken.
    entries: Vec<(u32, u32)>,
    /// The first free entry of the pool (the free ones linked as the lists are).
    free: u32,
    /// A bit per slot, set where the slot holds robots: the next tick with robots is
    /// found a word (64 ticks) at a time, however sparse the ticks.
    occupied: Vec<u64>,
    /// Robots listed in the ring.
    in_near: usize,
    /// The robots of the pending phase ends further ahead than the ring, by tick (a
    /// calendar: taking a tick costs one map operation per tick, not a heap operation
    /// per robot). A tick's robots may be in both: those scheduled before the ring
    /// reached it.
    later: BTreeMap<u64, Vec<u32>>,
    /// Emptied lists of `later`, reused.
    spare: Vec<Vec<u32>>,
    /// A bit per robot, all clear between ticks: where a tick's robots are put in
    /// order (see [`ascending`]).
    marks: Vec<u64>,
}

/// No entry: the end of a list.
const NONE: u32 = u32::MAX;

impl Default for Agenda {
    fn default() -> Self {
        Agenda {
            heads: Vec::new(),
            entries: Vec::new(),
            free: NONE,
            occupied: Vec::new(),
            in_near: 0,
            later: BTreeMap::new(),
            spare: Vec::new(),
            marks: Vec::new(),
        }
    }
}

/// Ticks ahead of the current one whose phase ends the [`Agenda`] lists by slot, at
/// first...
const NEAR: u64 = 64;
/// ...and at most (a ring of 2^14 slots, 64 KiB of heads): phases that end further
/// ahead wait in a map.
const FAR: u64 = 1 << 14;

/// The longest list of robots the [`Agenda`] keeps for reuse.
const SPARE_CAPACITY: usize = 1024;

impl Agenda {
    /// Schedules robot `robot`'s next phase end at `tick`, the current tick `now` or
    /// later.
    pub fn schedule(&mut self, now: u64, tick: u64, robot: u32) {
        debug_assert!(tick >= now, "a phase ends at the current tick or later");
        let ahead = tick - now;
        if ahead >= self.heads.len() as u64 && ahead < FAR {
            self.widen(now, ahead + 1);
        }
        let span = self.heads.len() as u64;
        if ahead < span {
            let slot = (tick & (span - 1)) as usize;
            let entry = (robot, self.heads[slot]);
            self.heads[slot] = if self.free == NONE {
                self.entries.push(entry);
                (self.entries.len() - 1) as u32
            } else {
                let e = self.free;
                self.free = self.entries[e as usize].1;
                self.entries[e as usize] = entry;
                e
            };
            self.occupied[slot / 64] |= 1 << (slot % 64);
            self.in_near += 1;
            return;
        }
        let spare = &mut self.spare;
        self.later
            .entry(tick)
            .or_insert_with(|| spare.pop().unwrap_or_default())
            .push(robot);
    }

    /// Makes the ring span at least `ticks` ticks ahead of the current one (a power of
    /// two from [`NEAR`] to [`FAR`]), each slot's list moved to its tick's new slot.
    fn widen(&mut self, now: u64, ticks: u64) {
        let old = self.heads.len() as u64;
        let span = ticks.next_power_of_two().clamp(NEAR, FAR).max(old);
        if span == old {
            return;
        }
        let mut heads = vec![NONE; span as usize];
        let mut occupied = vec![0u64; (span as usize).div_ceil(64)];
        for (slot, &head) in self.heads.iter().enumerate() {
            if head == NONE {
                continue;
            }
            // The slot's tick: the one of `now..now + old` it stands for.
            let tick = now + (slot as u64).wrapping_sub(now) % old;
            let to = (tick & (span - 1)) as usize;
            occupied[to / 64] |= 1 << (to % 64);
            heads[to] = head;
        }
        self.heads = heads;
        self.occupied = occupied;
    }

    /// The first tick at or after the current one with robots in the ring.
    fn next_near(&self, now: u64) -> Option<u64> {
        if self.in_near == 0 {
            return None;
        }
        let span = self.heads.len();
        let start = (now as usize) & (span - 1);
        let words = self.occupied.len();
        // The words from the current slot's on, around the ring and back to it (its
        // bits before the current slot last: they stand for the ticks furthest ahead).
        for k in 0..=words {
            let w = (start / 64 + k) % words;
            let mut bits = self.occupied[w];
            if k == 0 {
                bits &= u64::MAX << (start % 64);
            } else if k == words {
                bits &= !(u64::MAX << (start % 64));
            }
            if bits != 0 {
                let slot = w * 64 + bits.trailing_zeros() as usize;
                return Some(now + ((slot + span - start) % span) as u64);
            }
        }
        unreachable!("robots are listed in the ring")
    }

    /// The next tick with phase ends at or after `now`, its robots put in `due` in
    /// ascending order (`n`: the swarm's size); `None` if nothing is scheduled.
    pub fn take_next(&mut self, now: u64, n: usize, due: &mut Vec<u32>) -> Option<u64> {
        let near = self.next_near(now);
        let far = self.later.first_key_value().map(|(&t, _)| t);
        let tick = near.into_iter().chain(far).min()?;
        due.clear();
        // The tick's robots in the ring's slot, in the map, or both (those scheduled
        // before it came near).
        if far == Some(tick) {
            let list = self.later.pop_first().expect("the first tick").1;
            due.extend_from_slice(&list);
            self.recycle(list);
        }
        if near == Some(tick) {
            let slot = (tick as usize) & (self.heads.len() - 1);
            let head = std::mem::replace(&mut self.heads[slot], NONE);
            self.occupied[slot / 64] &= !(1 << (slot % 64));
            // The list's robots, its entries handed back to the free ones.
            let mut e = head;
            loop {
                let (robot, next) = self.entries[e as usize];
                due.push(robot);
                self.in_near -= 1;
                if next == NONE {
                    self.entries[e as usize].1 = self.free;
                    break;
                }
                e = next;
            }
            self.free = head;
        }
        ascending(due, &mut self.marks, n);
        Some(tick)
    }

    /// Calls `f(tick, robot)` for each phase end scheduled after the current tick `now`
    /// and at or before `last`, in no particular order; nothing is taken.
    pub fn peek(&self, now: u64, last: u64, mut f: impl FnMut(u64, u32)) {
        let span = self.heads.len() as u64;
        if self.in_near > 0 {
            for tick in now + 1..=last.min(now + span - 1) {
                let slot = (tick & (span - 1)) as usize;
                let mut e = self.heads[slot];
                while e != NONE {
                    let (robot, next) = self.entries[e as usize];
                    f(tick, robot);
                    e = next;
                }
            }
        }
        if last > now {
            for (&tick, robots) in self.later.range(now + 1..=last) {
                robots.iter().for_each(|&r| f(tick, r));
            }
        }
    }

    /// Keeps an emptied list of the map for reuse, but not the long ones of a crowded
    /// tick (a random start puts a tenth of the swarm on each of the first ticks):
    /// kept, they would hold several times the swarm's worth of room.
    fn recycle(&mut self, mut list: Vec<u32>) {
        if list.capacity() <= SPARE_CAPACITY {
            list.clear();
            self.spare.push(list);
        }
    }
}

/// `robots` (distinct robots of a swarm of `n`) put in ascending order. A crowded
/// tick's list holds a good part of the swarm (at coarse durations a tenth): marked in
/// `marks`, a bit per robot, and read back in order, about ten times cheaper than a
/// sort; a short list is sorted. `marks` is left clear.
fn ascending(robots: &mut [u32], marks: &mut Vec<u64>, n: usize) {
    let words = n.div_ceil(64);
    // Reading the marks costs a word per 64 robots of the swarm, sorting about
    // log2(len) comparisons a robot.
    if robots.len() < 64 || robots.len() * 8 < words || words == 0 {
        robots.sort_unstable();
        return;
    }
    if marks.len() < words {
        marks.resize(words, 0);
    }
    let mut distinct = true;
    for &r in robots.iter() {
        let (w, bit) = (r as usize / 64, 1u64 << (r % 64));
        distinct &= marks[w] & bit == 0;
        marks[w] |= bit;
    }
    if !distinct {
        // A robot listed twice (the agenda never does so): sorted, the marks cleared.
        for &r in robots.iter() {
            marks[r as usize / 64] = 0;
        }
        robots.sort_unstable();
        return;
    }
    let mut at = 0;
    for (w, word) in marks[..words].iter_mut().enumerate() {
        let mut bits = std::mem::take(word);
        while bits != 0 {
            robots[at] = (w * 64) as u32 + bits.trailing_zeros();
            at += 1;
            bits &= bits - 1;
        }
    }
    debug_assert_eq!(at, robots.len());
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::Agenda;
    use crate::asynchrony::AsyncClock;

    /// The calendar gives ticks in order, each with its robots ascending (also robots
    /// scheduled out of order, twice at one tick, or at the tick being processed), and
    /// reports when nothing is left.
    #[test]
    fn the_agenda_gives_ticks_in_order_with_robots_ascending() {
        let mut clock = AsyncClock::new(8);
        for (tick, robot) in [(5, 3), (2, 7), (5, 1), (9, 0), (2, 2), (5, 6)] {
            clock.schedule(tick, robot);
        }
        assert!(clock.advance());
        assert_eq!((clock.tick, clock.due.clone()), (2, vec![2, 7]));
        // Scheduled during tick 2 for tick 2 itself: the next tick taken is 2 again.
        clock.schedule(2, 4);
        clock.schedule(9, 5);
        assert!(clock.advance());
        assert_eq!((clock.tick, clock.due.clone()), (2, vec![4]));
        assert!(clock.advance());
        assert_eq!((clock.tick, clock.due.clone()), (5, vec![1, 3, 6]));
        assert!(clock.advance());
        assert_eq!((clock.tick, clock.due.clone()), (9, vec![0, 5]));
        assert!(!clock.advance());
        assert!(clock.due.is_empty());
    }

    /// A tick whose slot lies before the current tick's in the ring (it wrapped around)
    /// is found, in the first ring and in a widened one, and widening keeps every
    /// robot at its tick.
    #[test]
    fn the_ring_finds_the_ticks_that_wrapped_around() {
        let mut agenda = Agenda::default();
        let mut due = Vec::new();
        agenda.schedule(0, 10, 0);
        assert_eq!(agenda.take_next(0, 8, &mut due), Some(10));
        // The first ring spans 64 ticks: tick 71 is slot 7, before tick 10's slot.
        agenda.schedule(10, 71, 1);
        assert_eq!(agenda.take_next(10, 8, &mut due), Some(71));
        assert_eq!(due, vec![1]);
        // Within 64 ticks, then far enough to widen the ring past them.
        agenda.schedule(71, 71 + 60, 2);
        agenda.schedule(71, 71 + 5000, 3);
        agenda.schedule(71, 71 + 3, 4);
        assert_eq!(agenda.heads.len(), 8192);
        let mut now = 71;
        for (tick, robot) in [(74, 4), (131, 2), (5071, 3)] {
            assert_eq!(agenda.take_next(now, 8, &mut due), Some(tick));
            assert_eq!(due, vec![robot]);
            now = tick;
        }
        assert_eq!(agenda.take_next(now, 8, &mut due), None);
    }

    /// The agenda, near ticks by slot and far ones in a map, against a plain map of
    /// sorted lists: the same ticks with the same robots, and the same robots seen
    /// ahead of their ticks ([`AsyncClock::peek`]), over random schedules of
    /// the current tick, near ones, the first ring's edge (63, 64 and 65 ahead), ticks
    /// that widen the ring, the widest ring's edge and beyond it, many robots a tick
    /// and few, some robots listed twice.
    #[test]
    fn the_agenda_near_and_far_is_a_map_of_ticks() {
        use monoculus_core::rng::Stream;
        let n = 3000u32;
        let mut stream = Stream::new(11, 0, 0, 0);
        let mut clock = AsyncClock::new(n as usize);
        let mut reference: BTreeMap<u64, Vec<u32>> = BTreeMap::new();
        let mut now = 0u64;
        let mut ticks = 0;
        for step in 0..4000 {
            let burst = if step % 97 == 0 {
                1500
            } else {
                1 + stream.below(20)
            };
            for _ in 0..burst {
                let ahead = match stream.below(12) {
                    0 => 0,
                    1 => 63 + stream.below(3) as u64,
                    2 => 64 + stream.below(2000) as u64,
                    3 if step > 2000 => super::FAR - 1 + stream.below(3) as u64,
                    4 if step > 1000 => stream.below(3 * super::FAR as usize) as u64,
                    _ => 1 + stream.below(12) as u64,
                };
                let robot = stream.below(n as usize) as u32;
                clock.schedule(now + ahead, robot);
                reference.entry(now + ahead).or_default().push(robot);
            }
            // What is scheduled after the current tick up to a tick near, at the ring's
            // edge or beyond it, without taking it.
            if step % 7 == 0 {
                let last = clock.tick + 1 + stream.below(3 * super::FAR as usize) as u64;
                let mut peeked = Vec::new();
                clock.peek(last, |t, r| peeked.push((t, r)));
                peeked.sort_unstable();
                let mut listed: Vec<(u64, u32)> = reference
                    .range(clock.tick + 1..=last)
                    .flat_map(|(&t, robots)| robots.iter().map(move |&r| (t, r)))
                    .collect();
                listed.sort_unstable();
                assert_eq!(peeked, listed, "step {step}: peeked up to {last}");
            }
            for _ in 0..1 + stream.below(3) {
                let expected = reference.pop_first().map(|(t, mut robots)| {
                    robots.sort_unstable();
                    (t, robots)
                });
                let got = clock.advance().then(|| (clock.tick, clock.due.clone()));
                assert_eq!(got, expected, "step {step}");
                if let Some((t, _)) = expected {
                    now = t;
                    ticks += 1;
                }
            }
        }
        while let Some((t, mut robots)) = reference.pop_first() {
            robots.sort_unstable();
            assert!(clock.advance());
            assert_eq!((clock.tick, clock.due.clone()), (t, robots));
        }
        assert!(!clock.advance(), "nothing left");
        assert!(ticks > 3000, "{ticks} ticks");
    }

    /// A tick's robots are put in order by their marks or by a sort, whichever is
    /// cheaper: the order of a sort either way, for lists short and long, sparse and
    /// dense in the swarm, with robots listed twice, and the marks left clear.
    #[test]
    fn a_ticks_robots_are_put_in_ascending_order_whatever_the_way() {
        use monoculus_core::rng::Stream;
        let mut marks = Vec::new();
        for (n, len, twice) in [
            (10, 5, false),
            (1000, 63, false),
            (1000, 64, false),
            (1000, 900, false),
            (100_000, 100, false),
            (100_000, 1500, false),
            (100_000, 60_000, false),
            (1000, 700, true),
            (1000, 50, true),
        ] {
            let mut stream = Stream::new(7, 1, n as u64, len as u64);
            let mut pool: Vec<u32> = (0..n as u32).collect();
            for i in 0..len {
                let j = i + stream.below(n - i);
                pool.swap(i, j);
            }
            let mut robots = pool[..len].to_vec();
            if twice {
                robots.push(robots[len / 2]);
            }
            let mut expected = robots.clone();
            expected.sort_unstable();
            super::ascending(&mut robots, &mut marks, n);
            assert_eq!(robots, expected, "n {n}, {len} robots, one twice: {twice}");
            assert!(marks.iter().all(|&w| w == 0), "marks left clear");
        }
        assert!(!marks.is_empty(), "the marks were used");
    }
}
