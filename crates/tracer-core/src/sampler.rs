//! The path tracer's sample sequence: for each pixel, `n` samples of as
//! many dimensions as a path asks for, deterministic (the same numbers for
//! the same pixel, sample and dimension, whatever the threads or tiles).
//!
//! Each 1D or 2D request of a path (the point in the pixel, the lens, each
//! bounce's light choice, light point, lobe and direction) draws from its
//! own copy of the first two dimensions of the Sobol sequence, Owen
//! scrambled, its sample order shuffled, both by a hash of the pixel and
//! the request's number: a "padded" Sobol sampler (as pbrt-v4's
//! `PaddedSobolSampler`), with Burley's hashed shuffle and scrambling
//! ("Practical Hash-based Owen Scrambling", 2020). Every 2D projection is
//! then a (0, 2)-sequence in base 2: each power-of-two prefix of it puts
//! one point in each of the elementary intervals of its area, which is
//! what makes edges and small lights converge faster than N^-1/2, while no
//! two requests are correlated.

use glam::Vec2;

/// The samples of one pixel: which pixel, which sample, and how many
/// dimensions the current sample has used.
#[derive(Debug, Clone, Copy)]
pub struct PixelSampler {
    /// A hash of the pixel (and the seed).
    pixel: u64,
    /// The current sample's number, its bits reversed (the scramblings
    /// work on reversed bits).
    reversed_sample: u32,
    dimension: u32,
}

impl PixelSampler {
    /// The sampler of pixel (i, j); `seed` picks another, independent set
    /// of scramblings (0 for renders; other seeds give independent
    /// renders, for tests). Any number of samples may be drawn: each
    /// power-of-two prefix of them is a net.
    pub fn new(i: u32, j: u32, seed: u32) -> PixelSampler {
        PixelSampler {
            pixel: crate::sampling::hash(i, j, seed ^ 0x5EED_0000),
            reversed_sample: 0,
            dimension: 0,
        }
    }

    /// Starts sample `s`, from its first dimension.
    pub fn start(&mut self, s: u32) {
        self.reversed_sample = s.reverse_bits();
        self.dimension = 0;
    }

    /// Passes over `requests` 1D or 2D requests without drawing them: the
    /// requests after them get the numbers they would have had.
    #[inline(always)]
    pub fn skip(&mut self, requests: u32) {
        self.dimension += requests;
    }

    /// The next request's hash (the pixel's, mixed with the request's
    /// number), the request counted.
    #[inline(always)]
    fn next_hash(&mut self) -> u64 {
        let h = dimension_hash(self.pixel, self.dimension);
        self.dimension += 1;
        h
    }

    /// The current sample's index into the Sobol sequence for the request
    /// of hash `h` (`sobol_index`).
    #[inline(always)]
    fn index(&self, h: u64) -> u32 {
        sobol_index(self.reversed_sample, h)
    }

    /// A number of [0, 1): the first Sobol dimension (the index's bits
    /// reversed), Owen scrambled, the reversals that cancel left out.
    #[inline(always)]
    pub fn get1(&mut self) -> f32 {
        let h = self.next_hash();
        first_value(self.index(h), h)
    }

    /// A point of [0, 1)^2.
    #[inline(always)]
    pub fn get2(&mut self) -> Vec2 {
        let h = self.next_hash();
        let index = self.index(h);
        Vec2::new(
            first_value(index, h),
            second_value(sobol_second_reversed(index), h),
        )
    }
}

/// The samplers of paths traced in SIMD lanes, kept by field (each lane's
/// pixel, sample and request), so that a request of every lane is worked
/// out a step at a time in SIMD registers. Each lane gives the numbers its
/// `PixelSampler` would.
#[derive(Debug, Clone, Copy)]
pub struct LaneSamplers<const N: usize> {
    pixel: [u64; N],
    reversed_sample: [u32; N],
    dimension: [u32; N],
}

impl<const N: usize> Default for LaneSamplers<N> {
    fn default() -> Self {
        Self::new()
    }
}

// Each lane's index reads several arrays at once: plain loops over the
// lanes, which the compiler turns into SIMD instructions.
#[allow(clippy::needless_range_loop)]
impl<const N: usize> LaneSamplers<N> {
    /// Lanes of no pixel yet.
    pub fn new() -> Self {
        LaneSamplers {
            pixel: [0; N],
            reversed_sample: [0; N],
            dimension: [0; N],
        }
    }

