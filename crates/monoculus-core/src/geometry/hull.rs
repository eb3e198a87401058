//! Convex hulls: area and diameter in the plane.

use glam::DVec2;

use super::Point;

/// Shape measures that depend on the dimension: the size of the convex hull (area in
/// d = 2, volume in d = 3) and the diameter of a point set.
pub trait HullGeometry: Point {
    /// Area (d = 2) or volume (d = 3) of the convex hull; 0 for degenerate sets.
    fn hull_measure(points: &[Self]) -> f64;
    /// The largest distance between two of the points; 0 for fewer than two.
    fn diameter(points: &[Self]) -> f64;
    /// Both, computing the hull once.
    fn hull_and_diameter(points: &[Self]) -> (f64, f64) {
        (Self::hull_measure(points), Self::diameter(points))
    }
    /// The perimeter of the convex hull, where the dimension has one (the plane);
    /// `None` in space.
    fn hull_perimeter(_points: &[Self]) -> Option<f64> {
        None
    }
    /// The vertices of the convex hull, in an order [`HullGeometry::strictly_inside`]
    /// understands (empty where no fast inside test exists).
    fn hull_vertices(_points: &[Self]) -> Vec<Self> {
        Vec::new()
    }
    /// [`HullGeometry::hull_and_diameter`] of a set, given the vertices
    /// [`HullGeometry::hull_vertices`] returned for it (not empty): the same values to
    /// the bit, without taking their hull again.
    ///
    /// ```
    /// use glam::DVec2;
    /// use monoculus_core::geometry::HullGeometry;
    /// let pts = [DVec2::ZERO, DVec2::X, DVec2::Y, DVec2::ONE, DVec2::splat(0.5)];
    /// let hull = DVec2::hull_vertices(&pts);
    /// assert_eq!(DVec2::vertices_hull_and_diameter(&hull), DVec2::hull_and_diameter(&pts));
    /// ```
    fn vertices_hull_and_diameter(vertices: &[Self]) -> (f64, f64) {
        Self::hull_and_diameter(vertices)
    }
    /// The points of a set that may be vertices of its hull, the set given as a pass
    /// over it that can be made twice: their hull, and so every measure taken from it
    /// (extents included), is the set's, to the bit; every point where no throw-away
    /// step exists. For sets too large to copy whole.
    fn hull_candidates_of<I: Iterator<Item = Self>>(points: impl Fn() -> I) -> Vec<Self> {
        points().collect()
    }
    /// Whether `p` lies strictly inside the hull with these vertices (exact orientation
    /// signs; `false` where no such test exists). Adding such points to a set leaves its
    /// hull exactly as it is: the exact chain never keeps an interior point.
    fn strictly_inside(_hull: &[Self], _p: Self) -> bool {
        false
    }
}

/// The convex hull of a planar point set, counter-clockwise from its lowest-x point,
/// without collinear points on its edges (Andrew's monotone chain with exact
/// orientations, after discarding points that are certainly interior: about O(n) for
/// a swarm, O(n log n) at worst).
pub fn convex_hull_2d(points: &[DVec2]) -> Vec<DVec2> {
    let mut pts = hull_candidates(points);
    pts.sort_unstable_by(by_x_then_y);
    monotone_chain(pts)
}

/// [`convex_hull_2d`] without the throw-away step: the chain over every point (the
/// reference the step is tested and benchmarked against).
pub fn convex_hull_2d_all(points: &[DVec2]) -> Vec<DVec2> {
    let mut pts = points.to_vec();
    pts.sort_unstable_by(by_x_then_y);
    monotone_chain(pts)
}

/// The order of the monotone chain. Total on the values: equal keys are equal points, so
/// the sorted sequence does not depend on the order the points come in.
fn by_x_then_y(a: &DVec2, b: &DVec2) -> std::cmp::Ordering {
    a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y))
}

/// The points that may be vertices of the hull: all but those that lie strictly left of
/// every edge of the polygon through the extreme points in eight directions (Akl and
/// Toussaint's throw-away step).
///
/// Why this cannot change the hull, whatever polygon is used: the polygon's vertices
/// are points of the set, and a point strictly left of each of its edges (by the exact
/// predicate) sees the boundary wind around it with every step turning forward, so it
/// is neither outside the polygon's hull nor on a supporting line of the set: it is
/// interior, and an exact chain never keeps an interior point. The sequence of vertices
/// is unique, so it is the same to the bit. Most points fall in a box inscribed in the
/// polygon (four comparisons); the rest take up to eight exact orientations.
fn hull_candidates(points: &[DVec2]) -> Vec<DVec2> {
    const FEW: usize = 64;
    if points.len() < FEW {
        return points.to_vec();
    }
    DVec2::hull_candidates_of(|| points.iter().copied())
}

