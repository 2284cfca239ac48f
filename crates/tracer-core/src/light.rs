use glam::Vec3;

/// A point light (lab 4.2); its colour carries the intensity.
#[derive(Debug, Clone, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    pub color: Vec3,
}
