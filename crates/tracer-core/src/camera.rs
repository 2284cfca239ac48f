//! The lab's camera: the projection matrix `P = [u v o]` and primary rays
//! through pixel centres (lab section 2); beyond the lab, a right-handed
//! image and a thin lens.

use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::sampling::concentric_disk;
use glam::{DVec2, DVec3, Mat3, Vec2, Vec3, Vec4};
use serde::{Deserialize, Serialize};

/// The lab's pinhole camera: the eye, the image size, and the projection
/// matrix that turns an image point into a ray direction. With the lab's
/// conventions world +x is on the image's left (lab section 0).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Camera {
    pub eye: Vec3,
    pub width: u32,
    pub height: u32,
    /// Columns u, v, o of the projection matrix.
    pub projection: Mat3,
    /// A thin lens, for depth of field; `None` is the lab's pinhole.
    pub lens: Option<Lens>,
    /// An orthographic camera's parallel rays (then `lens` is None).
    /// Boxed: most cameras have none.
    pub parallel: Option<Box<Parallel>>,
}

/// An orthographic camera: rays along `forward`, each from its image
/// point's place on the plane through the eye facing the view.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Parallel {
    /// The unit view direction.
    pub forward: Vec3,
    /// Where the ray of image point (0, 0), the image's top left, starts.
    pub corner: Vec3,
    /// The step in scene units of one pixel along a row and down a column.
    pub across: Vec3,
    pub down: Vec3,
}

/// A thin lens centred on the eye, facing the view direction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Lens {
    /// The lens' radius (the aperture): 0 would be a pinhole.
    pub radius: f32,
    /// Distance from the eye, along the view direction, of the plane that
    /// is sharp.
    pub focus_distance: f32,
    /// The unit view direction.
    pub forward: Vec3,
}

/// `v` times the power of two that brings its largest component into
/// [1, 2): the same direction, exactly (`v` unchanged when zero or not
/// finite).
fn power_of_two_scaled(v: Vec3) -> Vec3 {
    let largest = v.abs().max_element();
    if largest == 0.0 || !largest.is_finite() {
        return v;
    }
    if !largest.is_normal() {
        // Subnormal: first into the normal range.
        return power_of_two_scaled(v * 2f32.powi(64));
    }
    let exponent = ((largest.to_bits() >> 23) & 0xff) as i32 - 127;
    // In two steps, each factor a normal float (2^-127 alone is not).
    let half = -exponent / 2;
    v * 2f32.powi(half) * 2f32.powi(-exponent - half)
}

impl Camera {
    /// `fov` is the horizontal field of view in degrees. The caller makes
    /// sure `look_at != eye` and `up` is not parallel to the view.
    pub fn new(eye: Vec3, look_at: Vec3, up: Vec3, fov: f32, width: u32, height: u32) -> Self {
        let look = look_at - eye;
        // Any non-zero `up` the file allows (1e19 or 1e-25) works: scaled
        // by a power of two, exactly, to about 1, its cross product neither
        // overflows nor underflows, and the usual ones give the same bits.
        let u = power_of_two_scaled(up).cross(look).normalize();
        let v = u.cross(look).normalize();
        let (w, h) = (width as f32, height as f32);
        let focal = w / (2.0 * (fov.to_radians() / 2.0).tan());
        let o = look.normalize() * focal - (w / 2.0 * u + h / 2.0 * v);
        Camera {
            eye,
            width,
            height,
            projection: Mat3::from_cols(u, v, o),
            lens: None,
            parallel: None,
        }
    }

    /// The same view with world +x on the image's right: the image's u
    /// axis turned round, v (down the image) kept, so nothing is mirrored
    /// compared with other renderers.
    pub fn right_handed(self) -> Camera {
        let [u, v, o] = self.projection.to_cols_array_2d().map(Vec3::from);
        let (w, h) = (self.width as f32, self.height as f32);
        // o is the ray to the image's corner: centre - w/2 u - h/2 v.
        let centre = o + w / 2.0 * u + h / 2.0 * v;
        let u = -u;
        let o = centre - (w / 2.0 * u + h / 2.0 * v);
        Camera {
            projection: Mat3::from_cols(u, v, o),
            ..self
        }
    }

    /// The same camera with a thin lens of `radius` focused at
    /// `focus_distance` (along the view direction); radius 0 keeps the
    /// pinhole.
    pub fn with_lens(self, radius: f32, focus_distance: f32) -> Camera {
        if radius <= 0.0 {
            return Camera { lens: None, ..self };
        }
        let forward = self.view_direction();
        Camera {
            lens: Some(Lens {
                radius,
                focus_distance,
                forward,
            }),
            ..self
        }
    }

