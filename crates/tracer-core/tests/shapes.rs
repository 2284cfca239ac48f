//! Planes, boxes and quads against geometry worked out by hand: distances,
//! normals and uv of single rays, a box against the twelve triangles it
//! stands for, the horizon a floor makes, and glass through a box.

use glam::{Vec2, Vec3};
use scene_format::Format;
use std::path::Path;
use tracer_core::integrate::whitted::refracted_path;
use tracer_core::{prepare, render, LinearImage, Ray, RenderJob, Scene};

fn scene_from(text: &str) -> Scene {
    let file = scene_format::load_str(text, Format::Toml, Path::new("shapes.toml"))
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    prepare(&file).expect("prepare")
}

fn render_image(scene: &Scene) -> LinearImage {
    render(scene, &RenderJob::full(scene), &|_| {}).image
}

const CAMERA: &str = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n";

fn near(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn a_quad_is_hit_at_the_analytic_distance_normal_and_uv() {
    // Corner (1, 2, -3), edges (4, 0, 0) and (0, 2, 2): the plane
    // -y + z = -5 (normal (0, -1, 1)/sqrt 2, from u x v = (0, -8, 8)).
    let scene = scene_from(&format!(
        "{CAMERA}[[objects]]\nquad = {{ corner = [1, 2, -3], edge_u = [4, 0, 0], edge_v = [0, 2, 2] }}\n"
    ));
    assert_eq!(scene.objects().len(), 2, "two triangles");
    let normal = Vec3::new(0.0, -1.0, 1.0) / 2f32.sqrt();
    for (s, t) in [(0.25, 0.5), (0.9, 0.8), (0.1, 0.05), (0.6, 0.3)] {
        let p = Vec3::new(1.0 + 4.0 * s, 2.0 + 2.0 * t, -3.0 + 2.0 * t);
        // From 5 units off the point along +z: the plane meets the ray
        // where z rises... the distance is 5 / |dir| along a unit ray.
        let origin = p + Vec3::new(0.0, 0.0, 5.0);
        let ray = Ray::new(origin, -Vec3::Z);
        for scene in [&scene, &scene.clone().brute_force()] {
            let hit = scene.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit");
            assert!((hit.t - 5.0).abs() < 1e-5, "{s}, {t}: t = {}", hit.t);
            assert!(
                near(hit.geometric_normal, normal),
                "{}",
                hit.geometric_normal
            );
            assert!(
                (hit.uv - Vec2::new(s, t)).length() < 1e-5,
                "{s}, {t}: {}",
                hit.uv
            );
            // The ray runs -z, against the normal's +z: the front.
            assert!(hit.front_face);
        }
    }
    // Beyond the edges: s = 1.1, and t = -0.1.
    for p in [Vec3::new(5.4, 3.0, -2.0), Vec3::new(2.0, 1.8, -3.2)] {
        let ray = Ray::new(p + Vec3::Z * 5.0, -Vec3::Z);
        assert_eq!(scene.closest_hit(&ray, 1e-4, f32::INFINITY), None, "{p}");
    }
}

#[test]
fn a_box_is_hit_on_each_face_with_the_outward_normal_and_face_uv() {
    let scene = scene_from(&format!(
        "{CAMERA}[[objects]]\nbox = {{ min = [-1, -2, -3], max = [2, 1, 1] }}\n"
    ));
    assert_eq!(scene.objects().len(), 12);
    // A ray along each axis, from 10 outside the box's centre (0.5, -0.5,
    // -1), offset so it does not cross a diagonal.
    let centre = Vec3::new(0.5, -0.5, -1.0);
    let (min, max) = (Vec3::new(-1.0, -2.0, -3.0), Vec3::new(2.0, 1.0, 1.0));
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let outward = Vec3::AXES[axis] * sign;
            let offset = Vec3::AXES[(axis + 1) % 3] * 0.3 + Vec3::AXES[(axis + 2) % 3] * 0.2;
            let origin = centre + offset + outward * 10.0;
            let ray = Ray::new(origin, -outward);
            let face = if sign > 0.0 { max[axis] } else { min[axis] };
            let expected_t = (origin[axis] - face).abs();
            let hit = scene.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit");
            assert!((hit.t - expected_t).abs() < 1e-5, "{outward}: {}", hit.t);
            assert_eq!(hit.geometric_normal, outward);
            assert!(hit.front_face, "{outward}");
            assert!(hit.uv.min_element() > 0.0 && hit.uv.max_element() < 1.0);
            // From inside, the same face is met from behind.
            let inside = Ray::new(centre + offset, outward);
            let back = scene
                .closest_hit(&inside, 1e-4, f32::INFINITY)
                .expect("a hit");
            assert_eq!(back.geometric_normal, outward);
            assert!(!back.front_face, "{outward}");
            assert!((back.t - (face - centre[axis]).abs()).abs() < 1e-5);
        }
    }
    // The +z face (z = 1) spans x from -1 to 2 (u) and y from -2 to 1 (v):
    // the point (0.5, 0.25) is at uv (0.5, 0.75).
    let ray = Ray::new(Vec3::new(0.5, 0.25, 10.0), -Vec3::Z);
    let hit = scene.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit");
    assert!(
        (hit.uv - Vec2::new(0.5, 0.75)).length() < 1e-5,
        "{}",
        hit.uv
    );
}

