//! Lights. An enum, so the shading loop dispatches statically; the lab's
//! point light is one variant, the sphere light (soft shadows) another,
//! glTF's spot and directional lights two more.
//! Path mode reads them, and every emissive surface, as one list chosen
//! by power (`lights.rs`): area lights' shapes in `area.rs`, what varies
//! over a textured one in `textured.rs`, the table that picks one in
//! `alias.rs`, a light sample drawn from the list in `sample.rs` and a
//! light's point seen from a shaded point in `toward.rs` (both for one
//! path or for lanes).

pub mod alias;
pub mod area;
pub mod distribution;
pub mod environment;
pub mod lights;
pub mod sample;
pub mod textured;
pub mod toward;

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// A light of the scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Light {
    /// The lab's point light (section 4.2).
    Point(PointLight),
    /// A light with a size: its shadows have a penumbra.
    Sphere(SphereLight),
    /// A point light that shines into a cone (glTF's spot light).
    Spot(SpotLight),
    /// Parallel light from infinitely far away (a sun).
    Directional(DirectionalLight),
}

impl Light {
    /// A point light, or a sphere light when `radius` is above 0.
    pub fn new(position: Vec3, color: Vec3, radius: f32) -> Light {
        if radius > 0.0 {
            Light::Sphere(SphereLight {
                centre: position,
                color,
                radius,
            })
        } else {
            Light::Point(PointLight { position, color })
        }
    }

    /// A spot light at `position` shining along `direction` (any length),
    /// full inside `inner` degrees of its axis, fading to nothing at
    /// `outer`.
    pub fn spot(position: Vec3, direction: Vec3, color: Vec3, (inner, outer): (f32, f32)) -> Light {
        Light::Spot(SpotLight {
            position,
            color,
            axis: direction.normalize_or(Vec3::NEG_Y),
            cos_inner: inner.to_radians().cos(),
            cos_outer: outer.to_radians().cos(),
        })
    }

    /// Parallel light travelling along `direction` (any length); `color`
    /// is the irradiance it gives a surface facing it.
    pub fn directional(direction: Vec3, color: Vec3) -> Light {
        Light::Directional(DirectionalLight {
            direction: direction.normalize_or(Vec3::NEG_Y),
            color,
        })
    }

    /// The colour, which carries the intensity.
    pub fn color(&self) -> Vec3 {
        match self {
            Light::Point(l) => l.color,
            Light::Sphere(l) => l.color,
            Light::Spot(l) => l.color,
            Light::Directional(l) => l.color,
        }
    }
}

/// A spot light: a point light whose intensity fades from its axis as
/// glTF's `KHR_lights_punctual` says (a smooth step in the cosine, squared).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpotLight {
    pub position: Vec3,
    pub color: Vec3,
    /// Unit, the way it shines.
    pub axis: Vec3,
    /// Cosines of the inner angle (full strength within) and the outer
    /// one (none beyond).
    pub cos_inner: f32,
    pub cos_outer: f32,
}

impl SpotLight {
    /// The fraction of its intensity the light sends toward `p`.
    pub fn falloff(&self, p: Vec3) -> f32 {
        cone_falloff(self.axis, self.cos_inner, self.cos_outer, p - self.position)
    }
}

/// The fraction of a spot light's intensity sent along `to` (any length)
/// by a cone about unit `axis`: glTF's smooth attenuation, 0 beyond the
/// outer cosine, 1 within the inner, its square between.
pub fn cone_falloff(axis: Vec3, cos_inner: f32, cos_outer: f32, to: Vec3) -> f32 {
    let cos = axis.dot(to.normalize_or_zero());
    let scale = 1.0 / (cos_inner - cos_outer).max(1e-3);
    let t = ((cos - cos_outer) * scale).clamp(0.0, 1.0);
    t * t
}

/// Light from infinitely far away, all along one direction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DirectionalLight {
    /// Unit, the way the light travels.
    pub direction: Vec3,
    /// The irradiance on a surface facing the light.
    pub color: Vec3,
}

/// How far away the lab's shading puts a directional light's point: far
/// beyond any scene (whose coordinates stay within 1e6), so that its light
/// arrives parallel to single precision.
pub const FAR_AWAY: f32 = 1e12;

/// A point light (lab 4.2); its colour carries the intensity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointLight {
    pub position: Vec3,
    pub color: Vec3,
}

/// A sphere that gives off light: seen from a shaded point it is a disk of
/// `radius` facing that point, sampled by shadow rays. Its colour is the
/// whole light's, as for a point light in the same place, so growing the
/// radius softens shadows without brightening the scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SphereLight {
    pub centre: Vec3,
    pub color: Vec3,
    pub radius: f32,
}

impl SphereLight {
    /// The point of the disk facing `from` at `disk`, a point of the unit
    /// disk.
    pub fn point_seen_from(&self, from: Vec3, disk: glam::Vec2) -> Vec3 {
        let axis = (self.centre - from).normalize_or(Vec3::Z);
        let (a, b) = axis.any_orthonormal_pair();
        self.centre + self.radius * (disk.x * a + disk.y * b)
    }
}
