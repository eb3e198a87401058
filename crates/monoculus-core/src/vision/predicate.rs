//! The exact visibility predicate of SPEC section 2, shared by every path.
//!
//! All visibility answers (brute force, angular sweep, band grid, R-tree) end in these two
//! functions, so fast paths differ from the oracle only in which candidates they test,
//! never in how a candidate is judged.

use super::VisionParams;
use crate::geometry::{Point, angle_between};

/// Whether robot position `r` blocks the view from `p` to `q`: `r` is farther than
/// `eps_pos` from `p` (a robot at the observer's own position has no direction and
/// blocks nothing), nearer than `|q - p| - eps_pos`, and within `eps_ang` of the ray.
/// With fat robots (SPEC 9.3, radius `robot_radius` > 0) also when `r` is nearer than
/// `q` and the segment from `p` to `q` passes within the radius of it.
#[inline]
pub fn blocks<P: Point>(p: P, r: P, q: P, v: &VisionParams) -> bool {
    let dr = r - p;
    let dq = q - p;
    let lr = dr.length();
    if lr <= v.eps_pos {
        return false;
    }
    let lq = dq.length();
    if lr < lq - v.eps_pos && angle_between(dr, dq) <= v.eps_ang {
        return true;
    }
    v.fat() && lr < lq && segment_distance(dr, dq) <= v.robot_radius
}

/// The distance from the point `r` to the segment from the origin to `q`.
#[inline]
pub fn segment_distance<P: Point>(r: P, q: P) -> f64 {
    let t = (r.dot(q) / q.dot(q)).clamp(0.0, 1.0);
    (r - q * t).length()
}

/// Whether `q` lies within the visibility range of the observer at `p` (SPEC 9.2:
/// `|q - p| <= V`; always, when the range is unlimited). Blockers need no test: a
/// blocker of `q` is nearer than `q`.
#[inline]
pub fn in_range<P: Point>(p: P, q: P, v: &VisionParams) -> bool {
    !v.limited() || (q - p).length() <= v.range
}

/// Whether `q` is far enough from the observer at `p` to be seen at all.
#[inline]
pub fn distinct<P: Point>(p: P, q: P, v: &VisionParams) -> bool {
    (q - p).length() > v.eps_pos
}
