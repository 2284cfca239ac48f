//! Instancing: a mesh named by several objects is prepared once and placed
//! by each, and finds the hits the same mesh flattened by the same
//! transform finds (to rounding), the ones worked out by hand, and, with the
//! BVH, exactly the brute-force loop's.

mod common;

use common::{load, scenes_dir};
use glam::Vec3;
use std::sync::Arc;
use tracer_core::geometry::{Shape, SurfaceHit};
use tracer_core::{render, Ray, RenderJob, Scene};

const HEAD: &str = r#"
[camera]
eye = [0, 2, 10]
look_at = [0, 0, 0]
width = 64
height = 48

[[lights]]
position = [4, 6, 8]

[materials.red]
diffuse = [0.9, 0.1, 0.1]

[materials.blue]
diffuse = [0.1, 0.1, 0.9]

[materials.glass]
diffuse = [0.05, 0.05, 0.05]
transmittance = 0.8
ior = 1.5
"#;

/// The scene of `HEAD` and `objects`, beside copies of the cube and
/// icosphere meshes.
fn scene(objects: &str) -> Scene {
    Scene::new(parts(objects))
}

/// What `scene` is made of.
fn parts(objects: &str) -> tracer_core::scene::SceneParts {
    let dir = tempfile::tempdir().expect("a temporary folder");
    for mesh in ["cube.obj", "icosphere.obj"] {
        std::fs::copy(
            scenes_dir().join("meshes").join(mesh),
            dir.path().join(mesh),
        )
        .expect("a copy");
    }
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, format!("{HEAD}{objects}")).expect("written");
    let file = load(&path);
    tracer_core::prepare::parts(&file).expect("prepare")
}

fn cube(transform: &str, material: &str) -> String {
    format!("[[objects]]\nmesh = {{ obj = \"cube.obj\" }}\nmaterial = \"{material}\"\ntransform = {transform}\n")
}

/// A cube far out of the way: with it, a scene's other cube is shared.
const ELSEWHERE: &str = "{ translate = [100, 0, 0] }";

fn is_instance(scene: &Scene, k: usize) -> bool {
    matches!(scene.objects()[k].shape, Shape::Instance(_))
}

#[test]
fn two_objects_naming_one_obj_share_one_triangle_store() {
    let flat = "[[objects]]\nmesh = { obj = \"cube.obj\", smooth = false }\n";
    let s = scene(&format!(
        "{}{}{flat}",
        cube("{ translate = [-2, 0, 0] }", "red"),
        cube("{ translate = [2, 0, 0] }", "blue"),
    ));
    // Two instances of one 12-triangle mesh; the cube named once with
    // another `smooth` is its own copy, flattened into its 12 triangles.
    assert_eq!(s.objects().len(), 2 + 12);
    assert!(is_instance(&s, 0) && is_instance(&s, 1) && !is_instance(&s, 2));
    let mesh = |k: usize| match &s.objects()[k].shape {
        Shape::Instance(i) => Arc::clone(i.mesh()),
        _ => panic!("an instance"),
    };
    assert!(Arc::ptr_eq(&mesh(0), &mesh(1)));
    assert_eq!(mesh(0).objects().len(), 12);
    assert_eq!(s.unique_primitives(), 12 + 2 + 12);
}

