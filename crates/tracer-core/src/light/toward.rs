//! A light's point seen from a shaded point, for any lane width: the
//! direction and distance to it, and the density by solid angle of a point
//! drawn by area on a flat light. Written once for the one-path tracer's
//! light samples (`area.rs`, `lights.rs`) and the lanes' (`matte_lanes`).

use crate::simd::{Real, V3};

/// How much shorter than a light's point's distance a shadow ray (or a
/// connection of shared paths) stops, relative: the light's own surface
/// must not count as in the way.
pub const SHADOW_SHORTEN: f32 = 1e-4;

/// The way from a shaded point to a light's point.
#[derive(Debug, Clone, Copy)]
pub struct Toward<N: Real> {
    /// Unit, toward the light's point.
    pub wi: V3<N>,
    pub distance: N,
    pub distance2: N,
    /// Where the point is a positive distance away (not the shaded point
    /// itself, nor NaN).
    pub apart: N::Mask,
}

/// The way from `from` to `point`.
#[inline(always)]
pub fn toward<N: Real>(from: V3<N>, point: V3<N>) -> Toward<N> {
    let to = point - from;
    let distance2 = to.length_squared();
    let distance = distance2.sqrt();
    Toward {
        wi: to / distance,
        distance,
        distance2,
        apart: !(distance.is_nan() | distance.le(N::zero())),
    }
}

/// Barycentric `(b1, b2)` of the flat shape `v0 + b1 e1 + b2 e2`.
#[inline(always)]
pub fn flat_shape_point<N: Real>(v0: V3<N>, (e1, e2): (V3<N>, V3<N>), (b1, b2): (N, N)) -> V3<N> {
    v0 + e1 * b1 + e2 * b2
}

/// The density by solid angle, d^2 / (cos A), of a point drawn uniformly
/// on a flat light of `area` and unit `normal`, seen the way `way`; and
/// where it is seen from its emitting side (a NaN cosine counts as seen:
/// its density is NaN, which the light sample then drops).
#[inline(always)]
pub fn flat_pdf<N: Real>(way: &Toward<N>, normal: V3<N>, area: N) -> (N, N::Mask) {
    let cos = -way.wi.dot(normal);
    (way.distance2 / (cos * area), !cos.le(N::zero()))
}
