//! `transform` on every shape: each test checks where a placed shape is
//! against geometry worked out by hand, never against an earlier render.

use glam::{Vec2, Vec3};
use scene_format::Format;
use std::path::Path;
use tracer_core::geometry::Shape;
use tracer_core::{prepare, Ray, Scene};

const HEAD: &str = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n";

fn scene(objects: &str) -> Scene {
    let text = format!("{HEAD}{objects}");
    let file = scene_format::load_str(&text, Format::Toml, Path::new("transforms.toml"))
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    prepare(&file).expect("prepare")
}

/// The distance along a unit ray from `origin` toward `dir` to the first hit.
fn distance(scene: &Scene, origin: Vec3, dir: Vec3) -> Option<f32> {
    let ray = Ray::new(origin, dir.normalize());
    scene.closest_hit(&ray, 1e-4, f32::INFINITY).map(|h| h.t)
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() < 1e-4
}

#[test]
fn a_sphere_is_moved_then_scaled_in_the_labs_order() {
    // [T, S]: scale by 2 about the origin first (centre (1,0,0) -> (2,0,0),
    // radius 0.5 -> 1), then move by (0, 3, 0): centre (2, 3, 0), radius 1.
    let s = scene(
        "[[objects]]\nsphere = { center = [1, 0, 0], radius = 0.5 }\n\
         transform = [{ translate = [0, 3, 0] }, { scale = 2 }]\n",
    );
    let t = distance(&s, Vec3::new(2.0, 3.0, 10.0), -Vec3::Z).expect("a hit");
    assert!(close(t, 9.0), "{t}");
    // Just outside its edge: a miss; just inside: a hit.
    assert!(distance(&s, Vec3::new(3.01, 3.0, 10.0), -Vec3::Z).is_none());
    assert!(distance(&s, Vec3::new(2.99, 3.0, 10.0), -Vec3::Z).is_some());
}

#[test]
fn a_turned_box_is_as_wide_as_its_diagonal() {
    // A unit cube about the origin turned 45 degrees about y: seen along z,
    // its nearest point is an edge at z = sqrt(2)/2, and it spans
    // x in (-sqrt(2)/2, sqrt(2)/2).
    let s = scene(
        "[[objects]]\nbox = { min = [-0.5, -0.5, -0.5], max = [0.5, 0.5, 0.5] }\n\
         transform = { rotate = [0, 45, 0] }\n",
    );
    let half_diagonal = 0.5 * 2f32.sqrt();
    let t = distance(&s, Vec3::new(0.0, 0.0, 10.0), -Vec3::Z).expect("a hit");
    assert!(close(t, 10.0 - half_diagonal), "{t}");
    // At x = 0.3 the face x + z = sqrt(2)/2 is met at z = sqrt(2)/2 - 0.3.
    let t = distance(&s, Vec3::new(0.3, 0.0, 10.0), -Vec3::Z).expect("a hit");
    assert!(close(t, 10.0 - (half_diagonal - 0.3)), "{t}");
    assert!(distance(&s, Vec3::new(half_diagonal + 0.01, 0.0, 10.0), -Vec3::Z).is_none());
}

#[test]
fn a_mirrored_box_still_faces_outward() {
    // Scale -1 on x mirrors: without turning the vertex order round, every
    // face's normal would point in, and a ray from outside meet back faces.
    let s = scene(
        "[[objects]]\nbox = { min = [0, 0, 0], max = [1, 1, 1] }\n\
         transform = { scale = [-1, 1, 1] }\n",
    );
    let centre = Vec3::new(-0.5, 0.5, 0.5);
    for dir in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
        let origin = centre + 5.0 * dir;
        let ray = Ray::new(origin, -dir);
        let hit = s.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit");
        assert!(close(hit.t, 4.5), "{dir}: {}", hit.t);
        assert!(hit.front_face, "{dir}: met a back face");
        assert!(hit.geometric_normal.dot(dir) > 0.999, "{dir}");
    }
}