    /// Lane `k` goes on from where `sampler` is.
    pub fn set(&mut self, k: usize, sampler: &PixelSampler) {
        self.pixel[k] = sampler.pixel;
        self.reversed_sample[k] = sampler.reversed_sample;
        self.dimension[k] = sampler.dimension;
    }

    /// Moves lane `k` past `requests` requests.
    pub fn skip(&mut self, k: usize, requests: u32) {
        self.dimension[k] += requests;
    }

    /// What `get1` gives each lane as its request `dimension + offset`.
    #[inline(always)]
    pub fn get1(&self, offset: u32) -> [f32; N] {
        let (h, index) = self.hashes_and_indices(offset);
        let mut x = [0.0; N];
        for k in 0..N {
            x[k] = first_value(index[k], h[k]);
        }
        x
    }

    /// What `get2` gives each lane as its request `dimension + offset`,
    /// by axis.
    #[inline(always)]
    pub fn get2(&self, offset: u32) -> ([f32; N], [f32; N]) {
        let (h, index) = self.hashes_and_indices(offset);
        let (mut x, mut y) = ([0.0; N], [0.0; N]);
        for k in 0..N {
            x[k] = first_value(index[k], h[k]);
        }
        // The table look-ups in a loop of their own: the rest vectorises.
        let mut second = [0u32; N];
        for k in 0..N {
            second[k] = sobol_second_reversed(index[k]);
        }
        for k in 0..N {
            y[k] = second_value(second[k], h[k]);
        }
        (x, y)
    }

    /// Each lane's hash and Sobol index for its request `dimension +
    /// offset` (`PixelSampler::hash` and `index`).
    #[inline(always)]
    fn hashes_and_indices(&self, offset: u32) -> ([u64; N], [u32; N]) {
        let (mut h, mut index) = ([0u64; N], [0u32; N]);
        for k in 0..N {
            h[k] = dimension_hash(self.pixel[k], self.dimension[k] + offset);
        }
        for k in 0..N {
            index[k] = sobol_index(self.reversed_sample[k], h[k]);
        }
        (h, index)
    }
}

/// Request `d`'s hash: the pixel's `pixel`, mixed with the request's number.
#[inline(always)]
fn dimension_hash(pixel: u64, d: u32) -> u64 {
    mix64(pixel ^ (u64::from(d) + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15))
}

/// The index into the Sobol sequence of the sample whose number, bits
/// reversed, is `reversed_sample`, for the request of hash `h`: the sample
/// order shuffled per request by an Owen scrambling of the index, which
/// maps the first 2^k indices to indices whose low k bits are all
/// different, and so to the same elementary intervals as the first 2^k
/// points.
#[inline(always)]
fn sobol_index(reversed_sample: u32, h: u64) -> u32 {
    lk_hash(reversed_sample, (h >> 32) as u32).reverse_bits() & INDEX_MASK
}

/// The first coordinate of the point of Sobol index `index` for the
/// request of hash `h`: the first Sobol dimension (the index's bits
/// reversed), Owen scrambled, the reversals that cancel left out.
#[inline(always)]
fn first_value(index: u32, h: u64) -> f32 {
    to_unit(lk_hash(index, h as u32).reverse_bits())
}

/// The second coordinate, from the second Sobol dimension of the index
/// (`sobol_second_reversed`), scrambled by a third seed from the product's
/// high bits: each depends on all of h's, unlike the two halves the first
/// two seeds are.
#[inline(always)]
fn second_value(second_reversed: u32, h: u64) -> f32 {
    let seed2 = (h.wrapping_mul(0xD1B5_4A32_D192_ED03) >> 32) as u32;
    to_unit(lk_hash(second_reversed, seed2).reverse_bits())
}

/// The index bits that reach a float: a point's top 24 bits (all a float
/// of [0, 1) keeps) depend on the index's low 24 bits only, as each
/// direction number of the first two dimensions starts at its own bit.
const INDEX_MASK: u32 = (1 << 24) - 1;

