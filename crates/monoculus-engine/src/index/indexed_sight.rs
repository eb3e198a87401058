//! [`IndexedSight`]: the engine's [`Sight`], answered through the spatial index of the
//! points' dimension ([`IndexPoint::Index`]: the band grid in the plane, an rstar R-tree
//! in space).

use std::sync::OnceLock;

use monoculus_core::metrics::bounds;
use monoculus_core::vision::{
    Near, Sight, VisionParams, beyond_brute, blocks, distinct, in_range, nearest_first_brute,
    within_brute,
};

use super::{IndexPoint, SpatialIndex, SpatialOrder};

/// One snapshot of the swarm with a spatial index over it, built on first use.
///
/// - `sees(i, j)`: in the plane, a walk along the segment i -> j through the band grid;
///   in space, one R-tree tube query. Then the exact predicate on the few robots found.
/// - `for_each_within`, `nearest_first`, `for_each_beyond`: the grid's bins in the
///   plane (rings of bins, bins outside the disc), the tree's queries in space.
/// - `visible_points(i)` (a full look): the angular sweep in the plane (O(n log n)),
///   one tube query per robot in space.
///
/// A sight taken [after](IndexedSight::after) another in which few robots moved keeps
/// the other's grid: the robots that moved since it was built are stale, skipped in
/// its bins and tested one by one (late ConvergeQuadrant rounds move a handful of
/// robots out of thousands). ASYNC's Looks see through a moving index instead
/// ([`crate::asynchrony::TickSight`]).
///
/// The index is the dimension's own ([`IndexPoint::Index`]) unless chosen: `I =
/// SpaceIndex<DVec2>` puts the plane in an R-tree (`vision.backend = "rtree"`).
///
/// A swarm of at most [`FEW_ROBOTS`] robots is answered without the index, robot by
/// robot: a walk through a grid costs more than testing a dozen robots. Each candidate
/// blocker is first tested by a filter on the same vectors the exact predicate computes
/// (never rejecting a blocker; in the plane two robots at a time, their coordinates kept
/// axis by axis), then by the predicate itself: the same answers.
pub struct IndexedSight<P: IndexPoint, I: SpatialIndex<P> = <P as IndexPoint>::Index> {
    positions: Vec<P>,
    index: I,
    /// Hull vertices (plane), for farthest-robot questions (built on first use).
    hull: OnceLock<Vec<P>>,
    vision: VisionParams,
    /// The bounding box (computed on first use).
    bounds: OnceLock<(P, P)>,
    /// At most [`FEW_ROBOTS`] robots: answered without the index.
    few: bool,
    /// Few robots: bit `j` set when robot `j` is alone (no other within `eps_pos`),
    /// found for all at once on first use.
    alone_few: OnceLock<u32>,
    /// Few robots in the plane: their coordinates, axis by axis.
    lanes: Option<Lanes>,
}

/// The most robots a sight answers without its index (measured: docs/performance.md).
///
/// ```
/// use monoculus_engine::index::FEW_ROBOTS;
/// // A hunt's swarms of 3 to 10 robots are all answered robot by robot.
/// assert!(FEW_ROBOTS >= 10);
/// ```
pub const FEW_ROBOTS: usize = 16;

// Which of few robots are alone is one bit each; their lanes are rows of two.
const _: () = assert!(FEW_ROBOTS < 32 && FEW_ROBOTS.is_multiple_of(2));

/// Whether `r` may block the view from `p` to `q` (else [`blocks`] is certainly false):
/// a filter on the vectors `blocks` computes, for point robots and `eps_ang < 0.5`.
/// `blocks` requires the angle `atan2(c, d)` between `r - p` and `q - p` (`c` the norm
/// of their cross product, `d` their dot product, both as `blocks` computes them) to be
/// at most `eps_ang`. Where `c > 2 eps_ang d`: either `d <= 0` and the angle is at
/// least a right angle (unless `c = d = 0`, which the filter lets through), or
/// `c / d > 2 eps_ang`, and `atan(2 x) > x` for `x < 0.6` with room for rounding. A
/// NaN is let through.
#[inline]
fn may_block<P: IndexPoint>(p: P, r: P, q: P, eps_ang: f64) -> bool {
    let (dr, dq) = (r - p, q - p);
    let (c, bound) = (dr.cross_norm(dq), 2.0 * eps_ang * dr.dot(dq));
    c <= bound || c.is_nan() || bound.is_nan()
}

