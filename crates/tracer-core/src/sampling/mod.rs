//! Deterministic sample positions: strata over a unit square, jittered by a
//! hash of where they are used, so an image is the same on every run and
//! at every thread count; the warps of the unit square onto shapes
//! (`warp.rs`) and the weights of multiple importance sampling (`mis.rs`),
//! as pbrt-v4's `util/sampling.h`.

pub mod mis;
pub mod warp;

use glam::Vec2;

/// A stream of random numbers seeded by a hash (SplitMix64): cheap to seed
/// per pixel sample, and the same stream for the same seed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The stream of pixel (i, j)'s sample `s`.
    pub fn for_sample(i: u32, j: u32, s: u32) -> Rng {
        Rng(hash(i, j, s))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        mix(self.0)
    }

    /// A point of the unit square [0, 1)^2.
    pub fn square(&mut self) -> Vec2 {
        let bits = self.next_u64();
        Vec2::new(unit_float(bits), unit_float(bits >> 32))
    }
}

/// A 64-bit mix of a pixel and a sample index (SplitMix64's finaliser).
pub fn hash(i: u32, j: u32, s: u32) -> u64 {
    let z = (u64::from(i) << 40) ^ (u64::from(j) << 20) ^ u64::from(s);
    mix(z.wrapping_add(0x9E37_79B9_7F4A_7C15))
}

fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A float in [0, 1) from the low 24 bits.
pub fn unit_float(bits: u64) -> f32 {
    (bits & 0xFF_FFFF) as f32 / (1u32 << 24) as f32
}

/// `n` strata of the unit square: a grid as square as `n` allows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Strata {
    columns: u32,
    rows: u32,
}

impl Strata {
    pub fn new(n: u32) -> Strata {
        let n = n.max(1);
        let columns = grid_columns(n);
        Strata {
            columns,
            rows: n / columns,
        }
    }

    /// The point of stratum `s` (0..n) at `jitter` (in [0, 1)^2) within it.
    pub fn point(&self, s: u32, jitter: Vec2) -> Vec2 {
        let cell = Vec2::new((s % self.columns) as f32, (s / self.columns) as f32);
        (cell + jitter) / Vec2::new(self.columns as f32, self.rows as f32)
    }
}

/// The largest divisor of `n` not above its square root: the columns of a
/// grid of exactly `n` strata.
fn grid_columns(n: u32) -> u32 {
    (1..=n.isqrt())
        .rev()
        .find(|c| n.is_multiple_of(*c))
        .unwrap_or(1)
}

/// A second order of `n` strata, so two quantities sampled from the same
/// sample index (the point in the pixel, the point on the lens) do not
/// move together: a pseudo-random permutation of `0..n`, a different one
/// for each seed (Kensler's hashed permutation, "Correlated Multi-Jittered
/// Sampling", 2013: a bijection of the next power of two, walked until it
/// lands below `n`). One fixed order for every pixel would pair the same n
/// of the n^2 (pixel stratum, lens stratum) cells in every pixel, so each
/// pixel would average over those cells only: biased wherever the colour
/// depends on both, as across a blur about a pixel wide.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shuffle {
    n: u32,
    /// The next power of two of `n`, less one.
    mask: u32,
}

impl Shuffle {
    pub fn new(n: u32) -> Shuffle {
        let n = n.max(1);
        Shuffle {
            n,
            mask: n.next_power_of_two() - 1,
        }
    }

