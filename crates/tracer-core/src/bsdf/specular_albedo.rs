//! The directional albedo E(cos_o) of a GGX layer whose facets reflect by
//! Schlick's F = F0 + (1 - F0)(1 - cos)^5 (what one scattering off it sends
//! back of light arriving along wo), tabulated over cos_o and roughness,
//! and its cosine-weighted mean over the hemisphere. The principled
//! material's opaque base takes what the layer leaves, 1 - E (`plastic.rs`).
//! No closed form exists, so the table is integrated numerically; the
//! tracer reads the table stored beside this file (`specular_albedo.bin`,
//! what `SpecularAlbedo::build` gives: 0.15 s a render saved), which a test
//! keeps equal to a fresh integration.
//!
//! E is linear in F0: E = F0 E_1 + (1 - F0) E_5, with E_1 the albedo of
//! F = 1 and E_5 that of F = (1 - cos)^5, so two tables of (cos_o,
//! roughness) give it for every F0 exactly (Karis 2013's split). The
//! exact Fresnel equations would need F0 as a third axis, along which E is
//! far from linear near an index of 1 (there F is 0 up to grazing, then
//! jumps to 1).

use super::conductor::schlick_weight;
use super::microfacet::{reflect_about, Ggx};
use glam::Vec3;
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Nodes of sqrt(cos_o) (E changes fastest near grazing angles, the more
/// so the smoother the layer) and of roughness (alpha = roughness^2), each
/// evenly from 0 to 1.
const COS: usize = 48;
const ROUGH: usize = 48;
/// Steps per axis of each node's integral over the microfacet normals.
const STEPS: usize = 48;
/// What E is raised by: above the table's largest error (quadrature and
/// interpolation; 2.6e-3 below the albedo at worst among 4000 random
/// points, at grazing angles of smooth layers mostly; the test
/// `the_specular_albedo_table_bounds_a_fine_integration` checks 400 more),
/// so that the base under the layer never takes light the layer reflected.
/// The price: a white opaque dielectric gives back 1 - MARGIN.
pub const MARGIN: f32 = 4e-3;

/// E_1 and E_5 over (roughness, cos_o), and their means over roughness.
#[derive(Debug)]
pub struct SpecularAlbedo {
    e: Vec<[f32; 2]>,
    mean: Vec<[f32; 2]>,
}

/// A layer's place in the table: its roughness as a node index and an
/// interpolation weight, and its F0 (found once per hit).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Layer {
    r: usize,
    wr: f32,
    f0: f32,
}

/// The table, read on first use from the stored integration (integrating
/// it takes 5 million evaluations of the integrand: 0.15 s here).
pub fn table() -> &'static SpecularAlbedo {
    static TABLE: OnceLock<SpecularAlbedo> = OnceLock::new();
    TABLE.get_or_init(|| SpecularAlbedo::from_bytes(STORED))
}

/// `SpecularAlbedo::build`'s table as `to_bytes` writes it.
const STORED: &[u8] = include_bytes!("specular_albedo.bin");

/// E_1 and E_5 of a layer of width `alpha` seen at `cos_o`: the integral
/// over the microfacet normals m of D(m) G2 F max(0, wo.m) / cos_o (light
/// reflected toward the wi of each facet, not shadowed), by the midpoint
/// rule on a grid of `steps`^2 over t and the azimuths of the facets wo
/// sees (half of them: the rest are their mirror image), with
/// tan(theta_m) = alpha tan(pi t / 2), which spreads D's mass evenly over t
/// whatever alpha. (Heitz's visible-normal sampling as a quadrature
/// converges slowly: its disk's rim, where the steepest facets are, is
/// where its map has a square root.)
pub fn integrate(cos_o: f32, alpha: f32, steps: usize) -> [f32; 2] {
    let cos_o = cos_o.clamp(1e-4, 1.0);
    let wo = Vec3::new((1.0 - cos_o * cos_o).sqrt(), 0.0, cos_o);
    let ggx = Ggx::new(alpha);
    if ggx.alpha == 0.0 {
        return [1.0, schlick_weight(cos_o)];
    }
    let a = f64::from(ggx.alpha);
    let dt = 1.0 / steps as f64;
    let mut sum = [0.0f64; 2];
    for i in 0..steps {
        let s = (PI / 2.0 * (i as f64 + 0.5) * dt).tan();
        let theta = (a * s).atan();
        // dtheta / dt, times the solid angle's sin(theta).
        let jacobian = a * PI / 2.0 * (1.0 + s * s) / (1.0 + a * a * s * s) * theta.sin();
        let dphi = seen_phi(f64::from(cos_o), theta) / steps as f64;
        for j in 0..steps {
            let m = polar(theta, (j as f64 + 0.5) * dphi);
            let cos = wo.dot(m);
            let wi: Vec3 = reflect_about(wo.into(), m.into()).into();
            if cos > 0.0 && wi.z > 0.0 {
                let e = ggx.d(m) * ggx.g2(wo, wi) * cos / cos_o;
                let e = f64::from(e) * jacobian * dphi;
                sum[0] += e;
                sum[1] += e * f64::from(schlick_weight(cos));
            }
        }
    }
    sum.map(|s| (2.0 * s * dt) as f32)
}

