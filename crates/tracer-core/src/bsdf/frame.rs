//! The local frame of a shaded point: the BSDFs work with directions
//! whose z is the cosine to the shading normal.

use crate::simd::{Real, V3};
use glam::Vec3;

/// Two unit tangents `s`, `t` making a right-handed orthonormal frame with
/// unit `n`, for any lane width, without branches on its direction (Duff
/// et al., "Building an orthonormal basis, revisited", 2017).
#[inline(always)]
pub fn tangents<N: Real>(n: V3<N>) -> (V3<N>, V3<N>) {
    let sign = N::one().copysign(n.z);
    let a = N::splat(-1.0) / (sign + n.z);
    let b = n.x * n.y * a;
    (
        V3::new(N::one() + sign * n.x * n.x * a, sign * b, -sign * n.x),
        V3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// Local direction `v` in the world, of the frame of axes `(s, t, n)`.
#[inline(always)]
pub fn to_world<N: Real>((s, t, n): (V3<N>, V3<N>, V3<N>), v: V3<N>) -> V3<N> {
    s * v.x + t * v.y + n * v.z
}

/// An orthonormal frame around a unit normal `n`, by lane (`simd::Real`):
/// the one-path tracer's is `Frame<f32>`.
#[derive(Debug, Clone, Copy)]
pub struct Frame<N: Real = f32> {
    pub s: V3<N>,
    pub t: V3<N>,
    pub n: V3<N>,
}

impl Frame<f32> {
    /// A frame around unit `n` (`tangents`).
    pub fn new(n: Vec3) -> Frame {
        Frame::around(V3::from(n))
    }

    /// World direction `v` in this frame.
    #[inline(always)]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        self.local(V3::from(v)).into()
    }

    /// Local direction `v` in the world.
    #[inline(always)]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.world(V3::from(v)).into()
    }
}

impl<N: Real> Frame<N> {
    /// A frame around each unit normal of `n` (`tangents`).
    #[inline(always)]
    pub fn around(n: V3<N>) -> Frame<N> {
        let (s, t) = tangents(n);
        Frame { s, t, n }
    }

    /// World direction `v` in this frame.
    #[inline(always)]
    pub fn local(&self, v: V3<N>) -> V3<N> {
        V3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    /// Local direction `v` in the world.
    #[inline(always)]
    pub fn world(&self, v: V3<N>) -> V3<N> {
        to_world((self.s, self.t, self.n), v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal_and_round_trip() {
        let normals = [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.3, -0.4, 0.866).normalize(),
            Vec3::new(1e-4, 1e-4, -1.0).normalize(),
        ];
        for n in normals {
            let f = Frame::new(n);
            let [s, t, n] = [f.s, f.t, f.n].map(Vec3::from);
            for (a, b) in [(s, t), (s, n), (t, n)] {
                assert!(a.dot(b).abs() < 1e-6, "{n}");
            }
            for v in [s, t, n] {
                assert!((v.length() - 1.0).abs() < 1e-6, "{n}");
            }
            assert!((s.cross(t) - n).length() < 1e-5, "right-handed: {n}");
            let v = Vec3::new(0.2, -0.7, 0.5);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-6);
            assert!((f.to_local(n) - Vec3::Z).length() < 1e-6);
        }
    }
}