/// The twelve triangles of the box from (-1, -1, -1) to (1, 0.5, 2),
/// written out by hand, each ordered so its normal points out.
const BOX_TRIANGLES: &str = r#"
[[objects]]
triangle = [[-1, -1, -1], [-1, -1, 2], [-1, 0.5, 2]]
[[objects]]
triangle = [[-1, -1, -1], [-1, 0.5, 2], [-1, 0.5, -1]]
[[objects]]
triangle = [[1, -1, -1], [1, 0.5, -1], [1, 0.5, 2]]
[[objects]]
triangle = [[1, -1, -1], [1, 0.5, 2], [1, -1, 2]]
[[objects]]
triangle = [[-1, -1, -1], [1, -1, -1], [1, -1, 2]]
[[objects]]
triangle = [[-1, -1, -1], [1, -1, 2], [-1, -1, 2]]
[[objects]]
triangle = [[-1, 0.5, -1], [-1, 0.5, 2], [1, 0.5, 2]]
[[objects]]
triangle = [[-1, 0.5, -1], [1, 0.5, 2], [1, 0.5, -1]]
[[objects]]
triangle = [[-1, -1, -1], [-1, 0.5, -1], [1, 0.5, -1]]
[[objects]]
triangle = [[-1, -1, -1], [1, 0.5, -1], [1, -1, -1]]
[[objects]]
triangle = [[-1, -1, 2], [1, -1, 2], [1, 0.5, 2]]
[[objects]]
triangle = [[-1, -1, 2], [1, 0.5, 2], [-1, 0.5, 2]]
"#;

fn box_scene(objects: &str) -> String {
    format!(
        "[camera]\neye = [3, 2.5, 7]\nlook_at = [0, -0.2, 0.5]\nwidth = 160\nheight = 120\n\
         [[lights]]\nposition = [4, 6, 5]\n[[lights]]\nposition = [-5, 1, 3]\ncolor = [0.4, 0.4, 0.4]\n\
         [materials.m]\nambient = [0.1, 0.1, 0.1]\ndiffuse = [0.6, 0.5, 0.3]\nspecular = [0.5, 0.5, 0.5]\nshininess = 20\n\
         {objects}"
    )
}

#[test]
fn a_box_renders_like_its_twelve_hand_written_triangles() {
    let triangles = BOX_TRIANGLES.replace("[[objects]]", "[[objects]]\nmaterial = \"m\"");
    let by_hand = render_image(&scene_from(&box_scene(&triangles)));
    let shape = "[[objects]]\nbox = { min = [-1, -1, -1], max = [1, 0.5, 2] }\nmaterial = \"m\"\n";
    let boxed = render_image(&scene_from(&box_scene(shape)));
    let lit = by_hand
        .pixels
        .iter()
        .filter(|p| p.max_element() > 0.0)
        .count();
    assert!(lit > 3000, "the box fills too little of the image: {lit}");
    // Both are the same surface; the triangles' diagonals may be split
    // differently, so pixels on a diagonal may round the other way.
    let differ = by_hand
        .pixels
        .iter()
        .zip(&boxed.pixels)
        .filter(|(a, b)| (**a - **b).abs().max_element() > 1e-5)
        .count();
    assert!(differ <= 4, "{differ} pixels differ");
}

