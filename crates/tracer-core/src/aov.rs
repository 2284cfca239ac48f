//! Images of one quantity per pixel instead of the shaded colour ("arbitrary
//! output variables"): the lab's ray-direction images (exercise 6, lab
//! section 2), the surface normal and the depth, for debugging scenes.

use crate::image::{Encoding, LinearImage, Saturation};
use crate::scene::Scene;
use crate::EPSILON;
use glam::Vec3;
use rayon::prelude::*;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Aov {
    /// `(dir.x + 1) / 2` of the primary ray in red, the lab's gradient-OX.png.
    RayDirX,
    /// `(dir.y + 1) / 2` in green, gradient-OY.png.
    RayDirY,
    /// `(dir.z + 1) / 2` in blue, gradient-OZ.png.
    RayDirZ,
    /// `(n + 1) / 2` of the lab's (unflipped) unit normal at the nearest hit;
    /// black where the ray hits nothing.
    Normal,
    /// Distance to the nearest hit, bright near, dark far: the nearest hit in
    /// the image is 1, the farthest 0.1, no hit 0.
    Depth,
}

impl Aov {
    pub const ALL: [Aov; 5] = [
        Aov::RayDirX,
        Aov::RayDirY,
        Aov::RayDirZ,
        Aov::Normal,
        Aov::Depth,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Aov::RayDirX => "ray-dir-x",
            Aov::RayDirY => "ray-dir-y",
            Aov::RayDirZ => "ray-dir-z",
            Aov::Normal => "normal",
            Aov::Depth => "depth",
        }
    }
}

/// AOVs are data: written linearly (gamma 1), each channel clamped.
pub const AOV_ENCODING: Encoding = Encoding {
    gamma: 1.0,
    saturation: Saturation::Clamp,
};

/// The image of `aov` for the scene's camera, one primary ray per pixel centre.
pub fn render_aov(scene: &Scene, aov: Aov) -> LinearImage {
    match aov {
        Aov::RayDirX => ray_dir(scene, 0),
        Aov::RayDirY => ray_dir(scene, 1),
        Aov::RayDirZ => ray_dir(scene, 2),
        Aov::Normal => per_pixel(scene, |i, j| {
            let ray = scene.camera.primary_ray(i, j);
            scene
                .closest_hit(&ray, EPSILON, f32::INFINITY)
                .map_or(Vec3::ZERO, |hit| (hit.normal + Vec3::ONE) / 2.0)
        }),
        Aov::Depth => depth(scene),
    }
}

/// Component `axis` of each primary direction, `(d + 1) / 2`, in channel `axis`.
fn ray_dir(scene: &Scene, axis: usize) -> LinearImage {
    per_pixel(scene, |i, j| {
        let d = scene.camera.primary_ray(i, j).dir;
        let mut rgb = Vec3::ZERO;
        rgb[axis] = (d[axis] + 1.0) / 2.0;
        rgb
    })
}

fn depth(scene: &Scene) -> LinearImage {
    // First the distances (infinite for a miss), then the grey levels.
    let distances = per_pixel(scene, |i, j| {
        let ray = scene.camera.primary_ray(i, j);
        let t = scene
            .closest_hit(&ray, EPSILON, f32::INFINITY)
            .map_or(f32::INFINITY, |h| h.t);
        Vec3::splat(t)
    });
    let hits = distances
        .pixels
        .iter()
        .map(|p| p.x)
        .filter(|t| t.is_finite());
    let (near, far) = hits.fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), t| {
        (lo.min(t), hi.max(t))
    });
    let span = far - near;
    let grey = |t: f32| {
        if !t.is_finite() {
            0.0
        } else if span > 0.0 {
            1.0 - 0.9 * (t - near) / span
        } else {
            1.0
        }
    };
    LinearImage {
        pixels: distances
            .pixels
            .iter()
            .map(|p| Vec3::splat(grey(p.x)))
            .collect(),
        ..distances
    }
}

