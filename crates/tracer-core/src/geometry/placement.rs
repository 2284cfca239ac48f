//! Where an object's transform takes its points.

use glam::{Mat3, Vec3};

/// An affine placement: scale, then rotate about x, y, z (in that order),
/// then translate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    linear: Mat3,
    translate: Vec3,
}

impl Placement {
    pub const IDENTITY: Placement = Placement {
        linear: Mat3::IDENTITY,
        translate: Vec3::ZERO,
    };

    /// Scale per axis, rotation angles in degrees about x, then y, then z,
    /// then the translation.
    pub fn new(scale: Vec3, rotate_degrees: Vec3, translate: Vec3) -> Placement {
        let [rx, ry, rz] = rotate_degrees.to_array().map(f32::to_radians);
        let rotation =
            Mat3::from_rotation_z(rz) * Mat3::from_rotation_y(ry) * Mat3::from_rotation_x(rx);
        Placement {
            linear: rotation * Mat3::from_diagonal(scale),
            translate,
        }
    }

    pub fn apply(&self, p: Vec3) -> Vec3 {
        self.linear * p + self.translate
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_then_rotate_then_translate() {
        let placement = Placement::new(
            Vec3::new(2.0, 1.0, 1.0),
            Vec3::new(0.0, 0.0, 90.0),
            Vec3::new(1.0, 2.0, 3.0),
        );
        let p = placement.apply(Vec3::X);
        // (1,0,0) -> scale (2,0,0) -> 90 deg about z (0,2,0) -> (1,4,3).
        assert!((p - Vec3::new(1.0, 4.0, 3.0)).length() < 1e-5, "{p}");
        let rx = Placement::new(Vec3::ONE, Vec3::new(90.0, 0.0, 90.0), Vec3::ZERO);
        // x first: y -> z; then z about z stays z.
        let q = rx.apply(Vec3::Y);
        assert!((q - Vec3::Z).length() < 1e-5, "{q}");
    }

    #[test]
    fn the_identity_keeps_points_exactly() {
        let p = Vec3::new(0.1, 0.2, 0.3);
        assert_eq!(Placement::IDENTITY.apply(p), p);
    }
}