/// Few robots in the plane, their coordinates axis by axis, two robots to a row (zeros
/// past the last robot): [`may_block`] for two robots at a time.
#[derive(Clone, Copy, Debug)]
struct Lanes {
    x: [[f64; 2]; FEW_ROBOTS / 2],
    y: [[f64; 2]; FEW_ROBOTS / 2],
}

impl Lanes {
    /// The lanes of `positions` if a sight over them is answered without its index
    /// ([`few`]) and they lie in the plane.
    fn of<P: IndexPoint>(positions: &[P], vision: &VisionParams) -> Option<Lanes> {
        if P::DIM != 2 || !few(positions, vision) {
            return None;
        }
        let mut lanes = Lanes {
            x: [[0.0; 2]; FEW_ROBOTS / 2],
            y: [[0.0; 2]; FEW_ROBOTS / 2],
        };
        for (k, r) in positions.iter().enumerate() {
            lanes.x[k / 2][k % 2] = r.axis(0);
            lanes.y[k / 2][k % 2] = r.axis(1);
        }
        Some(lanes)
    }

    /// Bit `k` set where robot `k` of the first `n` [`may_block`] the view from `p` to
    /// `q`: the same vectors and products as `may_block` (`r - p`, `q - p`, the cross
    /// product's norm and the dot product, as glam computes them, in the same order),
    /// so the same bits.
    fn may_block<P: IndexPoint>(&self, n: usize, p: P, q: P, eps_ang: f64) -> u32 {
        let (px, py) = (p.axis(0), p.axis(1));
        let (qx, qy) = (q.axis(0) - px, q.axis(1) - py);
        let two_eps = 2.0 * eps_ang;
        let mut maybe = 0u32;
        for row in 0..n.div_ceil(2).min(FEW_ROBOTS / 2) {
            let (xs, ys) = (&self.x[row], &self.y[row]);
            maybe |= pair_may_block(xs, ys, (px, py), (qx, qy), two_eps) << (2 * row);
        }
        maybe & ((1 << n) - 1)
    }
}

/// [`may_block`] for two robots (coordinates `xs`, `ys`) seen from `p` towards `p + dq`,
/// `two_eps` twice the angular tolerance: bit `l` for robot `l`. On x86_64 both at once
/// in SSE2's two double-precision lanes, each lane's arithmetic the scalar one's.
#[inline(always)]
fn pair_may_block(
    xs: &[f64; 2],
    ys: &[f64; 2],
    p: (f64, f64),
    dq: (f64, f64),
    two_eps: f64,
) -> u32 {
    // SAFETY: SSE2 is part of every x86_64 CPU (the target's baseline), all these
    // intrinsics need; the loads read the two elements of `xs` and `ys`. One of the
    // workspace's four unsafe blocks (the others: `prefetch`, the AVX2 walk and the C
    // allocator's threshold set in the command line).
    #[cfg(target_arch = "x86_64")]
    #[allow(unsafe_code, reason = "SSE2 intrinsics, in the x86_64 baseline")]
    unsafe {
        use std::arch::x86_64::*;
        let rx = _mm_sub_pd(_mm_loadu_pd(xs.as_ptr()), _mm_set1_pd(p.0));
        let ry = _mm_sub_pd(_mm_loadu_pd(ys.as_ptr()), _mm_set1_pd(p.1));
        let (qx, qy) = (_mm_set1_pd(dq.0), _mm_set1_pd(dq.1));
        let no_sign = _mm_set1_pd(f64::from_bits(!(1 << 63)));
        let cross = _mm_and_pd(_mm_sub_pd(_mm_mul_pd(rx, qy), _mm_mul_pd(ry, qx)), no_sign);
        let dot = _mm_add_pd(_mm_mul_pd(rx, qx), _mm_mul_pd(ry, qy));
        let bound = _mm_mul_pd(_mm_set1_pd(two_eps), dot);
        // Not greater: also where either side is NaN, as `may_block`.
        _mm_movemask_pd(_mm_cmpngt_pd(cross, bound)) as u32
    }
    #[cfg(not(target_arch = "x86_64"))]
    (0..2).fold(0, |bits, l| {
        let (rx, ry) = (xs[l] - p.0, ys[l] - p.1);
        let cross = ((rx * dq.1) - (ry * dq.0)).abs();
        let bound = two_eps * ((rx * dq.0) + (ry * dq.1));
        bits | u32::from(cross <= bound || cross.is_nan() || bound.is_nan()) << l
    })
}

/// Whether a sight over `positions` is answered without its index: few robots, seen as
/// points, with an angular tolerance [`may_block`] holds for.
fn few<P: IndexPoint>(positions: &[P], vision: &VisionParams) -> bool {
    positions.len() <= FEW_ROBOTS && !vision.fat() && vision.eps_ang < 0.5
}

