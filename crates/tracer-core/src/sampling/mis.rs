//! The weights of multiple importance sampling (Veach 1997).

use crate::simd::Real;

/// Veach's power heuristic (exponent 2) for one sample of each strategy:
/// the weight of the strategy of density `a` at a point where the other
/// has density `b`; 1 where `a` is infinite (a point light), 0 where both
/// are 0.
#[inline(always)]
pub fn power_heuristic<N: Real>(a: N, b: N) -> N {
    let (a2, b2) = (a * a, b * b);
    let sum = a2 + b2;
    let w = N::select(sum.eq(N::zero()), N::zero(), a2 / sum);
    N::select(a2.is_infinite(), N::one(), w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_power_heuristic_weighs_by_squares() {
        assert_eq!(power_heuristic(1.0, 1.0), 0.5);
        assert_eq!(power_heuristic(3.0, 1.0), 0.9);
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        assert_eq!(power_heuristic(f32::INFINITY, 2.0), 1.0);
        assert_eq!(
            power_heuristic(f32::MAX, 1.0),
            1.0,
            "a^2 overflows to infinity"
        );
        assert_eq!(power_heuristic(1.0, f32::INFINITY), 0.0);
    }
}