/// The throw-away step of [`hull_candidates`]: the polygon through a set's extreme
/// points, and a box inside it.
struct ThrowAway {
    edges: Vec<(DVec2, DVec2)>,
    boxed: Option<(DVec2, DVec2)>,
}

impl ThrowAway {
    /// The step for the set `points` lists; `None` where its extreme points span no
    /// polygon (nothing can be thrown away).
    fn of(points: impl Iterator<Item = DVec2>) -> Option<Self> {
        let octagon = extreme_octagon(points)?;
        let mut polygon = octagon.to_vec();
        polygon.dedup();
        while polygon.len() > 1 && polygon.first() == polygon.last() {
            polygon.pop();
        }
        if polygon.len() < 3 {
            return None;
        }
        let mut step = ThrowAway {
            edges: (0..polygon.len())
                .map(|i| (polygon[i], polygon[(i + 1) % polygon.len()]))
                .collect(),
            boxed: None,
        };
        step.boxed = inscribed_box(&octagon, &|p| step.interior(p));
        Some(step)
    }

    /// Strictly left of every edge.
    fn interior(&self, p: DVec2) -> bool {
        self.edges.iter().all(|&(a, b)| orient(a, b, p) > 0.0)
    }

    /// Whether `p` is not thrown away.
    fn may_be_vertex(&self, p: DVec2) -> bool {
        let in_box = self
            .boxed
            .is_some_and(|(lo, hi)| p.cmpge(lo).all() && p.cmple(hi).all());
        !in_box && !self.interior(p)
    }
}

/// The points extreme in eight directions, counter-clockwise from "down": the lowest,
/// then the largest x - y, x, x + y, y, y - x, and the smallest x, x + y (the first
/// found where several tie; rounded projections are fine, as any points will do). One
/// pass; `None` for no point.
fn extreme_octagon(mut points: impl Iterator<Item = DVec2>) -> Option<[DVec2; 8]> {
    let project = |p: DVec2| [p.x, p.y, p.x + p.y, p.x - p.y];
    let start = points.next()?;
    let first = project(start);
    let (mut lo, mut hi) = (first, first);
    let (mut arg_lo, mut arg_hi) = ([start; 4], [start; 4]);
    for p in points {
        let v = project(p);
        for k in 0..4 {
            if v[k] < lo[k] {
                lo[k] = v[k];
                arg_lo[k] = p;
            }
            if v[k] > hi[k] {
                hi[k] = v[k];
                arg_hi[k] = p;
            }
        }
    }
    let (x, y, sum, diff) = (0, 1, 2, 3);
    Some([
        arg_lo[y],
        arg_hi[diff],
        arg_hi[x],
        arg_hi[sum],
        arg_hi[y],
        arg_lo[diff],
        arg_lo[x],
        arg_lo[sum],
    ])
}

/// A box whose four corners pass `interior` (then so does all of it: the points that
/// pass are an intersection of half-planes, which is convex), as large as a few tries
/// find. First tries: the box between the octagon's inner sides (`octagon` as from
/// [`extreme_octagon`]), which is nearly all of it for square-ish swarms, shrunk a
/// little at a time about its centre; then the octagon's bounding box shrunk about the
/// vertices' mean (diamonds and other shapes).
fn inscribed_box(
    octagon: &[DVec2; 8],
    interior: &impl Fn(DVec2) -> bool,
) -> Option<(DVec2, DVec2)> {
    let [b, br, r, ur, t, ul, l, ll] = *octagon;
    let tight = (
        DVec2::new(l.x.max(ul.x).max(ll.x), b.y.max(ll.y).max(br.y)),
        DVec2::new(r.x.min(ur.x).min(br.x), t.y.min(ul.y).min(ur.y)),
    );
    let (lo, hi) = octagon.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let mean = octagon.iter().copied().sum::<DVec2>() / 8.0;
    let tries = [1.0, 0.999, 0.99, 0.95]
        .map(|s| (tight, 0.5 * (tight.0 + tight.1), s))
        .into_iter()
        .chain([0.98, 0.9, 0.75, 0.5, 0.3].map(|s| ((lo, hi), mean, s)));
    tries
        .filter(|&((a, b), _, _)| a.cmplt(b).all())
        .find_map(|((a, b), centre, s)| {
            let (a, b) = (centre + s * (a - centre), centre + s * (b - centre));
            let corners = [a, DVec2::new(b.x, a.y), b, DVec2::new(a.x, b.y)];
            corners.iter().all(|&c| interior(c)).then_some((a, b))
        })
}

