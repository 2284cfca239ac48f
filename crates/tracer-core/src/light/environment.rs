//! Light from every direction, from far away: a latitude-longitude image
//! (or one colour), seen by rays that leave the scene and, in path mode,
//! sampled as a light in proportion to its luminance (a 2D distribution
//! over the image, weighted by the solid angle of each row).

use super::distribution::Distribution2D;
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
    fn to_own(&self, d: Vec3) -> Vec3 {
        let (c, s) = self.turn;
        // The inverse of a counter-clockwise turn about +y.
        Vec3::new(c * d.x - s * d.z, d.y, s * d.x + c * d.z)
    }

    /// Direction `d` of the environment's own frame in the world.
    #[inline(always)]
    fn to_world(&self, d: Vec3) -> Vec3 {
        let (c, s) = self.turn;
        Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z)
    }

    /// The radiance arriving from world direction `dir` (unit, pointing
    /// away from the scene).
    #[inline(always)]
    pub fn radiance(&self, dir: Vec3) -> Vec3 {
        match &self.kind {
            Kind::Uniform(radiance) => *radiance,
            Kind::Image {
                width,
                height,
                texels,
                ..
            } => texel((*width, *height, texels), direction_to_uv(self.to_own(dir))),
        }
    }

    /// A direction drawn by `u`: uniformly over the sphere for one colour,
    /// in proportion to luminance times solid angle for an image.
    #[inline(always)]
    pub fn sample(&self, u: Vec2) -> Option<EnvironmentSample> {
        match &self.kind {
            Kind::Image {
                distribution,
                texels,
                width,
                ..
            } if !self.uniform => {
                let (uv, density, (column, row)) = distribution.sample(u);
                let (dir, sin) = uv_to_direction(uv);
                if density <= 0.0 || sin <= 0.0 {
                    return None;
                }
                let wi = self.to_world(dir);
                Some(EnvironmentSample {
                    wi,
                    // The drawn cell's texel: the direction is not mapped
                    // back to the square (an arc cosine and an arc tangent).
                    radiance: texels[row * *width as usize + column],
                    pdf: density / (2.0 * PI * PI * sin),
                })
            }
            // One colour (or an image sampled uniformly, for comparison).
            _ => {
                let z = 1.0 - 2.0 * u.x;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = 2.0 * PI * u.y;
                let wi = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                Some(EnvironmentSample {
                    wi,
                    radiance: self.radiance(wi),
                    pdf: 1.0 / (4.0 * PI),
                })
            }
        }
    }

    /// The density `sample` gives world direction `dir`, by solid angle.
    #[inline(always)]
    pub fn pdf(&self, dir: Vec3) -> f32 {
        self.radiance_and_pdf(dir).1
    }

    /// `radiance` and `pdf` of `dir` together: the point of the image is
    /// worked out once (an arc cosine and an arc tangent).
    #[inline(always)]
    pub fn radiance_and_pdf(&self, dir: Vec3) -> (Vec3, f32) {
        let Kind::Image {
            width,
            height,
            texels,
            distribution,
        } = &self.kind
        else {
            return (self.radiance(dir), 1.0 / (4.0 * PI));
        };
        let own = self.to_own(dir);
        let uv = direction_to_uv(own);
        let radiance = texel((*width, *height, texels), uv);
        if self.uniform {
            return (radiance, 1.0 / (4.0 * PI));
        }
        let sin = (1.0 - own.y * own.y).max(0.0).sqrt();
        if sin <= 0.0 {
            return (radiance, 0.0);
        }
        (radiance, distribution.density(uv) / (2.0 * PI * PI * sin))
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

/// The texel at point `uv` of an image of `width` x `height` `texels`.
#[inline(always)]
fn texel((width, height, texels): (u32, u32, &[Vec3]), uv: Vec2) -> Vec3 {
    let x = ((uv.x * width as f32) as u32).min(width - 1);
    let y = ((uv.y * height as f32) as u32).min(height - 1);
    texels[(y * width + x) as usize]
}

/// The point of the latitude-longitude square a unit direction of the
/// environment's frame falls on: v from +y (0) down to -y (1), u around
/// from +z (0) through -x, -z (1/2: the centre column), +x.
#[inline(always)]
pub fn direction_to_uv(d: Vec3) -> Vec2 {
    let v = d.y.clamp(-1.0, 1.0).acos() / PI;
    let u = d.x.atan2(-d.z) / (2.0 * PI) + 0.5;
    Vec2::new(
        u.clamp(0.0, 1.0 - f32::EPSILON),
        v.clamp(0.0, 1.0 - f32::EPSILON),
    )
}

/// The direction of point `uv` of the square, and the sine of its angle
/// from +y.
#[inline(always)]
pub fn uv_to_direction(uv: Vec2) -> (Vec3, f32) {
    let theta = PI * uv.y;
    let phi = 2.0 * PI * (uv.x - 0.5);
    let (sin, cos) = theta.sin_cos();
    (Vec3::new(sin * phi.sin(), cos, -sin * phi.cos()), sin)
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
                let world = env.to_world(d);
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
}
