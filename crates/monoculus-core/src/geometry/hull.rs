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
    /// The vertices of the convex hull, in an order [`HullGeometry::strictly_inside`]
    /// understands (empty where no fast inside test exists).
    fn hull_vertices(_points: &[Self]) -> Vec<Self> {
        Vec::new()
    }
    /// The same vertices, sorting the points starting from `order` (robot indices in
    /// the order the last call sorted them, or empty), which is updated. Sorting is
    /// adaptive: when few robots moved since, it costs about O(n), not O(n log n).
    fn hull_vertices_from(points: &[Self], _order: &mut Vec<u32>) -> Vec<Self> {
        Self::hull_vertices(points)
    }
    /// Whether `p` lies strictly inside the hull with these vertices, by a margin that
    /// rounding cannot cross; `false` when unsure. Adding such points to a set leaves
    /// its hull exactly as it is.
    fn strictly_inside(_hull: &[Self], _p: Self) -> bool {
        false
    }
}

/// The convex hull of a planar point set, counter-clockwise, without collinear
/// points on its edges (Andrew's monotone chain, O(n log n)).
pub fn convex_hull_2d(points: &[DVec2]) -> Vec<DVec2> {
    let mut pts: Vec<DVec2> = points.to_vec();
    pts.sort_by(by_x_then_y);
    monotone_chain(pts)
}

/// The order of the monotone chain. Total on the values: equal keys are equal points, so
/// the sorted sequence does not depend on the order the points come in.
fn by_x_then_y(a: &DVec2, b: &DVec2) -> std::cmp::Ordering {
    a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y))
}

/// [`convex_hull_2d`], sorting from the order of the previous call (see
/// [`HullGeometry::hull_vertices_from`]): the same vertices.
pub fn convex_hull_2d_from(points: &[DVec2], order: &mut Vec<u32>) -> Vec<DVec2> {
    if order.len() != points.len() {
        *order = (0..points.len() as u32).collect();
    }
    let mut keyed: Vec<(DVec2, u32)> = order.iter().map(|&i| (points[i as usize], i)).collect();
    keyed.sort_by(|a, b| by_x_then_y(&a.0, &b.0));
    for (slot, &(_, i)) in order.iter_mut().zip(&keyed) {
        *slot = i;
    }
    monotone_chain(keyed.into_iter().map(|(p, _)| p).collect())
}

/// Andrew's monotone chain over points sorted by [`by_x_then_y`].
fn monotone_chain(mut pts: Vec<DVec2>) -> Vec<DVec2> {
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(2 * pts.len());
    for &p in &pts {
        while hull.len() >= 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
            hull.pop();
        }
        hull.push(p);
    }
    let lower_len = hull.len() + 1;
    for &p in pts.iter().rev().skip(1) {
        while hull.len() >= lower_len && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
        {
            hull.pop();
        }
        hull.push(p);
    }
    hull.pop();
    hull
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

    fn hull_vertices_from(points: &[Self], order: &mut Vec<u32>) -> Vec<Self> {
        convex_hull_2d_from(points, order)
    }

    /// O(log h): find the wedge from vertex 0 containing `p`, then test the edge.
    fn strictly_inside(hull: &[Self], p: Self) -> bool {
        let h = hull.len();
        if h < 3 {
            return false;
        }
        let scale = hull
            .iter()
            .fold(p.abs().max_element(), |m, v| m.max(v.abs().max_element()));
        let margin = 1e-9 * scale * scale;
        let o = hull[0];
        let cross = |a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
        // Counter-clockwise: p must be left of o->hull[1] and right of o->hull[h-1].
        if cross(hull[1], p) <= margin || cross(hull[h - 1], p) >= -margin {
            return false;
        }
        let (mut lo, mut hi) = (1, h - 1);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if cross(hull[mid], p) > 0.0 {
                lo = mid
            } else {
                hi = mid
            }
        }
        (hull[hi] - hull[lo]).perp_dot(p - hull[lo]) > margin
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sorting from a stale order (after some points moved), from a shuffled one, or
    /// with duplicates and signed zeros gives the very same vertices as sorting afresh.
    #[test]
    fn hull_from_a_previous_order_is_the_hull() {
        let mut rng = crate::rng::Stream::new(5, 0, 0, 0);
        let mut pts: Vec<DVec2> = (0..300)
            .map(|_| DVec2::new(rng.uniform_in(-3.0, 3.0), rng.uniform_in(-3.0, 3.0)))
            .collect();
        pts.extend([DVec2::new(0.0, -0.0), DVec2::new(-0.0, 0.0), pts[7], pts[7]]);
        let mut order = Vec::new();
        for round in 0..50 {
            assert_eq!(
                convex_hull_2d_from(&pts, &mut order),
                convex_hull_2d(&pts),
                "round {round}"
            );
            let mut sorted = order.clone();
            sorted.sort_unstable();
            assert!(sorted.iter().enumerate().all(|(k, &i)| k == i as usize));
            // A few robots move, some to the hull and beyond it.
            for _ in 0..(1 + round % 7) {
                let i = rng.below(pts.len());
                pts[i] += DVec2::new(rng.uniform_in(-2.0, 2.0), rng.uniform_in(-2.0, 2.0));
            }
            if round % 10 == 9 {
                order = rng
                    .permutation(pts.len())
                    .into_iter()
                    .map(|i| i as u32)
                    .collect();
            }
        }
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