    /// The same view as an orthographic camera whose image spans
    /// `view_width` scene units across: parallel rays along the view
    /// direction, from the plane through the eye (no lens).
    pub fn orthographic(self, view_width: f32) -> Camera {
        let [u, v, _] = self.projection.to_cols_array_2d().map(Vec3::from);
        let (w, h) = (self.width as f32, self.height as f32);
        let step = view_width / w;
        let parallel = Parallel {
            forward: self.view_direction(),
            corner: self.eye - (w / 2.0 * step) * u - (h / 2.0 * step) * v,
            across: step * u,
            down: step * v,
        };
        Camera {
            lens: None,
            parallel: Some(Box::new(parallel)),
            ..self
        }
    }

    /// Whether every ray leaves the eye itself (no lens, not
    /// orthographic): the rays `pinhole_rays4` makes.
    pub fn is_pinhole(&self) -> bool {
        self.lens.is_none() && self.parallel.is_none()
    }

    /// The unit direction through the image's centre.
    pub fn view_direction(&self) -> Vec3 {
        let centre = Vec2::new(self.width as f32, self.height as f32) / 2.0;
        (self.projection * centre.extend(1.0)).normalize()
    }

    /// The camera ray of the sample `sampler` has started, through pixel
    /// (i, j): a point of the pixel, then (with a lens) a point of the lens.
    #[inline(always)]
    pub fn sampled_ray(&self, sampler: &mut PixelSampler, (i, j): (u32, u32)) -> Ray {
        let at = Vec2::new(i as f32, j as f32) + sampler.get2();
        let lens = match self.lens {
            Some(_) => concentric_disk(sampler.get2()),
            None => Vec2::ZERO,
        };
        self.lens_ray(at.x, at.y, lens)
    }

    /// The ray through image point (fx, fy) from `lens_point`, a point of
    /// the unit disk: on a thin lens it leaves that point of the lens and
    /// crosses the pinhole ray where it meets the plane in focus; without
    /// a lens it is the pinhole ray; an orthographic camera's ray is
    /// parallel to the view, from the image point's place.
    #[inline(always)]
    pub fn lens_ray(&self, fx: f32, fy: f32, lens_point: Vec2) -> Ray {
        if let Some(p) = &self.parallel {
            return Ray::new(p.corner + fx * p.across + fy * p.down, p.forward);
        }
        let pinhole = self.ray(fx, fy);
        let Some(lens) = &self.lens else {
            return pinhole;
        };
        let focus = pinhole.at(lens.focus_distance / pinhole.dir().dot(lens.forward));
        // u and v are unit vectors across the image: the lens' plane.
        let offset = lens.radius * lens_point;
        let origin =
            self.eye + offset.x * self.projection.x_axis + offset.y * self.projection.y_axis;
        Ray::new(origin, (focus - origin).normalize())
    }

    /// The same camera with every image point moved by `by` pixels: the
    /// ray through (fx, fy) is the one through (fx + by.x, fy + by.y) here
    /// (to rounding). `tracer compare` renders a reference through the
    /// pixels' corners so, to recognise a tracer that aims there.
    pub fn with_pixel_shift(self, by: Vec2) -> Camera {
        let mut projection = self.projection;
        projection.z_axis += by.x * projection.x_axis + by.y * projection.y_axis;
        let parallel = self.parallel.map(|p| {
            Box::new(Parallel {
                corner: p.corner + by.x * p.across + by.y * p.down,
                ..*p
            })
        });
        Camera {
            projection,
            parallel,
            ..self
        }
    }

    /// The ray through image point (fx, fy); a pixel's centre is (i + 0.5, j + 0.5).
    #[inline(always)]
    pub fn ray(&self, fx: f32, fy: f32) -> Ray {
        let dir = self.projection * Vec3::new(fx, fy, 1.0);
        Ray::new(self.eye, dir.normalize())
    }

    /// The pinhole rays through image points (fx[k], fy[k]), four at once
    /// (the lens, if any, left out): each lane does `ray`'s arithmetic in
    /// `ray`'s order, so each ray is `ray`'s, bit for bit.
    #[inline(always)]
    pub fn pinhole_rays4(&self, fx: Vec4, fy: Vec4) -> [Ray; 4] {
        let [x, y, z] = self.pinhole_dirs4(fx, fy);
        std::array::from_fn(|k| Ray::new(self.eye, Vec3::new(x[k], y[k], z[k])))
    }

