//! Lights. An enum, so the shading loop dispatches statically; the lab's
//! point light is one variant, the sphere light (soft shadows) another.
//! Path mode reads them, and every emissive surface, as one list chosen
//! by power (`lights.rs`): area lights' shapes in `area.rs`, the table
//! that picks one in `alias.rs`.

pub mod alias;
pub mod area;
pub mod distribution;
pub mod environment;
pub mod lights;

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// A light of the scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Light {
    /// The lab's point light (section 4.2).
    Point(PointLight),
    /// A light with a size: its shadows have a penumbra.
    Sphere(SphereLight),
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

    /// The colour, which carries the intensity.
    pub fn color(&self) -> Vec3 {
        match self {
            Light::Point(l) => l.color,
            Light::Sphere(l) => l.color,
        }
    }
}

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
