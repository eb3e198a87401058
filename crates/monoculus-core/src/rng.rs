//! Seeded, portable random streams.
//!
//! One seed drives a run. Every random decision draws from a [`Stream`] keyed by
//! `(seed, purpose, robot, round)`, so no thread interleaving, and no choice of which
//! robots were skipped, can change a result. The helpers here (uniform floats, bounded
//! integers, normals) are written out rather than taken from `rand`, so that the streams
//! stay bit-identical across versions of the `rand` family.

use rand_core::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// What a stream is used for: part of its key, so that streams never overlap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u64)]
pub enum Purpose {
    /// Initial positions of a run.
    Init = 1,
    /// A robot's decision in one activation (frame, target choice).
    Decide = 2,
    /// The scheduler's activation draws.
    Activate = 3,
    /// A robot's fixed, whole-run frame (termination algorithm).
    RobotFrame = 4,
    /// Observation and movement errors.
    Error = 5,
    /// Which robots are faulty, when they crash (SPEC 9.1).
    Fault = 6,
}

/// SplitMix64 finaliser: a bijective 64-bit mixer.
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A PCG random stream derived from a key.
#[derive(Clone, Debug)]
pub struct Stream {
    rng: Pcg64Mcg,
}

impl Stream {
    /// The stream for `(seed, purpose, robot, round)`; `purpose` is any small tag.
    pub fn new(seed: u64, purpose: u64, robot: u64, round: u64) -> Self {
        let a = mix64(seed ^ mix64(purpose));
        let b = mix64(a ^ mix64(robot.wrapping_add(0x1234_5678)));
        let c = mix64(b ^ mix64(round.wrapping_add(0xABCD_EF01)));
        let mut bytes = [0u8; 16];
        bytes[..8].copy_from_slice(&c.to_le_bytes());
        bytes[8..].copy_from_slice(&mix64(c ^ 0x5151_5151).to_le_bytes());
        Stream {
            rng: Pcg64Mcg::from_seed(bytes),
        }
    }

    /// The stream for a [`Purpose`].
    pub fn keyed(seed: u64, purpose: Purpose, robot: u64, round: u64) -> Self {
        Self::new(seed, purpose as u64, robot, round)
    }

    /// 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.rng.next_u64()
    }

    /// Uniform in [0, 1), with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    pub fn uniform_in(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// A fair coin.
    pub fn coin(&mut self) -> bool {
        self.next_u64() >> 63 == 1
    }

    /// True with probability `p`.
    pub fn bernoulli(&mut self, p: f64) -> bool {
        self.uniform() < p
    }

    /// Uniform integer in `0..n` (`n > 0`), by Lemire's multiply-shift with rejection,
    /// so exactly uniform: a draw whose low word is below `2^64 mod n` is rejected.
    /// That bound is below `n`, so it is computed (a 64-bit division, the main cost of
    /// a draw) only for the rare draws whose low word is below `n`; the draws kept are
    /// the same either way.
    #[inline]
    pub fn below(&mut self, n: usize) -> usize {
        debug_assert!(n > 0);
        let n = n as u64;
        let mut m = (self.next_u64() as u128) * (n as u128);
        if (m as u64) < n {
            let threshold = n.wrapping_neg() % n;
            while (m as u64) < threshold {
                m = (self.next_u64() as u128) * (n as u128);
            }
        }
        (m >> 64) as usize
    }

    /// A standard normal deviate (Box-Muller).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform(); // (0, 1]
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }

    /// A uniformly random permutation of `0..n` (Fisher-Yates).
    pub fn permutation(&mut self, n: usize) -> Vec<usize> {
        let mut p: Vec<usize> = (0..n).collect();
        for i in (1..n).rev() {
            let j = self.below(i + 1);
            p.swap(i, j);
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let a: Vec<u64> = (0..4).map(|_| Stream::new(1, 2, 3, 4).next_u64()).collect();
        assert!(a.windows(2).all(|w| w[0] == w[1]));
        let keys = [
            (1, 2, 3, 4),
            (2, 2, 3, 4),
            (1, 3, 3, 4),
            (1, 2, 4, 4),
            (1, 2, 3, 5),
        ];
        let firsts: Vec<u64> = keys
            .iter()
            .map(|&(s, p, r, t)| Stream::new(s, p, r, t).next_u64())
            .collect();
        for i in 0..firsts.len() {
            for j in i + 1..firsts.len() {
                assert_ne!(firsts[i], firsts[j]);
            }
        }
    }

    #[test]
    fn below_is_uniform_enough() {
        let mut s = Stream::new(9, 9, 9, 9);
        let mut counts = [0usize; 7];
        for _ in 0..70_000 {
            counts[s.below(7)] += 1;
        }
        for c in counts {
            assert!((9_400..10_600).contains(&c), "{counts:?}");
        }
    }

    /// `below` computes the rejection bound only when a draw could fall under it: the
    /// draws are those of the plain method (bound computed every time), also for sizes
    /// near 2^64 where about half the draws are rejected.
    #[test]
    fn below_draws_as_the_plain_method() {
        fn plain(s: &mut Stream, n: u64) -> u64 {
            let threshold = n.wrapping_neg() % n;
            loop {
                let m = (s.next_u64() as u128) * (n as u128);
                if (m as u64) >= threshold {
                    return (m >> 64) as u64;
                }
            }
        }
        let sizes = [
            1,
            2,
            3,
            7,
            100_000,
            1 << 40,
            (1 << 63) + 1,
            u64::MAX - 1,
            u64::MAX,
        ];
        for (t, &n) in sizes.iter().enumerate() {
            let (mut a, mut b) = (
                Stream::new(3, 1, t as u64, 0),
                Stream::new(3, 1, t as u64, 0),
            );
            for _ in 0..20_000 {
                assert_eq!(a.below(n as usize) as u64, plain(&mut b, n), "n = {n}");
            }
        }
    }

    #[test]
    fn normal_has_unit_variance() {
        let mut s = Stream::new(5, 5, 5, 5);
        let xs: Vec<f64> = (0..50_000).map(|_| s.normal()).collect();
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / xs.len() as f64;
        assert!(
            mean.abs() < 0.02 && (var - 1.0).abs() < 0.03,
            "{mean} {var}"
        );
    }
}
