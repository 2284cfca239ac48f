//! The GGX (Trowbridge-Reitz) distribution of microfacet normals, isotropic:
//! its density D, Smith's separable shadowing-masking (Walter et al. 2007,
//! as Mitsuba 3),
//! and the sampling of the normals a direction sees (Heitz 2018, "Sampling
//! the GGX distribution of visible normals"). Directions are local (z = the
//! shading normal); `wo.z > 0` is the viewer's side.

use crate::simd::{Real, V3};
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

    /// The density of unit microfacet normal `m` per solid angle (`d`).
    #[inline(always)]
    pub fn d(&self, m: Vec3) -> f32 {
        d(self.alpha, V3::from(m))
    }

    /// Smith's Lambda for direction `w` (`lambda`).
    #[inline(always)]
    pub fn lambda(&self, w: Vec3) -> f32 {
        lambda(self.alpha, V3::from(w))
    }

    /// The share of microfacets seen from `w` that are not masked (`g1`).
    #[inline(always)]
    pub fn g1(&self, w: Vec3) -> f32 {
        g1(self.alpha, V3::from(w))
    }

    /// The share of microfacets seen from both `wo` and `wi` (`g2`).
    #[inline(always)]
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        g2(self.alpha, V3::from(wo), V3::from(wi))
    }

    /// The density of the normals `wo` sees (`visible_d`).
    #[inline(always)]
    pub fn visible_d(&self, wo: Vec3, m: Vec3) -> f32 {
        visible_d(self.alpha, V3::from(wo), V3::from(m))
    }

    /// A microfacet normal that `wo` sees, drawn by `u` (`sample_visible`).
    #[inline(always)]
    pub fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        sample_visible(self.alpha, V3::from(wo), (u.x, u.y)).into()
    }
}

// The formulas, for any lane width (`simd::Real`): the one-path tracer's
// `Ggx` instantiates them on f32.

/// GGX of width `alpha`: the density of unit microfacet normal `m` per
/// solid angle, projected (its integral with m.z over the hemisphere is
/// 1): alpha^2 / (pi (cos^2 (alpha^2 - 1) + 1)^2), the bracket written as
/// sin^2 + alpha^2 cos^2 so that near the normal nothing cancels. Nothing
/// below the surface.
#[inline(always)]
pub fn d<N: Real>(alpha: N, m: V3<N>) -> N {
    let a2 = alpha * alpha;
    let t = m.x * m.x + m.y * m.y + a2 * m.z * m.z;
    // Tested as `<=`, not `>`, so that a NaN goes through as a NaN.
    let inside = !m.z.le(N::zero()) & !t.le(N::zero());
    N::select(inside, a2 / (N::splat(PI) * t * t), N::zero())
}

/// Smith's Lambda for direction `w` (either side: it depends on the slope
/// only): (sqrt(1 + alpha^2 tan^2) - 1) / 2, written as x / (2 (1 +
/// sqrt(1 + x))) so that a small x keeps its digits. At the horizon tan^2
/// is capped, so Lambda is huge but finite.
#[inline(always)]
pub fn lambda<N: Real>(alpha: N, w: V3<N>) -> N {
    let tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z).max(N::splat(1e-30));
    let x = alpha * alpha * tan2;
    x / (N::splat(2.0) * (N::one() + (N::one() + x).sqrt()))
}

/// The share of microfacets seen from `w` that are not masked.
#[inline(always)]
pub fn g1<N: Real>(alpha: N, w: V3<N>) -> N {
    N::one() / (N::one() + lambda(alpha, w))
}

/// The share of microfacets seen from both `wo` and `wi`: Smith's
/// separable form G1(wo) G1(wi), Walter et al.'s (2007) and Mitsuba 3's,
/// so that the materials scene matches Mitsuba's render of it (the
/// height-correlated form of Heitz 2014, pbrt-v4's, is up to a few per
/// cent above it on rough surfaces at grazing angles). Symmetric in its
/// arguments; used for transmission too.
#[inline(always)]
pub fn g2<N: Real>(alpha: N, wo: V3<N>, wi: V3<N>) -> N {
    g1(alpha, wo) * g1(alpha, wi)
}