/// Andrew's monotone chain over points sorted by [`by_x_then_y`].
fn monotone_chain(mut pts: Vec<DVec2>) -> Vec<DVec2> {
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let mut hull: Vec<DVec2> = Vec::with_capacity(2 * pts.len());
    for &p in &pts {
        while hull.len() >= 2 && orient(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
            hull.pop();
        }
        hull.push(p);
    }
    let lower_len = hull.len() + 1;
    for &p in pts.iter().rev().skip(1) {
        while hull.len() >= lower_len
            && orient(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
        {
            hull.pop();
        }
        hull.push(p);
    }
    hull.pop();
    hull
}

/// Twice the signed area of the triangle `o, a, b`, with the exact sign: positive when
/// the turn `o -> a -> b` is counter-clockwise, zero only when the three are collinear
/// (Shewchuk's adaptive predicate: one rounded cross product unless that is too close
/// to zero to trust).
#[inline]
fn orient(o: DVec2, a: DVec2, b: DVec2) -> f64 {
    let c = |p: DVec2| robust::Coord { x: p.x, y: p.y };
    robust::orient2d(c(o), c(a), c(b))
}

/// Area of a simple polygon given in order (shoelace formula).
pub fn polygon_area(polygon: &[DVec2]) -> f64 {
    if polygon.len() < 3 {
        return 0.0;
    }
    let mut twice = 0.0;
    for i in 0..polygon.len() {
        let j = (i + 1) % polygon.len();
        twice += polygon[i].perp_dot(polygon[j]);
    }
    0.5 * twice.abs()
}

/// The diameter of a convex polygon, realised by two of its vertices. Hulls of random
/// swarms are small (O(log n) vertices for a uniform square), so the quadratic scan is
/// cheap.
fn hull_diameter(hull: &[DVec2]) -> f64 {
    let mut best: f64 = 0.0;
    for i in 0..hull.len() {
        for j in i + 1..hull.len() {
            best = best.max(hull[i].distance_squared(hull[j]));
        }
    }
    best.sqrt()
}

impl HullGeometry for DVec2 {
    fn hull_measure(points: &[Self]) -> f64 {
        polygon_area(&convex_hull_2d(points))
    }

    fn diameter(points: &[Self]) -> f64 {
        hull_diameter(&convex_hull_2d(points))
    }

    fn hull_and_diameter(points: &[Self]) -> (f64, f64) {
        let hull = convex_hull_2d(points);
        (polygon_area(&hull), hull_diameter(&hull))
    }

    fn hull_vertices(points: &[Self]) -> Vec<Self> {
        convex_hull_2d(points)
    }

    /// The hull of its own vertices is the same sequence (it is unique and the chain
    /// starts at the least point): its area and diameter are taken straight from them.
    fn vertices_hull_and_diameter(vertices: &[Self]) -> (f64, f64) {
        (polygon_area(vertices), hull_diameter(vertices))
    }

    fn hull_candidates_of<I: Iterator<Item = Self>>(points: impl Fn() -> I) -> Vec<Self> {
        match ThrowAway::of(points()) {
            Some(step) => points().filter(|&p| step.may_be_vertex(p)).collect(),
            None => points().collect(),
        }
    }

    fn hull_perimeter(points: &[Self]) -> Option<f64> {
        let hull = convex_hull_2d(points);
        Some(match hull.len() {
            0 | 1 => 0.0,
            // A segment's hull, walked there and back.
            2 => 2.0 * hull[0].distance(hull[1]),
            h => (0..h).map(|i| hull[i].distance(hull[(i + 1) % h])).sum(),
        })
    }

    /// O(log h): find the wedge from vertex 0 containing `p`, then test the edge, all
    /// with the exact predicate of the chain.
    fn strictly_inside(hull: &[Self], p: Self) -> bool {
        let h = hull.len();
        if h < 3 {
            return false;
        }
        let o = hull[0];
        // Counter-clockwise: p must be left of o->hull[1] and right of o->hull[h-1].
        if orient(o, hull[1], p) <= 0.0 || orient(o, hull[h - 1], p) >= 0.0 {
            return false;
        }
        let (mut lo, mut hi) = (1, h - 1);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if orient(o, hull[mid], p) > 0.0 {
                lo = mid
            } else {
                hi = mid
            }
        }
        orient(hull[lo], hull[hi], p) > 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The throw-away step against the chain over every point, to the bit: random,
    /// lattice, collinear, co-located, cocircular and near-degenerate sets.
    #[test]
    fn throwing_away_interior_points_keeps_the_hull() {
        let mut rng = crate::rng::Stream::new(5, 0, 0, 0);
        let mut sets: Vec<Vec<DVec2>> = Vec::new();
        for n in [64, 100, 1000, 5000] {
            sets.push(
                (0..n)
                    .map(|_| DVec2::new(rng.uniform_in(-3.0, 3.0), rng.uniform_in(0.0, 0.1)))
                    .collect(),
            );
            // A diamond: the box must shrink to fit inside.
            sets.push(
                (0..n)
                    .map(|_| {
                        let (u, v) = (rng.uniform_in(0.0, 1.0), rng.uniform_in(0.0, 1.0));
                        DVec2::new(u - v, u + v)
                    })
                    .collect(),
            );
        }
        // Lattice with spacing 0.1 (inexact coordinates) and its edge midpoints.
        sets.push(
            (0..900)
                .map(|i| DVec2::new((i % 30) as f64 * 0.1, (i / 30) as f64 * 0.1))
                .collect(),
        );
        // Collinear, co-located, cocircular.
        sets.push(
            (0..200)
                .map(|i| DVec2::new(i as f64 * 0.3, i as f64 * 0.7))
                .collect(),
        );
        sets.push(vec![DVec2::new(1.5, -2.0); 100]);
        sets.push(
            (0..360)
                .map(|i| DVec2::from_angle((i as f64).to_radians()) * 7.0)
                .collect(),
        );
        // Points a few ulps off the edges of a square, and signed zeros.
        let mut near: Vec<DVec2> = (0..400)
            .map(|i| {
                let t = rng.uniform_in(0.0, 1.0);
                let off = (i % 5) as f64 - 2.0;
                match i % 4 {
                    0 => DVec2::new(t, off * f64::EPSILON),
                    1 => DVec2::new(1.0 + off * f64::EPSILON, t),
                    2 => DVec2::new(t, 1.0 + off * f64::EPSILON),
                    _ => DVec2::new(off * f64::EPSILON, t),
                }
            })
            .collect();
        near.extend([DVec2::new(0.0, -0.0), DVec2::new(-0.0, 0.0), DVec2::ONE]);
        sets.push(near);
        for (k, pts) in sets.iter().enumerate() {
            let expected = convex_hull_2d_all(pts);
            assert_eq!(convex_hull_2d(pts), expected, "set {k}");
            let mut shuffled = pts.clone();
            shuffled.reverse();
            assert_eq!(convex_hull_2d(&shuffled), expected, "set {k} reversed");
            // The same step over a pass made twice (sets of any size): the hull, the
            // measures and the extents of what it keeps are the set's.
            let kept = DVec2::hull_candidates_of(|| pts.iter().copied());
            assert_eq!(convex_hull_2d_all(&kept), expected, "set {k} streamed");
            let bounds = |p: &[DVec2]| crate::metrics::extents(p);
            assert_eq!(bounds(&kept), bounds(pts), "set {k} extents");
            assert_eq!(
                DVec2::hull_and_diameter(&kept).0.to_bits(),
                DVec2::hull_and_diameter(pts).0.to_bits(),
                "set {k} area"
            );
            // The hull of the vertices is the vertices; their measures are the set's.
            assert_eq!(
                convex_hull_2d(&expected),
                expected,
                "set {k} hull of the hull"
            );
            let bits = |(a, d): (f64, f64)| (a.to_bits(), d.to_bits());
            assert_eq!(
                bits(DVec2::vertices_hull_and_diameter(&expected)),
                bits(DVec2::hull_and_diameter(pts)),
                "set {k} measures from the vertices"
            );
        }
        for pts in [&[][..], &[DVec2::ONE][..], &[DVec2::ZERO, DVec2::ONE][..]] {
            assert_eq!(DVec2::hull_candidates_of(|| pts.iter().copied()), pts);
        }
        // And it throws most of a uniform square away.
        let square: Vec<DVec2> = (0..10_000)
            .map(|_| DVec2::new(rng.uniform_in(0.0, 100.0), rng.uniform_in(0.0, 100.0)))
            .collect();
        let kept = hull_candidates(&square).len();
        assert!(kept < 500, "kept {kept} of 10000");
        let streamed = DVec2::hull_candidates_of(|| square.iter().copied()).len();
        assert_eq!(streamed, kept);
    }

    #[test]
    fn hull_of_square_with_interior_and_edge_points() {
        let pts = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 2.0),
            DVec2::new(0.0, 2.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(0.0, 0.0),
        ];
        let hull = convex_hull_2d(&pts);
        assert_eq!(hull.len(), 4);
        assert!((DVec2::hull_measure(&pts) - 4.0).abs() < 1e-12);
        assert!((DVec2::diameter(&pts) - 8f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn strictly_inside_agrees_with_hull_growth() {
        let mut s = crate::rng::Stream::new(8, 8, 8, 8);
        let pts: Vec<DVec2> = (0..200)
            .map(|_| DVec2::new(s.uniform_in(0.0, 10.0), s.uniform_in(0.0, 5.0)))
            .collect();
        let hull = DVec2::hull_vertices(&pts);
        let area = DVec2::hull_measure(&pts);
        for _ in 0..2000 {
            let q = DVec2::new(s.uniform_in(-1.0, 11.0), s.uniform_in(-1.0, 6.0));
            let mut with = pts.clone();
            with.push(q);
            if DVec2::strictly_inside(&hull, q) {
                assert_eq!(DVec2::hull_measure(&with).to_bits(), area.to_bits(), "{q}");
            } else {
                assert!(DVec2::hull_measure(&with) >= area);
            }
        }
        assert!(
            !DVec2::strictly_inside(&hull, hull[0]),
            "a vertex is not strictly inside"
        );
    }

    /// The hull of a set and more points is that of the set's vertices and the points
    /// not strictly inside them, to the bit (what the committed-hull measure relies on):
    /// random, lattice and collinear sets, with points on their edges and vertices.
    #[test]
    fn more_points_are_measured_with_the_vertices_alone() {
        let mut s = crate::rng::Stream::new(9, 9, 9, 9);
        let mut sets: Vec<Vec<DVec2>> = Vec::new();
        for n in [1, 2, 3, 10, 40] {
            sets.push(
                (0..n)
                    .map(|_| DVec2::new(s.uniform_in(0.0, 4.0), s.uniform_in(0.0, 3.0)))
                    .collect(),
            );
        }
        sets.push(
            (0..25)
                .map(|k| DVec2::new((k % 5) as f64, (k / 5) as f64))
                .collect(),
        );
        sets.push(
            (0..9)
                .map(|k| DVec2::new(k as f64 * 0.1, k as f64 * 0.3))
                .collect(),
        );
        for (k, pts) in sets.iter().enumerate() {
            let vertices = DVec2::hull_vertices(pts);
            for trial in 0..200 {
                let mut more: Vec<DVec2> = (0..trial % 7)
                    .map(|_| match s.below(3) {
                        0 => pts[s.below(pts.len())],
                        1 => {
                            let (a, b) = (pts[s.below(pts.len())], pts[s.below(pts.len())]);
                            a.lerp(b, 0.5)
                        }
                        _ => DVec2::new(s.uniform_in(-0.5, 4.5), s.uniform_in(-0.5, 3.5)),
                    })
                    .collect();
                let mut all = more.clone();
                all.extend_from_slice(pts);
                more.retain(|&d| !DVec2::strictly_inside(&vertices, d));
                more.extend_from_slice(&vertices);
                assert_eq!(
                    DVec2::hull_measure(&more).to_bits(),
                    DVec2::hull_measure(&all).to_bits(),
                    "set {k}, trial {trial}"
                );
            }
        }
    }

    #[test]
    fn degenerate_sets() {
        assert_eq!(DVec2::hull_measure(&[]), 0.0);
        assert_eq!(DVec2::diameter(&[DVec2::ONE]), 0.0);
        let line: Vec<DVec2> = (0..5).map(|i| DVec2::new(i as f64, 0.0)).collect();
        assert_eq!(DVec2::hull_measure(&line), 0.0);
        assert!((DVec2::diameter(&line) - 4.0).abs() < 1e-12);
    }

    #[test]
    fn diameter_matches_brute_force() {
        let mut s = crate::rng::Stream::new(1, 1, 1, 1);
        for _ in 0..20 {
            let pts: Vec<DVec2> = (0..60)
                .map(|_| DVec2::new(s.uniform_in(-5.0, 5.0), s.uniform_in(-3.0, 3.0)))
                .collect();
            let mut brute: f64 = 0.0;
            for a in &pts {
                for b in &pts {
                    brute = brute.max(a.distance(*b));
                }
            }
            assert!((DVec2::diameter(&pts) - brute).abs() < 1e-12);
        }
    }
}
