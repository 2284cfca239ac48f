//! The Lambertian lobe: the lab's `diffuse` read as an albedo.

use crate::sampling::concentric_disk;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Light scattered equally in every direction of the hemisphere: f =
/// albedo / pi, so a white surface (albedo 1) reflects all it receives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lambert {
    pub albedo: Vec3,
}

impl Lambert {
    /// f for local directions with `wo.z >= 0`: nothing below the surface.
    #[inline(always)]
    pub fn eval(&self, wi: Vec3) -> Vec3 {
        if wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.albedo * FRAC_1_PI
    }

    /// The density of `sample`'s directions: cosine-weighted.
    #[inline(always)]
    pub fn pdf(wi: Vec3) -> f32 {
        wi.z.max(0.0) * FRAC_1_PI
    }

    /// A cosine-weighted direction of the upper hemisphere from a point of
    /// the unit square (Malley's method: the disk lifted onto it).
    #[inline(always)]
    pub fn sample(u: Vec2) -> Vec3 {
        let d = concentric_disk(u);
        let z = (1.0 - d.length_squared()).max(0.0).sqrt();
        Vec3::new(d.x, d.y, z)
    }
}