/// The density of the normals `wo` sees, per solid angle of `m`: D_wo(m) =
/// G1(wo) max(0, wo.m) D(m) / wo.z, what `sample_visible` draws (it
/// integrates to 1 over m); nothing for a `wo` below the surface.
#[inline(always)]
pub fn visible_d<N: Real>(alpha: N, wo: V3<N>, m: V3<N>) -> N {
    let seen = g1(alpha, wo) * wo.dot(m).max(N::zero()) * d(alpha, m) / wo.z;
    N::select(!wo.z.le(N::zero()), seen, N::zero())
}

/// A microfacet normal drawn from D_wo by the point `u` of the unit square
/// (Heitz 2018): the view stretched to the distribution of alpha 1, where
/// the visible normals are a hemisphere's projected onto the view's disk,
/// a point of that disk (the half hidden by the slope squeezed onto the
/// seen half), lifted, and unstretched. `wo.z > 0`.
#[inline(always)]
pub fn sample_visible<N: Real>(alpha: N, wo: V3<N>, (u1, u2): (N, N)) -> V3<N> {
    let a = alpha;
    let z = V3::splat(Vec3::Z);
    let vh = V3::new(a * wo.x, a * wo.y, wo.z.max(N::zero())).normalize_or(z);
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = V3::select(
        len2.gt(N::zero()),
        V3::new(-vh.y, vh.x, N::zero()) / len2.sqrt(),
        V3::splat(Vec3::X),
    );
    let t2 = vh.cross(t1);
    let r = u1.sqrt();
    let (sin, cos) = (N::splat(2.0 * PI) * u2).sin_cos();
    let p1 = r * cos;
    let s = N::splat(0.5) * (N::one() + vh.z);
    let p2 = (N::one() - s) * (N::one() - p1 * p1).max(N::zero()).sqrt() + s * r * sin;
    let lift = (N::one() - p1 * p1 - p2 * p2).max(N::zero()).sqrt();
    let nh = t1 * p1 + t2 * p2 + vh * lift;
    V3::new(a * nh.x, a * nh.y, nh.z.max(N::zero())).normalize_or(z)
}

/// The facet that reflects `wo` into `wi` (their half vector) and what a
/// reflection lobe of width `alpha` reads of it, whatever its Fresnel
/// term: f |cos_i| = F D G2 / (4 wo.z), its density the visible normal's
/// over the Jacobian 4 wo.m from m to wi.
pub struct Reflection<N: Real> {
    /// wo.m.
    pub cos: N,
    pub d: N,
    pub g2: N,
    /// The density of m among the normals wo sees (`visible_d`).
    pub visible: N,
    /// 4 wo.m, kept above 0.
    pub jacobian: N,
    /// Where the half vector exists (wo + wi is not zero).
    pub half: N::Mask,
}

/// `Reflection` of local `wo` into `wi` through GGX of width `alpha`.
#[inline(always)]
pub fn reflection<N: Real>(alpha: N, wo: V3<N>, wi: V3<N>) -> Reflection<N> {
    let (m, half) = (wo + wi).try_normalize();
    let cos = wo.dot(m);
    Reflection {
        cos,
        d: d(alpha, m),
        g2: g2(alpha, wo, wi),
        visible: visible_d(alpha, wo, m),
        jacobian: (N::splat(4.0) * cos).max(N::splat(f32::MIN_POSITIVE)),
        half,
    }
}

/// `w` mirrored about unit microfacet normal `m`.
#[inline(always)]
pub fn reflect_about<N: Real>(w: V3<N>, m: V3<N>) -> V3<N> {
    m * (N::splat(2.0) * w.dot(m)) - w
}