impl<P: IndexPoint> IndexedSight<P> {
    /// A sight over `positions` with the dimension's index, built when first needed.
    pub fn new(positions: Vec<P>, vision: VisionParams) -> Self {
        Self::with_index(positions, vision)
    }
}

impl<P: IndexPoint, I: SpatialIndex<P>> IndexedSight<P, I> {
    /// A sight over `positions` with the index `I`, built when first needed.
    pub fn with_index(positions: Vec<P>, vision: VisionParams) -> Self {
        IndexedSight {
            bounds: OnceLock::new(),
            index: I::new(&positions),
            few: few(&positions, &vision),
            alone_few: OnceLock::new(),
            lanes: Lanes::of(&positions, &vision),
            positions,
            hull: OnceLock::new(),
            vision,
        }
    }

    /// A sight over `positions`, a later configuration of the swarm `previous` saw. In
    /// the plane, if `previous` built its grid and since then at most n / 64 robots moved,
    /// all within the grid's box, the grid is kept and those robots are marked stale;
    /// otherwise as [`IndexedSight::new`]. Every answer is the same either way (tested).
    pub fn after(previous: Self, positions: Vec<P>, vision: VisionParams) -> Self {
        let index = I::after(
            previous.index,
            &previous.positions,
            &positions,
            previous.vision == vision,
        );
        IndexedSight {
            bounds: OnceLock::new(),
            index,
            few: few(&positions, &vision),
            alone_few: OnceLock::new(),
            lanes: Lanes::of(&positions, &vision),
            positions,
            hull: OnceLock::new(),
            vision,
        }
    }

    /// Gives the sight the vertices of its positions' hull, as
    /// [`HullGeometry::hull_vertices`](monoculus_core::geometry::HullGeometry) gives
    /// them (taken by the caller anyway), so that it need not take the hull again.
    pub(crate) fn know_hull(&self, vertices: &[P]) {
        debug_assert!(vertices.iter().all(|v| self.positions.contains(v)));
        self.hull.get_or_init(|| vertices.to_vec());
    }

    /// Builds the index now (else it is built by the first query that needs it).
    pub fn build_index(&self) {
        self.index.build(&self.positions);
    }

    /// The robots in an order that keeps neighbours in space together, once the index
    /// is [built](IndexedSight::build_index) (in the plane; `None` in space).
    pub fn order(&self) -> Option<SpatialOrder<'_>> {
        self.index.order()
    }

    /// How many robots moved since the grid in use was built (0 for a fresh one).
    pub fn stale_robots(&self) -> usize {
        self.index.stale_robots()
    }

    /// Gives the positions back (to reuse the allocation).
    pub fn into_positions(self) -> Vec<P> {
        self.positions
    }
}

impl<P: IndexPoint, I: SpatialIndex<P>> Sight<P> for IndexedSight<P, I> {
    fn positions(&self) -> &[P] {
        &self.positions
    }

    fn vision(&self) -> &VisionParams {
        &self.vision
    }

    fn bounds(&self) -> (P, P) {
        *self.bounds.get_or_init(|| bounds(&self.positions))
    }

    fn sees(&self, i: usize, j: usize) -> bool {
        let (p, q) = (self.positions[i], self.positions[j]);
        if i == j || !distinct(p, q, &self.vision) || !in_range(p, q, &self.vision) {
            return false;
        }
        if self.few {
            // The filter over every robot without a branch (a bit each), then the
            // predicate for the few it lets through.
            let v = &self.vision;
            let mut maybe = match &self.lanes {
                Some(lanes) => lanes.may_block(self.positions.len(), p, q, v.eps_ang),
                None => (self.positions.iter().enumerate()).fold(0, |m, (k, &r)| {
                    m | u32::from(may_block(p, r, q, v.eps_ang)) << k
                }),
            };
            maybe &= !(1 << i | 1 << j);
            while maybe != 0 {
                let k = maybe.trailing_zeros() as usize;
                if blocks(p, self.positions[k], q, v) {
                    return false;
                }
                maybe &= maybe - 1;
            }
            return true;
        }
        self.index
            .clear(self.positions.as_slice(), &self.vision, i, j)
    }

    fn for_each_within(&self, i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        if self.few {
            return within_brute(&self.positions, i, radius, f);
        }
        self.index
            .for_each_within(self.positions.as_slice(), i, radius, f);
    }

