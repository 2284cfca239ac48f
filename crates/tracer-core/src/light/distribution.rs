//! Drawing a point of the unit square in proportion to a piecewise-constant
//! function over a grid of cells (an environment image's luminance): a
//! row from the rows' totals, then a column from that row's values, each by
//! inverting a cumulative sum.

use glam::Vec2;
use serde::{Deserialize, Serialize};

/// One dimension: a piecewise-constant function over n equal cells.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Distribution1D {
    /// The cumulative sums, normalised: n + 1 of them, 0 first, 1 last.
    cdf: Vec<f32>,
    /// The function's integral over [0, 1] (its mean).
    integral: f32,
    /// `Sums::guide` of `cdf`.
    guide: Vec<u32>,
}

/// A dimension's cumulative sums and their guide, wherever they are kept.
#[derive(Debug, Clone, Copy)]
struct Sums<'a> {
    /// n + 1 of them, 0 first, 1 last.
    cdf: &'a [f32],
    /// For each k of 0..=g (`guides(n)`), how many of `cdf` are at most
    /// k / g: a draw u's search starts between two of them, not over all
    /// of `cdf` (a search of all is a chain of cache misses per draw).
    guide: &'a [u32],
}

impl Distribution1D {
    /// The distribution of `values` (each >= 0); all zeros are uniform.
    fn new(values: &[f32]) -> Distribution1D {
        let (cdf, integral) = cumulative(values);
        Distribution1D {
            guide: guide(&cdf),
            cdf,
            integral,
        }
    }

    #[inline(always)]
    fn sums(&self) -> Sums<'_> {
        Sums {
            cdf: &self.cdf,
            guide: &self.guide,
        }
    }
}

/// The normalised cumulative sums of `values` (n + 1 of them; even steps
/// where all are zero) and their mean.
fn cumulative(values: &[f32]) -> (Vec<f32>, f32) {
    let n = values.len();
    let mut sums = Vec::with_capacity(n + 1);
    let mut acc = 0.0f64;
    sums.push(0.0);
    for &v in values {
        acc += f64::from(v) / n as f64;
        sums.push(acc);
    }
    let cdf: Vec<f32> = if acc > 0.0 {
        sums.iter().map(|&s| (s / acc) as f32).collect()
    } else {
        (0..=n).map(|k| k as f32 / n as f32).collect()
    };
    (cdf, acc as f32)
}

impl Sums<'_> {
    #[inline(always)]
    fn len(&self) -> usize {
        self.cdf.len() - 1
    }

    /// The point of [0, 1) that `u` maps to, and its cell.
    #[inline(always)]
    fn sample(&self, u: f32) -> (f32, usize) {
        let n = self.len();
        // The last cell whose cumulative sum is at most u.
        let cell = self.at_most(u).clamp(1, n) - 1;
        let (lo, hi) = (self.cdf[cell], self.cdf[cell + 1]);
        let within = if hi > lo { (u - lo) / (hi - lo) } else { 0.5 };
        (
            ((cell as f32 + within) / n as f32).min(1.0 - f32::EPSILON),
            cell,
        )
    }

    /// How many of `cdf` are at most `u`: counted between the guide's
    /// counts at the two k / g below u and the two above (u g rounds to
    /// within one of its floor), which hold it as `cdf` is sorted.
    #[inline(always)]
    fn at_most(&self, u: f32) -> usize {
        let g = self.guide.len().wrapping_sub(1);
        if !(0.0..1.0).contains(&u) || g != guides(self.len()) {
            return self.cdf.partition_point(|&c| c <= u);
        }
        let k = ((u * g as f32) as usize).min(g);
        // Clamped to the sums, so that no guide can index past them.
        let lo = (self.guide[k.saturating_sub(1)] as usize).min(self.cdf.len());
        let hi = (self.guide[(k + 2).min(g)] as usize).clamp(lo, self.cdf.len());
        // A count rather than a binary search: its loads do not wait on
        // one another (the sums are sorted, so the two agree).
        lo + self.cdf[lo..hi].iter().filter(|&&c| c <= u).count()
    }

    /// The density of cell `cell` (of the point's x in [0, 1)).
    #[inline(always)]
    fn density(&self, cell: usize) -> f32 {
        (self.cdf[cell + 1] - self.cdf[cell]) * self.len() as f32
    }
}

