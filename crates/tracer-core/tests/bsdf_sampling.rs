//! Each BSDF's sampling against its own density and evaluation, as pbrt-v4
//! and Mitsuba 3 test theirs: a chi-square test of the directions drawn
//! against the density integrated over the cells of the sphere (the
//! density's mass includes the share of samples that fail, so it must
//! integrate to one with them), each sample's weight against f cos / pdf,
//! the specular lobes' shares against the Fresnel equations, and
//! reciprocity.

use glam::{Vec2, Vec3};
use statrs::distribution::{ChiSquared, ContinuousCDF};
use std::f32::consts::PI;
use tracer_core::bsdf::{BlinnPhong, Bsdf, Lambert};
use tracer_core::geometry::SurfaceHit;
use tracer_core::material::{Glass, Material, Phong};
use tracer_core::optics::fresnel_reflectance;
use tracer_core::sampling::Rng;

/// Cells of cos(theta) (from -1 to 1) and of phi: each of equal solid angle.
const COS_CELLS: usize = 16;
const PHI_CELLS: usize = 32;
/// Samples per test.
const SAMPLES: usize = 400_000;
/// Significance of each test, Sidak-corrected for the number of tests.
const SIGNIFICANCE: f64 = 0.01;
const TESTS: f64 = 16.0;

/// The cell of unit direction `w`.
fn cell(w: Vec3) -> usize {
    let c = (((w.z + 1.0) / 2.0 * COS_CELLS as f32) as usize).min(COS_CELLS - 1);
    let phi = w.y.atan2(w.x).rem_euclid(2.0 * PI);
    let p = ((phi / (2.0 * PI) * PHI_CELLS as f32) as usize).min(PHI_CELLS - 1);
    c * PHI_CELLS + p
}

/// The integral of `pdf` over each cell (midpoint rule on a fine grid of
/// cos(theta) and phi, where the solid angle is d cos d phi).
fn expected_mass(pdf: &dyn Fn(Vec3) -> f64) -> Vec<f64> {
    const FINE: usize = 24;
    let (dc, dp) = (
        2.0 / (COS_CELLS * FINE) as f64,
        2.0 * std::f64::consts::PI / (PHI_CELLS * FINE) as f64,
    );
    let mut mass = vec![0.0; COS_CELLS * PHI_CELLS];
    for ci in 0..COS_CELLS * FINE {
        let cos = -1.0 + (ci as f64 + 0.5) * dc;
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        for pi in 0..PHI_CELLS * FINE {
            let phi = (pi as f64 + 0.5) * dp;
            let w = Vec3::new(
                (sin * phi.cos()) as f32,
                (sin * phi.sin()) as f32,
                cos as f32,
            );
            let k = (ci / FINE) * PHI_CELLS + pi / FINE;
            mass[k] += pdf(w) * dc * dp;
        }
    }
    mass
}

/// Pearson's chi-square test of `observed` counts against `expected`
/// ones, cells expecting fewer than 5 pooled.
fn chi_square(name: &str, observed: &[f64], expected: &[f64]) {
    let (mut stat, mut cells) = (0.0, 0usize);
    let (mut pooled_o, mut pooled_e) = (0.0, 0.0);
    for (&o, &e) in observed.iter().zip(expected) {
        if e < 5.0 {
            pooled_o += o;
            pooled_e += e;
            continue;
        }
        stat += (o - e).powi(2) / e;
        cells += 1;
    }
    if pooled_e > 0.0 {
        stat += (pooled_o - pooled_e).powi(2) / pooled_e.max(5.0);
        cells += 1;
    }
    let dof = (cells - 1) as f64;
    let p = 1.0 - ChiSquared::new(dof).unwrap().cdf(stat);
    let threshold = 1.0 - (1.0 - SIGNIFICANCE).powf(1.0 / TESTS);
    assert!(
        p > threshold,
        "{name}: chi-square {stat:.1} on {dof} degrees of freedom, p = {p:.2e}"
    );
}

/// Draws `SAMPLES` directions by `sample` (from uniform numbers; None for
/// a failed sample) and tests them against the density `pdf`: the share
/// of samples that succeed is the density's integral (within 4 standard
/// errors and the integration's 1e-3), and the directions are distributed
/// as the density says (chi-square, given how many succeeded).
fn test_sampling(
    name: &str,
    mut sample: impl FnMut(f32, Vec2) -> Option<Vec3>,
    pdf: &dyn Fn(Vec3) -> f64,
) {
    let mut rng = Rng::new(0xB5DF);
    let mut observed = vec![0.0; COS_CELLS * PHI_CELLS];
    for _ in 0..SAMPLES {
        let pick = rng.square().x;
        if let Some(w) = sample(pick, rng.square()) {
            observed[cell(w)] += 1.0;
        }
    }
    let mass = expected_mass(pdf);
    let integral: f64 = mass.iter().sum();
    let drawn: f64 = observed.iter().sum();
    let share = drawn / SAMPLES as f64;
    let sigma = (share * (1.0 - share) / SAMPLES as f64).sqrt();
    assert!(
        (share - integral).abs() <= 4.0 * sigma + 1e-3,
        "{name}: {share} of the samples succeed, but the density integrates to {integral}"
    );
    let expected: Vec<f64> = mass.iter().map(|m| m / integral * drawn).collect();
    chi_square(name, &observed, &expected);
}

