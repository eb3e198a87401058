//! The [`Point`] trait: what the simulator needs of a vector in d dimensions.

use glam::{DMat2, DMat3, DVec2, DVec3};

use crate::rng::Stream;

/// A position or direction in d-dimensional Euclidean space, in f64.
///
/// Implemented for [`DVec2`] (d = 2) and [`DVec3`] (d = 3). Everything above the
/// geometry (visibility, observations, algorithms, the engine) is written against this
/// trait, so a new dimension only needs an implementation here.
pub trait Point:
    Copy
    + Send
    + Sync
    + std::fmt::Debug
    + PartialEq
    + Default
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<f64, Output = Self>
    + std::ops::Neg<Output = Self>
    + std::ops::AddAssign
    + 'static
{
    /// The dimension d.
    const DIM: usize;
    /// An orthogonal matrix: a rotation, possibly composed with a mirror.
    type Frame: Copy + Send + Sync + std::fmt::Debug + PartialEq;

    /// The origin.
    fn zero() -> Self;
    /// Coordinate `axis` (0-based, `axis < DIM`).
    fn axis(self, axis: usize) -> f64;
    /// The unit vector along `axis`.
    fn unit_axis(axis: usize) -> Self;
    /// Builds a point from its first `DIM` coordinates.
    fn from_slice(coords: &[f64]) -> Self;
    /// Dot product.
    fn dot(self, other: Self) -> f64;
    /// Euclidean length.
    #[inline]
    fn length(self) -> f64 {
        self.dot(self).sqrt()
    }
    /// Squared Euclidean length.
    #[inline]
    fn length_squared(self) -> f64 {
        self.dot(self)
    }
    /// Euclidean distance.
    fn distance(self, other: Self) -> f64 {
        (self - other).length()
    }
    /// Length of the cross product (d = 3) or |perp dot| (d = 2): |a||b| sin(angle).
    fn cross_norm(self, other: Self) -> f64;
    /// The unit vector in the direction of `self`; `self` must be non-zero.
    #[inline]
    fn normalized(self) -> Self {
        self * (1.0 / self.length())
    }
    /// Component-wise minimum.
    fn min_by_axis(self, other: Self) -> Self;
    /// Component-wise maximum.
    fn max_by_axis(self, other: Self) -> Self;

    /// The identity frame.
    fn identity_frame() -> Self::Frame;
    /// A uniformly random rotation, mirrored with probability 1/2.
    fn random_frame(stream: &mut Stream) -> Self::Frame;
    /// Maps a global vector into the frame (local coordinates).
    fn to_local(frame: &Self::Frame, v: Self) -> Self;
    /// Maps a local vector back to global coordinates.
    fn to_global(frame: &Self::Frame, v: Self) -> Self;
    /// A rotation by a small random angle: normal with standard deviation `sigma`
    /// (about a random axis in d = 3).
    fn random_tilt(sigma: f64, stream: &mut Stream) -> Self::Frame;
    /// The unit vector `dir` turned by a random angle of standard deviation `sigma`.
    fn perturb_direction(dir: Self, sigma: f64, stream: &mut Stream) -> Self {
        Self::to_global(&Self::random_tilt(sigma, stream), dir).normalized()
    }
}

impl Point for DVec2 {
    const DIM: usize = 2;
    type Frame = DMat2;

    #[inline]
    fn zero() -> Self {
        DVec2::ZERO
    }
    #[inline]
    fn axis(self, axis: usize) -> f64 {
        self[axis]
    }
    #[inline]
    fn unit_axis(axis: usize) -> Self {
        let mut v = DVec2::ZERO;
        v[axis] = 1.0;
        v
    }
    #[inline]
    fn from_slice(coords: &[f64]) -> Self {
        DVec2::new(coords[0], coords[1])
    }
    #[inline]
    fn dot(self, other: Self) -> f64 {
        DVec2::dot(self, other)
    }
    #[inline]
    fn cross_norm(self, other: Self) -> f64 {
        self.perp_dot(other).abs()
    }
    #[inline]
    fn min_by_axis(self, other: Self) -> Self {
        self.min(other)
    }
    #[inline]
    fn max_by_axis(self, other: Self) -> Self {
        self.max(other)
    }
    fn identity_frame() -> DMat2 {
        DMat2::IDENTITY
    }
    fn random_frame(stream: &mut Stream) -> DMat2 {
        let angle = stream.uniform() * std::f64::consts::TAU;
        let rotation = DMat2::from_angle(angle);
        if stream.coin() {
            rotation * DMat2::from_diagonal(DVec2::new(1.0, -1.0))
        } else {
            rotation
        }
    }
    #[inline]
    fn to_local(frame: &DMat2, v: Self) -> Self {
        frame.transpose() * v
    }
    #[inline]
    fn to_global(frame: &DMat2, v: Self) -> Self {
        *frame * v
    }
    fn random_tilt(sigma: f64, stream: &mut Stream) -> DMat2 {
        DMat2::from_angle(sigma * stream.normal())
    }
}

