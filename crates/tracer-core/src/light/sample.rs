//! A light sample: a light picked from the table in proportion to its
//! power (`lights.rs`), a point of it drawn and seen from a shaded point.
//! Written once for any lane width (`simd::Real`): the one-path tracer's
//! `Lights::sample` is `Lights::sample_of` on one lane, and paths traced in
//! lanes call it on sixteen. The lights of each kind are worked out
//! together where some lane picked one (`mask.any()`), so one lane costs
//! what its own light costs; what differs from light to light beyond a few
//! numbers (a spot's cone, an ellipsoid, an emission texture) is read a
//! lane at a time.

use super::area::{sphere_sample, AreaPoint, AreaPoints, AreaShape, Flat};
use super::cone_falloff;
use super::lights::{AreaLight, Emits, Lights};
use super::toward::toward;
use crate::simd::{Mask, Real, V3};
use glam::{Vec2, Vec3};

/// What a light sample brings to a shaded point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightSample {
    /// Unit, toward the light.
    pub wi: Vec3,
    pub distance: f32,
    /// The radiance arriving along `wi` (a point light's intensity over
    /// the distance squared).
    pub radiance: Vec3,
    /// The density of `wi` (solid angle), the pick included; for a point
    /// light, the probability of the pick.
    pub pdf: f32,
    /// A point light: no other sampling can find it.
    pub point: bool,
}

/// Light samples by lane: `LightSample`'s fields, where there is one, and
/// the light each lane picked.
#[derive(Clone, Copy)]
pub struct LightSamples<N: Real> {
    pub wi: V3<N>,
    pub distance: N,
    pub radiance: V3<N>,
    pub pdf: N,
    pub point: N::Mask,
    /// Where a light was picked and its point is seen (not from behind a
    /// flat light, inside a sphere or outside a spot's cone).
    pub ok: N::Mask,
    /// Each lane's light, its index in the table (0 where none was picked).
    pub light: N::Array<u32>,
}

/// Which part of `sample_of` draws a lane's light.
#[derive(Clone, Copy, Default, PartialEq, Eq)]
enum Part {
    /// No light picked: none wanted, or no light.
    #[default]
    None,
    Point,
    Flat,
    Sphere,
    Ellipsoid,
    Environment,
}

/// One part's draws, before the pick's probability.
struct Drawn<N: Real> {
    wi: V3<N>,
    distance: N,
    radiance: V3<N>,
    pdf: N,
    ok: N::Mask,
}

impl<N: Real> Drawn<N> {
    fn none() -> Drawn<N> {
        Drawn {
            wi: V3::zero(),
            distance: N::zero(),
            radiance: V3::zero(),
            pdf: N::zero(),
            ok: N::Mask::splat(false),
        }
    }

    /// `other`'s draws in `lanes`, these elsewhere.
    #[inline(always)]
    fn or(self, lanes: N::Mask, other: Drawn<N>) -> Drawn<N> {
        Drawn {
            wi: V3::select(lanes, other.wi, self.wi),
            distance: N::select(lanes, other.distance, self.distance),
            radiance: V3::select(lanes, other.radiance, self.radiance),
            pdf: N::select(lanes, other.pdf, self.pdf),
            ok: N::Mask::select(lanes, other.ok, self.ok),
        }
    }
}

impl Lights {
    /// One light picked by `pick`, a point of it by `u`, seen from `from`:
    /// `sample_of` on one lane.
    #[inline(always)]
    pub fn sample(&self, from: Vec3, pick: f32, u: Vec2) -> Option<LightSample> {
        let s = self.sample_of(V3::from(from), pick, (u.x, u.y), true);
        s.ok.then(|| LightSample {
            wi: s.wi.into(),
            distance: s.distance,
            radiance: s.radiance.into(),
            pdf: s.pdf,
            point: s.point,
        })
    }

