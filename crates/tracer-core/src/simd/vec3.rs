//! A 3D vector of lane numbers: one vector per lane, kept by axis. Every
//! operation is glam's `Vec3` operation with its operands in its order, so
//! `V3<f32>` gives the bits `Vec3` gives.

use super::Real;
use glam::Vec3;
use std::ops::{Add, Div, Mul, Neg, Sub};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct V3<N> {
    pub x: N,
    pub y: N,
    pub z: N,
}

impl<N: Real> V3<N> {
    #[inline(always)]
    pub fn new(x: N, y: N, z: N) -> Self {
        V3 { x, y, z }
    }

    /// `v` in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        V3::new(N::splat(v.x), N::splat(v.y), N::splat(v.z))
    }

    #[inline(always)]
    pub fn zero() -> Self {
        V3::splat(Vec3::ZERO)
    }

    /// Lane `k` of each axis from `f(k)`.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> Vec3) -> Self {
        let mut v = V3::zero();
        for k in 0..N::LANES {
            v.set_lane(k, f(k));
        }
        v
    }

    /// Lane `k`'s vector.
    #[inline(always)]
    pub fn lane(&self, k: usize) -> Vec3 {
        Vec3::new(self.x.lane(k), self.y.lane(k), self.z.lane(k))
    }

    #[inline(always)]
    pub fn set_lane(&mut self, k: usize, v: Vec3) {
        self.x.set_lane(k, v.x);
        self.y.set_lane(k, v.y);
        self.z.set_lane(k, v.z);
    }

    /// 1 / each component, for slab tests: a zero component would give
    /// 0 * inf = NaN there, so one below 1e-30 in size is taken as 1e-30
    /// of its sign. The tree's one ray and the matte lanes' sixteen alike.
    #[inline(always)]
    pub fn safe_recip(self) -> Self {
        let safe = |d: N| {
            let tiny = d.abs().lt(N::splat(1e-30));
            N::one() / N::select(tiny, N::splat(1e-30).copysign(d), d)
        };
        V3::new(safe(self.x), safe(self.y), safe(self.z))
    }

    #[inline(always)]
    pub fn dot(self, o: Self) -> N {
        (self.x * o.x) + (self.y * o.y) + (self.z * o.z)
    }

    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        V3::new(
            self.y * o.z - o.y * self.z,
            self.z * o.x - o.z * self.x,
            self.x * o.y - o.x * self.y,
        )
    }

    #[inline(always)]
    pub fn length_squared(self) -> N {
        self.dot(self)
    }

    #[inline(always)]
    pub fn length(self) -> N {
        self.dot(self).sqrt()
    }

    /// `Vec3::normalize`: times the reciprocal of the length.
    #[inline(always)]
    pub fn normalize(self) -> Self {
        self * (N::one() / self.length())
    }

    /// `Vec3::try_normalize` lane by lane: the unit vector, and where it is
    /// one (the length's reciprocal finite and above 0).
    #[inline(always)]
    pub fn try_normalize(self) -> (Self, N::Mask) {
        let rcp = N::one() / self.length();
        (self * rcp, rcp.gt(N::zero()) & !rcp.is_infinite())
    }

    /// The unit vector, or `fallback` where there is none.
    #[inline(always)]
    pub fn normalize_or(self, fallback: V3<N>) -> Self {
        let (unit, ok) = self.try_normalize();
        V3::select(ok, unit, fallback)
    }

    /// Lane by lane, `a` where `m` is set, else `b`.
    #[inline(always)]
    pub fn select(m: N::Mask, a: Self, b: Self) -> Self {
        V3::new(
            N::select(m, a.x, b.x),
            N::select(m, a.y, b.y),
            N::select(m, a.z, b.z),
        )
    }

    /// The largest of the three axes (`Vec3::max_element`).
    #[inline(always)]
    pub fn max_element(self) -> N {
        self.x.max(self.y).max(self.z)
    }

    /// Whether all three axes are zero, lane by lane.
    #[inline(always)]
    pub fn is_zero(self) -> N::Mask {
        let zero = N::zero();
        self.x.eq(zero) & self.y.eq(zero) & self.z.eq(zero)
    }

    /// Whether some axis is not a number, lane by lane.
    #[inline(always)]
    pub fn is_nan(self) -> N::Mask {
        self.x.is_nan() | self.y.is_nan() | self.z.is_nan()
    }

    /// `Vec3::element_sum`.
    #[inline(always)]
    pub fn element_sum(self) -> N {
        self.x + self.y + self.z
    }

    /// Each axis `f` of the other's.
    #[inline(always)]
    pub fn map(self, f: impl Fn(N) -> N) -> Self {
        V3::new(f(self.x), f(self.y), f(self.z))
    }
}

impl From<Vec3> for V3<f32> {
    #[inline(always)]
    fn from(v: Vec3) -> Self {
        V3::new(v.x, v.y, v.z)
    }
}

impl From<V3<f32>> for Vec3 {
    #[inline(always)]
    fn from(v: V3<f32>) -> Self {
        Vec3::new(v.x, v.y, v.z)
    }
}

impl<N: Real> Add for V3<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        V3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<N: Real> Sub for V3<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        V3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

/// Axis by axis.
impl<N: Real> Mul for V3<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        V3::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
}

/// Every axis by the lane's number.
impl<N: Real> Mul<N> for V3<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: N) -> Self {
        V3::new(self.x * s, self.y * s, self.z * s)
    }
}

impl<N: Real> Div<N> for V3<N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, s: N) -> Self {
        V3::new(self.x / s, self.y / s, self.z / s)
    }
}

impl<N: Real> Neg for V3<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        V3::new(-self.x, -self.y, -self.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::F16;

    /// The scalar instantiation is glam's arithmetic, bit for bit, and each
    /// lane of the wide one is too.
    #[test]
    fn operations_are_glams_bit_for_bit() {
        let vs = [
            Vec3::new(0.3, -1.7, 2.2),
            Vec3::new(1e-20, 3e5, -0.0),
            Vec3::new(-7.0, 0.1, 0.7),
            Vec3::new(1.0, 1.0, 1.0),
        ];
        for a in vs {
            for b in vs {
                let (va, vb) = (V3::<f32>::from(a), V3::<f32>::from(b));
                let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                assert_eq!(bits(Vec3::from(va.cross(vb))), bits(a.cross(b)));
                assert_eq!(va.dot(vb).to_bits(), a.dot(b).to_bits());
                assert_eq!(bits(Vec3::from(va.normalize())), bits(a.normalize()));
                assert_eq!(va.length().to_bits(), a.length().to_bits());
                let wa = V3::<F16>::splat(a);
                let wb = V3::<F16>::from_fn(|k| if k % 2 == 0 { b } else { a });
                let n = wa.cross(wb).normalize();
                for k in 0..16 {
                    let other = if k % 2 == 0 { b } else { a };
                    let want = a.cross(other).normalize();
                    assert_eq!(bits(n.lane(k)), bits(want), "lane {k}");
                }
            }
        }
    }
}
