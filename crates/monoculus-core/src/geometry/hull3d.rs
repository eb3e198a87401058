//! Convex hulls in space: volume and diameter (incremental construction).

use std::collections::BTreeSet;

use glam::DVec3;

use super::HullGeometry;

/// The triangles (vertex indices, counter-clockwise seen from outside) of the convex
/// hull of `points`, or `None` if the points are coplanar (no volume). Incremental
/// construction: O(n h) for h hull faces, cheap for random swarms.
pub fn convex_hull_3d(points: &[DVec3]) -> Option<Vec<[usize; 3]>> {
    let n = points.len();
    if n < 4 {
        return None;
    }
    let (lo, hi) = points
        .iter()
        .fold((points[0], points[0]), |(l, h), &p| (l.min(p), h.max(p)));
    let scale = (hi - lo).length();
    if scale == 0.0 {
        return None;
    }
    let eps = 1e-12 * scale;
    // An initial tetrahedron: two far-apart points, the farthest from their line, the
    // farthest from their plane.
    let a = (0..n).min_by(|&i, &j| points[i].x.total_cmp(&points[j].x))?;
    let b = (0..n).max_by(|&i, &j| {
        (points[i] - points[a])
            .length_squared()
            .total_cmp(&(points[j] - points[a]).length_squared())
    })?;
    let ab = points[b] - points[a];
    if ab.length() <= eps {
        return None;
    }
    let c = (0..n).max_by(|&i, &j| {
        ab.cross(points[i] - points[a])
            .length_squared()
            .total_cmp(&ab.cross(points[j] - points[a]).length_squared())
    })?;
    let normal = ab.cross(points[c] - points[a]);
    if normal.length() <= eps * ab.length() {
        return None;
    }
    let unit = normal.normalize();
    let d = (0..n).max_by(|&i, &j| {
        unit.dot(points[i] - points[a])
            .abs()
            .total_cmp(&unit.dot(points[j] - points[a]).abs())
    })?;
    if unit.dot(points[d] - points[a]).abs() <= eps {
        return None;
    }
    let inside = (points[a] + points[b] + points[c] + points[d]) * 0.25;
    let outward = |f: [usize; 3]| -> [usize; 3] {
        let nrm = (points[f[1]] - points[f[0]]).cross(points[f[2]] - points[f[0]]);
        if nrm.dot(inside - points[f[0]]) > 0.0 {
            [f[0], f[2], f[1]]
        } else {
            f
        }
    };
    let mut faces: Vec<[usize; 3]> = vec![
        outward([a, b, c]),
        outward([a, b, d]),
        outward([a, c, d]),
        outward([b, c, d]),
    ];
    let sees = |f: &[usize; 3], p: DVec3| {
        let nrm = (points[f[1]] - points[f[0]]).cross(points[f[2]] - points[f[0]]);
        let len = nrm.length();
        len > 0.0 && nrm.dot(p - points[f[0]]) / len > eps
    };
    for (i, &p) in points.iter().enumerate() {
        if [a, b, c, d].contains(&i) {
            continue;
        }
        let visible: Vec<bool> = faces.iter().map(|f| sees(f, p)).collect();
        if !visible.iter().any(|&v| v) {
            continue;
        }
        // An ordered set: the face order, and so the rounding of the volume, must not
        // depend on hashing (results are bitwise reproducible).
        let edges: BTreeSet<(usize, usize)> = faces
            .iter()
            .zip(&visible)
            .filter(|(_, v)| **v)
            .flat_map(|(f, _)| [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])])
            .collect();
        let horizon: Vec<(usize, usize)> = edges
            .iter()
            .copied()
            .filter(|&(u, v)| !edges.contains(&(v, u)))
            .collect();
        let mut kept: Vec<[usize; 3]> = faces
            .iter()
            .zip(&visible)
            .filter(|(_, v)| !**v)
            .map(|(f, _)| *f)
            .collect();
        kept.extend(horizon.into_iter().map(|(u, v)| [u, v, i]));
        faces = kept;
    }
    Some(faces)
}

