//! Images of one quantity per pixel instead of the shaded colour ("arbitrary
//! output variables"): the lab's ray-direction images (exercise 6, lab
//! section 2), the surface normal and the depth, for debugging scenes; and
//! the albedo and shading normal of what a pixel sees through mirrors and
//! glass, and the light it gives off, the denoiser's guides (`guide.rs`). The pixel driver (`render`)
//! computes them, sample by sample.

mod guide;

use crate::geometry::SurfaceHit;
use crate::image::{Encoding, Saturation};
use crate::ray::Ray;
use crate::sampling::Rng;
use crate::scene::Scene;
use glam::Vec3;

/// One quantity per pixel.
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
    /// Distance to the nearest hit, bright near, dark far: 1 at the nearest
    /// point of the scene's bounding box, 0.1 at its farthest corner (as seen
    /// from the eye), 0 for no hit. The range is the scene's, not the
    /// image's, so a region of the image gets the greys of the whole.
    Depth,
    /// The albedo (0 to 1) of the first surface the pixel sees that is not
    /// a perfect mirror or smooth glass, seen through those
    /// (`Material::albedo`, times the colours of the mirrors and glass on
    /// the way); where the ray leaves the scene, what it sees there (the
    /// environment or background, clamped to 0..1). The denoiser's albedo.
    Albedo,
    /// `(n + 1) / 2` of the shading normal of that surface, turned toward
    /// the ray (in world space); grey (the zero normal) where the ray
    /// leaves the scene. The denoiser's normal, `2 v - 1`.
    ShadingNormal,
    /// The radiance given off toward the eye by what the pixel sees, as
    /// path mode reads it: the front sides of emitting surfaces, and the
    /// environment or background where the ray leaves the scene, through
    /// perfect mirrors and smooth glass (times their colours; both
    /// branches of glass followed at its first surfaces); not clamped. The part of a path-traced pixel that has no noise but its
    /// edges': the denoiser leaves it out of what it filters.
    Emission,
    /// The part of `Emission` seen through a mirror or glass, not by the
    /// primary ray itself: the denoiser's, which finds the rest in the
    /// render's own camera rays (not in `ALL`).
    ReflectedEmission,
}

impl Aov {
    pub const ALL: [Aov; 8] = [
        Aov::RayDirX,
        Aov::RayDirY,
        Aov::RayDirZ,
        Aov::Normal,
        Aov::Depth,
        Aov::Albedo,
        Aov::ShadingNormal,
        Aov::Emission,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Aov::RayDirX => "ray-dir-x",
            Aov::RayDirY => "ray-dir-y",
            Aov::RayDirZ => "ray-dir-z",
            Aov::Normal => "normal",
            Aov::Depth => "depth",
            Aov::Albedo => "albedo",
            Aov::ShadingNormal => "shading-normal",
            Aov::Emission => "emission",
            Aov::ReflectedEmission => "reflected-emission",
        }
    }

    /// Whether its value depends on the ray's nearest hit.
    pub(crate) fn needs_hit(self) -> bool {
        !matches!(self, Aov::RayDirX | Aov::RayDirY | Aov::RayDirZ)
    }
}

/// AOVs are data: written linearly (gamma 1), each channel clamped.
pub const AOV_ENCODING: Encoding = Encoding {
    gamma: 1.0,
    saturation: Saturation::Clamp,
};

/// What the AOVs of one render share: the depth range of the scene.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AovContext {
    near: f32,
    far: f32,
}

impl AovContext {
    pub(crate) fn new(scene: &Scene) -> AovContext {
        let eye = scene.camera().eye;
        let (near, far) = scene.bounds().map_or((0.0, 0.0), |(lo, hi)| {
            // The nearest point of the box (the eye itself when inside), and
            // the farthest corner.
            let near = (eye.clamp(lo, hi) - eye).length();
            let far_corner = Vec3::select(eye.cmplt((lo + hi) / 2.0), hi, lo);
            (near, (far_corner - eye).length())
        });
        AovContext { near, far }
    }