    /// Where permutation `seed` puts `s` (in `0..n`).
    pub fn apply(&self, s: u32, seed: u32) -> u32 {
        let (w, p) = (self.mask, seed);
        let mut i = s;
        // Each step is a bijection of the low bits under the mask (xor,
        // odd multipliers, xor-shifts of the masked bits), so is the whole.
        loop {
            i ^= p;
            i = i.wrapping_mul(0xe170_893d);
            i ^= p >> 16;
            i ^= (i & w) >> 4;
            i ^= p >> 8;
            i = i.wrapping_mul(0x0929_eb3f);
            i ^= p >> 23;
            i ^= (i & w) >> 1;
            i = i.wrapping_mul(1 | p >> 27);
            i = i.wrapping_mul(0x6935_fa69);
            i ^= (i & w) >> 11;
            i = i.wrapping_mul(0x74dc_b303);
            i ^= (i & w) >> 2;
            i = i.wrapping_mul(0x9e50_1cc3);
            i ^= (i & w) >> 2;
            i = i.wrapping_mul(0xc860_a3df);
            i &= w;
            i ^= i >> 5;
            if i < self.n {
                break;
            }
        }
        (i + p % self.n) % self.n
    }
}

/// `warp::concentric_disk` of one point.
pub fn concentric_disk(p: Vec2) -> Vec2 {
    let (x, y) = warp::concentric_disk((p.x, p.y));
    Vec2::new(x, y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strata_tile_the_square_once_each() {
        for n in [2, 3, 4, 6, 9, 16, 7] {
            let strata = Strata::new(n);
            let (columns, rows) = (strata.columns, strata.rows);
            assert_eq!(columns * rows, n);
            let mut seen = vec![false; n as usize];
            let mut rng = Rng::new(n as u64);
            for s in 0..n {
                let p = strata.point(s, rng.square());
                assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
                let cell = (p.y * rows as f32) as u32 * columns + (p.x * columns as f32) as u32;
                assert!(!seen[cell as usize], "n {n}: stratum {cell} twice");
                seen[cell as usize] = true;
            }
        }
        assert_eq!(grid_columns(16), 4);
        assert_eq!(grid_columns(6), 2);
        assert_eq!(grid_columns(7), 1);
    }

    #[test]
    fn a_shuffle_is_a_permutation() {
        for n in [1, 2, 5, 16, 64, 100, 4096] {
            let shuffle = Shuffle::new(n);
            for seed in [0, 1, 0xdead_beef, u32::MAX] {
                let mut seen = vec![false; n as usize];
                for s in 0..n {
                    let t = shuffle.apply(s, seed) as usize;
                    assert!(!seen[t], "n {n}, seed {seed}: {t} twice");
                    seen[t] = true;
                }
            }
        }
    }

    #[test]
    fn over_seeds_a_shuffle_sends_a_sample_to_every_stratum_alike() {
        // What makes a pixel's lens strata unbiased: over the pixels'
        // seeds, sample s's lens stratum is any of the n equally often.
        let (n, seeds) = (16, 16_000);
        let shuffle = Shuffle::new(n);
        for s in [0, 5, 15] {
            let mut counts = vec![0; n as usize];
            for seed in 0..seeds {
                let seed = Rng::new(seed).next_u64() as u32;
                counts[shuffle.apply(s, seed) as usize] += 1;
            }
            // 1000 expected, binomial sd about 31.
            assert!(
                counts.iter().all(|&c| (850..1150).contains(&c)),
                "{counts:?}"
            );
        }
    }

    #[test]
    fn the_concentric_map_keeps_area_and_stays_in_the_disk() {
        // Uniform on the square -> uniform on the disk: the fraction within
        // radius 1/2 is a quarter.
        let mut rng = Rng::new(7);
        let n = 20_000;
        let mut inner = 0;
        for _ in 0..n {
            let d = concentric_disk(rng.square());
            assert!(d.length() <= 1.0 + 1e-6);
            inner += usize::from(d.length() < 0.5);
        }
        let fraction = inner as f32 / n as f32;
        assert!((fraction - 0.25).abs() < 0.01, "{fraction}");
    }

    #[test]
    fn streams_are_deterministic_and_differ_by_seed() {
        let a = Rng::for_sample(1, 2, 3).square();
        assert_eq!(a, Rng::for_sample(1, 2, 3).square());
        assert_ne!(a, Rng::for_sample(2, 2, 3).square());
        assert_ne!(a, Rng::for_sample(1, 2, 4).square());
    }
}
