//! Light from every direction, from far away: a latitude-longitude image
//! (or one colour), seen by rays that leave the scene and, in path mode,
//! sampled as a light in proportion to its luminance (a 2D distribution
//! over the image, weighted by the solid angle of each row).

use super::distribution::Distribution2D;
use crate::simd::{Mask, Real, V3};
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::f32::consts::PI;
use std::sync::Arc;

/// The environment: its radiance, and the turn about +y it was given.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Environment {
    kind: Kind,
    /// cos and sin of the turn about +y (counter-clockwise from above).
    turn: (f32, f32),
    /// Directions drawn uniformly over the sphere rather than by the
    /// image's luminance (tests compare the two).
    #[serde(default)]
    uniform: bool,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
enum Kind {
    /// The same radiance from everywhere.
    Uniform(Vec3),
    /// A latitude-longitude image (its strength applied), row 0 straight
    /// up, the centre column toward -z, and how its texels are drawn.
    Image {
        width: u32,
        height: u32,
        texels: Arc<Vec<Vec3>>,
        distribution: Distribution2D,
    },
}

/// A direction drawn toward the environment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnvironmentSample {
    /// Unit, world.
    pub wi: Vec3,
    pub radiance: Vec3,
    /// Its density, by solid angle.
    pub pdf: f32,
}

/// Directions drawn toward the environment, by lane, and where there is
/// one (`ok`).
#[derive(Debug, Clone, Copy)]
pub struct EnvironmentSamples<N: Real> {
    /// Unit, world.
    pub wi: V3<N>,
    pub radiance: V3<N>,
    /// Its density, by solid angle.
    pub pdf: N,
    pub ok: N::Mask,
}

/// Rec. 709 luminance.
fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

impl Environment {
    /// The same `radiance` from every direction.
    pub fn uniform(radiance: Vec3) -> Environment {
        Environment {
            kind: Kind::Uniform(radiance),
            turn: (1.0, 0.0),
            uniform: true,
        }
    }

    /// The latitude-longitude image of `width` x `height` `texels` (linear
    /// radiance, row by row from the top), times `strength`, turned by
    /// `rotate_degrees` about +y.
    pub fn image(
        width: u32,
        height: u32,
        texels: &[[f32; 3]],
        strength: f32,
        rotate_degrees: f32,
    ) -> Environment {
        let texels: Vec<Vec3> = texels.iter().map(|t| Vec3::from(*t) * strength).collect();
        // Each texel weighed by its luminance and the solid angle of its row
        // (rows near the poles cover less of the sphere).
        let weights: Vec<f32> = texels
            .iter()
            .enumerate()
            .map(|(k, t)| {
                let row = (k as u32 / width) as f32;
                let sin = (PI * (row + 0.5) / height as f32).sin();
                luminance(*t).max(0.0) * sin
            })
            .collect();
        let distribution = Distribution2D::new(&weights, width as usize);
        let angle = rotate_degrees.to_radians();
        Environment {
            kind: Kind::Image {
                width,
                height,
                texels: Arc::new(texels),
                distribution,
            },
            turn: (angle.cos(), angle.sin()),
            uniform: false,
        }
    }

    /// The same environment, its directions drawn uniformly over the
    /// sphere: the baseline its importance sampling is measured against.
    pub fn sampled_uniformly(self) -> Environment {
        Environment {
            uniform: true,
            ..self
        }
    }

    /// Direction `d` in the environment's own frame (before its turn).
    #[inline(always)]
    fn to_own<N: Real>(&self, d: V3<N>) -> V3<N> {
        let (c, s) = self.turn;
        // The inverse of a counter-clockwise turn about +y.
        V3::new(d.x * c - d.z * s, d.y, d.x * s + d.z * c)
    }

    /// Direction `d` of the environment's own frame in the world.
    #[inline(always)]
    fn to_world<N: Real>(&self, d: V3<N>) -> V3<N> {
        let (c, s) = self.turn;
        V3::new(d.x * c + d.z * s, d.y, d.x * -s + d.z * c)
    }

