//! How the work of one ASYNC tick is shared between threads: per robot where a tick
//! has many events, each robot changed by one thread, the results then taken in robot
//! order, so that they are those of one thread whatever the thread count.

use rayon::prelude::*;

/// Events in a tick from which its work is worth sharing between threads.
pub(super) const MANY_EVENTS: usize = 256;

/// What a tick's Looks cost (seconds a Look, a running mean of the ticks so far), to
/// share them between threads only where that pays: handing work to a sleeping thread
/// costs several microseconds, and a thread kept busy spinning between a tick's short
/// parallel sections takes the core's other half from this one. At a thousand times
/// the coarse durations a tick has two or three Looks of a few microseconds each: run
/// on one thread (measured in docs/performance.md). The choice changes which thread
/// decides, never a decision.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LookCost {
    /// Seconds of one thread a Look took, on average; 0 until a tick was timed.
    per_look: f64,
}

/// The Looks' work (on one thread) from which a tick shares them between threads.
const SHARED_WORK: f64 = 30e-6;
/// Looks from which a tick shares them, before any was timed.
const SHARED_LOOKS: usize = 8;
/// The weight of the last tick in [`LookCost`]'s running mean.
const WEIGHT: f64 = 1.0 / 16.0;

impl LookCost {
    /// Whether `looks` Looks are worth sharing between the `threads` threads.
    pub(crate) fn share(&self, looks: usize, threads: usize) -> bool {
        if threads < 2 || looks < 2 {
            return false;
        }
        if self.per_look == 0.0 {
            return looks >= SHARED_LOOKS;
        }
        looks as f64 * self.per_look >= SHARED_WORK
    }

    /// `looks` Looks took `seconds`, shared between `threads` threads or not.
    pub(crate) fn record(&mut self, looks: usize, seconds: f64, threads: usize) {
        if looks == 0 {
            return;
        }
        let per_look = seconds * threads as f64 / looks as f64;
        self.per_look = if self.per_look == 0.0 {
            per_look
        } else {
            self.per_look + WEIGHT * (per_look - self.per_look)
        };
    }
}

/// `f` of each robot of `robots`, in their order: on all threads where they are
/// [`MANY_EVENTS`] or more (each reads a robot's clock and position, misses in the
/// caches), else on this one.
pub(super) fn map_events<T: Send>(robots: &[u32], f: impl Fn(u32) -> T + Sync + Send) -> Vec<T> {
    if robots.len() >= MANY_EVENTS {
        robots.par_iter().with_min_len(64).map(|&r| f(r)).collect()
    } else {
        robots.iter().map(|&r| f(r)).collect()
    }
}

/// Robots' entries of a table by robot (their clocks) updated a chunk at a time:
/// `change(i, robot, its entry)` for the robots of the chunk (`i` their place in
/// `robots`), on all threads where they are [`MANY_EVENTS`] or more, then
/// `then(robot, what change gave)` for each, in robot order. `robots` must be strictly
/// ascending, and `change` must read nothing `then` writes: in a chunk of fewer than
/// [`MANY_EVENTS`] robots, each is changed and then taken in turn. The chunks bound what is held
/// between the two (a random start at 10^6 has 10^5 robots Looking on each of the
/// first ticks).
pub(super) fn update_robots<C: Send, T: Send>(
    table: &mut [C],
    robots: &[u32],
    change: impl Fn(usize, u32, &mut C) -> T + Sync + Send,
    mut then: impl FnMut(u32, T),
) {
    assert!(
        robots.windows(2).all(|w| w[0] < w[1]),
        "the robots of an event are ascending"
    );
    let change = &change;
    for (c, chunk) in robots.chunks(UPDATE_CHUNK).enumerate() {
        let first = c * UPDATE_CHUNK;
        if chunk.len() < MANY_EVENTS {
            // Each robot changed and then taken in turn, with no list between (a
            // fine-grained tick has a robot or two).
            for (k, &r) in chunk.iter().enumerate() {
                then(r, change(first + k, r, &mut table[r as usize]));
            }
            continue;
        }
        // Runs of robots, each given the stretch of the table from its first
        // robot to the next run's first: the robots ascending, the stretches are
        // disjoint, and each thread changes entries no other holds.
        let mut runs = Vec::with_capacity(chunk.len().div_ceil(RUN));
        let (mut rest, mut from) = (&mut *table, 0);
        for (k, run) in chunk.chunks(RUN).enumerate() {
            let to = chunk
                .get((k + 1) * RUN)
                .map_or(from + rest.len(), |&r| r as usize);
            let (stretch, after) = std::mem::take(&mut rest).split_at_mut(to - from);
            runs.push((first + k * RUN, run, from, stretch));
            (rest, from) = (after, to);
        }
        // Each run's results written in place, in its own stretch of the output:
        // no lists to join afterwards on one thread.
        let mut out: Vec<Option<T>> = std::iter::repeat_with(|| None).take(chunk.len()).collect();
        out.par_chunks_mut(RUN)
            .zip(runs)
            .for_each(|(slots, (i, run, from, stretch))| {
                for (k, (&r, slot)) in run.iter().zip(slots).enumerate() {
                    *slot = Some(change(i + k, r, &mut stretch[r as usize - from]));
                }
            });
        for (&r, x) in chunk.iter().zip(out) {
            then(r, x.expect("every robot of the chunk changed"));
        }
    }
}