impl HullGeometry for DVec3 {
    fn hull_measure(points: &[Self]) -> f64 {
        let Some(faces) = convex_hull_3d(points) else {
            return 0.0;
        };
        let o = points[faces[0][0]];
        faces
            .iter()
            .map(|f| (points[f[0]] - o).dot((points[f[1]] - o).cross(points[f[2]] - o)) / 6.0)
            .sum::<f64>()
            .abs()
    }

    fn diameter(points: &[Self]) -> f64 {
        // Realised by two hull vertices; for coplanar sets, by two of the points.
        let candidates: Vec<DVec3> = match convex_hull_3d(points) {
            Some(faces) => {
                let mut v: Vec<usize> = faces.iter().flatten().copied().collect();
                v.sort_unstable();
                v.dedup();
                v.into_iter().map(|i| points[i]).collect()
            }
            None => points.to_vec(),
        };
        let mut best: f64 = 0.0;
        for i in 0..candidates.len() {
            for j in i + 1..candidates.len() {
                best = best.max(candidates[i].distance_squared(candidates[j]));
            }
        }
        best.sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Stream;

    #[test]
    fn volume_is_bitwise_reproducible() {
        let mut s = Stream::new(3, 1, 4, 1);
        let pts: Vec<DVec3> = (0..300)
            .map(|_| DVec3::new(s.uniform(), s.uniform(), s.uniform()))
            .collect();
        let first = DVec3::hull_measure(&pts);
        for _ in 0..20 {
            assert_eq!(DVec3::hull_measure(&pts).to_bits(), first.to_bits());
        }
    }

    #[test]
    fn cube_with_interior_points() {
        let mut pts = vec![];
        for x in [0.0, 2.0] {
            for y in [0.0, 3.0] {
                for z in [0.0, 1.0] {
                    pts.push(DVec3::new(x, y, z));
                }
            }
        }
        let mut s = Stream::new(1, 2, 3, 4);
        for _ in 0..100 {
            pts.push(DVec3::new(
                s.uniform() * 2.0,
                s.uniform() * 3.0,
                s.uniform(),
            ));
        }
        assert!((DVec3::hull_measure(&pts) - 6.0).abs() < 1e-9);
        assert!((DVec3::diameter(&pts) - 14f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn ball_volume_and_degenerate_sets() {
        let mut s = Stream::new(5, 6, 7, 8);
        let pts: Vec<DVec3> = (0..4000)
            .map(|_| DVec3::new(s.normal(), s.normal(), s.normal()).normalize())
            .collect();
        let v = DVec3::hull_measure(&pts);
        let ball = 4.0 / 3.0 * std::f64::consts::PI;
        assert!(v < ball && v > 0.97 * ball, "{v}");
        let flat: Vec<DVec3> = (0..50)
            .map(|_| DVec3::new(s.uniform(), s.uniform(), 0.5))
            .collect();
        assert_eq!(DVec3::hull_measure(&flat), 0.0);
        assert!(DVec3::diameter(&flat) > 0.5);
        assert_eq!(DVec3::hull_measure(&[DVec3::ZERO; 5]), 0.0);
    }

    #[test]
    fn volume_matches_a_random_tetrahedron_and_is_order_independent() {
        let mut s = Stream::new(9, 9, 9, 9);
        for _ in 0..50 {
            let t: Vec<DVec3> = (0..4)
                .map(|_| DVec3::new(s.uniform(), s.uniform(), s.uniform()))
                .collect();
            let exact = (t[1] - t[0]).dot((t[2] - t[0]).cross(t[3] - t[0])).abs() / 6.0;
            let mut pts = t.clone();
            for _ in 0..30 {
                let w: Vec<f64> = (0..4).map(|_| s.uniform()).collect();
                let sum: f64 = w.iter().sum();
                pts.push(
                    t.iter()
                        .zip(&w)
                        .fold(DVec3::ZERO, |acc, (p, w)| acc + *p * (w / sum)),
                );
            }
            assert!(
                (DVec3::hull_measure(&pts) - exact).abs() < 1e-12,
                "inside points change nothing"
            );
            pts.reverse();
            assert!((DVec3::hull_measure(&pts) - exact).abs() < 1e-12);
        }
    }
}