/// `w` refracted through microfacet `m` (`w.m > 0`), with `eta` = n(w's
/// side) / n(the other side), and where there is one (not past the
/// critical angle).
#[inline(always)]
pub fn refract_about<N: Real>(w: V3<N>, m: V3<N>, eta: N) -> (V3<N>, N::Mask) {
    let cos_i = w.dot(m);
    let sin2_t = eta * eta * (N::one() - cos_i * cos_i).max(N::zero());
    let cos_t = (N::one() - sin2_t).sqrt();
    let (t, unit) = (w * -eta + m * (eta * cos_i - cos_t)).try_normalize();
    (t, unit & !sin2_t.ge(N::one()))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::sampling::Rng;
    use crate::simd::F16;

    /// A direction of either hemisphere drawn by `rng` (unit, or not quite:
    /// the formulas are fed what the tracer feeds them), now and then one
    /// in the surface, along the normal, or not a number.
    pub(crate) fn direction(rng: &mut Rng, k: usize) -> Vec3 {
        match k {
            0 => Vec3::Z,
            1 => Vec3::new(1.0, 0.0, 0.0),
            2 => Vec3::new(0.6, 0.0, -0.8),
            3 => Vec3::new(f32::NAN, 0.0, 1.0),
            _ => {
                let (a, b) = (rng.square(), rng.square());
                Vec3::new(a.x - 0.5, a.y - 0.5, b.x - 0.3).normalize() * (0.999 + 0.002 * b.y)
            }
        }
    }

    /// Sixteen lanes give each lane's one-lane value, bit for bit: the
    /// formulas are written once, and the one-path tracer's `Ggx` is them
    /// on f32.
    #[test]
    fn ggx_in_lanes_is_the_one_lane_ggx() {
        let mut rng = Rng::new(11);
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        for round in 0..300 {
            let alphas = [0.0, 1e-4, 0.0625, 0.3, 1.0];
            let alpha: [f32; 16] = std::array::from_fn(|k| alphas[(k + round) % 5]);
            let wo: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + round) % 20));
            let m: [Vec3; 16] = std::array::from_fn(|k| direction(&mut rng, (k + 2 * round) % 20));
            let u: [Vec2; 16] = std::array::from_fn(|_| rng.square());
            let lanes = |v: &[Vec3; 16]| V3::<F16>::from_fn(|k| v[k]);
            let a = F16::from_fn(|k| alpha[k]);
            let (wo16, m16) = (lanes(&wo), lanes(&m));
            let u16 = (F16::from_fn(|k| u[k].x), F16::from_fn(|k| u[k].y));
            let (d16, g16) = (d(a, m16), g1(a, wo16));
            let (vis16, drawn16) = (visible_d(a, wo16, m16), sample_visible(a, wo16, u16));
            for k in 0..16 {
                let ggx = Ggx { alpha: alpha[k] };
                let case = format!("round {round}, lane {k}");
                assert_eq!(d16.lane(k).to_bits(), ggx.d(m[k]).to_bits(), "{case}");
                assert_eq!(g16.lane(k).to_bits(), ggx.g1(wo[k]).to_bits(), "{case}");
                let vis = ggx.visible_d(wo[k], m[k]);
                assert_eq!(vis16.lane(k).to_bits(), vis.to_bits(), "{case}");
                let drawn = ggx.sample_visible(wo[k], u[k]);
                assert_eq!(bits(drawn16.lane(k)), bits(drawn), "{case}");
            }
        }
    }

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
        let (t, ok) = refract_about(V3::from(w), V3::from(m), 1.0 / 1.5);
        let t = Vec3::from(t);
        assert!(ok);
        let (sin_i, sin_t) = (w.cross(m).length(), t.cross(m).length());
        assert!((sin_i - 1.5 * sin_t).abs() < 1e-5);
        assert!(t.dot(m) < 0.0);
    }
}
