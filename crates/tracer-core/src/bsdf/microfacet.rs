//! The GGX (Trowbridge-Reitz) distribution of microfacet normals, isotropic:
//! its density D, Smith's separable shadowing-masking (Walter et al. 2007,
//! as Mitsuba 3),
//! and the sampling of the normals a direction sees (Heitz 2018, "Sampling
//! the GGX distribution of visible normals"). Directions are local (z = the
//! shading normal); `wo.z > 0` is the viewer's side.

use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Below this alpha a surface is a mirror (as pbrt-v4's `EffectivelySmooth`):
/// D would be a spike that neither f32 nor a sampler resolves.
pub const SMOOTH_ALPHA: f32 = 1e-3;

/// GGX of width `alpha` (isotropic; alpha = roughness^2 in the glTF and
/// Blender sense).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ggx {
    pub alpha: f32,
}

impl Ggx {
    /// Width `alpha`, clamped to [0, 1] (a NaN to 0: a mirror).
    pub fn new(alpha: f32) -> Ggx {
        let alpha = if alpha.is_nan() { 0.0 } else { alpha };
        Ggx {
            alpha: alpha.clamp(0.0, 1.0),
        }
    }

    /// The width of perceptual `roughness` (0..1): alpha = roughness^2.
    pub fn from_roughness(roughness: f32) -> Ggx {
        Ggx::new(roughness * roughness)
    }

    /// Whether the surface is taken as smooth: a single direction.
    pub fn is_smooth(&self) -> bool {
        self.alpha < SMOOTH_ALPHA
    }

    /// The density of unit microfacet normal `m` per solid angle, projected
    /// (its integral with m.z over the hemisphere is 1):
    /// alpha^2 / (pi (cos^2 (alpha^2 - 1) + 1)^2), the bracket written as
    /// sin^2 + alpha^2 cos^2 so that near the normal nothing cancels.
    #[inline(always)]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let t = m.x * m.x + m.y * m.y + a2 * m.z * m.z;
        if t <= 0.0 {
            return 0.0;
        }
        a2 / (PI * t * t)
    }

    /// Smith's Lambda for direction `w` (either side: it depends on the
    /// slope only): (sqrt(1 + alpha^2 tan^2) - 1) / 2, written as
    /// x / (2 (1 + sqrt(1 + x))) so that a small x keeps its digits. At the
    /// horizon tan^2 is capped, so Lambda is huge but finite.
    #[inline(always)]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z).max(1e-30);
        let x = self.alpha * self.alpha * tan2;
        x / (2.0 * (1.0 + (1.0 + x).sqrt()))
    }

    /// The share of microfacets seen from `w` that are not masked.
    #[inline(always)]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// The share of microfacets seen from both `wo` and `wi`: Smith's
    /// separable form G1(wo) G1(wi), Walter et al.'s (2007) and Mitsuba 3's,
    /// so that the materials scene matches Mitsuba's render of it (the
    /// height-correlated form of Heitz 2014, pbrt-v4's, is up to a few per
    /// cent above it on rough surfaces at grazing angles). Symmetric in its
    /// arguments; used for transmission too.
    #[inline(always)]
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.g1(wo) * self.g1(wi)
    }

    /// G2 / G1(wo), the weight of a visible-normal sample (its D and cosines
    /// cancel): G1(wi), which a grazing wo (G1 near 0) does not divide.
    #[inline(always)]
    pub fn g2_over_g1(&self, _wo: Vec3, wi: Vec3) -> f32 {
        self.g1(wi)
    }

    /// The density of the normals `wo` sees, per solid angle of `m`:
    /// D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z, what `sample_visible`
    /// draws (it integrates to 1 over m).
    #[inline(always)]
    pub fn visible_d(&self, wo: Vec3, m: Vec3) -> f32 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        self.g1(wo) * wo.dot(m).max(0.0) * self.d(m) / wo.z
    }

    /// A microfacet normal drawn from D_wo by the point `u` of the unit
    /// square (Heitz 2018): the view stretched to the distribution of
    /// alpha 1, where the visible normals are a hemisphere's projected onto
    /// the view's disk, a point of that disk (the half hidden by the slope
    /// squeezed onto the seen half), lifted, and unstretched. `wo.z > 0`.
    #[inline(always)]
    pub fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let a = self.alpha;
        let vh = Vec3::new(a * wo.x, a * wo.y, wo.z.max(0.0))
            .try_normalize()
            .unwrap_or(Vec3::Z);
        let len2 = vh.x * vh.x + vh.y * vh.y;
        let t1 = if len2 > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) / len2.sqrt()
        } else {
            Vec3::X
        };
        let t2 = vh.cross(t1);
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let p1 = r * phi.cos();
        let s = 0.5 * (1.0 + vh.z);
        let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
        let lift = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
        let nh = p1 * t1 + p2 * t2 + lift * vh;
        Vec3::new(a * nh.x, a * nh.y, nh.z.max(0.0))
            .try_normalize()
            .unwrap_or(Vec3::Z)
    }
}

/// `w` mirrored about unit microfacet normal `m`.
#[inline(always)]
pub fn reflect_about(w: Vec3, m: Vec3) -> Vec3 {
    2.0 * w.dot(m) * m - w
}

/// `w` refracted through microfacet `m` (`w.m > 0`), with `eta` = n(w's
/// side) / n(the other side); None past the critical angle.
#[inline(always)]
pub fn refract_about(w: Vec3, m: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = w.dot(m);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    (-eta * w + (eta * cos_i - cos_t) * m).try_normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_alpha_1_d_is_uniform_and_g1_of_the_normal_is_1() {
        let ggx = Ggx::new(1.0);
        for m in [
            Vec3::Z,
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::new(0.0, 0.99, 0.141),
        ] {
            assert!((ggx.d(m.normalize()) - 1.0 / PI).abs() < 1e-6);
        }
        assert_eq!(ggx.g1(Vec3::Z), 1.0);
        assert_eq!(Ggx::new(0.3).lambda(Vec3::Z), 0.0);
    }

    #[test]
    fn refraction_about_a_facet_follows_snell() {
        let m = Vec3::new(0.3, 0.1, 0.9).normalize();
        let w = Vec3::new(-0.5, 0.2, 0.8).normalize();
        let t = refract_about(w, m, 1.0 / 1.5).unwrap();
        let (sin_i, sin_t) = (w.cross(m).length(), t.cross(m).length());
        assert!((sin_i - 1.5 * sin_t).abs() < 1e-5);
        assert!(t.dot(m) < 0.0);
    }
}
