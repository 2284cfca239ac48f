//! Numbers that are one value or several at once, so that each formula of
//! the tracer is written once and runs on one ray or on a group of rays in
//! SIMD lanes (as Mitsuba 3's Dr.Jit types and pbrt-v4's wavefront
//! integrator share one source between their scalar and wide forms).
//!
//! - `Real`: a number per lane with its masks, comparisons and selects:
//!   `f32` (one lane; its mask is `bool`), `F16` (sixteen lanes, `wide.rs`)
//!   and glam's `Vec4` (four, `four.rs`: what the BVH's four-triangle
//!   blocks and the lab's four-ray scenes use).
//! - `V3`: a 3D vector of such numbers, whose operations are glam's `Vec3`
//!   operations in their order, so a formula instantiated for `f32` gives
//!   the bits the scalar code gave.
//!
//! Branches become selects: a formula computes both sides and keeps, lane
//! by lane, the one its mask says. Each lane's arithmetic is IEEE's, the
//! same in every width: nothing is fused or reordered.

mod four;
mod vec3;
mod wide;

pub use vec3::V3;
pub use wide::{F16, M16};

use std::fmt::Debug;
use std::ops::{Add, BitAnd, BitOr, Div, Index, IndexMut, Mul, Neg, Not, Sub};

/// A flag per lane.
pub trait Mask:
    Copy + Debug + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self>
{
    fn splat(b: bool) -> Self;
    fn from_fn(f: impl FnMut(usize) -> bool) -> Self;
    /// Lane `k`'s flag.
    fn lane(self, k: usize) -> bool;
    fn set_lane(&mut self, k: usize, b: bool);
    /// Whether some lane is set.
    fn any(self) -> bool;
    /// Whether every lane is set.
    fn all(self) -> bool;
    /// Whether no lane is set.
    #[inline(always)]
    fn none(self) -> bool {
        !self.any()
    }
    /// Lane by lane, `a`'s flag where `m` is set, else `b`'s.
    #[inline(always)]
    fn select(m: Self, a: Self, b: Self) -> Self {
        (m & a) | (!m & b)
    }
}

/// A number per lane: `LANES` of them, one operation for all.
pub trait Real:
    Copy
    + Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f32, Output = Self>
    + Sub<f32, Output = Self>
    + Mul<f32, Output = Self>
    + Div<f32, Output = Self>
{
    type Mask: Mask;
    /// Something per lane (an index, a reference), read and written lane
    /// by lane.
    type Array<T: Copy + Default>: Copy
        + Default
        + Index<usize, Output = T>
        + IndexMut<usize, Output = T>;
    const LANES: usize;

    fn splat(x: f32) -> Self;
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self;
    /// Lane `k`'s value.
    fn lane(self, k: usize) -> f32;
    fn set_lane(&mut self, k: usize, x: f32);

    fn sqrt(self) -> Self;
    fn abs(self) -> Self;
    /// `f32::min` lane by lane: a NaN gives way to the other operand.
    fn min(self, o: Self) -> Self;
    /// `f32::max` lane by lane: a NaN gives way to the other operand.
    fn max(self, o: Self) -> Self;
    /// The size of `self` with the sign of `sign`.
    fn copysign(self, sign: Self) -> Self;
    fn powf(self, e: Self) -> Self;
    fn exp2(self) -> Self;
    /// The sine and the cosine, as `f32::sin` and `f32::cos`.
    fn sin_cos(self) -> (Self, Self);
    fn acos(self) -> Self;
    fn asin(self) -> Self;
    /// `self.atan2(x)`: the angle of (x, self).
    fn atan2(self, x: Self) -> Self;

    fn lt(self, o: Self) -> Self::Mask;
    fn le(self, o: Self) -> Self::Mask;
    fn gt(self, o: Self) -> Self::Mask;
    fn ge(self, o: Self) -> Self::Mask;
    fn eq(self, o: Self) -> Self::Mask;
    fn is_nan(self) -> Self::Mask;
    fn is_infinite(self) -> Self::Mask;

    /// Lane by lane, `a` where `m` is set, else `b`.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;

    #[inline(always)]
    fn zero() -> Self {
        Self::splat(0.0)
    }

    #[inline(always)]
    fn one() -> Self {
        Self::splat(1.0)
    }

    /// `x.clamp(lo, hi)` lane by lane, as `f32::clamp` (a NaN stays NaN).
    #[inline(always)]
    fn clamp(self, lo: f32, hi: f32) -> Self {
        let below = self.lt(Self::splat(lo));
        let above = self.gt(Self::splat(hi));
        Self::select(
            below,
            Self::splat(lo),
            Self::select(above, Self::splat(hi), self),
        )
    }
}

impl Mask for bool {
    #[inline(always)]
    fn splat(b: bool) -> bool {
        b
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> bool) -> bool {
        f(0)
    }
    #[inline(always)]
    fn lane(self, _k: usize) -> bool {
        self
    }
    #[inline(always)]
    fn set_lane(&mut self, _k: usize, b: bool) {
        *self = b;
    }
    #[inline(always)]
    fn any(self) -> bool {
        self
    }
    #[inline(always)]
    fn all(self) -> bool {
        self
    }
}

impl Real for f32 {
    type Mask = bool;
    type Array<T: Copy + Default> = [T; 1];
    const LANES: usize = 1;