    /// The radiance arriving from world direction `dir` (unit, pointing
    /// away from the scene): `radiance_of` on one lane.
    #[inline(always)]
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        self.radiance_of(V3::from(dir)).into()
    }

    /// A direction drawn by `u` (`sample_of` on one lane).
    #[inline(always)]
    pub fn sample(&self, u: Vec2) -> Option<EnvironmentSample> {
        let s = self.sample_of((u.x, u.y));
        s.ok.then(|| EnvironmentSample {
            wi: s.wi.into(),
            radiance: s.radiance.into(),
            pdf: s.pdf,
        })
    }

    /// The density `sample` gives world direction `dir`, by solid angle.
    #[inline(always)]
    pub fn pdf(&self, dir: Vec3) -> f32 {
        self.radiance_and_pdf(dir).1
    }

    /// `radiance` and `pdf` of `dir` together (`radiance_and_pdf_of` on
    /// one lane).
    #[inline(always)]
    pub fn radiance_and_pdf(&self, dir: Vec3) -> (Vec3, f32) {
        let (radiance, pdf) = self.radiance_and_pdf_of(V3::from(dir));
        (radiance.into(), pdf)
    }

    // Its formulas, for any lane width (`simd::Real`); the image and its
    // distribution are read a lane at a time.

    /// The radiance arriving from each world direction of `dir`.
    #[inline(always)]
    pub fn radiance_of<N: Real>(&self, dir: V3<N>) -> V3<N> {
        match &self.kind {
            Kind::Uniform(radiance) => V3::splat(*radiance),
            Kind::Image {
                width,
                height,
                texels,
                ..
            } => texels_at((*width, *height, texels), lat_long(self.to_own(dir))),
        }
    }

    /// Directions drawn by `u`: uniformly over the sphere for one colour,
    /// in proportion to luminance times solid angle for an image.
    #[inline(always)]
    pub fn sample_of<N: Real>(&self, (u1, u2): (N, N)) -> EnvironmentSamples<N> {
        match &self.kind {
            Kind::Image {
                distribution,
                texels,
                width,
                ..
            } if !self.uniform => {
                let (mut uv, mut density) = ((N::zero(), N::zero()), N::zero());
                let mut radiance = V3::zero();
                for k in 0..N::LANES {
                    let u = Vec2::new(u1.lane(k), u2.lane(k));
                    let (point, d, (column, row)) = distribution.sample(u);
                    uv.0.set_lane(k, point.x);
                    uv.1.set_lane(k, point.y);
                    density.set_lane(k, d);
                    // The drawn cell's texel: the direction is not mapped
                    // back to the square (an arc cosine and an arc tangent).
                    radiance.set_lane(k, texels[row * *width as usize + column]);
                }
                let (dir, sin) = lat_long_direction(uv);
                EnvironmentSamples {
                    wi: self.to_world(dir),
                    radiance,
                    pdf: density / (sin * (2.0 * PI * PI)),
                    ok: !density.le(N::zero()) & !sin.le(N::zero()),
                }
            }
            // One colour (or an image sampled uniformly, for comparison).
            _ => {
                let z = N::one() - u1 * 2.0;
                let r = (N::one() - z * z).max(N::zero()).sqrt();
                let (sin, cos) = (u2 * (2.0 * PI)).sin_cos();
                let wi = V3::new(r * cos, r * sin, z);
                EnvironmentSamples {
                    wi,
                    radiance: self.radiance_of(wi),
                    pdf: N::splat(1.0 / (4.0 * PI)),
                    ok: N::Mask::splat(true),
                }
            }
        }
    }

    /// `radiance_of` and the density `sample_of` gives each direction of
    /// `dir`, by solid angle: the point of the image is worked out once
    /// (an arc cosine and an arc tangent).
    #[inline(always)]
    pub fn radiance_and_pdf_of<N: Real>(&self, dir: V3<N>) -> (V3<N>, N) {
        let Kind::Image {
            width,
            height,
            texels,
            distribution,
        } = &self.kind
        else {
            return (self.radiance_of(dir), N::splat(1.0 / (4.0 * PI)));
        };
        let own = self.to_own(dir);
        let uv = lat_long(own);
        let radiance = texels_at((*width, *height, texels), uv);
        if self.uniform {
            return (radiance, N::splat(1.0 / (4.0 * PI)));
        }
        let sin = (N::one() - own.y * own.y).max(N::zero()).sqrt();
        let density = N::from_fn(|k| distribution.density(Vec2::new(uv.0.lane(k), uv.1.lane(k))));
        let pdf = density / (sin * (2.0 * PI * PI));
        (radiance, N::select(sin.le(N::zero()), N::zero(), pdf))
    }

    /// The integral of the radiance's luminance over the sphere: with the
    /// scene's radius, its power (as pbrt-v4 weighs an infinite light).
    pub fn luminance_integral(&self) -> f32 {
        match &self.kind {
            Kind::Uniform(radiance) => 4.0 * PI * luminance(*radiance),
            // The distribution's mean is of luminance * sin over the
            // square; the sphere's element is 2 pi^2 sin du dv.
            Kind::Image { distribution, .. } => 2.0 * PI * PI * distribution.mean(),
        }
    }
}

