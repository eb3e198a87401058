//! How the work of one ASYNC tick is shared between threads: per robot where a tick
//! has many events, each robot changed by one thread, the results then taken in robot
//! order, so that they are those of one thread whatever the thread count.

use bevy_ecs::prelude::*;
use bevy_ecs::query::QueryData;
use rayon::prelude::*;

use super::RobotEntities;

/// Events in a tick from which its work is worth sharing between threads.
pub(super) const MANY_EVENTS: usize = 256;

/// `f` of each robot of `robots`, in their order: on all threads where they are
/// [`MANY_EVENTS`] or more (each reads a robot's clock and position, misses in the
/// caches), else on this one.
pub(super) fn map_events<T: Send>(robots: &[u32], f: impl Fn(u32) -> T + Sync + Send) -> Vec<T> {
    map_indexed(robots.len(), |i| f(robots[i]))
}

/// `f(i)` for `i` in `0..n`, in order: on all threads where `n` is [`MANY_EVENTS`] or
/// more, else on this one.
fn map_indexed<T: Send>(n: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
    if n >= MANY_EVENTS {
        (0..n).into_par_iter().with_min_len(64).map(f).collect()
    } else {
        (0..n).map(f).collect()
    }
}

/// Robots updated a chunk at a time: `change(i, robot, its components)` for the
/// robots of the chunk (`i` their place in `robots`), on all threads where they are
/// [`MANY_EVENTS`] or more, then `then(robot, what change gave)` for each, in robot
/// order. `robots` must be strictly ascending. The chunks bound what is held between
/// the two (a random start at 10^6 has 10^5 robots Looking on each of the first ticks).
pub(super) fn update_robots<'s, D: QueryData, T: Send>(
    query: &mut Query<'_, 's, D>,
    entities: &RobotEntities,
    robots: &[u32],
    change: impl Fn(usize, u32, D::Item<'_, 's>) -> T + Sync + Send,
    mut then: impl FnMut(u32, T),
) where
    for<'a> &'a Query<'a, 's, D>: Send,
{
    // Held exclusively here (`&mut`), and each robot once, so each call of `change`
    // holds components no other call holds.
    let query = &*query;
    assert!(
        robots.windows(2).all(|w| w[0] < w[1]),
        "the robots of an event are ascending"
    );
    for (c, chunk) in robots.chunks(UPDATE_CHUNK).enumerate() {
        let changed = map_indexed(chunk.len(), |i| {
            let r = chunk[i];
            // SAFETY: the robots are distinct (asserted above) and each has an entity of
            // its own, so no two calls hold the same entity's components: the only
            // aliasing `get_unchecked` leaves to its caller. One of the workspace's four
            // unsafe blocks (the others: `prefetch`, the AVX2 walk, the C allocator's
            // threshold).
            #[allow(
                unsafe_code,
                reason = "components of distinct robots written from several threads"
            )]
            let item = unsafe { query.get_unchecked(entities.0[r as usize]) };
            change(c * UPDATE_CHUNK + i, r, item.expect("robot entity"))
        });
        for (&r, x) in chunk.iter().zip(changed) {
            then(r, x);
        }
    }
}

/// Robots [`update_robots`] changes at once.
const UPDATE_CHUNK: usize = 8192;

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

    /// A robot's clock, different for each robot.
    fn clock(r: u32) -> Timing<DVec2> {
        Timing::new(Phase::Idle, 0, u64::from(r) + 1, u64::from(r % 7), 0, None)
    }

    /// Robots updated from several threads, more than a chunk of them: each robot of
    /// the list changed once with its own place in the list, the others untouched, and
    /// what each change gave handed back in robot order, whatever the thread count.
    #[test]
    fn robots_updated_at_once_are_changed_each_once_and_reported_in_order() {
        use bevy_ecs::system::RunSystemOnce;
        let n = 7 * UPDATE_CHUNK as u32 + 100;
        // Every third robot but a run of consecutive ones: chunks of both kinds.
        let chosen: Vec<u32> = (0..n)
            .filter(|r| r % 3 == 1 || (1000..1500).contains(r))
            .collect();
        assert!(chosen.len() > 2 * UPDATE_CHUNK);
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut world = World::new();
            let entities: Vec<Entity> = (0..n).map(|r| world.spawn(clock(r)).id()).collect();
            world.insert_resource(RobotEntities(entities.clone()));
            let list = chosen.clone();
            let reported = pool.install(|| {
                world
                    .run_system_once(
                        move |mut robots: Query<&mut Timing<DVec2>>, ids: Res<RobotEntities>| {
                            let mut reported = Vec::new();
                            update_robots(
                                &mut robots,
                                &ids,
                                &list,
                                |i, r, mut timing| {
                                    timing.looked += 1 + i as u64;
                                    (i, r, timing.until)
                                },
                                |r, got| reported.push((r, got)),
                            );
                            reported
                        },
                    )
                    .unwrap()
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
                let timing = *world.get::<Timing<DVec2>>(entities[r as usize]).unwrap();
                let mut want = clock(r);
                if let Some(i) = place[r as usize] {
                    want.looked = 1 + i;
                }
                assert_eq!(timing, want, "robot {r}, {threads} threads");
            }
        }
    }

    #[test]
    #[should_panic(expected = "ascending")]
    fn robots_listed_twice_are_refused() {
        use bevy_ecs::system::RunSystemOnce;
        let mut world = World::new();
        let entities: Vec<Entity> = (0..4).map(|r| world.spawn(clock(r)).id()).collect();
        world.insert_resource(RobotEntities(entities));
        world
            .run_system_once(
                |mut robots: Query<&mut Timing<DVec2>>, ids: Res<RobotEntities>| {
                    update_robots(&mut robots, &ids, &[0, 2, 2, 3], |_, _, _| (), |_, _| ());
                },
            )
            .unwrap();
    }
}