#[test]
fn a_ray_at_an_instance_finds_the_distance_and_normal_worked_out_by_hand() {
    // Scaled 2 along x, turned 90 degrees about z (x goes to y), moved 5
    // along x: the box [4.5, 5.5] x [-1, 1] x [-0.5, 0.5]. Mirrored in x
    // first, it is the same box, its faces still facing out.
    for scale in ["[2, 1, 1]", "[-2, 1, 1]"] {
        let t = format!("{{ scale = {scale}, rotate = [0, 0, 90], translate = [5, 0, 0] }}");
        let s = scene(&format!("{}{}", cube(&t, "red"), cube(ELSEWHERE, "blue")));
        assert!(is_instance(&s, 0));
        let hit = |origin: Vec3, dir: Vec3| {
            s.closest_hit(&Ray::new(origin, dir), 1e-4, f32::INFINITY)
                .expect("a hit")
        };
        let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-5;
        // From above, a direction of length 2: t in its units, 9 / 2.
        let top = hit(Vec3::new(5.0, 10.0, 0.0), Vec3::new(0.0, -2.0, 0.0));
        assert!((top.t - 4.5).abs() < 1e-5, "{scale}: {}", top.t);
        assert!(close(top.geometric_normal, Vec3::Y), "{scale}: {top:?}");
        assert!(top.front_face && top.object == 0);
        // From the left: the face at x = 4.5, facing -x.
        let side = hit(Vec3::new(0.0, 0.3, 0.2), Vec3::X);
        assert!((side.t - 4.5).abs() < 1e-5, "{scale}: {}", side.t);
        assert!(close(side.geometric_normal, -Vec3::X), "{scale}: {side:?}");
        // From inside: the top face's back, 1 away.
        let inside = hit(Vec3::new(5.0, 0.0, 0.0), Vec3::Y);
        assert!((inside.t - 1.0).abs() < 1e-5, "{scale}: {}", inside.t);
        assert!(close(inside.geometric_normal, Vec3::Y) && !inside.front_face);
        assert!(s.occluded(&Ray::new(Vec3::new(5.0, 10.0, 0.0), -Vec3::Y), 1e-4, 9.5));
        assert!(!s.occluded(&Ray::new(Vec3::new(5.0, 10.0, 0.0), -Vec3::Y), 1e-4, 8.5));
    }
}

/// Whether barycentric `uv` is within `e` of its triangle's edge.
fn near_edge(h: &SurfaceHit, e: f32) -> bool {
    h.uv.x < e || h.uv.y < e || h.uv.x + h.uv.y > 1.0 - e
}

#[test]
fn an_instance_finds_the_hits_of_its_transform_flattened() {
    // Each with where it puts the cube's centre, and whether it mirrors.
    let transforms = [
        (
            "{ translate = [0.5, -0.2, 1] }",
            Vec3::new(0.5, -0.2, 1.0),
            false,
        ),
        (
            "{ scale = [1.5, 0.5, 2], rotate = [30, -20, 70], translate = [0.3, 0.1, -0.4] }",
            Vec3::new(0.3, 0.1, -0.4),
            false,
        ),
        (
            "{ scale = [-1, 2, 1], rotate = [10, 45, 0] }",
            Vec3::ZERO,
            true,
        ),
        (
            "[{ rotate = [0, 0, 30] }, { scale = [2, 1, -0.5] }, { translate = [0, 1, 0] }]",
            Vec3::new(-0.5, 0.75f32.sqrt(), 0.0),
            true,
        ),
    ];
    for (t, centre, mirrors) in transforms {
        let shared = scene(&format!("{}{}", cube(t, "red"), cube(ELSEWHERE, "blue")));
        let flat = scene(&cube(t, "red"));
        assert!(is_instance(&shared, 0) && !is_instance(&flat, 0));
        let (mut hits, mut front, mut back) = (0, 0, 0);
        for k in 0..4000 {
            // Rays from around the cube and from inside it, toward its middle.
            let a = k as f32 * 0.618;
            let origin = centre
                + if k % 4 == 0 {
                    Vec3::new(a.sin(), a.cos(), (a * 1.3).sin()) * 0.1
                } else {
                    Vec3::new(a.sin() * 6.0, (a * 0.7).cos() * 4.0, a.cos() * 6.0)
                };
            let aim = centre + Vec3::new((a * 3.1).sin(), (a * 2.3).cos(), (a * 1.7).sin()) * 0.4;
            let ray = Ray::new(origin, aim - origin);
            let (i, f) = (
                shared.closest_hit(&ray, 1e-4, f32::INFINITY),
                flat.closest_hit(&ray, 1e-4, f32::INFINITY),
            );
            match (i, f) {
                (Some(i), Some(f)) => {
                    assert!(
                        (i.t - f.t).abs() <= 1e-5 * f.t,
                        "{t}, ray {k}: {i:?} vs {f:?}"
                    );
                    let n = (i.geometric_normal - f.geometric_normal).length();
                    assert!(n < 1e-5, "{t}, ray {k}: {i:?} vs {f:?}");
                    // A mirrored flat triangle lists its last two corners the
                    // other way round (to keep its front outward), and so
                    // its barycentrics; the instance keeps the file's order.
                    let uv = if mirrors {
                        glam::Vec2::new(f.uv.y, f.uv.x)
                    } else {
                        f.uv
                    };
                    assert!((i.uv - uv).length() < 1e-4 || near_edge(&f, 1e-4));
                    assert_eq!((i.front_face, i.material), (f.front_face, f.material));
                    assert_eq!(i.shading_normal, i.geometric_normal);
                    hits += 1;
                    (front, back) = (front + f.front_face as u32, back + !f.front_face as u32);
                }
                // Only a ray grazing an edge may round into one and not the other.
                (Some(h), None) | (None, Some(h)) => assert!(near_edge(&h, 1e-4), "{t}, ray {k}"),
                (None, None) => {}
            }
        }
        assert!(
            hits > 3000 && front > 2000 && back > 800,
            "{t}: {hits} hits, {front} front, {back} back"
        );
    }
}

