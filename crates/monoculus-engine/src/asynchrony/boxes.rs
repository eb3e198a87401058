//! Boxes for the kept hulls' inside tests: boxes strictly inside a convex polygon (tried
//! before its exact test), its bounding box, and the boxes that hold what a hull lost
//! when it shrank.

use crate::IndexPoint;

/// Closed boxes strictly inside a convex polygon, tried before its exact test: one
/// shrunk about the mean of its vertices, one nearly as wide as the polygon and one
/// nearly as tall (a polygon with its corners cut, such as a swarm's hull, holds a
/// cross of them beside the first); `None` where none fits.
pub(crate) type InnerBoxes<P> = [Option<(P, P)>; 3];

/// [`InnerBoxes`] of the convex polygon `poly` (counter-clockwise, in the plane): its
/// bounding box scaled about the mean of its vertices, by the same factor on both axes
/// or by nearly one on one axis, each the largest tried whose four corners are strictly
/// inside (then so is the whole box); none in space or for fewer than three vertices.
pub(crate) fn inner_boxes<P: IndexPoint>(poly: &[P]) -> InnerBoxes<P> {
    if P::DIM != 2 || poly.len() < 3 {
        return [None; 3];
    }
    let (lo, hi) = monoculus_core::metrics::bounds(poly);
    let centre = poly.iter().fold(P::zero(), |c, &v| c + v) * (1.0 / poly.len() as f64);
    let at = |x: f64, y: f64| P::unit_axis(0) * x + P::unit_axis(1) * y;
    // The bounding box scaled by `sx` across and `sy` down, if it fits.
    let scaled = |sx: f64, sy: f64| {
        let shrink = |c: f64, v: f64, s: f64| c + (v - c) * s;
        let (x0, x1) = (
            shrink(centre.axis(0), lo.axis(0), sx),
            shrink(centre.axis(0), hi.axis(0), sx),
        );
        let (y0, y1) = (
            shrink(centre.axis(1), lo.axis(1), sy),
            shrink(centre.axis(1), hi.axis(1), sy),
        );
        [at(x0, y0), at(x1, y0), at(x1, y1), at(x0, y1)]
            .iter()
            .all(|&c| P::strictly_inside(poly, c))
            .then_some((at(x0, y0), at(x1, y1)))
    };
    const EVEN: [f64; 9] = [0.95, 0.925, 0.9, 0.85, 0.8, 0.7, 0.6, 0.5, 0.35];
    const NEARLY_ALL: [f64; 2] = [0.99, 0.97];
    const ACROSS: [f64; 6] = [0.9, 0.8, 0.7, 0.6, 0.5, 0.35];
    let long = |wide: bool| {
        NEARLY_ALL.iter().find_map(|&long| {
            ACROSS.iter().find_map(|&short| {
                if wide {
                    scaled(long, short)
                } else {
                    scaled(short, long)
                }
            })
        })
    };
    [
        EVEN.iter().find_map(|&s| scaled(s, s)),
        long(true),
        long(false),
    ]
}

/// The bounding box of the convex polygon `poly` in the plane (`None` in space, or for
/// fewer than three vertices): every point strictly inside the polygon is in it.
pub(super) fn outer_box<P: IndexPoint>(poly: &[P]) -> Option<(P, P)> {
    (P::DIM == 2 && poly.len() >= 3).then(|| monoculus_core::metrics::bounds(poly))
}

/// Whether `p` may lie strictly inside a polygon with the bounding box `bounds`: it
/// lies in that closed box, or there is none.
#[inline]
pub(super) fn may_be_in<P: IndexPoint>(bounds: Option<(P, P)>, p: P) -> bool {
    bounds.is_none_or(|b| in_box(Some(b), p))
}

/// Whether `p` lies in one of the closed boxes.
#[inline]
pub(crate) fn in_boxes<P: IndexPoint>(boxes: &InnerBoxes<P>, p: P) -> bool {
    boxes.iter().any(|&b| in_box(b, p))
}

/// Whether `p` lies in the closed box (if any).
#[inline]
pub(super) fn in_box<P: IndexPoint>(boxed: Option<(P, P)>, p: P) -> bool {
    boxed.is_some_and(|(a, b)| {
        (p.axis(0) >= a.axis(0))
            & (p.axis(0) <= b.axis(0))
            & (p.axis(1) >= a.axis(1))
            & (p.axis(1) <= b.axis(1))
    })
}

/// Closed boxes that hold every point strictly inside the convex polygon `before` and
/// not strictly inside `after` (both as [`HullGeometry::hull_vertices`] gives them, in
/// the plane).
///
/// The vertices of `before` that are still vertices of `after` span a convex polygon
/// inside `after`; `before` is that polygon and the caps its chords cut off, each a
/// stretch of lost vertices and the two kept ones at its ends. A point strictly inside
/// `before` and outside every cap is in that polygon and not on its boundary (its
/// edges are edges of `before`, which the point is not on, or chords, which lie in the
/// caps), so it is strictly inside `after`. Each cap is given as its bounding box. With
/// fewer than two vertices kept, or a degenerate polygon either side, the box of all of
/// `before`.
///
/// [`HullGeometry::hull_vertices`]: monoculus_core::geometry::HullGeometry::hull_vertices
pub(super) fn lost_ground<P: IndexPoint>(before: &[P], after: &[P]) -> Vec<(P, P)> {
    let order =
        |a: &P, b: &P| (a.axis(0).total_cmp(&b.axis(0))).then(a.axis(1).total_cmp(&b.axis(1)));
    let mut sorted = after.to_vec();
    sorted.sort_unstable_by(order);
    let kept: Vec<bool> = before
        .iter()
        .map(|v| sorted.binary_search_by(|p| order(p, v)).is_ok())
        .collect();
    let h = before.len();
    if P::DIM != 2 || h < 3 || after.len() < 3 || kept.iter().filter(|&&k| k).count() < 2 {
        return if h == 0 {
            Vec::new()
        } else {
            vec![monoculus_core::metrics::bounds(before)]
        };
    }
    let first = kept.iter().position(|&k| k).unwrap_or(0);
    // From each kept vertex followed by lost ones, through the next kept vertex.
    let mut caps = Vec::new();
    let mut cap: Vec<P> = Vec::new();
    for step in 1..=h {
        let (at, previous) = ((first + step) % h, (first + step - 1) % h);
        if !kept[at] {
            if cap.is_empty() {
                cap.push(before[previous]);
            }
            cap.push(before[at]);
        } else if !cap.is_empty() {
            cap.push(before[at]);
            caps.push(monoculus_core::metrics::bounds(&cap));
            cap.clear();
        }
    }
    caps
}