#[test]
fn a_floor_meets_the_horizon_where_the_view_tilt_puts_it() {
    // Eye 1 above the floor y = 0, looking down by atan(0.1). A pixel row
    // whose centre is y_off pixels above the image's centre looks along
    // forward * f + up * y_off, f = (width / 2) / tan(fov / 2) the focal
    // length in pixels; its world y is proportional to y_off - f tan(tilt),
    // so it meets the floor exactly when y_off < 0.1 f. Width 200, fov 50:
    // 0.1 f = 21.445; y_off = 80 - (j + 0.5) for height 160, so rows with
    // y_off from -79.5 to 20.5 see the floor: 101 of them in every column.
    let scene = scene_from(
        "[camera]\neye = [0, 1, 0]\nlook_at = [0, 0, -10]\nwidth = 200\nheight = 160\n\
         [[lights]]\nposition = [0, 5, 0]\n\
         [[objects]]\nplane = { point = [3, 0, 7], normal = [0, 2, 0] }\n\
         material = { ambient = [0.5, 0.5, 0.5] }\n",
    );
    let image = render_image(&scene);
    for i in 0..image.width {
        let floor = (0..image.height)
            .filter(|&j| image.get(i, j).max_element() > 0.0)
            .count();
        assert_eq!(floor, 101, "column {i}");
    }
    // The floor is the lower part of the picture.
    assert!(image.get(100, 159).max_element() > 0.0);
    assert_eq!(image.get(100, 0), Vec3::ZERO);
    // One ray, by hand: from (0, 1, 0) down at 45 degrees meets y = 0 at
    // distance sqrt 2, uv (x, -z) of the point (0, 0, -1) from (3, 0, 7).
    let ray = Ray::new(Vec3::Y, Vec3::new(0.0, -1.0, -1.0).normalize());
    let hit = scene.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit");
    assert!((hit.t - 2f32.sqrt()).abs() < 1e-6);
    assert_eq!((hit.geometric_normal, hit.front_face), (Vec3::Y, true));
    assert!(
        (hit.uv - Vec2::new(-3.0, 8.0)).length() < 1e-5,
        "{}",
        hit.uv
    );
}

#[test]
fn light_through_a_glass_box_is_shifted_by_the_textbook_amount() {
    // A slab 0.5 thick (y from -0.25 to 0.25), index 1.5, as a box.
    let (n, d) = (1.5f64, 0.5f64);
    let scene = scene_from(
        "[camera]\neye = [0, 20, 0.1]\nlook_at = [0, 0, 0]\n[render]\nmax_depth = 8\n\
         [materials.glass]\ntransmittance = 1\nior = 1.5\n\
         [[objects]]\nbox = { min = [-5, -0.25, -5], max = [5, 0.25, 5] }\nmaterial = \"glass\"\n",
    );
    let across = Vec3::new(0.6, 0.0, 0.8);
    for degrees in [0.0f64, 20.0, 40.0, 60.0] {
        let theta_i = degrees.to_radians();
        let dir = (-Vec3::Y * theta_i.cos() as f32 + across * theta_i.sin() as f32).normalize();
        let entry = Vec3::Y * 0.25 + across * 0.3;
        let ray = Ray::new(entry - 3.0 * dir, dir);
        let path = refracted_path(&scene, &ray, 10);
        assert_eq!(path.len(), 3, "{degrees} deg: in, through, out");
        // Out parallel to the way in, and d sin(i - r) / cos(r) off its line.
        assert!(
            (path[2].dir() - dir).length() < 1e-5,
            "{degrees}: {}",
            path[2].dir()
        );
        let theta_r = (theta_i.sin() / n).asin();
        let offset = (path[2].origin() - ray.origin()).cross(dir).length() as f64;
        let expected = d * (theta_i - theta_r).sin() / theta_r.cos();
        assert!(
            (offset - expected).abs() < 1e-5,
            "{degrees}: {offset} vs {expected}"
        );
    }
}

/// Rays from `origins` at `n - 1` points spread along the diagonal of the
/// quad `corner`, `edge_u`, `edge_v` (from corner + edge_u to corner +
/// edge_v, where its two triangles meet): how many find no hit, or are
/// not blocked as shadow rays, in the BVH's search and the brute force.
fn diagonal_misses(corner: Vec3, edge_u: Vec3, edge_v: Vec3, origins: &[Vec3], n: u32) -> usize {
    let [c, u, v] = [corner, edge_u, edge_v].map(|p| p.to_array());
    let scene = scene_from(&format!(
        "{CAMERA}[[objects]]\nquad = {{ corner = {c:?}, edge_u = {u:?}, edge_v = {v:?} }}\n"
    ));
    let (a, b) = (corner + edge_u, corner + edge_v);
    let mut misses = 0;
    for scene in [&scene, &scene.clone().brute_force()] {
        for &origin in origins {
            for k in 1..n {
                let p = a + (b - a) * (k as f32 / n as f32);
                let ray = Ray::new(origin, p - origin);
                let hit = scene.closest_hit(&ray, 1e-4, f32::INFINITY);
                let blocked = scene.occluded(&ray, 1e-4, 2.0);
                misses += usize::from(hit.is_none()) + usize::from(!blocked);
            }
        }
    }
    misses
}