/// The texel at each point `uv` of an image of `width` x `height`
/// `texels`.
#[inline(always)]
fn texels_at<N: Real>((width, height, texels): (u32, u32, &[Vec3]), uv: (N, N)) -> V3<N> {
    V3::from_fn(|k| {
        let x = ((uv.0.lane(k) * width as f32) as u32).min(width - 1);
        let y = ((uv.1.lane(k) * height as f32) as u32).min(height - 1);
        texels[(y * width + x) as usize]
    })
}

/// The point of the latitude-longitude square a unit direction of the
/// environment's frame falls on, for any lane width: v from +y (0) down
/// to -y (1), u around from +z (0) through -x, -z (1/2: the centre
/// column), +x.
#[inline(always)]
fn lat_long<N: Real>(d: V3<N>) -> (N, N) {
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    let u = d.x.atan2(-d.z) / (2.0 * PI) + 0.5;
    (
        u.clamp(0.0, 1.0 - f32::EPSILON),
        v.clamp(0.0, 1.0 - f32::EPSILON),
    )
}

/// The direction of point `(u, v)` of the square, and the sine of its
/// angle from +y, for any lane width.
#[inline(always)]
fn lat_long_direction<N: Real>((u, v): (N, N)) -> (V3<N>, N) {
    let theta = v * PI;
    let phi = (u - 0.5) * (2.0 * PI);
    let (sin, cos) = theta.sin_cos();
    let (sin_phi, cos_phi) = phi.sin_cos();
    (V3::new(sin * sin_phi, cos, -sin * cos_phi), sin)
}

impl Environment {
    /// Whether an environment read back from a file (`--cache`) has the
    /// texels and the distribution its size says.
    pub(crate) fn is_whole(&self) -> bool {
        match &self.kind {
            Kind::Uniform(_) => true,
            Kind::Image {
                width,
                height,
                texels,
                distribution,
            } => {
                let (w, h) = (*width as usize, *height as usize);
                w > 0
                    && h > 0
                    && texels.len() as u64 == u64::from(*width) * u64::from(*height)
                    && distribution.is_whole(w, h)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `lat_long` of one direction.
    fn direction_to_uv(d: Vec3) -> Vec2 {
        let (u, v) = lat_long(V3::from(d));
        Vec2::new(u, v)
    }

    /// `lat_long_direction` of one point.
    fn uv_to_direction(uv: Vec2) -> (Vec3, f32) {
        let (d, sin) = lat_long_direction((uv.x, uv.y));
        (d.into(), sin)
    }

    /// A sky of `width` x `height` varied texels, times `strength`,
    /// turned by `degrees`.
    fn varied_sky((width, height): (u32, u32), strength: f32, degrees: f32) -> Environment {
        let texels: Vec<[f32; 3]> = (0..width * height)
            .map(|k| {
                let x = (k * 37 % 11) as f32;
                [x, 0.5 * x, 0.1]
            })
            .collect();
        Environment::image(width, height, &texels, strength, degrees)
    }

    #[test]
    fn directions_and_points_of_the_square_map_both_ways() {
        // The centre looks along -z, the top up, a quarter right +x.
        let (d, _) = uv_to_direction(Vec2::new(0.5, 0.5));
        assert!((d - Vec3::NEG_Z).length() < 1e-6, "{d}");
        let (d, _) = uv_to_direction(Vec2::new(0.75, 0.5));
        assert!((d - Vec3::X).length() < 1e-6, "{d}");
        assert!((uv_to_direction(Vec2::new(0.3, 0.0)).0 - Vec3::Y).length() < 1e-6);
        for uv in [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.6, 0.9),
            Vec2::new(0.99, 0.5),
        ] {
            let back = direction_to_uv(uv_to_direction(uv).0);
            assert!((back - uv).length() < 1e-5, "{uv} -> {back}");
        }
    }

    #[test]
    fn a_turn_moves_the_image_counter_clockwise_seen_from_above() {
        // A bright texel at the centre (toward -z), turned 90 degrees:
        // counter-clockwise from above takes -z to -x.
        let mut texels = vec![[0.0; 3]; 8 * 4];
        texels[4 + 8 * 2] = [1.0; 3];
        texels[4 + 8] = [1.0; 3];
        let env = Environment::image(8, 4, &texels, 1.0, 90.0);
        let toward = |d: Vec3| env.radiance(d.normalize()).x;
        assert_eq!(toward(Vec3::new(-1.0, 0.01, -0.1)), 1.0);
        assert_eq!(toward(Vec3::new(0.0, 0.01, -1.0)), 0.0);
    }

    #[test]
    fn the_sampling_density_integrates_to_one_and_matches_pdf() {
        // A sky of varied texels: the density by solid angle, integrated
        // over the sphere (midpoint rule in u, v), is 1; each sample's pdf
        // is `pdf` of its direction.
        let env = varied_sky((16, 8), 2.0, 30.0);
        let n = 400;
        let mut total = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let uv = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let (d, sin) = uv_to_direction(uv);
                let world: Vec3 = env.to_world(V3::from(d)).into();
                let area = 2.0 * PI * PI * sin / (n * n) as f32;
                total += f64::from(env.pdf(world) * area);
            }
        }
        assert!((total - 1.0).abs() < 2e-3, "{total}");
        let s = env.sample(Vec2::new(0.3, 0.7)).unwrap();
        assert!((s.pdf / env.pdf(s.wi) - 1.0).abs() < 1e-3);
        assert_eq!(s.radiance, env.radiance(s.wi));
    }

