//! Four lanes: glam's `Vec4` (one SSE register on x86_64), the width of
//! the BVH's four-triangle blocks and of the lab's four-ray scenes.

use super::{Mask, Real};
use glam::{BVec4A, Vec4};

impl Mask for BVec4A {
    #[inline(always)]
    fn splat(b: bool) -> BVec4A {
        BVec4A::splat(b)
    }
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize) -> bool) -> BVec4A {
        BVec4A::from_array(std::array::from_fn(f))
    }
    #[inline(always)]
    fn lane(self, k: usize) -> bool {
        self.test(k)
    }
    #[inline(always)]
    fn set_lane(&mut self, k: usize, b: bool) {
        self.set(k, b);
    }
    #[inline(always)]
    fn any(self) -> bool {
        BVec4A::any(self)
    }
    #[inline(always)]
    fn all(self) -> bool {
        BVec4A::all(self)
    }
}

impl Real for Vec4 {
    type Mask = BVec4A;
    type Array<T: Copy + Default> = [T; 4];
    const LANES: usize = 4;

    #[inline(always)]
    fn splat(x: f32) -> Vec4 {
        Vec4::splat(x)
    }
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize) -> f32) -> Vec4 {
        Vec4::from_array(std::array::from_fn(f))
    }
    #[inline(always)]
    fn lane(self, k: usize) -> f32 {
        self[k]
    }
    #[inline(always)]
    fn set_lane(&mut self, k: usize, x: f32) {
        self[k] = x;
    }
    #[inline(always)]
    fn sqrt(self) -> Vec4 {
        sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> Vec4 {
        Vec4::abs(self)
    }
    // glam's `min` and `max` are SSE's, which give a NaN's other operand
    // only on one side: lane by lane keeps `f32`'s rule.
    #[inline(always)]
    fn min(self, o: Vec4) -> Vec4 {
        Real::from_fn(|k| self[k].min(o[k]))
    }
    #[inline(always)]
    fn max(self, o: Vec4) -> Vec4 {
        Real::from_fn(|k| self[k].max(o[k]))
    }
    #[inline(always)]
    fn copysign(self, sign: Vec4) -> Vec4 {
        Vec4::copysign(self, sign)
    }
    #[inline(always)]
    fn powf(self, e: Vec4) -> Vec4 {
        Real::from_fn(|k| self[k].powf(e[k]))
    }
    #[inline(always)]
    fn exp2(self) -> Vec4 {
        Real::from_fn(|k| self[k].exp2())
    }
    #[inline(always)]
    fn sin_cos(self) -> (Vec4, Vec4) {
        (
            Real::from_fn(|k| self[k].sin()),
            Real::from_fn(|k| self[k].cos()),
        )
    }
    #[inline(always)]
    fn acos(self) -> Vec4 {
        Real::from_fn(|k| self[k].acos())
    }
    #[inline(always)]
    fn asin(self) -> Vec4 {
        Real::from_fn(|k| self[k].asin())
    }
    #[inline(always)]
    fn atan2(self, x: Vec4) -> Vec4 {
        Real::from_fn(|k| self[k].atan2(x[k]))
    }
    #[inline(always)]
    fn lt(self, o: Vec4) -> BVec4A {
        self.cmplt(o)
    }
    #[inline(always)]
    fn le(self, o: Vec4) -> BVec4A {
        self.cmple(o)
    }
    #[inline(always)]
    fn gt(self, o: Vec4) -> BVec4A {
        self.cmpgt(o)
    }
    #[inline(always)]
    fn ge(self, o: Vec4) -> BVec4A {
        self.cmpge(o)
    }
    #[inline(always)]
    fn eq(self, o: Vec4) -> BVec4A {
        self.cmpeq(o)
    }
    #[inline(always)]
    fn is_nan(self) -> BVec4A {
        self.is_nan_mask()
    }
    #[inline(always)]
    fn is_infinite(self) -> BVec4A {
        self.abs().cmpeq(Vec4::INFINITY)
    }
    #[inline(always)]
    fn select(m: BVec4A, a: Vec4, b: Vec4) -> Vec4 {
        Vec4::select(m, a, b)
    }
}

/// The square root of each lane, correctly rounded as `f32::sqrt` (the
/// compiler makes it one SSE instruction).
#[inline(always)]
fn sqrt(v: Vec4) -> Vec4 {
    Vec4::from_array(v.to_array().map(f32::sqrt))
}
