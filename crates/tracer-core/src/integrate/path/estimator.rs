//! The estimator: the radiance of one path. Unidirectional, as pbrt-v4's
//! `PathIntegrator` and Mitsuba 3's `path`: at each bounce a light sample
//! (next-event estimation) and a BSDF sample, combined by multiple
//! importance sampling with the power heuristic, and Russian roulette once
//! paths are long. The drivers that run it over pixels and rows are in
//! `mod.rs`.

use super::inside::Inside;
use super::roulette::{roulette, ROULETTE_DEPTH};
use super::{PathTracer, Strategy};
use crate::bsdf::Bsdf;
use crate::geometry::SurfaceHit;
use crate::integrate::record::{PathEvent, PathEventKind, Recorder};
use crate::light::toward::SHADOW_SHORTEN;
use crate::material::{Glass, Material};
use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::sampling::mis::power_heuristic;
use crate::simd::V3;
use crate::EPSILON;
use glam::{Vec2, Vec3};

/// What the last bounce knows of the direction it sent the path in.
#[derive(Debug, Clone, Copy)]
struct Bounce {
    /// Where the path left from (where its light sample started).
    from: Vec3,
    /// The BSDF's density of the direction among its smooth lobes.
    pdf: f32,
    /// A specular lobe (or the camera): emitters met count whole.
    specular: bool,
}

impl<'a, R: Recorder> PathTracer<'a, R> {
    /// The radiance arriving along `ray` (from its origin), one path's
    /// estimate, its random numbers from `sampler`.
    pub fn radiance(&mut self, ray: Ray, sampler: &mut PixelSampler) -> Vec3 {
        let scene = self.scene;
        let mut ray = ray;
        let (mut radiance, mut throughput) = (Vec3::ZERO, Vec3::ONE);
        // The throughput without the eta^2 of refraction, for the roulette.
        let mut eta_scale = 1.0;
        let mut bounce = Bounce {
            from: ray.origin(),
            pdf: 0.0,
            specular: true,
        };
        let mut depth = 0;
        let mut inside = Inside::default();
        loop {
            self.stats.nearest += 1;
            let Some(hit) = scene.closest_hit(&ray, EPSILON, f32::INFINITY) else {
                if let Some(g) = inside.innermost() {
                    // Out of open glass, which is never left: an infinite
                    // stretch of it, as a light sample toward the sky sees.
                    throughput *= g.absorbed_over(f32::INFINITY);
                }
                let (escaped, weight) = self.escaped(ray.dir(), &bounce);
                let added = throughput * (escaped * weight);
                radiance += added;
                let kind = PathEventKind::Escaped {
                    radiance: escaped,
                    weight,
                };
                self.record(kind, throughput, added);
                break;
            };
            let material = scene.material(hit.material);
            // The segment ran inside glass: the glass entered, or the one
            // whose inside this hit shows (a path that began inside it).
            let medium = inside.innermost().or(match material {
                Material::Glass(g) if !hit.front_face => Some(g),
                _ => None,
            });
            if let Some(g) = medium {
                throughput *= g.absorbed_over(hit.t);
            }
            let p = ray.at(hit.t);
            let vertex = PathEventKind::Vertex {
                depth,
                point: p,
                normal: hit.shading_normal,
                material: hit.material,
                front_face: hit.front_face,
            };
            self.record(vertex, throughput, Vec3::ZERO);
            let (emitted, weight) = self.emitted(material, &hit, &ray, p, &bounce);
            if emitted != Vec3::ZERO {
                let added = throughput * (emitted * weight);
                radiance += added;
                let kind = PathEventKind::Emitted {
                    radiance: emitted,
                    weight,
                };
                self.record(kind, throughput, added);
            }
            if depth == self.max_depth {
                break;
            }
            depth += 1;
            let wo = -ray.dir();
            let bsdf = Bsdf::new(material, &hit, wo);
            self.rec.scattering(&hit, &bsdf);
            let from = if hit.front_face {
                p + hit.shadow_offset
            } else {
                p
            };
            if bsdf.has_smooth_lobes() && self.strategy != Strategy::Bsdf {
                let (pick, u) = (sampler.get1(), sampler.get2());
                let medium = inside.innermost();
                radiance += self.light_sample(&bsdf, from, (pick, u), throughput, medium);
            } else {
                // The light sample's two requests, unused: every later
                // bounce keeps its numbers whatever this one was.
                sampler.skip(2);
            }
            let (lobe, u) = (sampler.get1(), sampler.get2());
            let Some(sample) = bsdf.sample(lobe, u) else {
                break;
            };
            let kind = PathEventKind::BsdfSample {
                wi: sample.wi,
                weight: sample.weight,
                pdf: sample.pdf,
                specular: sample.specular,
            };
            self.record(kind, throughput, Vec3::ZERO);
            throughput *= sample.weight;
            if let (true, Material::Glass(g)) = (sample.transmitted, material) {
                if hit.front_face {
                    inside.enter(g);
                } else {
                    inside.leave(g);
                }
            }
            // Without the weight's eta^2: the roulette looks at energy.
            eta_scale /= sample.eta * sample.eta;
            bounce = Bounce {
                from,
                pdf: sample.pdf,
                specular: sample.specular,
            };
            if depth < ROULETTE_DEPTH {
                sampler.skip(1);
            } else {
                let r = roulette(V3::from(throughput), eta_scale, true, sampler.get1());
                if r.played {
                    let kind = PathEventKind::Roulette {
                        survive: r.q,
                        survived: r.survived,
                    };
                    self.record(kind, throughput, Vec3::ZERO);
                    if !r.survived {
                        break;
                    }
                    throughput = r.throughput.into();
                }
            }
            if throughput == Vec3::ZERO {
                break;
            }
            ray = Ray::new(p, sample.wi);
        }
        radiance
    }

