//! The smallest enclosing disc (ball in space) of a point set: Welzl's randomized
//! incremental algorithm, expected linear time, in any dimension the [`Point`] trait
//! has.
//!
//! ConvergeLocality's theorem states its goal with it (SPEC section 11): every robot
//! within a disc of radius c.

use super::Point;
use crate::rng::Stream;

/// A ball: its centre and radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball<P> {
    /// The centre.
    pub center: P,
    /// The radius (0 for a single point).
    pub radius: f64,
}

/// Points this much (relative to the radius) outside a ball still count as inside it:
/// the points that define a ball lie on its boundary only up to rounding.
const SLACK: f64 = 1e-12;

impl<P: Point> Ball<P> {
    fn point(p: P) -> Self {
        Ball {
            center: p,
            radius: 0.0,
        }
    }

    /// Whether `p` lies in the ball, up to rounding.
    pub fn contains(&self, p: P) -> bool {
        (p - self.center).length() <= self.radius * (1.0 + SLACK)
    }

    /// The ball with `a` and `b` at the ends of a diameter.
    fn two(a: P, b: P) -> Self {
        Ball {
            center: (a + b) * 0.5,
            radius: (a - b).length() * 0.5,
        }
    }

    /// The smallest ball with `a`, `b` and `c` on its boundary: their circumscribed
    /// circle's (its centre in their plane). Points on a line have none: the smallest
    /// ball holding all three then.
    fn three(a: P, b: P, c: P) -> Self {
        let (u, v) = (b - a, c - a);
        match solve(&[u, v]) {
            Some(x) => {
                let center = a + u * x[0] + v * x[1];
                Ball {
                    center,
                    radius: max_distance(center, &[a, b, c]),
                }
            }
            None => smallest_holding(&[a, b, c]),
        }
    }

    /// The ball with `a`, `b`, `c` and `d` on its boundary (space only); four points in a
    /// plane have none: the smallest ball holding all four then.
    fn four(a: P, b: P, c: P, d: P) -> Self {
        let (u, v, w) = (b - a, c - a, d - a);
        match solve(&[u, v, w]) {
            Some(x) => {
                let center = a + u * x[0] + v * x[1] + w * x[2];
                Ball {
                    center,
                    radius: max_distance(center, &[a, b, c, d]),
                }
            }
            None => smallest_holding(&[a, b, c, d]),
        }
    }
}

fn max_distance<P: Point>(center: P, points: &[P]) -> f64 {
    points
        .iter()
        .map(|&p| (p - center).length())
        .fold(0.0, f64::max)
}

/// The smallest ball holding every one of a few points (at most 4), by trying the balls
/// of their pairs and triples: for the degenerate cases of [`Ball::three`] and
/// [`Ball::four`].
fn smallest_holding<P: Point>(points: &[P]) -> Ball<P> {
    let mut best: Option<Ball<P>> = None;
    let mut consider = |b: Ball<P>| {
        if points.iter().all(|&p| b.contains(p)) && best.is_none_or(|x| b.radius < x.radius) {
            best = Some(b);
        }
    };
    for i in 0..points.len() {
        for j in i + 1..points.len() {
            consider(Ball::two(points[i], points[j]));
            for k in j + 1..points.len() {
                let (a, b, c) = (points[i], points[j], points[k]);
                if solve(&[b - a, c - a]).is_some() {
                    consider(Ball::three(a, b, c));
                }
            }
        }
    }
    best.unwrap_or_else(|| Ball::point(points[0]))
}