#[test]
fn a_ray_on_a_quads_diagonal_hits_it() {
    // Rounding made u + v a little over 1 in both halves for about one
    // such ray in seven: a crack along the diagonal.
    let origins = [
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::new(0.3, -0.7, 7.0),
        Vec3::new(3.1, 2.9, 5.3),
        Vec3::new(-2.0, 1.5, -6.0),
    ];
    // Points exact in f32 (steps of 1/1024 between corners of small
    // integers), then any quads.
    let quads = [
        (
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ),
        (
            Vec3::new(1.0, 2.0, -3.0),
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 2.0),
        ),
        (
            Vec3::new(-0.3, 0.7, -1.1),
            Vec3::new(1.7, 0.3, 0.1),
            Vec3::new(-0.2, 1.3, 0.9),
        ),
        (
            Vec3::new(2.2, -1.9, 0.4),
            Vec3::new(-3.1, 0.7, 1.3),
            Vec3::new(0.9, 2.6, -0.8),
        ),
    ];
    for (k, (corner, edge_u, edge_v)) in quads.into_iter().enumerate() {
        let n = if k < 2 { 1024 } else { 3001 };
        let misses = diagonal_misses(corner, edge_u, edge_v, &origins, n);
        assert_eq!(misses, 0, "quad {k}: {misses} rays through the diagonal");
    }
}

#[test]
fn a_sphere_gives_its_hits_uv_only_where_its_material_reads_them() {
    // Two spheres seen head on: a plain one at x = -3, a checkered one at
    // x = 3. Only the second's hits carry uv; `explain` still tells the
    // first one's, as the lab's mapping gives it.
    let scene = scene_from(&format!(
        "{CAMERA}[materials.plain]\ndiffuse = [0.5, 0.5, 0.5]\n\
         [materials.checked]\ndiffuse = [0.5, 0.5, 0.5]\n\
         texture = {{ checker = [[0, 0, 0], [1, 1, 1]] }}\n\
         [[objects]]\nsphere = {{ center = [-3, 0, 0], radius = 1 }}\nmaterial = \"plain\"\n\
         [[objects]]\nsphere = {{ center = [3, 0, 0], radius = 1 }}\nmaterial = \"checked\"\n"
    ));
    let without_uv = |k: usize| scene.sphere_without_uv(k).is_some();
    assert!(without_uv(0) && !without_uv(1));
    // Through a point off the front pole, where uv is not (0.5, 0.5).
    let hit_at = |x: f32| {
        let ray = Ray::new(Vec3::new(x + 0.3, 0.4, 10.0), -Vec3::Z);
        scene.closest_hit(&ray, 1e-4, f32::INFINITY).expect("a hit")
    };
    let (plain, checked) = (hit_at(-3.0), hit_at(3.0));
    assert_eq!(plain.uv, Vec2::ZERO);
    let lab_uv = |h: &tracer_core::geometry::SurfaceHit| {
        tracer_core::geometry::Sphere::texture_uv(h.geometric_normal)
    };
    assert_eq!(checked.uv, lab_uv(&checked));
    // The first pixel of the middle row that sees the plain sphere: its
    // uv in explain is the mapping's, not the hit's 0.
    let camera = scene.camera();
    let pixel = (0..camera.width)
        .map(|i| (i, camera.height / 2))
        .find(|&(i, j)| {
            let ray = camera.primary_ray(i, j);
            matches!(scene.closest_hit(&ray, 1e-4, f32::INFINITY), Some(h) if h.object == 0)
        })
        .expect("the plain sphere in view");
    let explained = tracer_core::explain::explain(&scene, pixel, 1, 0);
    let tracer_core::explain::Trace::Whitted { ray } = &explained.trace else {
        panic!("Whitted")
    };
    let hit = ray.hit.as_ref().expect("a hit");
    assert_eq!(hit.object, 0);
    let expected = tracer_core::geometry::Sphere::texture_uv(hit.normal);
    assert!((hit.uv - expected).length() < 1e-6, "{} {expected}", hit.uv);
    assert_ne!(hit.uv, Vec2::ZERO);
}