    /// Tells the recorder of `kind`, the throughput before it and what it
    /// added.
    #[inline(always)]
    fn record(&mut self, kind: PathEventKind, throughput: Vec3, added: Vec3) {
        self.rec.path(PathEvent {
            kind,
            throughput,
            added,
        });
    }

    /// The light emitted toward the path by the surface it met at `p`, and
    /// its weight against the light sample that could have found it: 1
    /// after the camera or a specular bounce, which no light sample can
    /// take.
    fn emitted(
        &self,
        material: &Material,
        hit: &SurfaceHit,
        ray: &Ray,
        p: Vec3,
        bounce: &Bounce,
    ) -> (Vec3, f32) {
        let emission = material.emission_at(hit);
        if emission == Vec3::ZERO || !hit.front_face {
            return (Vec3::ZERO, 0.0);
        }
        match self.strategy {
            _ if bounce.specular => return (emission, 1.0),
            Strategy::Mis => {}
            Strategy::Lights => return (emission, 0.0),
            Strategy::Bsdf => return (emission, 1.0),
        }
        let cos = -ray.dir().dot(hit.geometric_normal);
        let lights = self.scene.path_lights();
        // The pick weighs a light by its mean radiance, not this point's.
        let mean = material.emission_mean();
        let light_pdf = lights.pdf_hit(bounce.from, p, cos, mean, hit.object);
        (emission, power_heuristic(bounce.pdf, light_pdf))
    }

    /// The light arriving along `dir` from outside the scene, and its
    /// weight: the environment, against the light sample that could have
    /// found it, or the background colour (no light sample finds it).
    fn escaped(&self, dir: Vec3, bounce: &Bounce) -> (Vec3, f32) {
        let Some(environment) = self.scene.environment() else {
            return (self.scene.trace_settings().background, 1.0);
        };
        // The scene's environment is the one its lights sample.
        let (radiance, pdf) = environment.radiance_and_pdf(dir);
        let weight = match self.strategy {
            _ if bounce.specular => 1.0,
            Strategy::Mis => {
                let light_pdf = self.scene.path_lights().pdf_environment(pdf);
                power_heuristic(bounce.pdf, light_pdf)
            }
            Strategy::Lights => 0.0,
            Strategy::Bsdf => 1.0,
        };
        (radiance, weight)
    }

    /// Next-event estimation: what a sampled point of a light (picked by
    /// `pick`, drawn by `u`) sends through `bsdf` at `from`, if nothing is
    /// in the way, weighted against the BSDF sample that could have found
    /// it, times the path's `throughput`; inside glass `medium`, less what
    /// it absorbs on the way.
    fn light_sample(
        &mut self,
        bsdf: &Bsdf,
        from: Vec3,
        (pick, u): (f32, Vec2),
        throughput: Vec3,
        medium: Option<&Glass>,
    ) -> Vec3 {
        let lights = self.scene.path_lights();
        let Some(light) = lights.sample(from, pick, u) else {
            self.record(PathEventKind::NoLightPoint, throughput, Vec3::ZERO);
            return Vec3::ZERO;
        };
        let (f, bsdf_pdf) = bsdf.eval(light.wi);
        let unlit = f == Vec3::ZERO || light.pdf.is_nan() || light.pdf <= 0.0;
        let blocked = !unlit && {
            self.stats.shadow += 1;
            let shadow = Ray::new(from, light.wi);
            let reach = light.distance * (1.0 - SHADOW_SHORTEN);
            self.scene.occluded(&shadow, EPSILON, reach)
        };
        let weight = if light.point || self.strategy == Strategy::Lights {
            1.0
        } else {
            power_heuristic(light.pdf, bsdf_pdf)
        };
        let absorbed = medium.map_or(Vec3::ONE, |g| g.absorbed_over(light.distance));
        let added = if blocked || unlit {
            Vec3::ZERO
        } else {
            // Times 1 outside glass: the same bits.
            throughput * (f * light.radiance * (weight / light.pdf)) * absorbed
        };
        let kind = PathEventKind::LightSample {
            wi: light.wi,
            distance: light.distance,
            radiance: light.radiance,
            light_pdf: light.pdf,
            f_cos: f,
            bsdf_pdf,
            weight,
            blocked,
            absorbed,
        };
        self.record(kind, throughput, added);
        added
    }
}
