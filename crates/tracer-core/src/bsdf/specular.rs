//! The lab's mirror (`reflectance`) and glass (`transmittance`, `ior`,
//! `fresnel`, as `material::Glass::split` divides a ray): lobes of a
//! single direction each.

use crate::optics::fresnel_reflectance;
use crate::simd::{Mask, Real, V3};
use glam::Vec3;

/// wo mirrored about the local normal, for any lane width.
#[inline(always)]
pub fn mirror<N: Real>(wo: V3<N>) -> V3<N> {
    V3::new(-wo.x, -wo.y, wo.z)
}

/// The direction refracted from local `wo` (`wo.z > 0`) with `eta` =
/// n(wo's side) / n(the other side), for any lane width; and where there
/// is one (not past the critical angle).
#[inline(always)]
pub fn refract<N: Real>(wo: V3<N>, eta: N) -> (V3<N>, N::Mask) {
    let cos_i = wo.z;
    let sin2_t = eta * eta * (N::one() - cos_i * cos_i).max(N::zero());
    let cos_t = (N::one() - sin2_t).sqrt();
    let along = V3::new(N::zero(), N::zero(), eta * cos_i - cos_t);
    let (wi, _) = (wo * -eta + along).try_normalize();
    (wi, !sin2_t.ge(N::one()))
}

/// A smooth interface: the lab's glass read physically. A ray reflects
/// with energy `reflected` and refracts with `transmitted`, as Whitted
/// mode splits it; radiance crossing into a denser medium is compressed
/// into a narrower cone, so a refracted path's throughput is scaled by
/// eta^2 (Veach's thesis, 5.2), which leaves a closed crossing (in and
/// out) unchanged.
#[derive(Debug, Clone, Copy)]
pub struct Interface<N: Real = f32> {
    /// n(wo's side) / n(the far side).
    pub eta: N,
    /// Reflected and transmitted energies of a ray along `wo`.
    pub reflected: N,
    pub transmitted: N,
    /// The refracted direction, where `refracts`.
    pub refracted: V3<N>,
    pub refracts: N::Mask,
}

impl Interface {
    /// The split of a ray along local `wo` meeting a dielectric: with
    /// `fresnel`, F reflected and (1 - F) `transmittance` transmitted;
    /// without, `reflectance` and `transmittance` as given (both reflected
    /// under total internal reflection). `eta` as in `Interface`.
    pub fn new(wo: Vec3, eta: f32, fresnel: bool, reflectance: f32, transmittance: f32) -> Self {
        let (refracted, refracts) = refract(V3::from(wo), eta);
        let (reflected, transmitted) = match (fresnel, refracts) {
            (true, _) => {
                let f = fresnel_reflectance(wo.z, eta);
                (f, (1.0 - f) * transmittance)
            }
            (false, false) => (reflectance + transmittance, 0.0),
            (false, true) => (reflectance, transmittance),
        };
        Interface {
            eta,
            reflected,
            transmitted: if refracts { transmitted } else { 0.0 },
            refracted,
            refracts,
        }
    }

    /// A mirror of energy `reflectance` (nothing transmitted).
    pub fn mirror(reflectance: f32) -> Interface {
        Interface {
            eta: 1.0,
            reflected: reflectance,
            transmitted: 0.0,
            refracted: V3::zero(),
            refracts: false,
        }
    }

    /// Several side by side, lane `k` being `each(k)`.
    pub fn lanes<N: Real>(each: impl Fn(usize) -> Interface) -> Interface<N> {
        Interface {
            eta: N::from_fn(|k| each(k).eta),
            reflected: N::from_fn(|k| each(k).reflected),
            transmitted: N::from_fn(|k| each(k).transmitted),
            refracted: V3::from_fn(|k| each(k).refracted.into()),
            refracts: N::Mask::from_fn(|k| each(k).refracts),
        }
    }
}

impl<N: Real> Interface<N> {
    /// The energy leaving along either direction.
    #[inline(always)]
    pub fn total(&self) -> N {
        self.reflected + self.transmitted
    }
}

/// One of the interface's two directions from local `wo`, picked with
/// probability in proportion to its energy by `u`, and its weight (energy
/// over probability, the transmitted one scaled by eta^2): the direction,
/// the weight, where it went through, and where there is one (energy
/// leaves).
#[inline(always)]
pub fn sample_interface<N: Real>(
    i: &Interface<N>,
    wo: V3<N>,
    u: N,
) -> (V3<N>, N, N::Mask, N::Mask) {
    let total = i.total();
    let crosses = i.refracts & (u * total).ge(i.reflected);
    let wi = V3::select(crosses, i.refracted, mirror(wo));
    let weight = N::select(crosses, total * i.eta * i.eta, total);
    (wi, weight, crosses, !total.le(N::zero()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refraction_follows_snell() {
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let (wt, through) = refract(V3::from(wo), 1.0 / 1.5);
        assert!(through, "into glass");
        let wt = Vec3::from(wt);
        assert!(wt.z < 0.0, "through the surface");
        let (sin_i, sin_t) = (wo.x, -wt.x);
        assert!((sin_i - 1.5 * sin_t).abs() < 1e-6);
        assert!((wt.length() - 1.0).abs() < 1e-6);
        // Out of glass past the critical angle (41.8 degrees): none.
        assert!(!refract(V3::from(Vec3::new(0.8, 0.0, 0.6)), 1.5).1);
    }

    #[test]
    fn a_fresnel_split_keeps_every_ray_s_energy() {
        for cos in [1.0f32, 0.7, 0.2] {
            let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
            for eta in [1.0 / 1.5, 1.5] {
                let i = Interface::new(wo, eta, true, 0.0, 1.0);
                assert!((i.total() - 1.0).abs() < 1e-6, "{cos} {eta}");
            }
        }
    }
}
