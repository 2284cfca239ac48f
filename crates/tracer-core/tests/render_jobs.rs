//! The pixel driver's jobs: regions, samples per pixel, AOVs, each checked
//! against geometry worked out by hand or against the whole image.

mod common;

use common::{load, on_threads, scenes_dir};
use glam::Vec3;
use scene_format::Format;
use std::path::Path;
use tracer_core::{prepare, render, LinearImage, Output, Region, RenderJob, Scene};

fn scene_from(text: &str) -> Scene {
    let file = scene_format::load_str(text, Format::Toml, Path::new("t.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    prepare(&file).expect("prepare")
}

fn render_job(scene: &Scene, job: &RenderJob) -> LinearImage {
    render(scene, job, &|_| {}).image
}

/// The lab's camera and a flat triangle in the plane z = 0 whose left edge
/// (world +x is on the image's left) is the line x = `edge`; ambient 0.8
/// under one white light, so a hit is 0.8 and a miss 0.
fn half_plane_scene(edge: f32) -> Scene {
    scene_from(&format!(
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
         [render]\ngamma = 1\n\
         [[lights]]\nposition = [0, 0, 20]\n\
         [[objects]]\ntriangle = [[{edge}, -50, 0], [{edge}, 50, 0], [{x}, 0, 0]]\n\
         material = {{ ambient = [0.8, 0.8, 0.8] }}\n",
        x = edge + 100.0
    ))
}

#[test]
fn sixteen_samples_see_an_edge_through_the_pixel_centre_as_half_covered() {
    // Where the ray through the centre line of column 249 (fx = 249.5)
    // meets z = 0: every point of the pixel left of it lies at larger x.
    let probe = half_plane_scene(0.0);
    let dir = probe.camera().ray(249.5, 200.5).dir();
    let edge = dir.x * 10.0 / -dir.z;
    let scene = half_plane_scene(edge);
    let job = RenderJob {
        samples: 16,
        ..RenderJob::full(&scene)
    };
    let image = render_job(&scene, &job);
    // 4 x 4 strata: the two left columns of strata hit, the two right miss.
    assert!(
        (image.get(249, 200).x - 0.4).abs() < 1e-6,
        "{}",
        image.get(249, 200)
    );
    assert!(
        (image.get(248, 200).x - 0.8).abs() < 1e-6,
        "{}",
        image.get(248, 200)
    );
    assert_eq!(image.get(250, 200), Vec3::ZERO);
    // One sample per pixel, the lab's ray through the centre: all or nothing.
    let lab = render_job(&scene, &RenderJob::full(&scene));
    assert_eq!((lab.get(248, 200).x, lab.get(250, 200).x), (0.8, 0.0));
}

#[test]
fn samples_give_the_same_image_on_any_number_of_threads() {
    let scene = prepare(&load(&scenes_dir().join("reflectance2.toml"))).unwrap();
    let job = RenderJob {
        samples: 4,
        ..RenderJob::full(&scene)
    };
    let on = |threads| on_threads(threads, || render_job(&scene, &job));
    let one = on(1);
    assert!(one == on(2) && one == on(3));
    // Anti-aliased, not the one-sample image.
    assert!(one != render_job(&scene, &RenderJob::full(&scene)));
}

#[test]
fn a_region_holds_exactly_those_pixels_of_the_whole_image() {
    let scene = prepare(&load(&scenes_dir().join("reflectance2.toml"))).unwrap();
    let whole = render_job(&scene, &RenderJob::full(&scene));
    for output in [Output::Shading, Output::Aov(tracer_core::aov::Aov::Normal)] {
        let whole = render_job(&scene, &RenderJob::full(&scene).with_output(output));
        let region = Region {
            x0: 123,
            y0: 57,
            x1: 411,
            y1: 300,
        };
        let job = RenderJob {
            region,
            ..RenderJob::full(&scene).with_output(output)
        };
        let rows = std::sync::atomic::AtomicU32::new(0);
        let part = render(&scene, &job, &|n| {
            rows.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
        })
        .image;
        assert_eq!(rows.into_inner(), 243, "progress counts the region's rows");
        assert_eq!((part.width, part.height), (288, 243));
        for j in 0..part.height {
            for i in 0..part.width {
                assert_eq!(part.get(i, j), whole.get(123 + i, 57 + j), "{output:?}");
            }
        }
    }
    let empty = Region {
        x0: 5,
        y0: 5,
        x1: 5,
        y1: 9,
    };
    let job = RenderJob {
        region: empty,
        ..RenderJob::full(&scene)
    };
    assert!(render_job(&scene, &job).pixels.is_empty());
    // A region reaching past the image keeps only the image's pixels.
    let past = Region {
        x0: 490,
        y0: 390,
        x1: 600,
        y1: 450,
    };
    let job = RenderJob {
        region: past,
        ..RenderJob::full(&scene)
    };
    let edge = render_job(&scene, &job);
    assert_eq!((edge.width, edge.height), (10, 10));
    assert_eq!(edge.get(9, 9), whole.get(499, 399));
    assert!(whole.pixels.iter().any(|p| p.max_element() > 0.0));
}

#[test]
fn hits_know_the_side_they_met() {
    // A triangle in z = 0 with normal +z (counter-clockwise seen from +z),
    // and a sphere.
    let scene = scene_from(
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
         [[objects]]\ntriangle = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n\
         [[objects]]\nsphere = { center = [5, 5, 0], radius = 1 }\n",
    );
    let at = |origin: Vec3, target: Vec3| {
        let ray = tracer_core::Ray::new(origin, target - origin);
        scene.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit")
    };
    let front = at(Vec3::new(0.2, 0.2, 5.0), Vec3::new(0.2, 0.2, 0.0));
    assert!(front.front_face);
    assert_eq!(front.geometric_normal, Vec3::Z);
    let back = at(Vec3::new(0.2, 0.2, -5.0), Vec3::new(0.2, 0.2, 0.0));
    assert!(!back.front_face);
    assert_eq!(
        back.geometric_normal,
        Vec3::Z,
        "the lab's normal is never flipped"
    );
    // Barycentrics: (0.2, 0.2) = v0 + 0.2 (v1 - v0) + 0.2 (v2 - v0).
    assert!((front.uv - glam::Vec2::new(0.2, 0.2)).length() < 1e-6);
    let outside = at(Vec3::new(5.0, 5.0, 5.0), Vec3::new(5.0, 5.0, 0.0));
    // t is in units of the direction (0, 0, -5): the hit at z = 1 is at 4 / 5.
    assert!(outside.front_face && (outside.t - 0.8).abs() < 1e-5);
    let inside = at(Vec3::new(5.0, 5.0, 0.0), Vec3::new(5.0, 5.0, 3.0));
    assert!(!inside.front_face && (inside.t - 1.0 / 3.0).abs() < 1e-5);
}

#[test]
fn the_sample_rays_are_the_rays_a_render_traces() {
    // The distance output of each pixel is the mean of its samples' nearest
    // hit distances: worked out here from `sample_rays`, one ray at a time,
    // through a lens (origins off the eye) and through a pinhole at 1 and 16.
    let mut lens = load(&scenes_dir().join("depth-of-field.toml"));
    (lens.camera.width, lens.camera.height) = (24, 16);
    let mut pinhole = load(&scenes_dir().join("bench/bunny.toml"));
    (pinhole.camera.width, pinhole.camera.height) = (24, 14);
    let cases = [(lens.clone(), 4), (pinhole.clone(), 16), (pinhole, 1)];
    for (k, (file, samples)) in cases.into_iter().enumerate() {
        let scene = prepare(&file).expect("prepare");
        let job = RenderJob::full(&scene)
            .with_samples(samples)
            .with_output(Output::Distance);
        let mut distances = Vec::new();
        tracer_core::sample_rays(&scene, &job, |ray| {
            let hit = scene.closest_hit(ray, tracer_core::EPSILON, f32::INFINITY);
            distances.push(hit.map_or(0.0, |h| h.t * ray.dir().length()));
        });
        let expected: Vec<Vec3> = distances
            .chunks(samples as usize)
            .map(|d| d.iter().fold(Vec3::ZERO, |sum, &d| sum + Vec3::splat(d)) / samples as f32)
            .collect();
        let image = render_job(&scene, &job);
        assert_eq!(image.pixels.len(), expected.len(), "case {k}");
        assert!(
            image.pixels == expected,
            "case {k}: other rays than the render's"
        );
        // Hits were compared (and, on the bunny, misses).
        assert!(distances.iter().any(|&d| d > 0.0), "case {k}");
    }
}

#[test]
fn a_render_into_an_image_already_used_writes_every_pixel_anew() {
    let scene = prepare(&load(&scenes_dir().join("reflectance2.toml"))).unwrap();
    let whole = render_job(&scene, &RenderJob::full(&scene));
    let never = std::sync::atomic::AtomicBool::new(false);
    let render_into = |job: &RenderJob, image: &mut LinearImage| {
        tracer_core::render_into(&scene, job, &|_| {}, &never, image).expect("not cancelled")
    };
    // Held another size and other values: a region, then the whole image,
    // then a region again (smaller than what the memory held).
    let mut image = LinearImage::new(7, 3);
    image.pixels.fill(Vec3::splat(f32::NAN));
    let region = Region {
        x0: 100,
        y0: 50,
        x1: 160,
        y1: 90,
    };
    let part = RenderJob {
        region,
        ..RenderJob::full(&scene)
    };
    for job in [&part, &RenderJob::full(&scene), &part] {
        let rays = render_into(job, &mut image);
        assert_eq!(rays, render(&scene, job, &|_| {}).rays);
        let (w, h) = (image.width, image.height);
        assert_eq!(image.pixels.len(), (w * h) as usize);
        let bits = |c: Vec3| c.to_array().map(f32::to_bits);
        for j in 0..h {
            for i in 0..w {
                let expected = whole.get(job.region.x0 + i, job.region.y0 + j);
                assert_eq!(bits(image.get(i, j)), bits(expected), "pixel ({i}, {j})");
            }
        }
    }
    assert_eq!((image.width, image.height), (60, 40));
}

#[test]
fn with_path_reuse_a_region_and_any_threads_give_the_whole_image_s_pixels() {
    // Groups of 5 pixels are fixed in the image (columns 0-4, 5-9, ...): a
    // region that cuts them traces them whole, so its pixels are the whole
    // image's, whatever the threads (3 camera rays a path where a pixel
    // shows the lamp's edge, too). The Cornell box is traced in lanes,
    // the same box with a sphere in it one path at a time.
    let text = std::fs::read_to_string(scenes_dir().join("cornell-box.toml")).unwrap();
    let sphere = "[materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n[[objects]]\n\
                  sphere = { center = [0.3, 0.5, 0.2], radius = 0.25 }\nmaterial = \"m\"\n";
    let small = |text: &str| {
        let mut file = scene_format::load_str(text, Format::Toml, Path::new("box.toml")).unwrap();
        file.render.path_reuse = Some(5);
        file.render.camera_rays = Some(3);
        file.render.samples = 4;
        (file.camera.width, file.camera.height) = (64, 48);
        file
    };
    let (boxes, with_sphere) = (small(&text), small(&format!("{text}\n{sphere}")));
    for file in [boxes, with_sphere] {
        let scene = prepare(&file).unwrap();
        let on = |threads, job: &RenderJob| on_threads(threads, || render_job(&scene, job));
        let whole = on(1, &RenderJob::full(&scene));
        assert!(whole == on(2, &RenderJob::full(&scene)));
        let region = Region {
            x0: 7,
            y0: 3,
            x1: 23,
            y1: 11,
        };
        let job = RenderJob {
            region,
            ..RenderJob::full(&scene)
        };
        let part = on(2, &job);
        for j in 0..part.height {
            for i in 0..part.width {
                assert_eq!(part.get(i, j), whole.get(i + 7, j + 3), "({i}, {j})");
            }
        }
        // The pixels are not those of paths alone: sharing is on.
        let alone = prepare(&scene_format::SceneFile {
            render: scene_format::RenderSettings {
                path_reuse: Some(1),
                ..file.render.clone()
            },
            ..file.clone()
        })
        .unwrap();
        assert!(whole != render_job(&alone, &RenderJob::full(&alone)));
    }
}
