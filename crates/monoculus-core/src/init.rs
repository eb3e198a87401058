//! Initial configurations (SPEC section 8), seeded. Reading positions from a file is
//! I/O and lives in the experiments crate.

use crate::geometry::{MAX_DIM, Point};
use crate::rng::Stream;

/// A generated initial shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InitShape {
    /// Uniform in the axis-aligned cube [0, side]^d (the paper's setting).
    Square {
        /// Side length L.
        side: f64,
    },
    /// Uniform in the ball of diameter `side` centred at (side/2, ..).
    Disc {
        /// Diameter.
        side: f64,
    },
    /// Uniform on the segment from the origin to (side, 0, ..): all robots collinear.
    Line {
        /// Length.
        side: f64,
    },
    /// The first n points, row by row, of a k^d grid filling [0, side]^d
    /// (k = ceil(n^(1/d))): many collinear triples, so occlusion matters. Deterministic.
    Lattice {
        /// Side length.
        side: f64,
    },
    /// `clusters` centres uniform in [0, side]^d; robot i joins centre i mod clusters,
    /// offset by a normal deviate of standard deviation `spread` on each axis.
    Clusters {
        /// Side of the square the centres are drawn in.
        side: f64,
        /// Number of clusters.
        clusters: usize,
        /// Standard deviation of the offsets.
        spread: f64,
    },
}

/// `n` robots in `shape`, drawn from the stream of `seed`.
pub fn generate<P: Point>(shape: &InitShape, n: usize, seed: u64) -> Vec<P> {
    let mut s = Stream::keyed(seed, crate::rng::Purpose::Init, 0, 0);
    let d = P::DIM;
    let mut c = [0.0; MAX_DIM];
    match *shape {
        InitShape::Square { side } => (0..n)
            .map(|_| {
                for x in c.iter_mut().take(d) {
                    *x = s.uniform() * side;
                }
                P::from_slice(&c)
            })
            .collect(),
        InitShape::Disc { side } => (0..n)
            .map(|_| {
                loop {
                    for x in c.iter_mut().take(d) {
                        *x = s.uniform_in(-1.0, 1.0);
                    }
                    let v = P::from_slice(&c);
                    if v.length_squared() <= 1.0 {
                        break P::from_slice(&[side / 2.0; MAX_DIM]) + v * (side / 2.0);
                    }
                }
            })
            .collect(),
        InitShape::Line { side } => (0..n)
            .map(|_| {
                let mut c = [0.0; MAX_DIM];
                c[0] = s.uniform() * side;
                P::from_slice(&c)
            })
            .collect(),
        InitShape::Lattice { side } => {
            let mut k = (n as f64).powf(1.0 / d as f64).ceil().max(1.0) as usize;
            while k.pow(d as u32) < n {
                k += 1;
            }
            let spacing = if k > 1 { side / (k - 1) as f64 } else { 0.0 };
            (0..n)
                .map(|i| {
                    let mut rest = i;
                    for x in c.iter_mut().take(d) {
                        *x = (rest % k) as f64 * spacing;
                        rest /= k;
                    }
                    P::from_slice(&c)
                })
                .collect()
        }
        InitShape::Clusters {
            side,
            clusters,
            spread,
        } => {
            let clusters = clusters.max(1);
            let centres: Vec<P> = (0..clusters)
                .map(|_| {
                    for x in c.iter_mut().take(d) {
                        *x = s.uniform() * side;
                    }
                    P::from_slice(&c)
                })
                .collect();
            (0..n)
                .map(|i| {
                    for x in c.iter_mut().take(d) {
                        *x = s.normal() * spread;
                    }
                    centres[i % clusters] + P::from_slice(&c)
                })
                .collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn shapes_have_n_points_in_range_and_are_seeded() {
        let shapes = [
            InitShape::Square { side: 10.0 },
            InitShape::Disc { side: 10.0 },
            InitShape::Line { side: 10.0 },
            InitShape::Lattice { side: 10.0 },
            InitShape::Clusters {
                side: 10.0,
                clusters: 3,
                spread: 0.5,
            },
        ];
        for shape in &shapes {
            let a: Vec<DVec2> = generate(shape, 50, 1);
            let b: Vec<DVec2> = generate(shape, 50, 1);
            assert_eq!(a.len(), 50);
            assert_eq!(a, b);
            if !matches!(shape, InitShape::Clusters { .. }) {
                for p in &a {
                    assert!(
                        p.x >= -1e-12
                            && p.x <= 10.0 + 1e-12
                            && p.y >= -1e-12
                            && p.y <= 10.0 + 1e-12
                    );
                }
            }
        }
        let disc: Vec<DVec2> = generate(&InitShape::Disc { side: 10.0 }, 200, 3);
        assert!(
            disc.iter()
                .all(|p| p.distance(DVec2::splat(5.0)) <= 5.0 + 1e-12)
        );
        let line: Vec<DVec2> = generate(&InitShape::Line { side: 10.0 }, 20, 3);
        assert!(line.iter().all(|p| p.y == 0.0));
        let lattice: Vec<DVec2> = generate(&InitShape::Lattice { side: 10.0 }, 9, 0);
        assert_eq!(lattice[4], DVec2::new(5.0, 5.0));
        let other: Vec<DVec2> = generate(&InitShape::Square { side: 10.0 }, 50, 2);
        assert_ne!(
            other,
            generate::<DVec2>(&InitShape::Square { side: 10.0 }, 50, 1)
        );
    }
}