/// SplitMix64's finaliser: a 64-bit hash.
#[inline(always)]
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The second dimension of the Sobol sequence, as 32-bit fixed point, for
/// an index below 2^24, its bits reversed (as the scrambling takes it):
/// its generator matrix is Pascal's triangle mod 2, each direction number
/// the one before xor itself shifted by one; the xor of the direction
/// numbers of the index's set bits, a byte at a time.
#[inline(always)]
fn sobol_second_reversed(index: u32) -> u32 {
    let [b0, b1, b2, _] = index.to_le_bytes();
    SOBOL_SECOND[0][b0 as usize] ^ SOBOL_SECOND[1][b1 as usize] ^ SOBOL_SECOND[2][b2 as usize]
}

/// For each byte k of the index and each value of it, the xor of the
/// direction numbers 8k .. 8k + 7 its bits select, bits reversed.
static SOBOL_SECOND: [[u32; 256]; 3] = sobol_second_tables();

const fn sobol_second_tables() -> [[u32; 256]; 3] {
    let mut directions = [0u32; 24];
    let mut v = 1u32 << 31;
    let mut k = 0;
    while k < 24 {
        directions[k] = v;
        v ^= v >> 1;
        k += 1;
    }
    let mut tables = [[0u32; 256]; 3];
    let mut byte = 0;
    while byte < 3 {
        let mut value = 0;
        while value < 256 {
            let mut x = 0;
            let mut bit = 0;
            while bit < 8 {
                if value & (1 << bit) != 0 {
                    x ^= directions[8 * byte + bit];
                }
                bit += 1;
            }
            tables[byte][value] = x.reverse_bits();
            value += 1;
        }
        byte += 1;
    }
    tables
}

/// An Owen scrambling of a 32-bit fixed-point number, on its reversed
/// bits (the scrambling of x is `lk_hash(x.reverse_bits()).reverse_bits()`):
/// each bit flipped by a hash of the bits above it in x, so every
/// elementary interval is permuted as a whole and the net's strata are
/// kept. Laine and Karras' hash, with Vegdahl's constants ("Building a
/// better LK hash", 2021), which make it close to a true Owen scrambling.
#[inline(always)]
fn lk_hash(mut v: u32, seed: u32) -> u32 {
    v ^= v.wrapping_mul(0x3d20_adea);
    v = v.wrapping_add(seed);
    v = v.wrapping_mul((seed >> 16) | 1);
    v ^= v.wrapping_mul(0x0552_6c56);
    v ^= v.wrapping_mul(0x53a2_2864);
    v
}

