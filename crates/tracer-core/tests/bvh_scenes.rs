//! The BVH and the threads change how fast an image is made, never the
//! image: checked against the brute-force loop and across thread counts.

mod common;

use common::{load, scenes_dir, LAB_SCENES};
use tracer_core::accel::brute_force;
use tracer_core::{prepare, render, LinearImage, RenderJob, Scene};

fn render_image(scene: &Scene) -> LinearImage {
    render(scene, &RenderJob::full(scene), &|_| {}).image
}

/// The bunny benchmark scene, made small enough for brute force.
fn small_bunny() -> Scene {
    let mut file = load(&scenes_dir().join("bench/bunny.toml"));
    (file.camera.width, file.camera.height) = (96, 54);
    prepare(&file).expect("prepare")
}

fn in_pool(threads: usize, scene: &Scene) -> LinearImage {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(|| render_image(scene))
}

#[test]
fn lab_scenes_are_identical_with_and_without_the_bvh() {
    for name in LAB_SCENES {
        let file = load(&scenes_dir().join(format!("{name}.toml")));
        let scene = prepare(&file).expect("prepare");
        assert!(scene.has_bvh());
        let fast = render_image(&scene);
        let slow = render_image(&scene.brute_force());
        assert!(fast == slow, "{name}: the BVH changed the image");
    }
}

#[test]
fn boxes_planes_and_quads_are_identical_with_and_without_the_bvh() {
    // The floor plane is tested beside the tree; glass sends rays through
    // the boxes' insides, so back faces and ties at edges are compared too.
    let mut file = load(&scenes_dir().join("boxes.toml"));
    (file.camera.width, file.camera.height) = (160, 100);
    let scene = prepare(&file).expect("prepare");
    let fast = render_image(&scene);
    let slow = render_image(&scene.brute_force());
    assert!(fast == slow, "the BVH changed the image");
}

#[test]
fn samples_searched_together_find_the_brute_force_image() {
    // At 16 samples a pixel's primary rays are searched as one packet
    // (`Bvh::closest_hits`); brute force takes each on its own. Boxes,
    // planes, quads and glass; and the bunny's silhouette, where a
    // packet's rays part between mesh and sky.
    let mut boxes = load(&scenes_dir().join("boxes.toml"));
    (boxes.camera.width, boxes.camera.height) = (64, 40);
    let mut bunny = load(&scenes_dir().join("bench/bunny.toml"));
    (bunny.camera.width, bunny.camera.height) = (32, 18);
    for (name, file) in [("boxes", boxes), ("bunny", bunny)] {
        let scene = prepare(&file).expect("prepare");
        let job = RenderJob::full(&scene).with_samples(16);
        let fast = render(&scene, &job, &|_| {}).image;
        let slow = render(&scene.brute_force(), &job, &|_| {}).image;
        assert!(fast == slow, "{name}: the packets changed the image");
    }
}

#[test]
fn shadow_rays_searched_ahead_find_the_brute_force_image() {
    // Six lights, a sphere light among them and more point lights than are
    // searched ahead (four), some behind the bunny: each sample's shading
    // takes the answers found ahead only for the very questions it asks.
    let mut file = load(&scenes_dir().join("bench/bunny.toml"));
    (file.camera.width, file.camera.height) = (24, 14);
    let light = file.lights[0].clone();
    let at = |position: [f32; 3], radius: f32| scene_format::model::Light {
        position: Some(position),
        radius,
        color: [0.3, 0.3, 0.3],
        direction: None,
        cone: None,
    };
    file.lights = vec![
        light,
        at([-3.0, 1.0, 2.0], 0.0),
        at([0.0, 4.0, 1.0], 0.5),
        at([2.0, -1.0, -4.0], 0.0),
        at([-1.0, 0.5, 5.0], 0.0),
        at([0.5, 3.0, -2.0], 0.0),
    ];
    let scene = prepare(&file).expect("prepare");
    let brute_force = scene.clone().brute_force();
    for samples in [1, 2] {
        let job = RenderJob::full(&scene).with_samples(samples);
        let fast = render(&scene, &job, &|_| {}).image;
        let slow = render(&brute_force, &job, &|_| {}).image;
        assert!(
            fast == slow,
            "{samples} samples: the shadows found ahead changed the image"
        );
    }
}

#[test]
fn the_bunny_is_identical_with_and_without_the_bvh() {
    let scene = small_bunny();
    assert_eq!(scene.objects().len(), 69_666);
    let fast = render_image(&scene);
    let slow = render_image(&scene.clone().brute_force());
    assert!(fast == slow, "the BVH changed the image");
    // About a quarter of the rays hit the bunny (bench README: 24.6 %), so
    // both hits and misses were compared.
    let background = glam::Vec3::new(0.1, 0.1, 0.15);
    let misses = fast.pixels.iter().filter(|&&p| p == background).count();
    let n = fast.pixels.len();
    assert!(misses > n / 2 && misses < n * 9 / 10, "{misses} of {n}");
}