    #[test]
    fn a_light_sample_carries_the_texel_its_direction_shows() {
        // Each sample reads the texel of the cell it drew; the direction
        // looked up again gives the same one, unless its rounding crosses
        // into a neighbour at the cell's edge.
        let env = varied_sky((24, 12), 1.5, 70.0);
        let n = 200;
        let mut differ = 0;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.37) / n as f32, (j as f32 + 0.61) / n as f32);
                let s = env.sample(u).unwrap();
                differ += usize::from(s.radiance != env.radiance(s.wi));
            }
        }
        assert!(differ * 1000 <= n * n, "{differ} of {} samples", n * n);
    }

    /// Sixteen lanes give each lane's one-lane draw, radiance and density,
    /// bit for bit: an image turned, the same sampled uniformly, a colour.
    #[test]
    fn the_environment_in_lanes_is_the_one_lane_environment() {
        use crate::simd::F16;
        let sky = varied_sky((64, 32), 3.0, 30.0);
        let envs = [
            sky.clone(),
            sky.sampled_uniformly(),
            Environment::uniform(Vec3::new(0.2, 0.5, 1.0)),
        ];
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        let mut rng = crate::sampling::Rng::new(5);
        for env in &envs {
            for round in 0..50 {
                let u: [Vec2; 16] = std::array::from_fn(|_| rng.square());
                let dirs: [Vec3; 16] = std::array::from_fn(|k| match (k + round) % 9 {
                    0 => Vec3::Y,
                    1 => -Vec3::Y,
                    _ => (rng.square().extend(rng.square().x) - 0.5).normalize(),
                });
                let u16 = (F16::from_fn(|k| u[k].x), F16::from_fn(|k| u[k].y));
                let drawn = env.sample_of(u16);
                let (radiance, pdf) = env.radiance_and_pdf_of(V3::<F16>::from_fn(|k| dirs[k]));
                for k in 0..16 {
                    let one = env
                        .sample(u[k])
                        .map(|s| (bits(s.wi), bits(s.radiance), s.pdf));
                    let lane = drawn.ok.lane(k).then(|| {
                        let (wi, r) = (drawn.wi.lane(k), drawn.radiance.lane(k));
                        (bits(wi), bits(r), drawn.pdf.lane(k))
                    });
                    assert_eq!(
                        lane.map(|l| (l.0, l.1, l.2.to_bits())),
                        one.map(|o| (o.0, o.1, o.2.to_bits()))
                    );
                    let (r, p) = env.radiance_and_pdf(dirs[k]);
                    assert_eq!(bits(radiance.lane(k)), bits(r), "{:?}", dirs[k]);
                    assert_eq!(pdf.lane(k).to_bits(), p.to_bits(), "{:?}", dirs[k]);
                    assert_eq!(
                        bits(env.radiance_of(V3::<F16>::from_fn(|_| dirs[k])).lane(k)),
                        bits(env.radiance(dirs[k]))
                    );
                }
            }
        }
    }
}
