//! Lights. An enum, so the shading loop dispatches statically; the lab's
//! point light is one variant, and new kinds (sphere lights, ...) join as
//! variants.

use glam::Vec3;

/// A light of the scene.
#[derive(Debug, Clone, PartialEq)]
pub enum Light {
    /// The lab's point light (section 4.2).
    Point(PointLight),
}

/// A point light (lab 4.2); its colour carries the intensity.
#[derive(Debug, Clone, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    pub color: Vec3,
}