#[test]
fn the_image_does_not_depend_on_the_thread_count() {
    let reflectance2 = prepare(&load(&scenes_dir().join("reflectance2.toml"))).unwrap();
    for scene in [reflectance2, small_bunny()] {
        let one = in_pool(1, &scene);
        assert!(one == in_pool(2, &scene));
        assert!(one == in_pool(3, &scene));
    }
}

#[test]
fn rays_and_rows_are_counted() {
    let file = load(&scenes_dir().join("sphere-intersection.toml"));
    let scene = prepare(&file).unwrap();
    let rows = std::sync::atomic::AtomicU32::new(0);
    let stats = render(&scene, &RenderJob::full(&scene), &|n| {
        rows.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
    })
    .rays;
    assert_eq!(rows.into_inner(), 400);
    // No mirrors: one nearest-hit ray per pixel.
    assert_eq!(stats.nearest, 500 * 400);
    // Every shadow ray starts on the sphere, which covers part of the image.
    assert!(stats.shadow > 0 && stats.shadow < 500 * 400);
}

/// Rays aimed exactly at the bunny's vertices and edge midpoints, where
/// neighbouring triangles meet and rounding decides which one is hit: the
/// cases where a box test could lose a hit that the brute-force loop finds.
#[test]
fn rays_at_shared_vertices_and_edges_find_the_brute_force_hits() {
    use glam::Vec3;
    use tracer_core::geometry::Shape;
    use tracer_core::Ray;
    let scene = small_bunny();
    let origins = [
        Vec3::new(0.0, 0.0, 4.743_032),
        Vec3::new(2.845_819, 2.845_819, 4.743_032),
        Vec3::new(-3.0, 0.5, -2.0),
    ];
    let mut hits = 0;
    for (k, object) in scene.objects().iter().enumerate().step_by(31) {
        let Shape::Triangle(t) = &object.shape else {
            continue;
        };
        let targets = [t.v0, (t.v0 + t.v1) * 0.5, (t.v1 + t.v2) * 0.5];
        for (origin, target) in origins.iter().zip(targets) {
            let ray = Ray::new(*origin, (target - *origin).normalize());
            let brute = brute_force::closest_hit(scene.objects(), &ray, 1e-4, f32::INFINITY);
            assert_eq!(
                scene.closest_hit(&ray, 1e-4, f32::INFINITY),
                brute,
                "triangle {k}"
            );
            let distance = (target - *origin).length() * 1.5;
            assert_eq!(
                scene.occluded(&ray, 1e-4, distance),
                brute_force::occluded(scene.objects(), &ray, 1e-4, distance),
                "triangle {k}"
            );
            hits += brute.is_some() as u32;
        }
    }
    assert!(hits > 2500, "{hits} hits");
}

#[test]
fn a_lean_scene_renders_as_the_full_one_without_its_objects() {
    // Textures, smooth meshes, boxes and glass: what shading reads of an
    // object must all be in the BVH once the objects are gone (the larger
    // scenes' are).
    let mut let_go_somewhere = false;
    for name in ["textures", "smooth-mesh", "boxes", "showcase"] {
        let mut file = load(&scenes_dir().join(format!("{name}.toml")));
        (file.camera.width, file.camera.height) = (120, 90);
        let parts = tracer_core::prepare::parts(&file).expect("prepare");
        let full = Scene::new(parts.clone());
        let lean = Scene::lean(parts);
        // A small scene keeps its objects, for the integrators' lanes.
        let let_go = full.objects().len() > tracer_core::scene::KEPT_OBJECTS;
        assert_eq!(lean.objects().is_empty(), let_go, "{name}");
        let_go_somewhere |= let_go;
        assert_eq!(lean.unique_primitives(), full.unique_primitives());
        assert_eq!(lean.bounds(), full.bounds());
        assert!(render_image(&lean) == render_image(&full), "{name}");
    }
    assert!(let_go_somewhere, "no scene let its objects go");
}

#[test]
#[should_panic(expected = "a lean scene has let its objects go")]
fn a_lean_scene_cannot_be_searched_by_brute_force() {
    let file = load(&scenes_dir().join("reflectance2.toml"));
    let parts = tracer_core::prepare::parts(&file).expect("prepare");
    let _ = Scene::lean(parts).brute_force();
}

#[test]
fn only_a_lean_scene_without_instances_is_serialized() {
    let file = load(&scenes_dir().join("smooth-mesh.toml"));
    let parts = tracer_core::prepare::parts(&file).expect("prepare");
    // The objects would be lost: refused.
    let error = serde_json::to_string(&Scene::new(parts.clone())).unwrap_err();
    assert!(error.to_string().contains("only a lean scene"), "{error}");
    let lean = Scene::lean(parts);
    let text = serde_json::to_string(&lean).expect("a lean scene is serialized");
    let back: Scene = serde_json::from_str(&text).expect("and read back");
    assert_eq!(back.unique_primitives(), lean.unique_primitives());
    assert!(render_image(&back) == render_image(&lean));
}