    #[inline(always)]
    fn splat(x: f32) -> f32 {
        x
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> f32 {
        f(0)
    }
    #[inline(always)]
    fn lane(self, _k: usize) -> f32 {
        self
    }
    #[inline(always)]
    fn set_lane(&mut self, _k: usize, x: f32) {
        *self = x;
    }
    #[inline(always)]
    fn sqrt(self) -> f32 {
        f32::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> f32 {
        f32::abs(self)
    }
    #[inline(always)]
    fn min(self, o: f32) -> f32 {
        f32::min(self, o)
    }
    #[inline(always)]
    fn max(self, o: f32) -> f32 {
        f32::max(self, o)
    }
    #[inline(always)]
    fn copysign(self, sign: f32) -> f32 {
        f32::copysign(self, sign)
    }
    #[inline(always)]
    fn powf(self, e: f32) -> f32 {
        f32::powf(self, e)
    }
    #[inline(always)]
    fn exp2(self) -> f32 {
        f32::exp2(self)
    }
    #[inline(always)]
    fn sin_cos(self) -> (f32, f32) {
        (f32::sin(self), f32::cos(self))
    }
    #[inline(always)]
    fn acos(self) -> f32 {
        f32::acos(self)
    }
    #[inline(always)]
    fn asin(self) -> f32 {
        f32::asin(self)
    }
    #[inline(always)]
    fn atan2(self, x: f32) -> f32 {
        f32::atan2(self, x)
    }
    #[inline(always)]
    fn lt(self, o: f32) -> bool {
        self < o
    }
    #[inline(always)]
    fn le(self, o: f32) -> bool {
        self <= o
    }
    #[inline(always)]
    fn gt(self, o: f32) -> bool {
        self > o
    }
    #[inline(always)]
    fn ge(self, o: f32) -> bool {
        self >= o
    }
    #[inline(always)]
    fn eq(self, o: f32) -> bool {
        self == o
    }
    #[inline(always)]
    fn is_nan(self) -> bool {
        f32::is_nan(self)
    }
    #[inline(always)]
    fn is_infinite(self) -> bool {
        f32::is_infinite(self)
    }
    #[inline(always)]
    fn select(m: bool, a: f32, b: f32) -> f32 {
        if m {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn clamp(self, lo: f32, hi: f32) -> f32 {
        f32::clamp(self, lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Some awkward numbers: signed zeros, NaN, infinities, tiny and huge.
    const SPECIAL: [f32; 16] = [
        0.0,
        -0.0,
        1.0,
        -1.5,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        1e-38,
        -3e38,
        0.1,
        7.25,
        -0.3,
        2.0,
        f32::MIN_POSITIVE,
        0.5,
        -2.0,
    ];

    fn same(a: f32, b: f32) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    /// Each operation of the wide types is the scalar one in every lane.
    #[test]
    fn wide_operations_are_the_scalar_ones_lane_by_lane() {
        let a = F16(SPECIAL);
        let mut rotated = SPECIAL;
        rotated.rotate_left(5);
        let b = F16(rotated);
        type Op = (&'static str, fn(F16, F16) -> F16, fn(f32, f32) -> f32);
        let ops: [Op; 9] = [
            ("add", |a, b| a + b, |a, b| a + b),
            ("sub", |a, b| a - b, |a, b| a - b),
            ("mul", |a, b| a * b, |a, b| a * b),
            ("div", |a, b| a / b, |a, b| a / b),
            ("min", Real::min, f32::min),
            ("max", Real::max, f32::max),
            ("copysign", Real::copysign, f32::copysign),
            ("sqrt", |a, _| Real::sqrt(a), |a, _| a.sqrt()),
            (
                "clamp",
                |a, _| Real::clamp(a, -1.0, 2.0),
                |a, _| a.clamp(-1.0, 2.0),
            ),
        ];
        for (name, wide, scalar) in ops {
            let got = wide(a, b);
            for k in 0..16 {
                let want = scalar(SPECIAL[k], rotated[k]);
                assert!(
                    same(got.lane(k), want),
                    "{name} lane {k}: {} vs {want}",
                    got.lane(k)
                );
            }
        }
        for k in 0..16 {
            let (x, y) = (SPECIAL[k], rotated[k]);
            assert_eq!(a.lt(b).lane(k), x < y);
            assert_eq!(a.ge(b).lane(k), x >= y);
            assert_eq!(a.eq(b).lane(k), x == y);
            assert_eq!(a.is_nan().lane(k), x.is_nan());
            assert_eq!(a.is_infinite().lane(k), x.is_infinite());
        }
        let m = a.lt(b);
        let s = F16::select(m, a, b);
        for k in 0..16 {
            let want = if SPECIAL[k] < rotated[k] {
                SPECIAL[k]
            } else {
                rotated[k]
            };
            assert!(same(s.lane(k), want));
        }
    }

    #[test]
    fn masks_answer_any_and_all() {
        assert!(M16::splat(true).all() && M16::splat(true).any());
        assert!(M16::splat(false).none());
        let one = M16::from_fn(|k| k == 11);
        assert!(one.any() && !one.all() && one.lane(11) && !one.lane(10));
        assert!((one | !one).all());
        assert!((one & !one).none());
    }
}