fn direction(theta: f32) -> Vec3 {
    Vec3::new(theta.sin(), 0.0, theta.cos())
}

#[test]
fn lambert_draws_cosine_weighted_directions() {
    test_sampling("lambert", |_, u| Some(Lambert::sample(u)), &|w| {
        f64::from(Lambert::pdf(w))
    });
}

#[test]
fn blinn_phong_draws_its_half_vector_density() {
    for shininess in [0.0, 1.0, 10.0, 80.0] {
        for theta in [0.0, 0.7, 1.3] {
            let lobe = BlinnPhong {
                specular: Vec3::ONE,
                shininess,
            };
            let wo = direction(theta);
            test_sampling(
                &format!("blinn-phong n = {shininess}, theta_o = {theta}"),
                |_, u| lobe.sample(wo, u),
                &|w| f64::from(lobe.pdf(wo, w)),
            );
        }
    }
}

#[test]
fn blinn_phong_is_normalised_to_its_specular_colour_at_normal_incidence() {
    // The albedo integral, by the midpoint rule over the hemisphere: ks at
    // normal incidence, below it elsewhere, for any shininess.
    let albedo = |lobe: &BlinnPhong, wo: Vec3| {
        let n = 400;
        let mut sum = 0.0f64;
        for i in 0..n {
            let cos = (i as f64 + 0.5) / n as f64;
            let sin = (1.0 - cos * cos).sqrt();
            for j in 0..2 * n {
                let phi = (j as f64 + 0.5) / (2 * n) as f64 * 2.0 * std::f64::consts::PI;
                let wi = Vec3::new(
                    (sin * phi.cos()) as f32,
                    (sin * phi.sin()) as f32,
                    cos as f32,
                );
                sum += f64::from(lobe.eval(wo, wi).x) * cos;
            }
        }
        sum * (1.0 / n as f64) * (std::f64::consts::PI / n as f64)
    };
    for shininess in [0.0, 1.0, 10.0, 100.0] {
        let lobe = BlinnPhong {
            specular: Vec3::ONE,
            shininess,
        };
        let normal = albedo(&lobe, Vec3::Z);
        assert!((normal - 1.0).abs() < 0.01, "n = {shininess}: {normal}");
        for theta in [0.5, 1.0, 1.4] {
            let a = albedo(&lobe, direction(theta));
            assert!(a <= normal + 1e-3, "n = {shininess}, theta {theta}: {a}");
        }
    }
}

/// A hit facing +z at the origin, seen from outside.
fn hit() -> SurfaceHit {
    SurfaceHit::facing(Vec3::Z, Vec2::ZERO)
}

fn lab(diffuse: f32, specular: f32, shininess: f32, reflectance: f32) -> Material {
    Material::Phong(Phong {
        ambient: Vec3::ZERO,
        diffuse: Vec3::splat(diffuse),
        specular: Vec3::splat(specular),
        shininess,
        reflectance,
        ..Phong::default_grey()
    })
}

#[test]
fn a_lab_material_draws_its_mixture_of_lobes() {
    // Diffuse and Blinn-Phong lobes picked by their albedos; the mirror's
    // share (specular samples) counted apart, against its probability.
    for (material, theta) in [
        (lab(0.4, 0.4, 20.0, 0.0), 0.3),
        (lab(0.6, 0.2, 5.0, 0.2), 1.1),
        (lab(0.0, 0.7, 60.0, 0.0), 0.8),
    ] {
        let wo = direction(theta);
        let bsdf = Bsdf::new(&material, &hit(), wo);
        let mut specular = 0usize;
        test_sampling(
            &format!("{material:?}"),
            |pick, u| match bsdf.sample(pick, u) {
                Some(s) if s.specular => {
                    specular += 1;
                    None
                }
                Some(s) => Some(s.wi),
                None => None,
            },
            &|w| f64::from(bsdf.eval(w).1),
        );
        let m = material.surface();
        let weights = [m.diffuse.x, m.specular.x, m.reflectance];
        let expected = weights[2] / weights.iter().sum::<f32>();
        let share = specular as f32 / SAMPLES as f32;
        let sigma = (expected * (1.0 - expected) / SAMPLES as f32).sqrt();
        assert!(
            (share - expected).abs() <= 4.0 * sigma + 1e-6,
            "{share} vs {expected}"
        );
    }
}

