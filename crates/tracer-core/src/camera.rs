//! The lab's camera: the projection matrix `P = [u v o]` and primary rays
//! through pixel centres (lab section 2).

use crate::ray::Ray;
use glam::{Mat3, Vec3};

/// The lab's pinhole camera: the eye, the image size, and the projection
/// matrix that turns an image point into a ray direction. With the lab's
/// conventions world +x is on the image's left (lab section 0).
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub width: u32,
    pub height: u32,
    /// Columns u, v, o of the projection matrix.
    pub projection: Mat3,
}

impl Camera {
    /// `fov` is the horizontal field of view in degrees. The caller makes
    /// sure `look_at != eye` and `up` is not parallel to the view.
    pub fn new(eye: Vec3, look_at: Vec3, up: Vec3, fov: f32, width: u32, height: u32) -> Self {
        let look = look_at - eye;
        let u = up.cross(look).normalize();
        let v = u.cross(look).normalize();
        let (w, h) = (width as f32, height as f32);
        let focal = w / (2.0 * (fov.to_radians() / 2.0).tan());
        let o = look.normalize() * focal - (w / 2.0 * u + h / 2.0 * v);
        Camera {
            eye,
            width,
            height,
            projection: Mat3::from_cols(u, v, o),
        }
    }

    /// The ray through image point (fx, fy); a pixel's centre is (i + 0.5, j + 0.5).
    pub fn ray(&self, fx: f32, fy: f32) -> Ray {
        let dir = self.projection * Vec3::new(fx, fy, 1.0);
        Ray::new(self.eye, dir.normalize())
    }

    /// The primary ray of pixel (column i, row j), through its centre.
    pub fn primary_ray(&self, i: u32, j: u32) -> Ray {
        self.ray(i as f32 + 0.5, j as f32 + 0.5)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lab's printed numbers used pi = 3.14; 1e-3 relative error allows for it.
    fn assert_rows(p: &Mat3, rows: [[f32; 3]; 3]) {
        for (r, row) in rows.iter().enumerate() {
            for (c, &expected) in row.iter().enumerate() {
                let got = p.col(c)[r];
                let tolerance = 1e-3 * expected.abs().max(1.0);
                assert!(
                    (got - expected).abs() <= tolerance,
                    "P[{r}][{c}] = {got}, expected {expected}"
                );
            }
        }
    }

    fn lab_camera() -> Camera {
        Camera::new(
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::ZERO,
            Vec3::Y,
            50.0,
            500,
            400,
        )
    }

    /// The lab turned degrees into radians with pi = 3.14: this fov, converted
    /// with the exact pi, gives the lab's angle. Element [0][2] of the oblique
    /// matrix is a difference of large terms and moves by 5e-3 relative with
    /// the exact pi, more than the 1e-3 the printed numbers are checked to.
    #[allow(clippy::approx_constant)] // 3.14 is the lab's pi, on purpose
    const LAB_FOV: f32 = 50.0 * 3.14 / std::f32::consts::PI;

    #[test]
    fn projection_matrix_of_the_default_camera() {
        let rows = [[-1.0, 0.0, 250.0], [0.0, -1.0, 200.0], [0.0, 0.0, -536.436]];
        assert_rows(&lab_camera().projection, rows);
        let lab = Camera::new(
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::ZERO,
            Vec3::Y,
            LAB_FOV,
            500,
            400,
        );
        assert!((lab.projection.col(2).z - -536.436).abs() < 0.001);
        // With the exact pi (lab-spec section 7).
        assert!((lab_camera().projection.col(2).z - -536.127).abs() < 0.001);
    }

    #[test]
    fn projection_matrix_of_the_oblique_camera() {
        let cam = Camera::new(
            Vec3::new(2.0, 5.0, 10.0),
            Vec3::new(-2.0, 1.0, 0.0),
            Vec3::Y,
            LAB_FOV,
            500,
            400,
        );
        let rows = [
            [-0.928477, 0.129302, 19.4956],
            [0.0, -0.937437, 0.724167],
            [0.371391, 0.323254, -624.406],
        ];
        assert_rows(&cam.projection, rows);
    }

    #[test]
    fn primary_directions_of_the_lab() {
        let cam = lab_camera();
        let (w, h) = (500.0, 400.0);
        let checks = [
            ((w / 2.0 - 1.0 + 0.5, h / 2.0 - 1.0 + 0.5), [0.0, 0.0, -1.0]),
            ((0.5, 0.5), [0.40, 0.32, -0.86]),
            ((w / 2.0 - 1.0 + 0.5, 0.5), [0.0, 0.35, -0.94]),
            ((0.5, h / 2.0 - 1.0 + 0.5), [0.42, 0.0, -0.91]),
            ((w - 1.0 + 0.5, h - 1.0 + 0.5), [-0.40, -0.32, -0.86]),
        ];
        for ((fx, fy), expected) in checks {
            let dir = cam.ray(fx, fy).dir;
            let diff = (dir - Vec3::from(expected)).abs().max_element();
            assert!(diff <= 0.01, "({fx}, {fy}): {dir:?}, expected {expected:?}");
        }
    }

    #[test]
    fn plus_x_is_on_the_left_and_plus_y_up() {
        let cam = lab_camera();
        let top_left = cam.primary_ray(0, 0).dir;
        assert!(top_left.x > 0.0 && top_left.y > 0.0);
    }
}