/// Robots [`update_robots`] changes at once...
const UPDATE_CHUNK: usize = 8192;
/// ...in runs of this many robots a task.
const RUN: usize = 64;

/// `rayon::join(a, b)` if `parallel`, else `a` then `b` on this thread.
pub(super) fn join_if<A: Send, B: Send>(
    parallel: bool,
    a: impl FnOnce() -> A + Send,
    b: impl FnOnce() -> B + Send,
) -> (A, B) {
    if parallel {
        rayon::join(a, b)
    } else {
        (a(), b())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::asynchrony::{Phase, Timing};
    use glam::DVec2;

    /// A tick's Looks are shared between threads where their work pays for it: never
    /// on one thread or for one Look, from [`SHARED_LOOKS`] before any was timed, then
    /// where the Looks' work on one thread (a shared tick's time counted on every
    /// thread) reaches [`SHARED_WORK`].
    #[test]
    fn looks_are_shared_where_their_work_pays_for_it() {
        let mut cost = LookCost::default();
        assert!(!cost.share(1000, 1) && !cost.share(1, 2));
        assert!(!cost.share(SHARED_LOOKS - 1, 2) && cost.share(SHARED_LOOKS, 2));
        // Looks of 5 us: six are worth sharing, five are not.
        cost.record(4, 20e-6, 1);
        assert!(cost.share(6, 2) && !cost.share(5, 2));
        // Ticks of cheaper Looks (1 us, shared between two threads: 0.5 us a tick
        // each) bring the mean down: then many more are needed.
        for _ in 0..200 {
            cost.record(10, 5e-6, 2);
        }
        assert!(!cost.share(6, 2) && !cost.share(29, 2) && cost.share(31, 2));
    }

    /// A robot's clock, different for each robot.
    fn clock(r: u32) -> Timing<DVec2> {
        Timing::new(Phase::Idle, 0, u64::from(r) + 1, u64::from(r % 7), 0, None)
    }

    /// Robots updated from several threads, more than a chunk of them, each chunk with
    /// runs of consecutive robots and gaps: each robot of the list changed once with
    /// its own place in the list, the others untouched, and what each change gave
    /// handed back in robot order, whatever the thread count.
    #[test]
    fn robots_updated_at_once_are_changed_each_once_and_reported_in_order() {
        let n = 7 * UPDATE_CHUNK as u32 + 100;
        // Every third robot but a run of consecutive ones, and the last robot: runs of
        // every kind. And a few of them, changed on one thread.
        let many: Vec<u32> = (0..n)
            .filter(|r| r % 3 == 1 || (1000..1500).contains(r) || *r == n - 1)
            .collect();
        assert!(many.len() > 2 * UPDATE_CHUNK);
        let few = many[..MANY_EVENTS - 1].to_vec();
        for (chosen, threads) in [(&many, 1), (&many, 2), (&many, 3), (&few, 2)] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut table: Vec<Timing<DVec2>> = (0..n).map(clock).collect();
            let mut reported = Vec::new();
            pool.install(|| {
                update_robots(
                    &mut table,
                    chosen,
                    |i, r, timing| {
                        timing.looked += 1 + i as u64;
                        (i, r, timing.until)
                    },
                    |r, got| reported.push((r, got)),
                )
            });
            let expected: Vec<(u32, (usize, u32, u64))> = chosen
                .iter()
                .enumerate()
                .map(|(i, &r)| (r, (i, r, u64::from(r) + 1)))
                .collect();
            assert_eq!(reported, expected, "{threads} threads");
            let mut place = vec![None; n as usize];
            for (i, &r) in chosen.iter().enumerate() {
                place[r as usize] = Some(i as u64);
            }
            for r in 0..n {
                let mut want = clock(r);
                if let Some(i) = place[r as usize] {
                    want.looked = 1 + i;
                }
                assert_eq!(table[r as usize], want, "robot {r}, {threads} threads");
            }
        }
    }

    #[test]
    #[should_panic(expected = "ascending")]
    fn robots_listed_twice_are_refused() {
        let mut table: Vec<Timing<DVec2>> = (0..4).map(clock).collect();
        update_robots(&mut table, &[0, 2, 2, 3], |_, _, _| (), |_, _| ());
    }
}