#[test]
fn each_sample_weighs_f_cos_over_its_density() {
    let mut rng = Rng::new(3);
    for material in [
        lab(0.5, 0.3, 15.0, 0.1),
        lab(0.9, 0.0, 0.0, 0.0),
        lab(0.1, 0.8, 200.0, 0.0),
    ] {
        for theta in [0.2, 0.9, 1.45] {
            let bsdf = Bsdf::new(&material, &hit(), direction(theta));
            for _ in 0..2000 {
                let (pick, u) = (rng.square().x, rng.square());
                let Some(s) = bsdf.sample(pick, u) else {
                    continue;
                };
                if s.specular {
                    continue;
                }
                let (f_cos, pdf) = bsdf.eval(s.wi);
                assert!((pdf - s.pdf).abs() <= 1e-4 * pdf, "{pdf} vs {}", s.pdf);
                let weight = f_cos / pdf;
                let error = (weight - s.weight).abs().max_element();
                assert!(
                    error <= 1e-4 * weight.max_element().max(1e-3),
                    "{weight} vs {}",
                    s.weight
                );
            }
        }
    }
}

#[test]
fn lambert_and_blinn_phong_are_reciprocal() {
    let mut rng = Rng::new(11);
    let lobe = BlinnPhong {
        specular: Vec3::ONE,
        shininess: 25.0,
    };
    let lambert = Lambert { albedo: Vec3::ONE };
    for _ in 0..1000 {
        let (a, b) = (Lambert::sample(rng.square()), Lambert::sample(rng.square()));
        let (ab, ba) = (lobe.eval(a, b).x, lobe.eval(b, a).x);
        assert!((ab - ba).abs() <= 1e-5 * ab.max(1.0), "{ab} vs {ba}");
        assert_eq!(lambert.eval(b), lambert.eval(a));
    }
}

#[test]
fn glass_reflects_and_refracts_in_fresnel_s_proportions() {
    // A Fresnel glass seen from outside and from inside: the share of
    // reflected samples is F, each refracted one bends by Snell's law and
    // weighs eta^2 (the weights' mean is the energy kept, 1).
    let glass = Material::Glass(Glass {
        surface: Phong {
            ambient: Vec3::ZERO,
            diffuse: Vec3::ZERO,
            ..Phong::default_grey()
        },
        transmittance: 1.0,
        ior: 1.5,
        fresnel: true,
        absorption: Vec3::ZERO,
    });
    for (front_face, theta) in [(true, 0.3), (true, 1.2), (false, 0.4), (false, 0.6)] {
        let hit = SurfaceHit {
            front_face,
            ..hit()
        };
        // From inside the ray travels against the normal.
        let wo = if front_face {
            direction(theta)
        } else {
            -direction(theta)
        };
        let bsdf = Bsdf::new(&glass, &hit, wo);
        let eta = if front_face { 1.0 / 1.5 } else { 1.5 };
        let f = fresnel_reflectance(theta.cos(), eta);
        let mut rng = Rng::new(5);
        let (mut reflected, mut weight_sum) = (0usize, 0.0f64);
        let n = 100_000;
        for _ in 0..n {
            let s = bsdf
                .sample(rng.square().x, rng.square())
                .expect("glass sends light on");
            assert!(s.specular);
            let cos_o = wo.dot(Vec3::Z);
            if s.transmitted {
                let (sin_i, sin_t) = ((1.0 - cos_o * cos_o).sqrt(), (1.0 - s.wi.z * s.wi.z).sqrt());
                assert!((sin_i * eta - sin_t).abs() < 1e-5, "Snell: {sin_i} {sin_t}");
                assert!(s.wi.z * cos_o < 0.0, "through the surface");
                weight_sum += f64::from(s.weight.x) / f64::from(eta * eta);
            } else {
                reflected += 1;
                assert!((s.wi.z - cos_o).abs() < 1e-6, "mirrored");
                weight_sum += f64::from(s.weight.x);
            }
        }
        let share = reflected as f32 / n as f32;
        let sigma = (f * (1.0 - f) / n as f32).sqrt();
        assert!(
            (share - f).abs() <= 4.0 * sigma + 1e-6,
            "F {f}, share {share}"
        );
        assert!(
            (weight_sum / n as f64 - 1.0).abs() < 1e-5,
            "energy {}",
            weight_sum / n as f64
        );
    }
    // Past the critical angle from inside, all is reflected.
    let inside = SurfaceHit {
        front_face: false,
        ..hit()
    };
    let bsdf = Bsdf::new(&glass, &inside, -direction(1.0));
    let s = bsdf.sample(0.99, Vec2::splat(0.5)).unwrap();
    assert!(!s.transmitted);
}
