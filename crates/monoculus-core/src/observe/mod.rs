//! Observations: what an algorithm is given in one activation.
//!
//! An observation wraps a [`Sight`] privately and answers only what a monoculus robot
//! can sense: directions (unit vectors in the robot's local frame), far/near bits (LD),
//! and on which side of the agreed axes robots lie (OLA). Positions and distances cannot
//! be read from these types. The one exception is [`PositionObservation`], the model of
//! the centre-of-gravity baseline, which by definition sees positions.
//!
//! Random choices ("choose any" in the paper) are made here, by one procedure shared by
//! every [`Sight`] implementation, so that the indexed engine and the brute-force oracle
//! choose the same targets from the same random stream: draw a robot uniformly, keep it
//! if it passes the algorithm's filter and represents a visible point, else draw again;
//! after [`REJECTION_DRAWS`] misses, list all eligible points and draw one of them.
//! Either way the result is uniform over the eligible visible points.

mod inspect;
mod ld;
mod ola;
mod positions;

pub use inspect::{Looked, inspect};
pub use ld::{LdObservation, Seen};
pub use ola::{OlaObservation, Side};
pub use positions::PositionObservation;

use crate::geometry::Point;
use crate::rng::Stream;
use crate::vision::Sight;

/// Lists robots by calling the given function with each.
pub(crate) type Enumerate<'a> = &'a dyn Fn(&mut dyn FnMut(usize));

/// A superset of the eligible robots, for when the uniform draws all missed.
pub(crate) struct Candidates<'a> {
    /// Lists them, in any order.
    pub list: Enumerate<'a>,
    /// Whether to draw among them ([`TargetPolicy::Random`]) before listing every
    /// eligible visible point ([`TargetPolicy::RandomListing`] lists at once).
    ///
    /// [`TargetPolicy::Random`]: crate::algorithms::TargetPolicy::Random
    /// [`TargetPolicy::RandomListing`]: crate::algorithms::TargetPolicy::RandomListing
    pub redraw: bool,
}

/// How many uniform draws the target sampler makes before it lists every eligible point.
pub const REJECTION_DRAWS: usize = 32;

/// [`TargetPolicy::Random`]: how many more uniform draws over the whole swarm
/// follow the first [`REJECTION_DRAWS`] before the candidates are listed. A draw that
/// lands on an ineligible robot costs one distance test, listing the candidates one
/// test per robot beyond c and more: where a few percent of the swarm is far (late
/// ConvergeLocality rounds), these draws find one at a fraction of the cost.
///
/// [`TargetPolicy::Random`]: crate::algorithms::TargetPolicy::Random
pub const EXTRA_UNIFORM_DRAWS: usize = 256;

/// A uniformly random visible point from robot `me` among the robots `eligible`
/// accepts; `None` if there is none.
///
/// `nobody` is asked only if every draw missed: a cheap proof that no robot is
/// eligible, which spares the full listing (the stream is not used after a `None`).
///
/// `candidates`, if given, lists a superset of the eligible robots (in any order) for
/// the full listing, which is then sorted, so the choice is the same as over all robots.
/// With `redraw`, [`EXTRA_UNIFORM_DRAWS`] more uniform draws over all robots come
/// first, then up to [`REJECTION_DRAWS`] draws among the candidates (the `k`-th
/// smallest robot index for a uniform `k`: the same whatever order they are listed in),
/// then the full listing; the result is uniform over the eligible visible points
/// either way (each step draws uniformly from a superset and keeps only eligible
/// visible points).
pub(crate) fn sample_visible_point<P: Point, S: Sight<P> + ?Sized>(
    sight: &S,
    me: usize,
    eligible: &dyn Fn(usize) -> bool,
    nobody: &dyn Fn() -> bool,
    candidates: Option<Candidates<'_>>,
    stream: &mut Stream,
) -> Option<usize> {
    let n = sight.len();
    if n < 2 {
        return None;
    }
    // Up to `draws` robots drawn uniformly; the first eligible visible one.
    let uniform = |draws: usize, stream: &mut Stream| {
        (0..draws)
            .map(|_| stream.below(n))
            .find(|&j| j != me && eligible(j) && sight.is_visible_point(me, j))
    };
    if let Some(j) = uniform(REJECTION_DRAWS, stream) {
        return Some(j);
    }
    if nobody() {
        return None;
    }
    if candidates.as_ref().is_some_and(|c| c.redraw)
        && let Some(j) = uniform(EXTRA_UNIFORM_DRAWS, stream)
    {
        return Some(j);
    }
    let pool: Vec<usize> = match candidates {
        Some(Candidates { list, redraw }) => {
            let mut v = Vec::new();
            list(&mut |j| v.push(j));
            if redraw && !v.is_empty() {
                for _ in 0..REJECTION_DRAWS {
                    let k = stream.below(v.len());
                    let j = *v.select_nth_unstable(k).1;
                    if j != me && eligible(j) && sight.is_visible_point(me, j) {
                        return Some(j);
                    }
                }
            }
            v.sort_unstable();
            v
        }
        None => (0..n).collect(),
    };
    let all: Vec<usize> = pool
        .into_iter()
        .filter(|&j| j != me && eligible(j) && sight.is_visible_point(me, j))
        .collect();
    if all.is_empty() {
        None
    } else {
        Some(all[stream.below(all.len())])
    }
}

/// The number of visible points from `me`, counted up to `limit`, and (if it is 1) the
/// visible one. The count does not depend on the order robots are tried in: first the
/// sight's [`Sight::neighbours`] (in general position two of them are visible and the
/// answer is found at once), then, if those do not reach `limit`, every robot nearest
/// first.
pub(crate) fn count_visible_up_to<P: Point, S: Sight<P> + ?Sized>(
    sight: &S,
    me: usize,
    limit: usize,
) -> (usize, Option<usize>) {
    let mut near = crate::vision::Near::new();
    sight.neighbours(me, &mut near);
    if near
        .as_slice()
        .iter()
        .filter(|&&j| sight.is_visible_point(me, j))
        .take(limit)
        .count()
        >= limit
    {
        return (limit, None);
    }
    let mut count = 0;
    let mut first = None;
    for j in sight.nearest_first(me) {
        if sight.is_visible_point(me, j) {
            count += 1;
            first.get_or_insert(j);
            if count >= limit {
                break;
            }
        }
    }
    (count, first)
}

/// The robot representing the only visible point from `me`, if exactly one is visible.
pub(crate) fn sole_visible<P: Point, S: Sight<P> + ?Sized>(sight: &S, me: usize) -> Option<usize> {
    match count_visible_up_to(sight, me, 2) {
        (1, first) => first,
        _ => None,
    }
}

/// The unit direction from robot `me` to robot `j`, global frame.
pub(crate) fn direction<P: Point, S: Sight<P> + ?Sized>(sight: &S, me: usize, j: usize) -> P {
    (sight.position(j) - sight.position(me)).normalized()
}