/// A piecewise-constant density over the unit square, `width` x `height`
/// cells, row 0 at v = 0.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Distribution2D {
    width: usize,
    /// Each row's cumulative sums (`width` + 1 a row), row after row: one
    /// list, so that a row is found by arithmetic, not by a pointer.
    cdf: Vec<f32>,
    /// Each row's guide (`guides(width)` + 1 a row), row after row.
    guide: Vec<u32>,
    /// The rows' totals.
    marginal: Distribution1D,
}

impl Distribution2D {
    /// The distribution of `values`, row by row, `width` a row.
    pub fn new(values: &[f32], width: usize) -> Distribution2D {
        let (mut cdf, mut guides, mut totals) = (Vec::new(), Vec::new(), Vec::new());
        for row in values.chunks(width) {
            let (sums, total) = cumulative(row);
            guides.extend(guide(&sums));
            cdf.extend(sums);
            totals.push(total);
        }
        Distribution2D {
            width,
            cdf,
            guide: guides,
            marginal: Distribution1D::new(&totals),
        }
    }

    /// Row `row`'s sums.
    #[inline(always)]
    fn row(&self, row: usize) -> Sums<'_> {
        let (n, g) = (self.width + 1, guides(self.width) + 1);
        Sums {
            cdf: &self.cdf[row * n..(row + 1) * n],
            guide: &self.guide[row * g..(row + 1) * g],
        }
    }

    /// A point of the square drawn by `u`, its density, and the cell
    /// (column, row) it is in.
    #[inline(always)]
    pub fn sample(&self, u: Vec2) -> (Vec2, f32, (usize, usize)) {
        let marginal = self.marginal.sums();
        let (v, row) = marginal.sample(u.y);
        let sums = self.row(row);
        let (x, column) = sums.sample(u.x);
        let density = marginal.density(row) * sums.density(column);
        (Vec2::new(x, v), density, (column, row))
    }

    /// The density at point `p` of the square.
    #[inline(always)]
    pub fn density(&self, p: Vec2) -> f32 {
        let marginal = self.marginal.sums();
        let height = marginal.len();
        let row = ((p.y * height as f32) as usize).min(height - 1);
        let column = ((p.x * self.width as f32) as usize).min(self.width - 1);
        marginal.density(row) * self.row(row).density(column)
    }

    /// The function's mean over the square.
    pub fn mean(&self) -> f32 {
        self.marginal.integral
    }
}

/// `Sums::guide` of `cdf`.
fn guide(cdf: &[f32]) -> Vec<u32> {
    let g = guides(cdf.len() - 1);
    (0..=g)
        .map(|k| cdf.partition_point(|&c| c <= k as f32 / g as f32) as u32)
        .collect()
}

/// How many steps the guide of `n` cells has: one per 8 cells (where cells
/// are even, a search of 8 to 24 sums, in a cache line or two), so that it
/// adds an eighth of the sums' memory, not as much again.
fn guides(n: usize) -> usize {
    n.div_ceil(8)
}

impl Sums<'_> {
    /// Whether sums read back from a file have `n` cells, and their guide
    /// is the one of the sums.
    fn is_whole(&self, n: usize) -> bool {
        n > 0 && self.cdf.len() == n + 1 && self.guide == guide(self.cdf)
    }
}