#[test]
fn a_stretched_plane_turns_its_normal_and_stretches_its_uv() {
    // The plane x + y = 0 stretched 2x along x holds (2, -1, 0), so its
    // normal is (1, 2, 0)/sqrt 5; the point (2, -1, 0) came from (1, -1, 0),
    // whose uv on the unplaced plane a placed plane keeps.
    let s = scene(
        "[[objects]]\nplane = { point = [0, 0, 0], normal = [1, 1, 0] }\n\
         transform = [{ scale = [2, 1, 1] }]\n",
    );
    let Shape::Plane(placed) = &s.objects()[0].shape else {
        panic!("a plane")
    };
    let n = Vec3::new(1.0, 2.0, 0.0).normalize();
    assert!((placed.normal - n).length() < 1e-6, "{}", placed.normal);
    let unplaced = tracer_core::geometry::Plane::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0));
    let uv = placed.uv(Vec3::new(2.0, -1.0, 0.0));
    assert!(
        (uv - unplaced.uv(Vec3::new(1.0, -1.0, 0.0))).length() < 1e-5,
        "{uv}"
    );
}

#[test]
fn a_quad_carries_its_uv_when_turned_and_mirrored() {
    // The unit quad in z = 0 turned 90 degrees about x lies in y = 0
    // (y -> z); mirrored in x it runs to x = -1. Its corner (0,0) and the
    // point s = 0.25, t = 0.75 must keep their uv.
    let s = scene(
        "[[objects]]\nquad = { corner = [0, 0, 0], edge_u = [1, 0, 0], edge_v = [0, 1, 0] }\n\
         transform = [{ scale = [-1, 1, 1] }, { rotate = [90, 0, 0] }]\n",
    );
    // (s, t) = (0.25, 0.75) -> (0.25, 0.75, 0) -> turned (0.25, 0, 0.75)
    // -> mirrored (-0.25, 0, 0.75). Seen from above (+y).
    let ray = Ray::new(Vec3::new(-0.25, 5.0, 0.75), -Vec3::Y);
    let hit = s.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit");
    assert!(close(hit.t, 5.0), "{}", hit.t);
    assert!(
        (hit.uv - Vec2::new(0.25, 0.75)).length() < 1e-5,
        "{}",
        hit.uv
    );
}

#[test]
fn the_table_form_is_the_list_translate_rotate_scale() {
    let objects = |transform: &str| {
        format!(
            "[[objects]]\nbox = {{ min = [0, 0, 0], max = [1, 2, 3] }}\ntransform = {transform}\n"
        )
    };
    let table = scene(&objects(
        "{ translate = [1, 2, 3], rotate = [10, 20, 30], scale = [2, 1, 0.5] }",
    ));
    let list = scene(&objects(
        "[{ translate = [1, 2, 3] }, { rotate = [10, 20, 30] }, { scale = [2, 1, 0.5] }]",
    ));
    // The same product, so the same vertices to the last bit.
    assert_eq!(table.objects(), list.objects());
    // And not some other order: scale first (the list reversed) differs.
    let reversed = scene(&objects(
        "[{ scale = [2, 1, 0.5] }, { rotate = [10, 20, 30] }, { translate = [1, 2, 3] }]",
    ));
    assert_ne!(table.objects(), reversed.objects());
}

/// A material whose texture reads the hits' uv.
const CHECKED: &str =
    "[materials.checked]\ndiffuse = [0.5, 0.5, 0.5]\ntexture = { checker = [[0, 0, 0], [1, 1, 1]] }\n";

#[test]
fn a_turned_sphere_turns_its_texture() {
    // The lab's mapping puts u = 0.5 + asin(n.x)/pi: the front (+z) is
    // u = 0.5, the +x side u = 1. Turned 90 degrees about y (z -> x), the
    // texture's front faces +x, so a ray from +x meets u = 0.5.
    // Checkered, so that its hits carry their uv (a plain sphere's leave
    // them out).
    let s = scene(&format!(
        "{CHECKED}[[objects]]\nsphere = {{ center = [0, 0, 0], radius = 1 }}\n\
         material = \"checked\"\ntransform = [{{ rotate = [0, 90, 0] }}]\n",
    ));
    let ray = Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::X);
    let hit = s.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit");
    assert!((hit.uv - Vec2::new(0.5, 0.5)).length() < 1e-5, "{}", hit.uv);
    // Unturned, the same ray meets the texture's u = 1 edge.
    let plain = scene(&format!(
        "{CHECKED}[[objects]]\nsphere = {{ center = [0, 0, 0], radius = 1 }}\nmaterial = \"checked\"\n"
    ));
    let hit = plain.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit");
    assert!((hit.uv.x - 1.0).abs() < 1e-5, "{}", hit.uv);
}
