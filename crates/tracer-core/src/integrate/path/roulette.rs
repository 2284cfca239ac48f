//! Russian roulette (Arvo and Kirk 1990), for one path or for lanes: past
//! the first bounces a path carrying little energy may end, and one that
//! goes on carries more, so the estimate keeps its mean.

use crate::simd::{Real, V3};

/// Bounces before Russian roulette may end a path: the first few carry
/// most of the light, and ending them early costs more noise than time.
pub(crate) const ROULETTE_DEPTH: u32 = 5;

/// The roulette of paths of throughput `throughput`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Roulette<N: Real> {
    /// The chance of going on: the throughput's largest channel, without
    /// refraction's eta^2 (the energy carried, not the radiance).
    pub q: N,
    /// Where the roulette is played (deep enough, and q below 1).
    pub played: N::Mask,
    /// Where the number drawn is below q.
    pub survived: N::Mask,
    /// The throughput a path goes on with: divided by q where played.
    pub throughput: V3<N>,
}

/// The roulette of the paths `deep` enough to play it, of throughput
/// `throughput` (`eta_scale`: 1 / the eta^2 of their refractions so far),
/// with the number `survive` each drew.
#[inline(always)]
pub(crate) fn roulette<N: Real>(
    throughput: V3<N>,
    eta_scale: N,
    deep: N::Mask,
    survive: N,
) -> Roulette<N> {
    let q = (throughput * eta_scale).max_element();
    let played = deep & q.lt(N::one());
    Roulette {
        q,
        played,
        survived: survive.lt(q),
        throughput: V3::select(played, throughput / q, throughput),
    }
}
