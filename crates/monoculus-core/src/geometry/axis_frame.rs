//! [`AxisFrame`]: the local frame of an OLA robot.

use crate::rng::Stream;

/// Largest dimension the simulator supports.
pub const MAX_DIM: usize = 3;

/// An OLA robot's view of the agreed axes: its local axis `k` is the global axis
/// `perm[k]` with sign `sign[k]`. The robot knows the lines, not their labels or
/// orientation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AxisFrame {
    perm: [u8; MAX_DIM],
    sign: [i8; MAX_DIM],
    dim: u8,
}

impl AxisFrame {
    /// The identity: local axes are the global axes.
    pub fn identity(dim: usize) -> Self {
        AxisFrame {
            perm: [0, 1, 2],
            sign: [1; MAX_DIM],
            dim: dim as u8,
        }
    }

    /// A random order and random signs of the `dim` axes.
    pub fn random(dim: usize, stream: &mut Stream) -> Self {
        let p = stream.permutation(dim);
        let mut perm = [0u8; MAX_DIM];
        let mut sign = [1i8; MAX_DIM];
        for k in 0..dim {
            perm[k] = p[k] as u8;
            sign[k] = if stream.coin() { -1 } else { 1 };
        }
        AxisFrame {
            perm,
            sign,
            dim: dim as u8,
        }
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.dim as usize
    }

    /// The global axis behind local axis `k`.
    pub fn global_axis(&self, k: usize) -> usize {
        self.perm[k] as usize
    }

    /// +1 or -1: the orientation of local axis `k` relative to its global axis.
    pub fn sign(&self, k: usize) -> f64 {
        self.sign[k] as f64
    }

    /// Local coordinate `k` of a global vector.
    pub fn local_coord<P: crate::geometry::Point>(&self, v: P, k: usize) -> f64 {
        self.sign(k) * v.axis(self.global_axis(k))
    }

    /// Maps a global vector to local coordinates.
    pub fn to_local<P: crate::geometry::Point>(&self, v: P) -> P {
        let mut c = [0.0; MAX_DIM];
        for (k, ck) in c.iter_mut().enumerate().take(self.dim()) {
            *ck = self.local_coord(v, k);
        }
        P::from_slice(&c)
    }

    /// Maps a local vector back to global coordinates.
    pub fn to_global<P: crate::geometry::Point>(&self, v: P) -> P {
        let mut c = [0.0; MAX_DIM];
        for k in 0..self.dim() {
            c[self.global_axis(k)] = self.sign(k) * v.axis(k);
        }
        P::from_slice(&c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, DVec3};

    #[test]
    fn round_trip() {
        let mut s = Stream::new(3, 3, 3, 3);
        for _ in 0..50 {
            let f = AxisFrame::random(3, &mut s);
            let v = DVec3::new(1.0, -2.0, 3.5);
            assert_eq!(f.to_global(f.to_local(v)), v);
            let g = AxisFrame::random(2, &mut s);
            let w = DVec2::new(1.0, -2.0);
            assert_eq!(g.to_global(g.to_local(w)), w);
            assert_eq!(g.to_local(w).length(), w.length());
        }
    }
}
