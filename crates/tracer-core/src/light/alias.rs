//! Picking one of many items in proportion to a weight, in constant time:
//! Walker's alias method, built as Vose describes ("A linear algorithm for
//! generating random numbers with a given distribution", 1991).

use serde::{Deserialize, Serialize};

/// Each item's probability, and for each of n equal slots the share its
/// own item keeps and the item that takes the rest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AliasTable {
    pmf: Vec<f32>,
    keep: Vec<f32>,
    alias: Vec<u32>,
}

impl AliasTable {
    /// The table of `weights` (each >= 0, finite); None when they are all 0.
    pub fn new(weights: &[f64]) -> Option<AliasTable> {
        let total: f64 = weights.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let n = weights.len();
        let scaled: Vec<f64> = weights.iter().map(|w| w / total * n as f64).collect();
        let mut keep = vec![1.0; n];
        let mut alias: Vec<u32> = (0..n as u32).collect();
        let (mut small, mut large): (Vec<usize>, Vec<usize>) =
            (0..n).partition(|&i| scaled[i] < 1.0);
        let mut left = scaled.clone();
        while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
            keep[s] = left[s];
            alias[s] = l as u32;
            left[l] -= 1.0 - left[s];
            if left[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // What is left in either list keeps its whole slot (rounding).
        Some(AliasTable {
            pmf: weights.iter().map(|w| (w / total) as f32).collect(),
            keep: keep.into_iter().map(|k| k as f32).collect(),
            alias,
        })
    }

    pub fn len(&self) -> usize {
        self.pmf.len()
    }

    pub fn is_empty(&self) -> bool {
        self.pmf.is_empty()
    }

    /// The probability of item `i`.
    pub fn pmf(&self, i: usize) -> f32 {
        self.pmf[i]
    }

    /// The item `u` (in [0, 1)) picks, and its probability.
    #[inline(always)]
    pub fn sample(&self, u: f32) -> (usize, f32) {
        let n = self.pmf.len();
        let x = u * n as f32;
        let slot = (x as usize).min(n - 1);
        let within = x - slot as f32;
        let i = if within < self.keep[slot] {
            slot
        } else {
            self.alias[slot] as usize
        };
        (i, self.pmf[i])
    }
}

impl AliasTable {
    /// Whether a table read back from a file (`--cache`) can be sampled:
    /// its lists of one length, not empty, every alias within them.
    pub(crate) fn is_whole(&self) -> bool {
        let n = self.pmf.len();
        n > 0
            && self.keep.len() == n
            && self.alias.len() == n
            && self.alias.iter().all(|&a| (a as usize) < n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn items_are_picked_in_proportion_to_their_weights() {
        let weights = [1.0, 0.0, 3.0, 0.5, 5.5];
        let table = AliasTable::new(&weights).unwrap();
        let n = 100_000;
        let mut counts = [0usize; 5];
        for k in 0..n {
            let (i, p) = table.sample((k as f32 + 0.5) / n as f32);
            assert_eq!(p, table.pmf(i));
            counts[i] += 1;
        }
        for (i, w) in weights.iter().enumerate() {
            let expected = w / 10.0;
            let got = counts[i] as f64 / n as f64;
            // Evenly spaced u: the error is the slots' rounding, not noise.
            assert!((got - expected).abs() < 1e-3, "{i}: {got} vs {expected}");
        }
        assert!(AliasTable::new(&[0.0, 0.0]).is_none());
        assert!(AliasTable::new(&[]).is_none());
    }
}
