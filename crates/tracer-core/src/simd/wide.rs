//! Sixteen lanes: an array of floats whose every operation is a loop the
//! compiler turns into SIMD instructions (two AVX registers, one AVX-512,
//! four SSE), in the widest form the processor has where the calling
//! function is compiled for it (`multiversion`).

// Plain loops over the lanes, indexing several arrays at once: the form
// the compiler turns into SIMD instructions.
#![allow(clippy::needless_range_loop)]

use super::{Mask, Real};
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

/// Sixteen floats.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub struct F16(pub [f32; 16]);

/// Sixteen flags, each all ones or all zeros (as SIMD comparisons give
/// them), so that a select is a blend.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C, align(64))]
pub struct M16(pub [u32; 16]);

const ON: u32 = u32::MAX;

#[inline(always)]
fn map(a: F16, f: impl Fn(f32) -> f32) -> F16 {
    let mut r = [0.0; 16];
    for k in 0..16 {
        r[k] = f(a.0[k]);
    }
    F16(r)
}

#[inline(always)]
fn zip(a: F16, b: F16, f: impl Fn(f32, f32) -> f32) -> F16 {
    let mut r = [0.0; 16];
    for k in 0..16 {
        r[k] = f(a.0[k], b.0[k]);
    }
    F16(r)
}

#[inline(always)]
fn compare(a: F16, b: F16, f: impl Fn(f32, f32) -> bool) -> M16 {
    let mut r = [0; 16];
    for k in 0..16 {
        r[k] = if f(a.0[k], b.0[k]) { ON } else { 0 };
    }
    M16(r)
}

#[inline(always)]
fn bits(a: M16, b: M16, f: impl Fn(u32, u32) -> u32) -> M16 {
    let mut r = [0; 16];
    for k in 0..16 {
        r[k] = f(a.0[k], b.0[k]);
    }
    M16(r)
}

impl Mask for M16 {
    #[inline(always)]
    fn splat(b: bool) -> M16 {
        M16([if b { ON } else { 0 }; 16])
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> bool) -> M16 {
        let mut r = [0; 16];
        for (k, x) in r.iter_mut().enumerate() {
            *x = if f(k) { ON } else { 0 };
        }
        M16(r)
    }
    #[inline(always)]
    fn lane(self, k: usize) -> bool {
        self.0[k] != 0
    }
    #[inline(always)]
    fn set_lane(&mut self, k: usize, b: bool) {
        self.0[k] = if b { ON } else { 0 };
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.0.iter().fold(0, |a, &x| a | x) != 0
    }
    #[inline(always)]
    fn all(self) -> bool {
        self.0.iter().fold(ON, |a, &x| a & x) != 0
    }
}

impl BitAnd for M16 {
    type Output = M16;
    #[inline(always)]
    fn bitand(self, o: M16) -> M16 {
        bits(self, o, |a, b| a & b)
    }
}

impl BitOr for M16 {
    type Output = M16;
    #[inline(always)]
    fn bitor(self, o: M16) -> M16 {
        bits(self, o, |a, b| a | b)
    }
}

impl Not for M16 {
    type Output = M16;
    #[inline(always)]
    fn not(self) -> M16 {
        bits(self, self, |a, _| !a)
    }
}

macro_rules! arithmetic {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for F16 {
            type Output = F16;
            #[inline(always)]
            fn $method(self, o: F16) -> F16 {
                zip(self, o, |a, b| a $op b)
            }
        }
        impl $trait<f32> for F16 {
            type Output = F16;
            #[inline(always)]
            fn $method(self, o: f32) -> F16 {
                map(self, |a| a $op o)
            }
        }
    };
}

arithmetic!(Add, add, +);
arithmetic!(Sub, sub, -);
arithmetic!(Mul, mul, *);
arithmetic!(Div, div, /);

impl Neg for F16 {
    type Output = F16;
    #[inline(always)]
    fn neg(self) -> F16 {
        map(self, |a| -a)
    }
}

impl Real for F16 {
    type Mask = M16;
    type Array<T: Copy + Default> = [T; 16];
    const LANES: usize = 16;

    #[inline(always)]
    fn splat(x: f32) -> F16 {
        F16([x; 16])
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> F16 {
        let mut r = [0.0; 16];
        for (k, x) in r.iter_mut().enumerate() {
            *x = f(k);
        }
        F16(r)
    }
    #[inline(always)]
    fn lane(self, k: usize) -> f32 {
        self.0[k]
    }
    #[inline(always)]
    fn set_lane(&mut self, k: usize, x: f32) {
        self.0[k] = x;
    }
    #[inline(always)]
    fn sqrt(self) -> F16 {
        map(self, f32::sqrt)
    }
    #[inline(always)]
    fn abs(self) -> F16 {
        map(self, f32::abs)
    }
    #[inline(always)]
    fn min(self, o: F16) -> F16 {
        zip(self, o, f32::min)
    }
    #[inline(always)]
    fn max(self, o: F16) -> F16 {
        zip(self, o, f32::max)
    }
    #[inline(always)]
    fn copysign(self, sign: F16) -> F16 {
        zip(self, sign, f32::copysign)
    }
    // The transcendental functions are libm's, lane by lane: the same
    // values as one lane's.
    #[inline(always)]
    fn powf(self, e: F16) -> F16 {
        zip(self, e, f32::powf)
    }
    #[inline(always)]
    fn exp2(self) -> F16 {
        map(self, f32::exp2)
    }
    #[inline(always)]
    fn sin_cos(self) -> (F16, F16) {
        // One loop: each lane's sine and cosine in one call (sincosf).
        let (mut sin, mut cos) = ([0.0; 16], [0.0; 16]);
        for k in 0..16 {
            (sin[k], cos[k]) = (self.0[k].sin(), self.0[k].cos());
        }
        (F16(sin), F16(cos))
    }
    #[inline(always)]
    fn acos(self) -> F16 {
        map(self, f32::acos)
    }
    #[inline(always)]
    fn asin(self) -> F16 {
        map(self, f32::asin)
    }
    #[inline(always)]
    fn atan2(self, x: F16) -> F16 {
        zip(self, x, f32::atan2)
    }
    #[inline(always)]
    fn lt(self, o: F16) -> M16 {
        compare(self, o, |a, b| a < b)
    }
    #[inline(always)]
    fn le(self, o: F16) -> M16 {
        compare(self, o, |a, b| a <= b)
    }
    #[inline(always)]
    fn gt(self, o: F16) -> M16 {
        compare(self, o, |a, b| a > b)
    }
    #[inline(always)]
    fn ge(self, o: F16) -> M16 {
        compare(self, o, |a, b| a >= b)
    }
    #[inline(always)]
    fn eq(self, o: F16) -> M16 {
        compare(self, o, |a, b| a == b)
    }
    #[inline(always)]
    fn is_nan(self) -> M16 {
        compare(self, self, |a, b| a != b)
    }
    #[inline(always)]
    fn is_infinite(self) -> M16 {
        compare(self, self, |a, _| a.abs() == f32::INFINITY)
    }
    #[inline(always)]
    fn select(m: M16, a: F16, b: F16) -> F16 {
        let mut r = [0.0; 16];
        for k in 0..16 {
            r[k] = f32::from_bits((a.0[k].to_bits() & m.0[k]) | (b.0[k].to_bits() & !m.0[k]));
        }
        F16(r)
    }
}