    /// Each `wanted` lane's light picked by `pick`, a point of it drawn by
    /// `u`, seen from `from`.
    #[inline(always)]
    pub fn sample_of<N: Real>(
        &self,
        from: V3<N>,
        pick: N,
        u: (N, N),
        wanted: N::Mask,
    ) -> LightSamples<N> {
        let (mut light, mut part) = (N::Array::<u32>::default(), N::Array::<Part>::default());
        let mut pmf = N::zero();
        if let Some(table) = self.table() {
            for k in 0..N::LANES {
                if wanted.lane(k) {
                    let (i, p) = table.sample(pick.lane(k));
                    (light[k], part[k]) = (i as u32, self.part(i));
                    pmf.set_lane(k, p);
                }
            }
        }
        let of = |p: Part| N::Mask::from_fn(|k| part[k] == p);
        let (points, flat, spheres) = (of(Part::Point), of(Part::Flat), of(Part::Sphere));
        let (ellipsoids, environment) = (of(Part::Ellipsoid), of(Part::Environment));
        let mut s = Drawn::none();
        if points.any() {
            s = s.or(points, self.point_sources(from, &light));
        }
        if flat.any() {
            let shapes = Flat::lanes(|k| self.area(light[k]).map(|a| &a.shape));
            s = s.or(flat, self.on_areas(shapes.sample(from, u), &light, flat));
        }
        if spheres.any() {
            let drawn = self.sphere_points(from, u, &light);
            s = s.or(spheres, self.on_areas(drawn, &light, spheres));
        }
        if ellipsoids.any() {
            let drawn = self.ellipsoid_points(from, u, &light, ellipsoids);
            s = s.or(ellipsoids, self.on_areas(drawn, &light, ellipsoids));
        }
        if let Some(e) = self.environment().filter(|_| environment.any()) {
            let e = e.sample_of(u);
            let drawn = Drawn {
                wi: e.wi,
                distance: N::splat(f32::INFINITY),
                radiance: e.radiance,
                pdf: e.pdf,
                ok: e.ok,
            };
            s = s.or(environment, drawn);
        }
        LightSamples {
            wi: s.wi,
            distance: s.distance,
            radiance: s.radiance,
            pdf: N::select(points, pmf, pmf * s.pdf),
            point: points,
            ok: s.ok,
            light,
        }
    }

    /// Which part draws light `i` of the table.
    #[inline(always)]
    fn part(&self, i: usize) -> Part {
        if i < self.points().len() {
            return Part::Point;
        }
        match self.area(i as u32).map(|a| &a.shape) {
            Some(AreaShape::Triangle { .. } | AreaShape::Parallelogram { .. }) => Part::Flat,
            Some(AreaShape::Sphere { .. }) => Part::Sphere,
            Some(AreaShape::Ellipsoid(_)) => Part::Ellipsoid,
            None if self.has_environment() => Part::Environment,
            None => Part::None,
        }
    }

    /// Light `i` of the table, if it is an area light. Parts gather their
    /// lights' numbers from every lane, picked or not, without a branch
    /// on the lane: a lane of another part (or of none, which reads light
    /// 0) gathers what it finds, and its draws are dropped.
    #[inline(always)]
    fn area(&self, i: u32) -> Option<&AreaLight> {
        let k = (i as usize).wrapping_sub(self.points().len());
        self.areas().get(k)
    }

    /// The point lights of the lanes seen from `from`: a point light's
    /// radiance is its intensity over the distance squared; a spot's cone
    /// and a directional light's parallel rays are read a lane at a time.
    #[inline(always)]
    fn point_sources<N: Real>(&self, from: V3<N>, light: &N::Array<u32>) -> Drawn<N> {
        let source = |k: usize| self.points().get(light[k] as usize);
        let position = V3::from_fn(|k| source(k).map_or(Vec3::ZERO, |p| p.position));
        let intensity = V3::from_fn(|k| source(k).map_or(Vec3::ZERO, |p| p.intensity));
        let way = toward(from, position);
        let mut s = Drawn {
            wi: way.wi,
            distance: way.distance,
            radiance: intensity / way.distance2,
            pdf: N::one(),
            ok: way.apart,
        };
        for (k, p) in (0..N::LANES).filter_map(|k| Some((k, source(k)?))) {
            match p.emits {
                Emits::Everywhere => {}
                Emits::Cone {
                    axis,
                    cos_inner,
                    cos_outer,
                } => {
                    let fraction = cone_falloff(axis, cos_inner, cos_outer, -way.wi.lane(k));
                    let radiance = p.intensity * (fraction / way.distance2.lane(k));
                    s.radiance.set_lane(k, radiance);
                    s.ok.set_lane(k, way.apart.lane(k) && !fraction.le(0.0));
                }
                Emits::Parallel { direction, .. } => {
                    s.wi.set_lane(k, -direction);
                    s.distance.set_lane(k, f32::INFINITY);
                    s.radiance.set_lane(k, p.intensity);
                    s.ok.set_lane(k, true);
                }
            }
        }
        s
    }