/// The coefficients x of the centre a + sum x_k u_k of the sphere through a and a + u_k,
/// in the span of the u_k: the Gram system G x = (|u_k|^2 / 2), by Cramer's rule. `None`
/// when the u_k are (nearly) linearly dependent.
fn solve<P: Point>(u: &[P]) -> Option<[f64; 3]> {
    let k = u.len();
    let mut g = [[0.0; 3]; 3];
    let mut rhs = [0.0; 3];
    for i in 0..k {
        for j in 0..k {
            g[i][j] = u[i].dot(u[j]);
        }
        rhs[i] = g[i][i] / 2.0;
    }
    let scale: f64 = (0..k).map(|i| g[i][i]).product();
    let det = |m: &[[f64; 3]; 3]| match k {
        2 => m[0][0] * m[1][1] - m[0][1] * m[1][0],
        _ => {
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        }
    };
    let d = det(&g);
    // (NaN, from points at infinity, is dependent too.)
    if d.is_nan() || d.abs() <= 1e-12 * scale {
        return None;
    }
    let mut x = [0.0; 3];
    for (c, xc) in x.iter_mut().enumerate().take(k) {
        let mut m = g;
        for r in 0..k {
            m[r][c] = rhs[r];
        }
        *xc = det(&m) / d;
    }
    Some(x)
}

/// The smallest disc (d = 2) or ball (d = 3) holding every point of `points`; `None` for
/// no points. The points are visited in an order drawn from a fixed stream, so the
/// result is the same on every call.
///
/// ```
/// use glam::DVec2;
/// use monoculus_core::geometry::enclosing_ball;
///
/// // A 3 x 3 lattice of spacing 0.8: diameter 2.26, inside a disc of radius 1.13.
/// let lattice: Vec<DVec2> = (0..9)
///     .map(|k| DVec2::new((k % 3) as f64 * 0.8, (k / 3) as f64 * 0.8))
///     .collect();
/// let ball = enclosing_ball(&lattice).unwrap();
/// assert!((ball.radius - 0.8 * 2f64.sqrt()).abs() < 1e-12);
/// assert!((ball.center - DVec2::new(0.8, 0.8)).length() < 1e-12);
/// ```
pub fn enclosing_ball<P: Point>(points: &[P]) -> Option<Ball<P>> {
    let mut p = points.to_vec();
    // Welzl's expected linear time needs a random order; a fixed stream keeps it
    // reproducible.
    let mut rng = Stream::new(0x454e_434c, 0, p.len() as u64, 0);
    for i in (1..p.len()).rev() {
        p.swap(i, rng.below(i + 1));
    }
    let mut ball = Ball::point(*p.first()?);
    for i in 1..p.len() {
        if ball.contains(p[i]) {
            continue;
        }
        ball = Ball::point(p[i]);
        for j in 0..i {
            if ball.contains(p[j]) {
                continue;
            }
            ball = Ball::two(p[i], p[j]);
            for k in 0..j {
                if ball.contains(p[k]) {
                    continue;
                }
                ball = Ball::three(p[i], p[j], p[k]);
                if P::DIM < 3 {
                    continue;
                }
                for l in 0..k {
                    if !ball.contains(p[l]) {
                        ball = Ball::four(p[i], p[j], p[k], p[l]);
                    }
                }
            }
        }
    }
    Some(ball)
}