/// A 32-bit fixed-point number as a float of [0, 1): its top 24 bits, so
/// the float is exact and never rounds up to 1.
#[inline(always)]
fn to_unit(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The second dimension one direction number at a time.
    fn sobol_second_by_bits(mut index: u32) -> u32 {
        let (mut v, mut x) = (1u32 << 31, 0);
        while index != 0 {
            if index & 1 != 0 {
                x ^= v;
            }
            index >>= 1;
            v ^= v >> 1;
        }
        x
    }

    #[test]
    fn the_second_sobol_dimension_is_a_0_2_net_with_the_first() {
        // Every power-of-two prefix of (radical inverse, sobol_second) puts
        // one point in each elementary interval of area 1/n: here the
        // 2^a x 2^b grids with a + b = log2 n.
        for log_n in [2u32, 4, 6, 8] {
            let n = 1u32 << log_n;
            for a in 0..=log_n {
                let b = log_n - a;
                let mut seen = vec![false; n as usize];
                for i in 0..n {
                    let top = |v: u32, bits: u32| v.checked_shr(32 - bits).unwrap_or(0);
                    let (x, y) = (i.reverse_bits(), sobol_second_reversed(i).reverse_bits());
                    assert_eq!(y, sobol_second_by_bits(i));
                    let cell = (top(x, a) << b) | top(y, b);
                    assert!(!seen[cell as usize], "n {n}, {a}x{b}: cell {cell} twice");
                    seen[cell as usize] = true;
                }
            }
        }
    }

    #[test]
    fn owen_scrambling_keeps_the_strata() {
        // Scrambled, a net stays a net: the 16 points of a pixel's 2D
        // request fall one in each cell of the 4x4 grid, whatever the pixel.
        for (i, j) in [(0, 0), (3, 7), (100, 250)] {
            let mut sampler = PixelSampler::new(i, j, 0);
            let mut seen = [false; 16];
            let mut quarters = [false; 4];
            for s in 0..16 {
                sampler.start(s);
                sampler.get1();
                let p = sampler.get2();
                let cell = (p.y * 4.0) as usize * 4 + (p.x * 4.0) as usize;
                assert!(!seen[cell], "pixel ({i}, {j}): cell {cell} twice");
                seen[cell] = true;
                // The first 4 (a power-of-two prefix) are a net too.
                if s < 4 {
                    let quarter = (p.y * 2.0) as usize * 2 + (p.x * 2.0) as usize;
                    assert!(
                        !quarters[quarter],
                        "pixel ({i}, {j}): quarter {quarter} twice"
                    );
                    quarters[quarter] = true;
                }
            }
        }
    }

    #[test]
    fn samples_are_uniform_and_independent_of_each_other_across_pixels() {
        // Over many pixels, the mean of a dimension is 1/2 and the
        // correlation of two dimensions is 0, within a few standard errors.
        let (mut sum, mut product, mut n) = (0.0f64, 0.0f64, 0.0f64);
        for j in 0..64 {
            for i in 0..64 {
                let mut sampler = PixelSampler::new(i, j, 0);
                for s in 0..4 {
                    sampler.start(s);
                    let a = sampler.get2();
                    let b = sampler.get1();
                    assert!((0.0..1.0).contains(&a.x) && (0.0..1.0).contains(&b));
                    sum += f64::from(a.x);
                    product += (f64::from(a.y) - 0.5) * (f64::from(b) - 0.5);
                    n += 1.0;
                }
            }
        }
        // sd of a uniform: 1/sqrt(12); of a product of two: 1/12.
        let mean_error = (sum / n - 0.5).abs();
        assert!(
            mean_error < 4.0 / (12.0f64.sqrt() * n.sqrt()),
            "{mean_error}"
        );
        let correlation = (product / n).abs();
        assert!(correlation < 4.0 / (12.0 * n.sqrt()), "{correlation}");
    }

    #[test]
    fn lanes_draw_what_each_lanes_pixel_sampler_draws() {
        // Lanes of different pixels, samples and requests: each request of
        // each lane is the one its own sampler gives, bit for bit.
        let mut lanes = LaneSamplers::<4>::new();
        let mut own = [(0, 0, 0), (3, 9, 1), (200, 7, 63), (5, 5, 1000)].map(|(i, j, s)| {
            let mut sampler = PixelSampler::new(i, j, 0);
            sampler.start(s);
            sampler.skip(s % 7);
            sampler
        });
        for (k, sampler) in own.iter().enumerate() {
            lanes.set(k, sampler);
        }
        for offset in 0..6 {
            let ones = lanes.get1(offset);
            let (xs, ys) = lanes.get2(offset);
            for (k, sampler) in own.iter_mut().enumerate() {
                let (mut a, mut b) = (*sampler, *sampler);
                a.skip(offset);
                b.skip(offset);
                assert_eq!(ones[k].to_bits(), a.get1().to_bits(), "lane {k}, {offset}");
                let p = b.get2();
                assert_eq!(
                    [xs[k], ys[k]].map(f32::to_bits),
                    p.to_array().map(f32::to_bits)
                );
            }
        }
        lanes.skip(2, 3);
        own[2].skip(3);
        assert_eq!(
            lanes.get1(0)[2].to_bits(),
            own[2].get1().to_bits(),
            "after a skip"
        );
    }

    #[test]
    fn a_sample_is_the_same_whenever_it_is_drawn() {
        let mut a = PixelSampler::new(5, 9, 0);
        a.start(17);
        let first = (a.get2(), a.get1(), a.get2());
        let mut b = PixelSampler::new(5, 9, 0);
        b.start(3);
        b.get2();
        b.start(17);
        assert_eq!(first, (b.get2(), b.get1(), b.get2()));
        let mut other = PixelSampler::new(5, 9, 1);
        other.start(17);
        assert_ne!(first.0, other.get2(), "another seed, other numbers");
        let mut skipping = PixelSampler::new(5, 9, 0);
        skipping.start(17);
        skipping.skip(2);
        assert_eq!(first.2, skipping.get2(), "a skipped request is passed over");
    }
}
