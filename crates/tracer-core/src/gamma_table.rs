//! The 8-bit code of a display value `x` in [0, 1], `quantize(x.powf(1 / gamma))`,
//! by table: the same byte as the `powf` it replaces, for every input,
//! at a fraction of its cost (a 500x400 image has 600,000 channels).
//!
//! The code rises with `x` from 0 to 255; the table holds the 255 inputs
//! where it steps (each found by bisecting the float's bits with `powf`
//! itself) and, for the float's top bits, the code where each run of
//! inputs starts. An input within a guard band of a step is computed with
//! `powf`: there, `powf`'s last-bit rounding could fall either side of
//! the step. Outside the bands the true power is several units in the last
//! place from any step, more than `powf`'s error (under one such unit in
//! glibc), so its byte is the table's whatever that rounding does.
//! `tests::every_input_gives_the_powf_byte` checks every float in [0, 1]
//! at the lab's gamma.

/// Inputs share a run of the coarse index when their bits agree above this
/// shift: 8,128 runs in [0, 1), each under one code step at gamma 2.2.
const SHIFT: u32 = 17;
/// The bits of 1.0, the largest input.
const ONE: u32 = 0x3F80_0000;

/// The steps of `x -> quantize(x.powf(inv))` for one `inv`.
#[derive(Debug, Clone)]
pub(crate) struct GammaTable {
    inv: f32,
    /// `steps[k]`: the bits of the smallest input whose code is at least
    /// k (k in 1..=255); `steps[0]` is 0 and `steps[256]` past 1.0.
    steps: [u32; 257],
    /// The code at the start of each run of `1 << SHIFT` inputs.
    runs: Vec<u8>,
    /// Half the width of the guard band around each step, in units in
    /// the last place of the input.
    band: u32,
}

/// The gammas the table is made for: its guard bands are wide enough
/// there (and a display's gamma is near 2).
const GAMMAS: std::ops::RangeInclusive<f32> = 0.1..=20.0;

impl GammaTable {
    /// The table for `gamma`, or None outside `GAMMAS` (computed then).
    pub(crate) fn new(gamma: f32) -> Option<GammaTable> {
        GAMMAS.contains(&gamma).then(|| GammaTable::made(gamma))
    }

    fn made(gamma: f32) -> GammaTable {
        let inv = 1.0 / gamma;
        let code = |bits: u32| quantize(f32::from_bits(bits).powf(inv));
        let mut steps = [0u32; 257];
        for (k, step) in steps.iter_mut().enumerate().skip(1).take(255) {
            *step = first_at_least(k as u8, code);
        }
        steps[256] = ONE + 1;
        // Non-decreasing even if powf were not: the bands cover the rest.
        for k in 1..257 {
            steps[k] = steps[k].max(steps[k - 1]);
        }
        let runs = (0..=ONE >> SHIFT)
            .map(|run| steps[1..].partition_point(|&s| s <= run << SHIFT) as u8)
            .collect();
        // Near a step the power moves `inv` times as fast as the input, in
        // relative terms: 16 units of the output (with a factor 2 for where
        // the two fall in their binades) need 32 / inv units of the input.
        let band = (32.0 * gamma).ceil().max(32.0) as u32;
        GammaTable {
            inv,
            steps,
            runs,
            band,
        }
    }

    /// `quantize(x.powf(1 / gamma))`, for `x` in [0, 1] or any other value.
    #[inline(always)]
    pub(crate) fn code(&self, x: f32) -> u8 {
        let bits = x.to_bits();
        // C's pow: +0 to any positive power is +0 (the black background).
        if bits == 0 {
            return 0;
        }
        // 1, negative numbers, NaN and anything above 1: computed.
        if bits >= ONE {
            return self.exact(x);
        }
        let mut k = self.runs[(bits >> SHIFT) as usize] as usize;
        while bits >= self.steps[k + 1] {
            k += 1;
        }
        let near_below = k > 0 && bits - self.steps[k] < self.band;
        let near_above = self.steps[k + 1] - bits <= self.band;
        if near_below || near_above {
            return self.exact(x);
        }
        k as u8
    }

