//! Per-run metrics of SPEC section 6 that are pure geometry.

use crate::geometry::Point;

/// The centroid of a non-empty point set.
pub fn centroid<P: Point>(points: &[P]) -> P {
    let mut sum = P::zero();
    for &p in points {
        sum += p;
    }
    sum * (1.0 / points.len().max(1) as f64)
}

/// Smallest and largest coordinate on each axis (both the origin for no points).
pub fn bounds<P: Point>(points: &[P]) -> (P, P) {
    let Some(&first) = points.first() else {
        return (P::zero(), P::zero());
    };
    points.iter().fold((first, first), |(lo, hi), &p| {
        (lo.min_by_axis(p), hi.max_by_axis(p))
    })
}

/// Extent of the bounding box on each axis.
pub fn extents<P: Point>(points: &[P]) -> P {
    let (lo, hi) = bounds(points);
    hi - lo
}

/// `d_opt`: the total distance the robots must travel, at the least, to gather inside
/// the ball of diameter `locality` centred at the initial centroid:
/// sum over i of max(0, |p_i - g| - c/2).
pub fn d_opt<P: Point>(points: &[P], locality: f64) -> f64 {
    let g = centroid(points);
    points
        .iter()
        .map(|&p| ((p - g).length() - locality / 2.0).max(0.0))
        .sum()
}

/// `d_max`: the largest distance of a robot from the centroid.
pub fn d_max<P: Point>(points: &[P]) -> f64 {
    let g = centroid(points);
    points.iter().map(|&p| (p - g).length()).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn d_opt_and_d_max_on_a_known_set() {
        let pts = [
            DVec2::new(-3.0, 0.0),
            DVec2::new(3.0, 0.0),
            DVec2::new(0.0, 0.5),
        ];
        // centroid (0, 1/6)
        let g = centroid(&pts);
        assert!((g - DVec2::new(0.0, 1.0 / 6.0)).length() < 1e-12);
        let di: Vec<f64> = pts.iter().map(|p| (*p - g).length()).collect();
        let expect: f64 = di.iter().map(|d| (d - 1.0).max(0.0)).sum();
        assert!((d_opt(&pts, 2.0) - expect).abs() < 1e-12);
        assert!((d_max(&pts) - di[0]).abs() < 1e-12);
        assert_eq!(extents(&pts), DVec2::new(6.0, 0.5));
    }
}
