//! The one band driver: an image's rows in bands of a few, rendered in
//! parallel on the current rayon pool (Whitted mode's pixels in
//! `render.rs`, path mode's pixel sums in `film.rs`).

use crate::integrate::RayStats;
use rayon::prelude::*;

/// Runs `band(first, items)` on each band of `rows` rows of `items` (`width`
/// a row), in parallel, where `first` is the band's first row (from 0),
/// calling `rows_done(n)` as bands finish: the sum of their ray counts.
pub fn in_bands<T: Send>(
    items: &mut [T],
    width: u32,
    rows: u32,
    rows_done: &(dyn Fn(u32) + Sync),
    band: impl Fn(u32, &mut [T]) -> RayStats + Sync,
) -> RayStats {
    let width = width as usize;
    if width == 0 {
        return RayStats::default();
    }
    items
        .par_chunks_mut(width * rows as usize)
        .enumerate()
        .map(|(k, items)| {
            let stats = band(k as u32 * rows, items);
            rows_done((items.len() / width) as u32);
            stats
        })
        .reduce(RayStats::default, |a, b| a + b)
}