    fn exact(&self, x: f32) -> u8 {
        quantize(x.powf(self.inv))
    }
}

/// The bits of the smallest x in (0, 1] with `code(x) >= k`, bisecting
/// the bits of positive floats (ordered as the floats are).
fn first_at_least(k: u8, code: impl Fn(u32) -> u8) -> u32 {
    let (mut lo, mut hi) = (0u32, ONE);
    if code(hi) < k {
        return ONE + 1;
    }
    // code(lo) < k <= code(hi), for all k >= 1 as code(0) = 0.
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if code(mid) >= k {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// The lab's truncation to 8 bits; `as` maps NaN to 0.
pub fn quantize(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0) as u8
}

/// The lab's rule at 16 bits: `(int)(c * 65535)`, truncated. As
/// 65535 = 255 * 257, a 16-bit value divided by 257 (truncated) is the
/// 8-bit value of the same colour, up to f32 rounding of the two products.
pub fn quantize16(c: f32) -> u16 {
    (c.clamp(0.0, 1.0) * 65535.0) as u16
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;

    fn exact(x: f32, gamma: f32) -> u8 {
        quantize(x.powf(1.0 / gamma))
    }

    /// Every float of [0, 1] (1,065,353,217 of them), in parallel: about a
    /// second per core and gamma.
    fn check_every_input(gamma: f32) {
        let table = GammaTable::made(gamma);
        let wrong = (0..=ONE)
            .into_par_iter()
            .find_first(|&bits| {
                let x = f32::from_bits(bits);
                table.code(x) != exact(x, gamma)
            })
            .map(f32::from_bits);
        assert_eq!(wrong, None, "gamma {gamma}");
    }

    #[test]
    fn every_input_gives_the_powf_byte() {
        // The lab's gamma, every scene's default.
        check_every_input(2.2);
    }

    #[test]
    fn inputs_near_every_step_give_the_powf_byte_at_other_gammas() {
        for gamma in [1.0, 1.8, 2.4, 0.45, 0.1, 3.0, 20.0] {
            let table = GammaTable::made(gamma);
            let near_steps = table.steps[1..256]
                .iter()
                .flat_map(|&s| s.saturating_sub(5000)..=(s + 5000).min(ONE));
            for bits in near_steps.chain((0..=ONE).step_by(997)) {
                let x = f32::from_bits(bits);
                assert_eq!(table.code(x), exact(x, gamma), "gamma {gamma}, x {x:e}");
            }
        }
    }

    #[test]
    fn values_outside_0_1_are_computed() {
        assert!(GammaTable::new(0.05).is_none() && GammaTable::new(f32::NAN).is_none());
        let table = GammaTable::made(2.2);
        for x in [-0.0, -1.0, 1.0, 1.5, f32::NAN, f32::INFINITY, 0.0] {
            assert_eq!(table.code(x), exact(x, 2.2), "{x}");
        }
        // 0.5^(1/2.2) = 0.7297 -> 186.08 -> 186
        assert_eq!(table.code(0.5), 186);
    }

    #[test]
    fn steps_are_where_the_code_changes() {
        let table = GammaTable::made(2.2);
        for k in 1..256 {
            let step = table.steps[k];
            assert_eq!(exact(f32::from_bits(step), 2.2), k as u8, "step {k}");
            assert_eq!(
                exact(f32::from_bits(step - 1), 2.2),
                k as u8 - 1,
                "below step {k}"
            );
        }
        // 1/255 is the first step's power: x = (1/255)^2.2, about 5.1e-6.
        let first = f32::from_bits(table.steps[1]);
        assert!(
            (first / (1.0f32 / 255.0).powf(2.2) - 1.0).abs() < 1e-4,
            "{first:e}"
        );
    }
}