/// The radius of [`enclosing_ball`] (0 for no points).
pub fn enclosing_radius<P: Point>(points: &[P]) -> f64 {
    enclosing_ball(points).map_or(0.0, |b| b.radius)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, DVec3};

    /// The oracle: every ball of two, three (and in space four) of the points, the
    /// smallest that holds them all.
    fn brute<P: Point>(points: &[P]) -> f64 {
        let n = points.len();
        let mut best = f64::INFINITY;
        let mut consider = |b: Ball<P>| {
            let r = max_distance(b.center, points);
            if r <= b.radius * (1.0 + 1e-9) + 1e-12 {
                best = best.min(b.radius);
            }
        };
        if n == 1 {
            return 0.0;
        }
        for i in 0..n {
            for j in i + 1..n {
                consider(Ball::two(points[i], points[j]));
                for k in j + 1..n {
                    consider(Ball::three(points[i], points[j], points[k]));
                    if P::DIM == 3 {
                        for l in k + 1..n {
                            consider(Ball::four(points[i], points[j], points[k], points[l]));
                        }
                    }
                }
            }
        }
        best
    }

    fn check<P: Point>(points: &[P], what: &str) {
        let ball = enclosing_ball(points).unwrap();
        for &p in points {
            assert!(
                (p - ball.center).length() <= ball.radius * (1.0 + 1e-9) + 1e-12,
                "{what}: {p:?} outside {ball:?}"
            );
        }
        let want = brute(points);
        assert!(
            (ball.radius - want).abs() <= 1e-9 * want.max(1e-12),
            "{what}: radius {} against {want}",
            ball.radius
        );
    }

    #[test]
    fn matches_the_oracle_in_the_plane() {
        let mut rng = Stream::new(1, 2, 3, 4);
        for case in 0..300 {
            let n = 1 + rng.below(14);
            let pts: Vec<DVec2> = match case % 4 {
                // Uniform in a square.
                0 => (0..n)
                    .map(|_| DVec2::new(rng.uniform() * 10.0, rng.uniform() * 10.0))
                    .collect(),
                // A lattice: many collinear and cocircular points.
                1 => (0..n)
                    .map(|_| DVec2::new(rng.below(4) as f64, rng.below(4) as f64))
                    .collect(),
                // One line.
                2 => (0..n)
                    .map(|_| {
                        let t = rng.uniform() * 7.0;
                        DVec2::new(1.0 + 2.0 * t, -3.0 + t)
                    })
                    .collect(),
                // On one circle, some twice.
                _ => (0..n)
                    .map(|_| {
                        let a = rng.below(6) as f64 * std::f64::consts::PI / 3.0;
                        DVec2::new(5.0 + 2.0 * a.cos(), 2.0 * a.sin())
                    })
                    .collect(),
            };
            check(&pts, &format!("plane case {case}: {pts:?}"));
        }
    }

    #[test]
    fn matches_the_oracle_in_space() {
        let mut rng = Stream::new(5, 6, 7, 8);
        for case in 0..200 {
            let n = 1 + rng.below(11);
            let pts: Vec<DVec3> = match case % 4 {
                0 => (0..n)
                    .map(|_| DVec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 10.0)
                    .collect(),
                1 => (0..n)
                    .map(|_| {
                        DVec3::new(
                            rng.below(3) as f64,
                            rng.below(3) as f64,
                            rng.below(3) as f64,
                        )
                    })
                    .collect(),
                // In one plane.
                2 => (0..n)
                    .map(|_| DVec3::new(rng.uniform() * 4.0, rng.uniform() * 4.0, 1.5))
                    .collect(),
                // On one line.
                _ => (0..n)
                    .map(|_| DVec3::new(1.0, 2.0, 3.0) * rng.uniform())
                    .collect(),
            };
            check(&pts, &format!("space case {case}: {pts:?}"));
        }
    }

    #[test]
    fn small_sets() {
        assert!(enclosing_ball::<DVec2>(&[]).is_none());
        assert_eq!(enclosing_radius::<DVec2>(&[]), 0.0);
        let one = [DVec2::new(3.0, 4.0)];
        assert_eq!(enclosing_ball(&one).unwrap().radius, 0.0);
        let same = [DVec3::new(1.0, 1.0, 1.0); 5];
        assert_eq!(enclosing_radius(&same), 0.0);
        // An equilateral triangle of side 2: radius 2 / sqrt(3).
        let tri = [
            DVec2::new(0.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(1.0, 3f64.sqrt()),
        ];
        assert!((enclosing_radius(&tri) - 2.0 / 3f64.sqrt()).abs() < 1e-12);
        // An obtuse triangle: the longest side's diametral disc.
        let obtuse = [
            DVec2::new(0.0, 0.0),
            DVec2::new(4.0, 0.0),
            DVec2::new(2.0, 0.5),
        ];
        assert!((enclosing_radius(&obtuse) - 2.0).abs() < 1e-12);
        // A regular tetrahedron of edge sqrt(8): radius sqrt(3).
        let tet = [
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(-1.0, -1.0, 1.0),
        ];
        assert!((enclosing_radius(&tet) - 3f64.sqrt()).abs() < 1e-12);
    }
}