    /// The unit directions of `pinhole_rays4`, by lane: x, y and z.
    #[inline(always)]
    pub fn pinhole_dirs4(&self, fx: Vec4, fy: Vec4) -> [Vec4; 3] {
        let p = &self.projection;
        // projection * (fx, fy, 1), a row at a time; z times 1 is z.
        let row = |c: usize| {
            Vec4::splat(p.x_axis[c]) * fx + Vec4::splat(p.y_axis[c]) * fy + Vec4::splat(p.z_axis[c])
        };
        let (x, y, z) = (row(0), row(1), row(2));
        // normalize: times 1 / sqrt((x x + y y) + z z).
        let length = Vec4::from_array((x * x + y * y + z * z).to_array().map(f32::sqrt));
        let recip = Vec4::ONE / length;
        [x * recip, y * recip, z * recip]
    }

    /// The primary ray of pixel (column i, row j), through its centre.
    pub fn primary_ray(&self, i: u32, j: u32) -> Ray {
        self.ray(i as f32 + 0.5, j as f32 + 0.5)
    }

    /// `ray` undone: the image coordinates of `offset`, a vector from the
    /// eye, as homogeneous (x, y, w), P^-1 offset: the image point is
    /// (x / w, y / w), in front of the eye when w > 0. A direction gives
    /// its vanishing point. Linear, so that a line can be clipped to the
    /// image before the division (`seen_at`); in f64, so that a point
    /// projects back to its image point to well under a pixel.
    pub fn image_homogeneous(&self, offset: DVec3) -> DVec3 {
        self.projection.as_dmat3().inverse() * offset
    }

    /// The image point where `point` is seen through the pinhole (the eye),
    /// (x from the left, y from the top, in pixels); None behind the eye.
    /// The point `ray(fx, fy)` meets is seen at (fx, fy).
    pub fn seen_at(&self, point: Vec3) -> Option<DVec2> {
        let q = self.image_homogeneous((point - self.eye).as_dvec3());
        (q.z > 0.0).then(|| DVec2::new(q.x / q.z, q.y / q.z))
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

    #[test]
    fn any_up_the_file_allows_gives_the_same_camera() {
        let camera = |up: Vec3| Camera::new(Vec3::new(0.0, 1.0, 4.0), Vec3::Y, up, 60.0, 32, 32);
        let usual = camera(Vec3::Y).projection;
        // Powers of two of any size: the same bits.
        for scale in [2f32.powi(100), 2f32.powi(-100), 2f32.powi(-140)] {
            assert_eq!(camera(Vec3::Y * scale).projection, usual, "{scale:e}");
        }
        // Once overflowing or underflowing: the same camera, to rounding.
        for scale in [1e19, 3e38, 1e-25, 1e-44] {
            let p = camera(Vec3::Y * scale).projection;
            assert!(p.abs_diff_eq(usual, 1e-4), "{scale:e}: {p} against {usual}");
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
            let dir = cam.ray(fx, fy).dir();
            let diff = (dir - Vec3::from(expected)).abs().max_element();
            assert!(diff <= 0.01, "({fx}, {fy}): {dir:?}, expected {expected:?}");
        }
    }

    #[test]
    fn plus_x_is_on_the_left_and_plus_y_up() {
        let cam = lab_camera();
        let top_left = cam.primary_ray(0, 0).dir();
        assert!(top_left.x > 0.0 && top_left.y > 0.0);
    }

    #[test]
    fn a_right_handed_camera_puts_plus_x_on_the_right_and_keeps_the_view() {
        let lab = lab_camera();
        let right = lab_camera().right_handed();
        let top_left = right.primary_ray(0, 0).dir();
        assert!(top_left.x < 0.0 && top_left.y > 0.0, "{top_left}");
        // The same rays, mirrored left to right.
        let mirrored = lab.primary_ray(499, 0).dir();
        assert!((top_left - mirrored).length() < 1e-6);
        let centre = (lab.view_direction() - right.view_direction()).length();
        assert!(centre < 1e-6);
    }

    #[test]
    fn four_pinhole_rays_at_once_are_each_rays_own() {
        // Points over and beyond the image, fractions of all kinds.
        let cam = lab_camera();
        let mut seed = 0x9E37_79B9u32;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            (seed >> 8) as f32 / (1u32 << 24) as f32 * 700.0 - 50.0
        };
        for _ in 0..10_000 {
            let (fx, fy) = (
                Vec4::from_array([(); 4].map(|_| next())),
                Vec4::from_array([(); 4].map(|_| next())),
            );
            let rays = cam.pinhole_rays4(fx, fy);
            for k in 0..4 {
                assert_eq!(rays[k], cam.ray(fx[k], fy[k]), "{} {}", fx[k], fy[k]);
            }
        }
    }