impl Point for DVec3 {
    const DIM: usize = 3;
    type Frame = DMat3;

    #[inline]
    fn zero() -> Self {
        DVec3::ZERO
    }
    #[inline]
    fn axis(self, axis: usize) -> f64 {
        self[axis]
    }
    #[inline]
    fn unit_axis(axis: usize) -> Self {
        let mut v = DVec3::ZERO;
        v[axis] = 1.0;
        v
    }
    #[inline]
    fn from_slice(coords: &[f64]) -> Self {
        DVec3::new(coords[0], coords[1], coords[2])
    }
    #[inline]
    fn dot(self, other: Self) -> f64 {
        DVec3::dot(self, other)
    }
    #[inline]
    fn cross_norm(self, other: Self) -> f64 {
        self.cross(other).length()
    }
    #[inline]
    fn min_by_axis(self, other: Self) -> Self {
        self.min(other)
    }
    #[inline]
    fn max_by_axis(self, other: Self) -> Self {
        self.max(other)
    }
    fn identity_frame() -> DMat3 {
        DMat3::IDENTITY
    }
    fn random_frame(stream: &mut Stream) -> DMat3 {
        // Uniform rotation from a uniform unit quaternion (Shoemake's method).
        let (u1, u2, u3) = (stream.uniform(), stream.uniform(), stream.uniform());
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        let (t2, t3) = (std::f64::consts::TAU * u2, std::f64::consts::TAU * u3);
        let q = glam::DQuat::from_xyzw(a * t2.sin(), a * t2.cos(), b * t3.sin(), b * t3.cos());
        let rotation = DMat3::from_quat(q.normalize());
        if stream.coin() {
            rotation * DMat3::from_diagonal(DVec3::new(1.0, 1.0, -1.0))
        } else {
            rotation
        }
    }
    #[inline]
    fn to_local(frame: &DMat3, v: Self) -> Self {
        frame.transpose() * v
    }
    #[inline]
    fn to_global(frame: &DMat3, v: Self) -> Self {
        *frame * v
    }
    fn random_tilt(sigma: f64, stream: &mut Stream) -> DMat3 {
        let axis = DVec3::new(stream.normal(), stream.normal(), stream.normal());
        let axis = if axis.length_squared() > 0.0 {
            axis.normalize()
        } else {
            DVec3::Z
        };
        DMat3::from_axis_angle(axis, sigma * stream.normal())
    }
}

/// The angle between two non-zero vectors, in [0, pi], computed as
/// `atan2(|a x b|, a . b)`, which stays accurate for tiny angles (unlike `acos`).
#[inline]
pub fn angle_between<P: Point>(a: P, b: P) -> f64 {
    a.cross_norm(b).atan2(a.dot(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_frames_are_orthogonal_and_both_chiralities_occur() {
        let mut stream = Stream::new(7, 1, 2, 3);
        let mut mirrored = 0;
        for _ in 0..200 {
            let f = DVec2::random_frame(&mut stream);
            let v = DVec2::new(0.3, -1.7);
            let back = DVec2::to_global(&f, DVec2::to_local(&f, v));
            assert!((back - v).length() < 1e-12);
            assert!((DVec2::to_local(&f, v).length() - v.length()).abs() < 1e-12);
            if f.determinant() < 0.0 {
                mirrored += 1;
            }
            let g = DVec3::random_frame(&mut stream);
            let w = DVec3::new(0.3, -1.7, 2.0);
            assert!((DVec3::to_global(&g, DVec3::to_local(&g, w)) - w).length() < 1e-12);
            assert!((g.determinant().abs() - 1.0).abs() < 1e-9);
        }
        assert!(
            mirrored > 60 && mirrored < 140,
            "mirrored {mirrored} of 200"
        );
    }

    #[test]
    fn tiny_angles_are_accurate() {
        let a = DVec2::new(1.0, 0.0);
        let b = DVec2::new(1.0, 1e-12);
        assert!((angle_between(a, b) - 1e-12).abs() < 1e-20);
        assert!((angle_between(a, -a) - std::f64::consts::PI).abs() < 1e-15);
    }
}