/// The azimuths (from wo's, 0 to pi) of the facets at `theta` that face
/// wo (wo.m > 0: cos phi > -cot theta_o cot theta): the grid covers those
/// only, so no edge of the integrand falls between its points.
fn seen_phi(cos_o: f64, theta: f64) -> f64 {
    let sin_o = (1.0 - cos_o * cos_o).max(0.0).sqrt();
    let (sin, cos) = theta.sin_cos();
    if sin_o * sin <= cos_o * cos {
        return PI;
    }
    (-cos_o * cos / (sin_o * sin)).clamp(-1.0, 1.0).acos()
}

/// The unit vector at polar angle `theta` and azimuth `phi`.
fn polar(theta: f64, phi: f64) -> Vec3 {
    let (sin, cos) = theta.sin_cos();
    Vec3::new(
        (sin * phi.cos()) as f32,
        (sin * phi.sin()) as f32,
        cos as f32,
    )
}

impl SpecularAlbedo {
    /// The table integrated afresh (what is stored).
    pub fn build() -> SpecularAlbedo {
        let mut e = vec![[0.0; 2]; ROUGH * COS];
        let mut mean = vec![[0.0; 2]; ROUGH];
        for (r, row) in e.chunks_mut(COS).enumerate() {
            let alpha = (r as f32 / (ROUGH - 1) as f32).powi(2);
            for (c, entry) in row.iter_mut().enumerate() {
                let sqrt_cos = c as f32 / (COS - 1) as f32;
                *entry = integrate(sqrt_cos * sqrt_cos, alpha, STEPS);
            }
            mean[r] = [0, 1].map(|k| cosine_mean(row.iter().map(|e| e[k])));
        }
        SpecularAlbedo { e, mean }
    }

    /// The table's numbers, E then the means, as little-endian floats.
    pub fn to_bytes(&self) -> Vec<u8> {
        let numbers = self.e.iter().chain(&self.mean).flatten();
        numbers.flat_map(|x| x.to_le_bytes()).collect()
    }

    /// The table `to_bytes` wrote (checked by the test that keeps the
    /// stored table equal to `build`'s).
    fn from_bytes(bytes: &[u8]) -> SpecularAlbedo {
        let mut pairs = bytes.chunks_exact(8).map(|b| {
            let x = |k: usize| f32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]);
            [x(0), x(4)]
        });
        let e = pairs.by_ref().take(ROUGH * COS).collect();
        let mean = pairs.take(ROUGH).collect();
        SpecularAlbedo { e, mean }
    }

    /// The place of a layer `ggx` of reflectance `f0` at normal incidence
    /// (a smooth one's is the mirror's, the first node's, exactly).
    pub fn layer(ggx: Ggx, f0: f32) -> Layer {
        let roughness = if ggx.is_smooth() {
            0.0
        } else {
            ggx.alpha.sqrt()
        };
        let (r, wr) = node(roughness, ROUGH);
        Layer {
            r,
            wr,
            f0: f0.clamp(0.0, 1.0),
        }
    }

    /// E at `cos_o` (interpolated linearly in sqrt(cos_o) and roughness),
    /// raised by `MARGIN`.
    #[inline(always)]
    pub fn albedo(&self, layer: &Layer, cos_o: f32) -> f32 {
        let (c, wc) = node(cos_o.max(0.0).sqrt(), COS);
        let at = |r: usize| {
            let (e0, e1) = (self.e[r * COS + c], self.e[r * COS + c + 1]);
            [0, 1].map(|k| e0[k] + wc * (e1[k] - e0[k]))
        };
        self.mix(layer, at(layer.r), at(layer.r + 1))
    }

    /// The cosine-weighted mean of `albedo` over the hemisphere,
    /// 2 int E mu dmu: exactly that of the interpolated E (the mean is
    /// linear in E, and `cosine_mean` exact).
    pub fn mean(&self, layer: &Layer) -> f32 {
        self.mix(layer, self.mean[layer.r], self.mean[layer.r + 1])
    }

    /// E_1 and E_5 at two roughness nodes, interpolated, mixed by F0 and
    /// raised by the margin.
    #[inline(always)]
    fn mix(&self, layer: &Layer, low: [f32; 2], high: [f32; 2]) -> f32 {
        let [e1, e5] = [0, 1].map(|k| low[k] + layer.wr * (high[k] - low[k]));
        e5 + layer.f0 * (e1 - e5) + MARGIN
    }
}