    /// Points of the lanes' sphere lights, each drawn by its cone from
    /// `from`.
    #[inline(always)]
    fn sphere_points<N: Real>(
        &self,
        from: V3<N>,
        u: (N, N),
        light: &N::Array<u32>,
    ) -> AreaPoints<N> {
        let (mut center, mut radius) = (V3::zero(), N::zero());
        for k in 0..N::LANES {
            if let Some(AreaShape::Sphere {
                center: c,
                radius: r,
            }) = self.area(light[k]).map(|a| &a.shape)
            {
                center.set_lane(k, *c);
                radius.set_lane(k, *r);
            }
        }
        sphere_sample(center, radius, from, u)
    }

    /// Points of the ellipsoid lights of `lanes`, a lane at a time.
    #[inline(always)]
    fn ellipsoid_points<N: Real>(
        &self,
        from: V3<N>,
        u: (N, N),
        light: &N::Array<u32>,
        lanes: N::Mask,
    ) -> AreaPoints<N> {
        let zero = (N::zero(), N::zero());
        let mut drawn = AreaPoints {
            point: V3::zero(),
            wi: V3::zero(),
            distance: N::zero(),
            pdf: N::zero(),
            at: zero,
            ok: N::Mask::splat(false),
        };
        for k in 0..N::LANES {
            let Some(light) = self.area(light[k]).filter(|_| lanes.lane(k)) else {
                continue;
            };
            let u = Vec2::new(u.0.lane(k), u.1.lane(k));
            let Some(p) = light.shape.sample(from.lane(k), u) else {
                continue;
            };
            drawn.point.set_lane(k, p.point);
            drawn.wi.set_lane(k, p.wi);
            drawn.distance.set_lane(k, p.distance);
            drawn.pdf.set_lane(k, p.pdf);
            drawn.ok.set_lane(k, true);
        }
        drawn
    }

    /// Points `drawn` on the area lights of `lanes`, with the radiance each
    /// gives off there (read from its texture, if it has one, a lane at a
    /// time).
    #[inline(always)]
    fn on_areas<N: Real>(
        &self,
        drawn: AreaPoints<N>,
        light: &N::Array<u32>,
        lanes: N::Mask,
    ) -> Drawn<N> {
        let radiance = V3::from_fn(|k| match self.area(light[k]) {
            Some(AreaLight {
                texture: None,
                radiance,
                ..
            }) => *radiance,
            Some(AreaLight {
                texture: Some(t),
                radiance,
                ..
            }) if lanes.lane(k) => t.radiance(*radiance, &lane_point(&drawn, k)),
            _ => Vec3::ZERO,
        });
        Drawn {
            wi: drawn.wi,
            distance: drawn.distance,
            radiance,
            pdf: drawn.pdf,
            ok: drawn.ok,
        }
    }
}