    fn nearest_first(&self, i: usize) -> Box<dyn Iterator<Item = usize> + '_> {
        if self.few {
            return Box::new(nearest_first_brute(&self.positions, i).into_iter());
        }
        self.index.nearest_first(self.positions.as_slice(), i)
    }

    /// The farthest robot is a hull vertex: O(h) after the hull (O(n log n), once).
    fn farthest(&self, i: usize) -> f64 {
        let p = self.positions[i];
        let hull = self.hull.get_or_init(|| P::hull_vertices(&self.positions));
        let set: &[P] = if hull.is_empty() {
            &self.positions
        } else {
            hull
        };
        set.iter().map(|&q| (q - p).length()).fold(0.0, f64::max)
    }

    fn for_each_beyond(&self, i: usize, radius: f64, f: &mut dyn FnMut(usize)) {
        if self.few {
            return beyond_brute(&self.positions, i, radius, f);
        }
        self.index
            .for_each_beyond(self.positions.as_slice(), i, radius, f);
    }

    fn alone(&self, j: usize) -> bool {
        if self.few {
            let alone = self.alone_few.get_or_init(|| {
                // Each pair once: a distance is the same either way round (`a - b` is
                // `-(b - a)` to the bit).
                let (pts, eps) = (&self.positions, self.vision.eps_pos);
                let mut alone = (1u32 << pts.len()) - 1;
                for a in 0..pts.len() {
                    for b in a + 1..pts.len() {
                        // Apart only if farther than `eps` (NaN is not apart).
                        let apart = (pts[b] - pts[a]).length() > eps;
                        if !apart {
                            alone &= !(1 << a | 1 << b);
                        }
                    }
                }
                alone
            });
            return alone >> j & 1 == 1;
        }
        self.index.alone(self.positions.as_slice(), &self.vision, j)
    }

    /// For few robots, every other one: they are counted without sorting them by
    /// distance.
    fn neighbours(&self, i: usize, near: &mut Near) {
        if self.few {
            for k in (0..self.positions.len()).filter(|&k| k != i) {
                near.push(k);
            }
            return;
        }
        self.index.neighbours(self.positions.as_slice(), i, near);
    }

    fn visible_points(&self, i: usize) -> Vec<usize> {
        self.index
            .visible_points(&self.positions, &self.vision, i, &|j| self.sees(i, j))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;
    use monoculus_core::rng::Stream;

    /// Two robots at a time give the bits of [`may_block`] one robot at a time, to the
    /// bit: random, lattice and collinear robots, robots on the observer and on the
    /// robot looked at, NaN, for every count of robots and tolerance.
    #[test]
    fn lanes_filter_as_one_robot_at_a_time() {
        let mut stream = Stream::new(5, 0, 0, 0);
        let mut sets: Vec<Vec<DVec2>> = Vec::new();
        for _ in 0..200 {
            let scale = 10f64.powi(stream.below(7) as i32 - 3);
            sets.push(
                (0..FEW_ROBOTS)
                    .map(|_| DVec2::new(stream.uniform(), stream.uniform()) * scale)
                    .collect(),
            );
        }
        sets.push(
            (0..FEW_ROBOTS)
                .map(|k| DVec2::new((k % 4) as f64, (k / 4) as f64))
                .collect(),
        );
        sets.push(
            (0..FEW_ROBOTS)
                .map(|k| DVec2::splat(k as f64 * 0.1))
                .collect(),
        );
        let mut with_nan = sets[0].clone();
        with_nan[3] = DVec2::new(f64::NAN, 1.0);
        sets.push(with_nan);
        let mut passed = 0;
        for eps_ang in [0.0, 1e-9, 1e-3, 0.49] {
            let vision = VisionParams {
                eps_ang,
                ..VisionParams::default()
            };
            for set in &sets {
                for n in 1..=FEW_ROBOTS {
                    let pts = &set[..n];
                    let lanes = Lanes::of(pts, &vision).expect("few robots in the plane");
                    for (i, j) in [(0, n - 1), (n / 2, 0), (n - 1, n / 3)] {
                        let (p, q) = (pts[i], pts[j]);
                        let one_at_a_time = (pts.iter().enumerate()).fold(0, |m, (k, &r)| {
                            m | u32::from(may_block(p, r, q, eps_ang)) << k
                        });
                        assert_eq!(lanes.may_block(n, p, q, eps_ang), one_at_a_time);
                        passed += (one_at_a_time & !(1 << i | 1 << j)).count_ones();
                    }
                }
            }
        }
        assert!(passed > 100, "robots pass the filter: {passed}");
    }
}
