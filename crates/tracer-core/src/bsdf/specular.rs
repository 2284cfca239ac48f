//! The lab's mirror (`reflectance`) and glass (`transmittance`, `ior`,
//! `fresnel`, as `material::Glass::split` divides a ray): lobes of a
//! single direction each.

use crate::optics::fresnel_reflectance;
use crate::simd::{Real, V3};
use glam::Vec3;

/// wo mirrored about the local normal (`mirror`).
#[inline(always)]
pub fn reflect(wo: Vec3) -> Vec3 {
    mirror(V3::from(wo)).into()
}

/// `reflect` for any lane width.
#[inline(always)]
pub fn mirror<N: Real>(wo: V3<N>) -> V3<N> {
    V3::new(-wo.x, -wo.y, wo.z)
}

/// The direction refracted from local `wo` (`wo.z > 0`) with `eta` =
/// n(wo's side) / n(the other side); None past the critical angle
/// (`refract_local`).
#[inline(always)]
pub fn refract(wo: Vec3, eta: f32) -> Option<Vec3> {
    let (wi, through) = refract_local(V3::from(wo), eta);
    through.then(|| wi.into())
}

/// `refract` for any lane width: the direction, and where there is one.
#[inline(always)]
pub fn refract_local<N: Real>(wo: V3<N>, eta: N) -> (V3<N>, N::Mask) {
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
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interface {
    /// n(wo's side) / n(the far side).
    pub eta: f32,
    /// Reflected and transmitted energies of a ray along `wo`.
    pub reflected: f32,
    pub transmitted: f32,
    /// The refracted direction, if any.
    pub refracted: Option<Vec3>,
}

impl Interface {
    /// The split of a ray along local `wo` meeting a dielectric: with
    /// `fresnel`, F reflected and (1 - F) `transmittance` transmitted;
    /// without, `reflectance` and `transmittance` as given (both reflected
    /// under total internal reflection). `eta` as in `Interface`.
    pub fn new(wo: Vec3, eta: f32, fresnel: bool, reflectance: f32, transmittance: f32) -> Self {
        let refracted = refract(wo, eta);
        let (reflected, transmitted) = match (fresnel, refracted) {
            (true, _) => {
                let f = fresnel_reflectance(wo.z, eta);
                (f, (1.0 - f) * transmittance)
            }
            (false, None) => (reflectance + transmittance, 0.0),
            (false, Some(_)) => (reflectance, transmittance),
        };
        Interface {
            eta,
            reflected,
            transmitted: if refracted.is_some() {
                transmitted
            } else {
                0.0
            },
            refracted,
        }
    }

    /// The energy leaving along either direction.
    pub fn total(&self) -> f32 {
        self.reflected + self.transmitted
    }

    /// One of the two directions, picked with probability in proportion to
    /// its energy by `u`, and its weight (energy over probability, the
    /// transmitted one scaled by eta^2): (direction, weight, whether
    /// transmitted).
    #[inline(always)]
    pub fn sample(&self, wo: Vec3, u: f32) -> Option<(Vec3, f32, bool)> {
        let total = self.total();
        if total <= 0.0 {
            return None;
        }
        match self.refracted {
            Some(wt) if u * total >= self.reflected => {
                Some((wt, total * self.eta * self.eta, true))
            }
            _ => Some((reflect(wo), total, false)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refraction_follows_snell() {
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let wt = refract(wo, 1.0 / 1.5).expect("into glass");
        assert!(wt.z < 0.0, "through the surface");
        let (sin_i, sin_t) = (wo.x, -wt.x);
        assert!((sin_i - 1.5 * sin_t).abs() < 1e-6);
        assert!((wt.length() - 1.0).abs() < 1e-6);
        // Out of glass past the critical angle (41.8 degrees): none.
        assert!(refract(Vec3::new(0.8, 0.0, 0.6), 1.5).is_none());
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