/// Lane `k` of `drawn`.
#[inline(always)]
fn lane_point<N: Real>(drawn: &AreaPoints<N>, k: usize) -> AreaPoint {
    AreaPoint {
        point: drawn.point.lane(k),
        wi: drawn.wi.lane(k),
        distance: drawn.distance.lane(k),
        pdf: drawn.pdf.lane(k),
        at: Vec2::new(drawn.at.0.lane(k), drawn.at.1.lane(k)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::UvMap;
    use crate::light::area::EllipsoidLight;
    use crate::light::environment::Environment;
    use crate::light::lights::PointSource;
    use crate::light::textured::{EmittingSurface, LightTexture, UvAt};
    use crate::simd::F16;
    use crate::texture::ColorTexture;
    use glam::Mat3;
    use std::sync::Arc;

    /// Every kind of light, in table order: a point light, a spot, a
    /// directional light, a triangle, a parallelogram with a checker
    /// texture, a sphere, an ellipsoid, and an image around them.
    fn every_kind() -> Lights {
        let spot = PointSource {
            emits: Emits::Cone {
                axis: Vec3::NEG_Y,
                cos_inner: 0.9,
                cos_outer: 0.6,
            },
            ..PointSource::point(Vec3::new(0.5, 3.0, 0.0), Vec3::splat(4.0))
        };
        let sun = PointSource {
            emits: Emits::Parallel {
                direction: Vec3::new(1.0, -2.0, 0.5).normalize(),
                radius: 1.0,
            },
            ..PointSource::point(Vec3::ZERO, Vec3::splat(2.0))
        };
        let points = vec![PointSource::point(Vec3::Y * 2.0, Vec3::ONE), spot, sun];
        let triangle = AreaShape::triangle(Vec3::new(-1.0, 2.0, 0.0), Vec3::X, Vec3::Z);
        let parallelogram = AreaShape::parallelogram(Vec3::new(2.0, 0.0, -1.0), Vec3::Z, Vec3::Y);
        let checker = ColorTexture::Checker {
            colors: [Vec3::new(1.0, 0.2, 0.2), Vec3::splat(0.1)],
            scale: Vec2::splat(4.0),
        };
        let texture = LightTexture {
            surface: Arc::new(EmittingSurface {
                texture: Some(checker),
                mask: None,
                mean: Vec3::splat(0.5),
            }),
            uv: UvAt::Map(UvMap::IDENTITY),
        };
        let textured = AreaLight {
            texture: Some(Box::new(texture)),
            ..AreaLight::new(parallelogram.unwrap(), Vec3::splat(3.0))
        };
        let sphere = AreaShape::Sphere {
            center: Vec3::new(-2.0, 1.0, 1.0),
            radius: 0.5,
        };
        let linear = Mat3::from_diagonal(Vec3::new(2.0, 0.5, 1.0));
        let ellipsoid = EllipsoidLight::new(Vec3::new(0.0, 1.0, -3.0), 0.7, linear).unwrap();
        let areas = vec![
            AreaLight::new(triangle.unwrap(), Vec3::new(5.0, 4.0, 3.0)),
            textured,
            AreaLight::new(sphere, Vec3::splat(2.0)),
            AreaLight::new(AreaShape::Ellipsoid(Box::new(ellipsoid)), Vec3::ONE),
        ];
        let texels: Vec<[f32; 3]> = (0..32u32)
            .map(|k| [(k * 7 % 5) as f32, 0.5, (k % 3) as f32])
            .collect();
        let sky = Environment::image(8, 4, &texels, 0.2, 30.0);
        Lights::new(points, areas, &[7, 8], Some((Arc::new(sky), 1.0)))
    }

    /// Sixteen lanes give each lane's one-lane light sample, bit for bit,
    /// of every kind of light, from points above, below and inside them,
    /// lanes left out where no sample is wanted.
    #[test]
    fn light_samples_in_lanes_are_the_one_lane_samples() {
        let lights = every_kind();
        let mut rng = crate::sampling::Rng::new(5);
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        let mut met = [[0usize; 2]; 8];
        for round in 0..400 {
            let from: [Vec3; 16] =
                std::array::from_fn(|_| (rng.square().extend(rng.square().x) - 0.5) * 8.0);
            let pick: [f32; 16] = std::array::from_fn(|_| rng.square().x);
            let u: [Vec2; 16] = std::array::from_fn(|_| rng.square());
            let wanted = crate::simd::M16::from_fn(|k| (k + round) % 5 != 0);
            let s = lights.sample_of(
                V3::<F16>::from_fn(|k| from[k]),
                F16::from_fn(|k| pick[k]),
                (F16::from_fn(|k| u[k].x), F16::from_fn(|k| u[k].y)),
                wanted,
            );
            for k in 0..16 {
                let one = wanted
                    .lane(k)
                    .then(|| lights.sample(from[k], pick[k], u[k]));
                let lane = wanted.lane(k).then(|| {
                    s.ok.lane(k).then(|| {
                        let (wi, radiance) = (s.wi.lane(k), s.radiance.lane(k));
                        let (d, pdf) = (s.distance.lane(k), s.pdf.lane(k));
                        (
                            bits(wi),
                            d.to_bits(),
                            bits(radiance),
                            pdf.to_bits(),
                            s.point.lane(k),
                        )
                    })
                });
                let one = one.map(|o| {
                    o.map(|o| {
                        let (wi, radiance) = (bits(o.wi), bits(o.radiance));
                        (wi, o.distance.to_bits(), radiance, o.pdf.to_bits(), o.point)
                    })
                });
                assert_eq!(lane, one, "round {round}, lane {k}");
                if let Some(drawn) = one {
                    met[s.light[k] as usize][usize::from(drawn.is_some())] += 1;
                }
            }
        }
        // Each light drawn many times, and each that can be missed (the
        // spot outside its cone, the shapes from behind or inside) missed.
        for (i, [missed, drawn]) in met.into_iter().enumerate() {
            assert!(drawn > 20, "light {i}: {met:?}");
            assert!(missed > 0 || [0, 2, 7].contains(&i), "light {i}: {met:?}");
        }
    }
}
