//! Snell's law and the Fresnel equations for a smooth dielectric surface.

use crate::simd::Real;
use glam::Vec3;

/// The refracted direction of unit `dir` at a surface of unit `normal`
/// (pointing back to the side `dir` comes from), with `eta` = n_from /
/// n_to; `None` past the critical angle (total internal reflection).
pub fn refract(dir: Vec3, normal: Vec3, eta: f32) -> Option<Vec3> {
    if eta == 1.0 {
        // No change of medium: the ray goes on exactly as it was.
        return Some(dir);
    }
    let cos_i = -dir.dot(normal);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((eta * dir + (eta * cos_i - cos_t) * normal).normalize())
}

/// The fraction of unpolarised light reflected at incidence cosine
/// `cos_i` (to the normal on the side the light comes from), with `eta` =
/// n_from / n_to: the mean of the s- and p-polarised Fresnel
/// reflectances; 1 past the critical angle. What is not reflected is
/// transmitted.
pub fn fresnel_reflectance<N: Real>(cos_i: N, eta: N) -> N {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (N::one() - cos_i * cos_i);
    let cos_t = (N::one() - sin2_t).sqrt();
    // With n_from = eta, n_to = 1 (only the ratio matters).
    let r_s = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_p = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let f = (r_s * r_s + r_p * r_p) / N::splat(2.0);
    let f = N::select(sin2_t.ge(N::one()), N::one(), f);
    // No interface: in f32, 1 - cos^2 rounds to 1 at grazing angles,
    // which would read as total internal reflection.
    N::select(eta.eq(N::one()), N::zero(), f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_normal_incidence_fresnel_is_the_textbook_value_and_conserves_energy() {
        for n in [1.33f32, 1.5, 2.4] {
            let expected = ((n - 1.0) / (n + 1.0)).powi(2);
            for eta in [1.0 / n, n] {
                let r = fresnel_reflectance(1.0, eta);
                assert!((r - expected).abs() < 1e-6, "n {n}, eta {eta}: {r}");
                let t = 1.0 - r;
                assert!((r + t - 1.0).abs() < 1e-7);
            }
        }
        assert_eq!(fresnel_reflectance(1.0, 1.0), 0.0, "no interface");
    }

    #[test]
    fn fresnel_grows_to_one_at_grazing_incidence() {
        let r_normal = fresnel_reflectance(1.0, 1.0 / 1.5);
        let r_60 = fresnel_reflectance(60f32.to_radians().cos(), 1.0 / 1.5);
        let r_grazing = fresnel_reflectance(1e-4, 1.0 / 1.5);
        assert!(r_normal < r_60 && r_60 < r_grazing && r_grazing > 0.99);
        // Brewster's angle, atan(1.5): the p-polarised part vanishes, so
        // the mean is half of r_s, which is ((cos_i - n cos_t) / ...)^2.
        let brewster = 1.5f32.atan();
        let (ci, ct) = (
            brewster.cos(),
            (std::f32::consts::FRAC_PI_2 - brewster).cos(),
        );
        let r_s = ((ci - 1.5 * ct) / (ci + 1.5 * ct)).powi(2);
        let r = fresnel_reflectance(ci, 1.0 / 1.5);
        assert!((r - r_s / 2.0).abs() < 1e-5, "{r} vs {}", r_s / 2.0);
    }

    #[test]
    fn snell_holds_and_past_the_critical_angle_nothing_is_refracted() {
        let n = 1.5f32;
        let normal = Vec3::Y;
        for degrees in [0.0f32, 20.0, 45.0, 80.0] {
            let a = degrees.to_radians();
            let dir = Vec3::new(a.sin(), -a.cos(), 0.0);
            let t = refract(dir, normal, 1.0 / n).expect("entering always refracts");
            // sin(theta_t) = sin(theta_i) / n, on the far side, same plane.
            assert!((t.x - a.sin() / n).abs() < 1e-6, "{degrees}: {t}");
            assert!(t.y < 0.0 && t.z == 0.0);
            assert!((t.length() - 1.0).abs() < 1e-6);
        }
        // Leaving the glass: the critical angle is asin(1 / n) = 41.8 deg.
        let critical = (1.0 / n).asin();
        for (a, refracts) in [(critical - 0.01, true), (critical + 0.01, false)] {
            let dir = Vec3::new(a.sin(), -a.cos(), 0.0);
            assert_eq!(refract(dir, normal, n).is_some(), refracts, "{a}");
            let f = fresnel_reflectance(a.cos(), n);
            assert_eq!(f == 1.0, !refracts, "{a}: {f}");
        }
    }
}
