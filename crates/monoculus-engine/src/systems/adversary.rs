//! The adversarial scheduler (SPEC 9.5): after the Look, it evaluates every robot's
//! decision on the snapshot and activates the robots its objective prefers, besides those
//! k-fairness forces.

use bevy_ecs::prelude::*;
use monoculus_core::algorithms::Algorithm;
use monoculus_core::vision::Sight;
use rayon::prelude::*;

use super::compute::{Item, KeptBy, MemoryOf, decide_items, lights_of};
use super::hull_grew;
use crate::algorithm::Rule;
use crate::components::{Activated, Robot, Waiting};
use crate::resources::{Clock, Params, Positions, Snapshot, SnapshotSight};
use crate::{IndexPoint, Objective, SchedulerSpec};

/// Every robot's decision this round, by index (states copied: nothing is changed).
fn decisions<P: IndexPoint, S: Sight<P>, A: Algorithm>(
    (params, algorithm): (&Params, &A),
    sight: &S,
    round: u64,
    robots: &[(usize, Option<KeptBy<P, A>>)],
) -> Vec<Option<P>> {
    let lights = lights_of::<A>(
        algorithm,
        sight.len(),
        robots
            .iter()
            .filter_map(|(i, m)| Some((*i, &m.as_ref()?.state))),
    );
    let mut items: Vec<Item<P, A>> = robots.iter().map(|(i, m)| (*i, round, m.clone())).collect();
    decide_items(params, algorithm, (sight, &lights), &mut items)
}

/// The robots the adversary activates besides the forced ones: by `objective`, among
/// the robots with a move (`moves[i]` for robot i at `points[i]`).
pub fn preferred<P: IndexPoint>(
    objective: Objective,
    points: &[P],
    moves: &[Option<P>],
) -> Vec<usize> {
    let movers: Vec<usize> = (0..moves.len()).filter(|&i| moves[i].is_some()).collect();
    if movers.is_empty() {
        return Vec::new();
    }
    let hull = P::hull_vertices(points);
    let (area, perimeter) = (
        P::hull_measure(points),
        P::hull_perimeter(points).expect("the adversary runs in the plane"),
    );
    // A robot inside the hull moving to a point strictly inside it leaves the hull as it
    // is; only the others need a new hull.
    let after = |i: usize| -> Option<(f64, f64)> {
        let to = points[i] + moves[i].expect("a mover");
        if !hull.contains(&points[i]) && P::strictly_inside(&hull, to) {
            return None;
        }
        let mut moved = points.to_vec();
        moved[i] = to;
        Some((
            P::hull_measure(&moved),
            P::hull_perimeter(&moved).expect("the plane"),
        ))
    };
    let changes: Vec<(usize, f64, f64)> = movers
        .par_iter()
        .map(|&i| {
            let (a, p) = after(i).unwrap_or((area, perimeter));
            (i, a, p)
        })
        .collect();
    if objective == Objective::Grow {
        let growing: Vec<usize> = changes
            .iter()
            .filter(|&&(_, a, _)| hull_grew(area, a))
            .map(|&(i, _, _)| i)
            .collect();
        if !growing.is_empty() {
            return growing;
        }
    }
    // Slow: the least reduction of the perimeter, the lowest index among equals.
    let slowest = changes
        .iter()
        .min_by(|x, y| {
            (perimeter - x.2)
                .total_cmp(&(perimeter - y.2))
                .then(x.0.cmp(&y.0))
        })
        .expect("movers");
    vec![slowest.0]
}

/// A robot as the adversary sees it: its activation, its wait, what it keeps.
type Scheduled<'a, P, A> = (
    &'a Robot,
    &'a mut Activated,
    &'a mut Waiting,
    Option<&'a MemoryOf<P, A>>,
);

/// The adversary's Activate, after the Look: every robot not activated in the last k - 1
/// rounds, and the robots [`preferred`] picks among those that would move.
pub fn choose_adversarially<P: IndexPoint, A: Algorithm>(
    params: Res<Params>,
    algorithm: Res<Rule<A>>,
    clock: Res<Clock>,
    snapshot: Res<Snapshot<P>>,
    positions: Res<Positions<P>>,
    mut robots: Query<Scheduled<P, A>>,
) {
    let SchedulerSpec::Adversary {
        objective,
        fairness,
    } = params.scheduler
    else {
        unreachable!("wired only for the adversary")
    };
    let mut order: Vec<(usize, Option<KeptBy<P, A>>)> = robots
        .iter()
        .map(|(r, _, _, m)| (r.index as usize, m.map(|m| m.0.clone())))
        .collect();
    order.sort_unstable_by_key(|r| r.0);
    let n = order.len();
    let sight = snapshot.sight.as_ref().expect("the Look runs first");
    let rule = (&*params, &*algorithm.0);
    let moves = match sight {
        SnapshotSight::Index(s) => decisions(rule, s, clock.round, &order),
        SnapshotSight::Exact(s) => decisions(rule, s, clock.round, &order),
        SnapshotSight::Rtree(s) => decisions(rule, s, clock.round, &order),
    };
    let chosen = preferred(objective, &positions.points, &moves);
    let k = fairness.unwrap_or(n as u32).max(1);
    for (robot, mut active, mut waiting) in robots.iter_mut().map(|(r, a, w, _)| (r, a, w)) {
        let i = robot.index as usize;
        active.0 = waiting.0 + 1 >= k || chosen.binary_search(&i).is_ok();
        waiting.0 = if active.0 { 0 } else { waiting.0 + 1 };
    }
}