impl Distribution2D {
    /// Whether a distribution read back from a file (`--cache`) has
    /// `width` x `height` cells, so every draw stays within its lists.
    pub(crate) fn is_whole(&self, width: usize, height: usize) -> bool {
        self.marginal.sums().is_whole(height)
            && self.width == width
            && self.cdf.len() == (width + 1) * height
            && self.guide.len() == (guides(width) + 1) * height
            && (0..height).all(|r| self.row(r).is_whole(width))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_are_drawn_in_proportion_to_their_values() {
        // 2 x 2 cells of values 1, 3 (top) and 0, 4 (bottom): total 8.
        let d = Distribution2D::new(&[1.0, 3.0, 0.0, 4.0], 2);
        assert!((d.mean() - 2.0).abs() < 1e-6);
        let n = 200;
        let mut counts = [0usize; 4];
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let (p, density, (column, row)) = d.sample(u);
                let cell = (p.y * 2.0) as usize * 2 + (p.x * 2.0) as usize;
                assert_eq!(row * 2 + column, cell, "{p}");
                counts[cell] += 1;
                assert!((density - d.density(p)).abs() < 1e-5, "{p} {density}");
            }
        }
        let shares = counts.map(|c| c as f32 / (n * n) as f32);
        for (share, expected) in shares.iter().zip([1.0 / 8.0, 3.0 / 8.0, 0.0, 4.0 / 8.0]) {
            assert!((share - expected).abs() < 0.005, "{shares:?}");
        }
        // The density is the value over the mean: 4 / 2 = 2 in the last cell.
        assert!((d.density(Vec2::new(0.75, 0.75)) - 2.0).abs() < 1e-5);
    }

    /// Values of many shapes: even, one bright cell among dark ones
    /// (most cells in a sliver of u), runs of zeros, a ramp.
    fn shapes() -> Vec<Vec<f32>> {
        let mut x = 0x2545_F491_u32;
        let mut rand = move || {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x as f32 / u32::MAX as f32
        };
        let mut sun = vec![1e-3; 512];
        sun[300] = 1e6;
        let zeros: Vec<f32> = (0..97).map(|i| if i % 7 < 4 { 0.0 } else { 1.0 }).collect();
        let ramp: Vec<f32> = (0..1000).map(|i| (i as f32).powi(3)).collect();
        let noise: Vec<f32> = (0..333).map(|_| rand().powi(8)).collect();
        vec![vec![1.0; 5], vec![2.0], sun, zeros, ramp, noise]
    }

    #[test]
    fn the_guided_search_finds_what_a_search_of_every_sum_finds() {
        for values in shapes() {
            let d = Distribution1D::new(&values);
            let d = d.sums();
            let n = d.len();
            let full = |u: f32| d.cdf.partition_point(|&c| c <= u);
            // Every sum, every k / n and k / g, and a float either side of
            // each; then a fine grid; then what lies outside [0, 1).
            let mut us: Vec<f32> = d.cdf.to_vec();
            us.extend((0..=n).map(|k| k as f32 / n as f32));
            let g = guides(n);
            us.extend((0..=g).map(|k| k as f32 / g as f32));
            let near: Vec<f32> = us
                .iter()
                .flat_map(|&u| {
                    [
                        f32::from_bits(u.to_bits() - 1),
                        f32::from_bits(u.to_bits() + 1),
                    ]
                })
                .collect();
            us.extend(near);
            us.extend((0..100_000).map(|i| i as f32 / 100_000.0));
            us.extend([
                -0.0,
                -1e-9,
                1.0,
                1.5,
                f32::NAN,
                f32::INFINITY,
                1.0 - f32::EPSILON / 2.0,
            ]);
            for u in us {
                assert_eq!(d.at_most(u), full(u), "u = {u:e}, n = {n}");
            }
        }
    }

    #[test]
    fn a_distribution_with_another_guide_is_not_whole() {
        let mut d = Distribution2D::new(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], 3);
        assert!(d.is_whole(3, 2));
        assert!(!d.is_whole(2, 3));
        d.guide[1] += 1;
        assert!(!d.is_whole(3, 2));
        let mut d = Distribution2D::new(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], 3);
        d.cdf.pop();
        assert!(!d.is_whole(3, 2));
    }

    #[test]
    fn a_zero_function_is_drawn_uniformly() {
        let d = Distribution2D::new(&[0.0; 6], 3);
        let (p, density, _) = d.sample(Vec2::new(0.5, 0.5));
        assert!((density - 1.0).abs() < 1e-6 && (0.0..1.0).contains(&p.x));
    }
}