    /// The AOV's value for one primary ray and its nearest hit (looked
    /// for only when the AOV `needs_hit`) in `scene`; `rng`, the sample's
    /// random numbers, picks the branch of glass the guides follow.
    pub(crate) fn value(
        &self,
        scene: &Scene,
        aov: Aov,
        (ray, hit): (&Ray, Option<&SurfaceHit>),
        rng: &mut Rng,
    ) -> Vec3 {
        match aov {
            Aov::RayDirX => channel(0, ray.dir().x),
            Aov::RayDirY => channel(1, ray.dir().y),
            Aov::RayDirZ => channel(2, ray.dir().z),
            Aov::Normal => hit.map_or(Vec3::ZERO, |hit| (hit.geometric_normal + Vec3::ONE) / 2.0),
            Aov::Depth => hit.map_or(Vec3::ZERO, |hit| {
                Vec3::splat(self.grey(hit.t * ray.dir().length()))
            }),
            Aov::Albedo => guide::seen(scene, ray, hit, rng).albedo,
            Aov::ShadingNormal => (guide::seen(scene, ray, hit, rng).normal + Vec3::ONE) / 2.0,
            Aov::Emission => guide::light(scene, ray, hit, rng),
            Aov::ReflectedEmission => guide::reflected(scene, ray, hit, rng),
        }
    }

    /// The distance from the ray's origin (the eye, or its point on the
    /// lens) to its nearest hit `hit`, in every channel; 0 for no hit.
    pub(crate) fn distance(&self, ray: &Ray, hit: Option<&SurfaceHit>) -> Vec3 {
        hit.map_or(Vec3::ZERO, |hit| Vec3::splat(hit.t * ray.dir().length()))
    }

    /// The depth grey of a hit at `distance` from the eye.
    fn grey(&self, distance: f32) -> f32 {
        let span = self.far - self.near;
        if span > 0.0 {
            (1.0 - 0.9 * (distance - self.near) / span).clamp(0.1, 1.0)
        } else {
            1.0
        }
    }
}