/// The node below `x` (in [0, 1], on `n` evenly spaced nodes) and the
/// weight of the one above; a NaN is taken as 0.
#[inline(always)]
fn node(x: f32, n: usize) -> (usize, f32) {
    let t = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) } * (n - 1) as f32;
    let i = (t as usize).min(n - 2);
    (i, t - i as f32)
}

/// 2 int_0^1 E(mu) mu dmu of the E linear in s = sqrt(mu) between the
/// values of `row` (at s evenly from 0 to 1): 4 int E(s) s^3 ds, by
/// three-point Gauss-Legendre on each piece, exact for its degree 4.
fn cosine_mean(row: impl Iterator<Item = f32>) -> f32 {
    let row: Vec<f64> = row.map(f64::from).collect();
    let h = 1.0 / (row.len() - 1) as f64;
    let x = (0.6f64).sqrt();
    let gauss = [(-x, 5.0 / 9.0), (0.0, 8.0 / 9.0), (x, 5.0 / 9.0)];
    let mut sum = 0.0;
    for (i, e) in row.windows(2).enumerate() {
        for (node, weight) in gauss {
            let t = (node + 1.0) / 2.0;
            let s = (i as f64 + t) * h;
            sum += weight * h / 2.0 * (e[0] + t * (e[1] - e[0])) * s * s * s;
        }
    }
    (4.0 * sum) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_albedo_has_that_mean() {
        let constant = cosine_mean([0.3; COS].into_iter());
        assert!((constant - 0.3).abs() < 1e-6);
        // E = s = sqrt(mu): 2 int mu^1.5 dmu = 4/5.
        let ramp = cosine_mean((0..COS).map(|i| i as f32 / (COS - 1) as f32));
        assert!((ramp - 0.8).abs() < 1e-6);
    }

    /// Where the stored table is kept.
    fn stored_path() -> std::path::PathBuf {
        let here = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        here.join("src/bsdf/specular_albedo.bin")
    }

    #[test]
    fn the_stored_table_is_a_fresh_integration() {
        let (stored, fresh) = (table(), SpecularAlbedo::build());
        assert_eq!(stored.e.len(), ROUGH * COS);
        assert_eq!(stored.mean.len(), ROUGH);
        // Equal here bit for bit; another maths library may round the
        // last bits of its sines otherwise.
        let numbers = |t: &SpecularAlbedo| -> Vec<f32> {
            t.e.iter().chain(&t.mean).flatten().copied().collect()
        };
        for (k, (a, b)) in numbers(stored).iter().zip(numbers(&fresh)).enumerate() {
            assert!(
                (a - b).abs() <= 1e-6,
                "number {k}: stored {a}, integrated {b}; after a change to the \
                 integration, store it again: cargo test -p tracer-core --release \
                 --lib store_the_specular_albedo_table -- --ignored"
            );
        }
    }

    /// Writes the table `build` integrates where `table` reads it.
    #[test]
    #[ignore = "writes src/bsdf/specular_albedo.bin"]
    fn store_the_specular_albedo_table() {
        std::fs::write(stored_path(), SpecularAlbedo::build().to_bytes()).unwrap();
    }

    #[test]
    fn a_smooth_layer_reflects_by_schlick() {
        for cos in [0.1f32, 0.5, 1.0] {
            let [e1, e5] = integrate(cos, 0.0, 4);
            assert_eq!(e1, 1.0);
            assert!((e5 - (1.0 - cos).powi(5)).abs() < 1e-6);
        }
    }
}