    #[test]
    fn lens_rays_meet_on_the_plane_in_focus() {
        let cam = lab_camera().with_lens(0.5, 4.0);
        let pinhole = cam.ray(100.5, 70.5);
        let focus = pinhole.at(4.0 / pinhole.dir().dot(Vec3::NEG_Z));
        assert!((focus.z - 6.0).abs() < 1e-5, "the plane z = 10 - 4");
        for lens_point in [Vec2::new(1.0, 0.0), Vec2::new(-0.3, 0.8)] {
            let ray = cam.lens_ray(100.5, 70.5, lens_point);
            assert!((ray.origin() - cam.eye).length() <= 0.5 + 1e-6);
            assert!(
                (ray.origin().z - 10.0).abs() < 1e-6,
                "the lens faces the view"
            );
            let t = (6.0 - ray.origin().z) / ray.dir().z;
            assert!((ray.at(t) - focus).length() < 1e-4, "{}", ray.at(t));
        }
        let no_lens = lab_camera().with_lens(0.0, 4.0);
        assert_eq!(no_lens.lens, None);
        assert_eq!(no_lens.lens_ray(3.5, 4.5, Vec2::X), no_lens.ray(3.5, 4.5));
    }

    #[test]
    fn an_orthographic_camera_casts_parallel_rays_across_its_width() {
        let cam = lab_camera().right_handed().orthographic(5.0);
        assert!(!cam.is_pinhole());
        // 500 pixels span 5 units: 0.01 a pixel, +x to the right.
        let left = cam.lens_ray(0.0, 200.0, Vec2::ZERO);
        let right = cam.lens_ray(500.0, 200.0, Vec2::ZERO);
        assert_eq!(left.dir(), Vec3::NEG_Z);
        assert_eq!(right.dir(), Vec3::NEG_Z);
        assert!(
            (left.origin() - Vec3::new(-2.5, 0.0, 10.0)).length() < 1e-5,
            "{}",
            left.origin()
        );
        assert!((right.origin() - Vec3::new(2.5, 0.0, 10.0)).length() < 1e-5);
        let top = cam.lens_ray(250.0, 0.0, Vec2::ZERO);
        assert!(
            (top.origin() - Vec3::new(0.0, 2.0, 10.0)).length() < 1e-5,
            "{}",
            top.origin()
        );
    }

    #[test]
    fn a_pixel_shift_moves_every_ray_by_that_much_of_the_image() {
        let cam = lab_camera();
        let shifted = cam.clone().with_pixel_shift(Vec2::new(-0.5, 0.5));
        for (fx, fy) in [(0.5, 0.5), (250.0, 200.0), (499.5, 399.5), (17.25, 301.0)] {
            let expected = cam.ray(fx - 0.5, fy + 0.5).dir();
            let found = shifted.ray(fx, fy).dir();
            assert!(
                (found - expected).length() < 1e-6,
                "{fx},{fy}: {found} {expected}"
            );
        }
        assert_eq!(cam.clone().with_pixel_shift(Vec2::ZERO), cam);
    }

    #[test]
    fn a_point_a_ray_meets_is_seen_at_the_rays_image_point() {
        let oblique = Camera::new(
            Vec3::new(3.0, 2.0, 9.0),
            Vec3::new(-1.0, 0.5, 0.0),
            Vec3::new(0.2, 1.0, 0.0),
            70.0,
            320,
            200,
        );
        for cam in [lab_camera(), lab_camera().right_handed(), oblique] {
            for (fx, fy) in [(0.5, 0.5), (250.25, 199.75), (319.5, 10.0), (-40.0, 600.0)] {
                for t in [0.5, 7.0, 300.0] {
                    let seen = cam.seen_at(cam.ray(fx, fy).at(t)).unwrap();
                    let off = (seen - DVec2::new(fx.into(), fy.into())).length();
                    assert!(off < 1e-3, "({fx}, {fy}) at t = {t}: seen at {seen}");
                }
            }
            // Behind the eye: not seen.
            let behind = cam.eye - 2.0 * cam.view_direction();
            assert_eq!(cam.seen_at(behind), None);
        }
    }
}