/// `(d + 1) / 2` in channel `axis`, the others 0.
fn channel(axis: usize, d: f32) -> Vec3 {
    let mut rgb = Vec3::ZERO;
    rgb[axis] = (d + 1.0) / 2.0;
    rgb
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::LinearImage;
    use crate::render::{render, Output, Region, RenderJob};
    use scene_format::Format;
    use std::path::Path;

    fn render_aov(scene: &Scene, aov: Aov) -> LinearImage {
        let job = RenderJob::full(scene).with_output(Output::Aov(aov));
        render(scene, &job, &|_| {}).image
    }

    /// The lab's camera (eye (0,0,10), fov 50, 500x400) and one sphere at the
    /// origin, r 1.6.
    fn lab_scene() -> Scene {
        let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
                    [[objects]]\nsphere = { center = [0, 0, 0], radius = 1.6 }\n";
        let file = scene_format::load_str(text, Format::Toml, Path::new("t.toml")).unwrap();
        crate::prepare::prepare(&file).unwrap()
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
    fn depth_greys_follow_the_scenes_box() {
        let d = render_aov(&lab_scene(), Aov::Depth);
        // The sphere's box is [-1.6, 1.6]^3 seen from (0, 0, 10): nearest at
        // 8.4, farthest corner (-1.6, -1.6, -1.6) at sqrt(2 * 1.6^2 + 11.6^2).
        let (near, far) = (8.4f32, (2.0 * 1.6f32 * 1.6 + 11.6 * 11.6).sqrt());
        let grey = |distance: f32| 1.0 - 0.9 * (distance - near) / (far - near);
        // The centre ray meets the sphere's front point, at 8.4: white.
        assert!(
            (d.get(249, 199).x - 1.0).abs() < 1e-3,
            "{}",
            d.get(249, 199)
        );
        assert_eq!(d.get(0, 0), Vec3::ZERO, "a miss is black");
        // Along the middle row the farthest hit nears the silhouette, where
        // the ray grazes the sphere at sqrt(10^2 - 1.6^2) from the eye.
        let row: Vec<f32> = (0..500)
            .map(|i| d.get(i, 199).x)
            .filter(|&g| g > 0.0)
            .collect();
        let darkest = row.iter().copied().fold(1.0, f32::min);
        let silhouette = grey((100.0f32 - 1.6 * 1.6).sqrt());
        assert!(
            darkest >= silhouette - 1e-3 && darkest < silhouette + 0.05,
            "{darkest} vs {silhouette}"
        );
    }

    #[test]
    fn the_distance_output_is_the_distance_to_the_hit_and_0_for_a_miss() {
        let scene = lab_scene();
        let job = RenderJob::full(&scene).with_output(Output::Distance);
        let d = render(&scene, &job, &|_| {}).image;
        // Pixel (249, 199)'s ray is off the axis by (0.5, 0.5) pixels of a
        // focal length 250 / tan(25 deg) = 536.13: it meets the sphere at
        // 10 cos - sqrt(100 cos^2 - (100 - 1.6^2)) = 8.40000... (cos ~ 1).
        let f = 250.0 / 25f32.to_radians().tan();
        let cos = f / (0.5f32 + f * f).sqrt();
        let expected = 10.0 * cos - (100.0 * cos * cos - (100.0 - 1.6 * 1.6)).sqrt();
        assert_near(d.get(249, 199), [expected; 3], 1e-4);
        assert_eq!(d.get(0, 0), Vec3::ZERO);
    }

    fn scene_of(text: &str) -> Scene {
        let file = scene_format::load_str(text, Format::Toml, Path::new("t.toml")).unwrap();
        crate::prepare::prepare(&file).unwrap()
    }

    /// The lab's camera looking down -z at a sphere of `material`, r 1.6.
    fn sphere_of(material: &str) -> Scene {
        scene_of(&format!(
            "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
             [[objects]]\nsphere = {{ center = [0, 0, 0], radius = 1.6 }}\nmaterial = {material}\n"
        ))
    }

    #[test]
    fn a_lambertian_spheres_albedo_is_its_diffuse_and_a_miss_the_background() {
        let scene = sphere_of("{ diffuse = [0.2, 0.5, 0.7], specular = [0, 0, 0] }");
        let albedo = render_aov(&scene, Aov::Albedo);
        assert_eq!(albedo.get(249, 199), Vec3::new(0.2, 0.5, 0.7));
        assert_eq!(albedo.get(260, 210), Vec3::new(0.2, 0.5, 0.7));
        assert_eq!(albedo.get(0, 0), Vec3::ZERO, "the black background");
        let principled = sphere_of("{ base_color = [0.9, 0.3, 0.1], roughness = 0.5 }");
        let albedo = render_aov(&principled, Aov::Albedo);
        assert_near(albedo.get(249, 199), [0.9, 0.3, 0.1], 1e-6);
    }

    /// A mirror plane at z = 0 facing the eye at z = 10, and behind the
    /// eye a diffuse wall at z = 20 facing the mirror: the mirror shows it.
    fn mirror_before_a_wall(mirror: &str) -> Scene {
        scene_of(&format!(
            "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
             [[objects]]\nplane = {{ point = [0, 0, 0], normal = [0, 0, 1] }}\nmaterial = {mirror}\n\
             [[objects]]\nplane = {{ point = [0, 0, 20], normal = [0, 0, -1] }}\n\
             material = {{ diffuse = [0.1, 0.6, 0.3], specular = [0, 0, 0] }}\n"
        ))
    }

    #[test]
    fn a_mirrors_albedo_and_normal_are_those_of_what_it_shows() {
        let scene =
            mirror_before_a_wall("{ diffuse = [0, 0, 0], specular = [0, 0, 0], reflectance = 1 }");
        let albedo = render_aov(&scene, Aov::Albedo);
        assert_near(albedo.get(249, 199), [0.1, 0.6, 0.3], 1e-6);
        assert_near(albedo.get(10, 20), [0.1, 0.6, 0.3], 1e-6);
        // The wall faces the mirror: the ray comes back along +z and meets
        // it head on, its normal (0, 0, -1) toward the ray.
        let normal = render_aov(&scene, Aov::ShadingNormal);
        assert_near(normal.get(249, 199), [0.5, 0.5, 0.0], 1e-3);
        // A smooth metal tints what it shows with its base colour.
        let gold =
            mirror_before_a_wall("{ base_color = [1, 0.5, 0.25], metallic = 1, roughness = 0 }");
        let albedo = render_aov(&gold, Aov::Albedo);
        assert_near(albedo.get(249, 199), [0.1, 0.3, 0.075], 1e-6);
        // A mirror that is also diffuse is a surface of its own.
        let half = mirror_before_a_wall(
            "{ diffuse = [0.5, 0.5, 0.5], specular = [0, 0, 0], reflectance = 0.5 }",
        );
        let albedo = render_aov(&half, Aov::Albedo);
        assert_near(albedo.get(249, 199), [0.5, 0.5, 0.5], 1e-6);
    }

    #[test]
    fn a_spheres_shading_normal_is_the_analytic_normal_where_each_pixel_ray_meets_it() {
        let scene = sphere_of("{ diffuse = [0.5, 0.5, 0.5] }");
        let normals = render_aov(&scene, Aov::ShadingNormal);
        let camera = scene.camera();
        let mut checked = 0;
        for (i, j) in [
            (249, 199),
            (200, 150),
            (300, 260),
            (180, 199),
            (249, 120),
            (300, 150),
        ] {
            // The one sample a pixel is the ray through its centre.
            let ray = camera.lens_ray(i as f32 + 0.5, j as f32 + 0.5, glam::Vec2::ZERO);
            let (o, d) = (ray.origin(), ray.dir().normalize());
            // |o + t d| = 1.6, the nearer root.
            let b = o.dot(d);
            let disc = b * b - (o.length_squared() - 1.6 * 1.6);
            assert!(disc > 0.0, "pixel ({i}, {j}) sees the sphere");
            let n = (o + (-b - disc.sqrt()) * d) / 1.6;
            let got = normals.get(i, j) * 2.0 - Vec3::ONE;
            assert!((got - n).length() < 1e-3, "({i}, {j}): {got} vs {n}");
            checked += 1;
        }
        assert_eq!(checked, 6);
        assert_eq!(
            normals.get(0, 0),
            Vec3::splat(0.5),
            "a miss: the zero normal"
        );
    }

    #[test]
    fn smooth_glass_shows_what_is_behind_it_weighted_by_fresnel() {
        // A thin slab of glass seen head on, a green wall behind it: of
        // the light through the two faces, 4 % is reflected at each (n =
        // 1.5), and what is reflected sees the black sky; the samples pick
        // a branch each, so the mean is near 0.96^2 of the wall's albedo.
        let scene = scene_of(
            "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
             [render]\nsamples = 64\n\
             [[objects]]\nbox = { min = [-50, -50, -0.5], max = [50, 50, 0.5] }\n\
             material = { transmission = 1, roughness = 0, base_color = [1, 1, 1] }\n\
             [[objects]]\nplane = { point = [0, 0, -5], normal = [0, 0, 1] }\n\
             material = { diffuse = [0, 1, 0], specular = [0, 0, 0] }\n",
        );
        let job = RenderJob {
            region: Region {
                x0: 200,
                y0: 150,
                x1: 300,
                y1: 250,
            },
            samples: 64,
            output: Output::Aov(Aov::Albedo),
        };
        let image = render(&scene, &job, &|_| {}).image;
        let mean = image.pixels.iter().map(|c| c.y).sum::<f32>() / image.pixels.len() as f32;
        let expected = 0.96f32 * 0.96;
        // 640,000 samples of a 0/1 choice of p ~ 0.08: sigma ~ 3e-4.
        assert!((mean - expected).abs() < 0.003, "{mean} vs {expected}");
        assert!(image.pixels.iter().all(|c| c.x == 0.0 && c.z == 0.0));
    }

    #[test]
    fn the_light_seen_through_glass_follows_both_branches_without_noise() {
        // The slab of glass before an emitting wall: through both faces
        // T^2 = 0.96^2 of the wall's light (R = 4 % reflected at each, n =
        // 1.5), and R^2 of that again for each pair of reflections inside,
        // T^2 / (1 - R^2) in all: the same in every pixel and sample but
        // for the fourth surface on (picked at random; picked from the
        // first, a sample would give 0 or the light over its chance).
        let scene = scene_of(
            "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
             [[objects]]\nbox = { min = [-50, -50, -0.5], max = [50, 50, 0.5] }\n\
             material = { transmission = 1, roughness = 0, base_color = [1, 1, 1] }\n\
             [[objects]]\nquad = { corner = [-50, -50, -5], edge_u = [100, 0, 0], edge_v = [0, 100, 0] }\n\
             material = { diffuse = [0, 0, 0], emission = [2, 2, 2] }\n",
        );
        let job = |aov| RenderJob {
            region: Region {
                x0: 200,
                y0: 150,
                x1: 300,
                y1: 250,
            },
            samples: 4,
            output: Output::Aov(aov),
        };
        let reflected = render(&scene, &job(Aov::ReflectedEmission), &|_| {}).image;
        // Head on; the pixels' rays meet the slab up to about 8 degrees
        // off, where R grows by a few thousandths.
        let expected = 2.0 * 0.96 * 0.96 / (1.0 - 0.04 * 0.04);
        for &c in &reflected.pixels {
            assert_near(c, [expected; 3], 3e-3);
        }
        // Nothing is seen directly: the whole emission is what glass shows.
        let emission = render(&scene, &job(Aov::Emission), &|_| {}).image;
        assert_eq!(emission.pixels, reflected.pixels);
    }

    #[test]
    fn the_emission_is_the_light_given_off_by_what_a_pixel_sees() {
        // An emitting sphere before a coloured background: its emission
        // where it is seen, the background where the ray leaves.
        let scene = scene_of(
            "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
             [render]\nbackground = [0.1, 0.2, 3]\n\
             [[objects]]\nsphere = { center = [0, 0, 0], radius = 1.6 }\n\
             material = { diffuse = [0.5, 0.5, 0.5], emission = [2, 1, 0.5] }\n",
        );
        let light = render_aov(&scene, Aov::Emission);
        assert_eq!(light.get(249, 199), Vec3::new(2.0, 1.0, 0.5));
        assert_eq!(light.get(0, 0), Vec3::new(0.1, 0.2, 3.0), "not clamped");
        // A mirror shows the emitting wall behind the eye, which faces it
        // (its edges' cross product); seen from behind, a wall gives off
        // nothing.
        let wall = |edges: &str| {
            scene_of(&format!(
                "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
                 [[objects]]\nplane = {{ point = [0, 0, 0], normal = [0, 0, 1] }}\n\
                 material = {{ reflectance = 0.5 }}\n\
                 [[objects]]\nquad = {{ corner = [-50, -50, 20], {edges} }}\n\
                 material = {{ diffuse = [0.5, 0.5, 0.5], emission = [4, 2, 1] }}\n"
            ))
        };
        let facing = render_aov(
            &wall("edge_u = [0, 100, 0], edge_v = [100, 0, 0]"),
            Aov::Emission,
        );
        assert_near(facing.get(249, 199), [2.0, 1.0, 0.5], 1e-6);
        let away = render_aov(
            &wall("edge_u = [100, 0, 0], edge_v = [0, 100, 0]"),
            Aov::Emission,
        );
        assert_eq!(away.get(249, 199), Vec3::ZERO);
    }

    #[test]
    fn light_through_absorbing_glass_loses_what_path_mode_loses() {
        // A slab of glass one unit thick that bends and reflects nothing
        // (ior 1, transmittance 1), absorbing 0.5 a unit of red, before an
        // emitting wall: Beer-Lambert's exp(-0.5) in red. The albedo
        // seen through it keeps the wall's colours.
        let scene = scene_of(
            "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
             [[objects]]\nbox = { min = [-50, -50, -0.5], max = [50, 50, 0.5] }\n\
             material = { transmittance = 1, ior = 1, absorption = [0.5, 0, 0] }\n\
             [[objects]]\nquad = { corner = [-50, -50, -5], edge_u = [100, 0, 0], edge_v = [0, 100, 0] }\n\
             material = { diffuse = [0.25, 0.5, 0.75], emission = [2, 2, 2] }\n",
        );
        let light = render_aov(&scene, Aov::Emission);
        assert_near(light.get(249, 199), [2.0 * (-0.5f32).exp(), 2.0, 2.0], 1e-4);
        let albedo = render_aov(&scene, Aov::Albedo);
        assert_near(albedo.get(249, 199), [0.25, 0.5, 0.75], 1e-6);
    }

    #[test]
    fn a_regions_depth_is_the_same_as_the_whole_images() {
        let scene = lab_scene();
        let whole = render_aov(&scene, Aov::Depth);
        let region = Region {
            x0: 240,
            y0: 150,
            x1: 330,
            y1: 210,
        };
        let job = RenderJob {
            region,
            samples: 1,
            output: Output::Aov(Aov::Depth),
        };
        let part = render(&scene, &job, &|_| {}).image;
        assert_eq!((part.width, part.height), (90, 60));
        for j in 0..60 {
            for i in 0..90 {
                assert_eq!(part.get(i, j), whole.get(240 + i, 150 + j), "({i}, {j})");
            }
        }
    }
}