/// An image whose pixel (i, j) is `f(i, j)`, rows in parallel.
fn per_pixel(scene: &Scene, f: impl Fn(u32, u32) -> Vec3 + Sync) -> LinearImage {
    let (width, height) = (scene.camera.width, scene.camera.height);
    let mut image = LinearImage::new(width, height);
    image
        .pixels
        .par_chunks_mut(width as usize)
        .enumerate()
        .for_each(|(j, row)| {
            for (i, pixel) in row.iter_mut().enumerate() {
                *pixel = f(i as u32, j as u32);
            }
        });
    image
}

#[cfg(test)]
mod tests {
    use super::*;
    use scene_format::Format;
    use std::path::Path;

    /// The lab's camera (eye (0,0,10), fov 50, 500x400) and one sphere at the
    /// origin, r 1.6.
    fn lab_scene() -> Scene {
        let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
                    [[objects]]\nsphere = { center = [0, 0, 0], radius = 1.6 }\n";
        let file = scene_format::load_str(text, Format::Toml, Path::new("t.toml")).unwrap();
        Scene::prepare(&file).unwrap()
    }

    fn assert_near(got: Vec3, expected: [f32; 3], tolerance: f32) {
        let diff = (got - Vec3::from(expected)).abs().max_element();
        assert!(diff <= tolerance, "{got:?}, expected {expected:?}");
    }

    #[test]
    fn ray_direction_images_hold_the_labs_primary_directions() {
        let scene = lab_scene();
        let x = render_aov(&scene, Aov::RayDirX);
        let y = render_aov(&scene, Aov::RayDirY);
        let z = render_aov(&scene, Aov::RayDirZ);
        // The lab's table: pixel -> dir; the image holds (d + 1) / 2, 0.005
        // being the lab's two printed decimals halved.
        let checks = [
            ((0, 0), [0.40, 0.32, -0.86]),
            ((249, 0), [0.0, 0.35, -0.94]),
            ((0, 199), [0.42, 0.0, -0.91]),
            ((499, 399), [-0.40, -0.32, -0.86]),
            ((249, 199), [0.0, 0.0, -1.0]),
        ];
        for ((i, j), d) in checks {
            let g = |c: f32| (c + 1.0) / 2.0;
            assert_near(x.get(i, j), [g(d[0]), 0.0, 0.0], 0.006);
            assert_near(y.get(i, j), [0.0, g(d[1]), 0.0], 0.006);
            assert_near(z.get(i, j), [0.0, 0.0, g(d[2])], 0.006);
        }
    }

    #[test]
    fn ray_dir_x_encodes_to_the_expected_bytes() {
        let image = render_aov(&lab_scene(), Aov::RayDirX).encode(&AOV_ENCODING);
        // Worked out from P: the top-left direction is (249.5, 199.5, -536.127),
        // x = 249.5 / 624.086 = 0.39979; (0.39979 + 1) / 2 * 255 = 178.47 -> 178.
        assert_eq!(image.get_pixel(0, 0).0, [178, 0, 0]);
        // Pixel (249, 199): (0.5, 0.5, -536.127), x = 0.000933;
        // (1.000933) / 2 * 255 = 127.62 -> 127.
        assert_eq!(image.get_pixel(249, 199).0, [127, 0, 0]);
    }

    #[test]
    fn the_normal_faces_the_camera_at_the_centre_and_misses_are_black() {
        let scene = lab_scene();
        let n = render_aov(&scene, Aov::Normal);
        // The centre ray meets the sphere at about (0, 0, 1.6): n = (0, 0, 1).
        assert_near(n.get(249, 199), [0.5, 0.5, 1.0], 0.01);
        assert_eq!(n.get(0, 0), Vec3::ZERO);
    }

    #[test]
    fn depth_is_brightest_nearest_and_black_for_misses() {
        let d = render_aov(&lab_scene(), Aov::Depth);
        let max = d.pixels.iter().map(|p| p.x).fold(0.0, f32::max);
        assert_eq!(max, 1.0);
        // The centre pixel is among the nearest: the sphere's front point.
        assert!(d.get(249, 199).x > 0.99);
        assert_eq!(d.get(0, 0), Vec3::ZERO);
        // The silhouette is farther than the centre.
        let edge = (0..250).find(|&i| d.get(i, 199).x > 0.0).unwrap();
        assert!(d.get(edge, 199).x < d.get(249, 199).x);
    }
}