#[test]
fn each_instance_shades_with_its_own_material() {
    let s = scene(&format!(
        "{}{}",
        cube("{ translate = [-2, 0, 0] }", "red"),
        cube("{ translate = [2, 0, 0] }", "blue"),
    ));
    let material = |x: f32| {
        let ray = Ray::new(Vec3::new(x, 0.0, 10.0), -Vec3::Z);
        let hit = s.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit");
        hit.material
    };
    let (red, blue) = (material(-2.0), material(2.0));
    assert_ne!(red, blue);
    assert_eq!(s.material(red), s.material(s.objects()[0].material));
    assert_eq!(s.material(blue), s.material(s.objects()[1].material));
}

#[test]
fn instanced_scenes_are_identical_with_and_without_the_bvh() {
    // Flat and smooth (icosphere) instances, mirrored and stretched, glass
    // (rays inside the instances, shadows through them), a floor.
    let ball = |t: &str, material: &str| {
        format!("[[objects]]\nmesh = {{ obj = \"icosphere.obj\" }}\nmaterial = \"{material}\"\ntransform = {t}\n")
    };
    let objects = [
        cube("{ rotate = [20, 30, 0], translate = [-2, 0, 0] }", "red"),
        cube(
            "{ scale = [-1, 1.5, 0.7], rotate = [0, 60, 10], translate = [2, 0, 1] }",
            "glass",
        ),
        cube("{ scale = 0.5, translate = [0, 1.5, 2] }", "blue"),
        ball("{ translate = [0, 0, -1] }", "red"),
        ball(
            "{ scale = [0.5, 1, 0.5], rotate = [0, 0, 30], translate = [0, -0.5, 3] }",
            "glass",
        ),
        ball(
            "{ scale = [-0.7, 0.7, 0.7], translate = [-1, 1.5, 1] }",
            "blue",
        ),
        "[[objects]]\nplane = { point = [0, -1.5, 0], normal = [0, 1, 0] }\n".to_string(),
        "[[objects]]\nsphere = { center = [1, 1.5, 0], radius = 0.5 }\nmaterial = \"blue\"\n"
            .to_string(),
    ];
    let s = scene(&objects.concat());
    assert_eq!(s.objects().len(), 8);
    let image = |s: &Scene| render(s, &RenderJob::full(s), &|_| {}).image;
    let fast = image(&s);
    let slow = image(&s.clone().brute_force());
    assert!(fast == slow, "the BVH changed the image");
    // A pixel's samples searched together (the flattened smooth ball makes
    // a tree of more than one node), then each ray among the instances.
    let smooth = "[[objects]]\nmesh = { obj = \"icosphere.obj\", smooth = true }\nmaterial = \"red\"\ntransform = { translate = [2, 1.5, -1] }\n";
    let s16 = scene(&(objects.concat() + smooth));
    let job = RenderJob::full(&s16).with_samples(16);
    let packets = render(&s16, &job, &|_| {}).image;
    let one_by_one = render(&s16.clone().brute_force(), &job, &|_| {}).image;
    assert!(packets == one_by_one, "the packets changed the image");
    // The render's own scene lets the objects go; the instances stay.
    let lean = Scene::lean(parts(&objects.concat()));
    assert_eq!(lean.unique_primitives(), s.unique_primitives());
    assert!(image(&lean) == fast, "the lean scene changed the image");
    // Its shared mesh would be written once an instance: not serialized.
    assert!(lean.has_instances() && !Scene::lean(parts(&objects[0])).has_instances());
    let error = serde_json::to_string(&lean).unwrap_err();
    assert!(error.to_string().contains("instances"), "{error}");
}
