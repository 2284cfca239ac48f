//! `tracer explain --draw OUT.png` and the JSON's `drawing`: the rays of a
//! pixel's tree where the image sees them, checked against positions
//! worked out by hand and against the image's own projection matrix
//! (`projection`, solved here on its own).

mod common;

use common::tracer;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn scene(name: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    p.to_str().unwrap().to_string()
}

/// A wall at z = 0 seen head-on from (0, 0, 10) through a 90-degree view,
/// 65x65 (pixel (32, 32) looks at the origin), a light at (4, 0, 4) and a
/// ball of radius 0.5 at (2, 0, 2), half way between the origin and the
/// light. By hand: the shadow ray from the origin to the light, along (1,
/// 0, 1)/sqrt(2), meets the ball at t = 2 sqrt(2) - 0.5, the point (2 -
/// 0.5/sqrt(2)) (1, 0, 1) = (1.6464, 0, 1.6464); the focal length is 65 / 2
/// = 32.5 pixels and +x is on the image's left, so a point (x, 0, z) is
/// seen at (32.5 - 32.5 x / (10 - z), 32.5): the ball's point at (26.095,
/// 32.5), the light at (10.833, 32.5).
const BLOCKED_WALL: &str = "\
[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfov = 90\nwidth = 65\nheight = 65\n\
[[lights]]\nposition = [4, 0, 4]\n\
[materials.grey]\nambient = [0.2, 0.2, 0.2]\ndiffuse = [0.6, 0.6, 0.6]\n\
[[objects]]\nplane = { point = [0, 0, 0], normal = [0, 0, 1] }\nmaterial = \"grey\"\n\
[[objects]]\nsphere = { center = [2, 0, 2], radius = 0.5 }\nmaterial = \"grey\"\n";

fn explain_json(dir: &Path, args: &[&str]) -> Value {
    let out = tracer(dir, args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

fn point(v: &Value) -> [f64; 2] {
    [v[0].as_f64().unwrap(), v[1].as_f64().unwrap()]
}

fn vec3(v: &Value) -> [f64; 3] {
    [0, 1, 2].map(|k| v[k].as_f64().unwrap())
}

fn near(a: [f64; 2], b: [f64; 2], within: f64) -> bool {
    (a[0] - b[0]).hypot(a[1] - b[1]) <= within
}

/// Where `p` is seen, by the JSON's own projection matrix P = [u v o]
/// (lab 1.2.3): P (x, y, 1) s = p - eye, solved by Cramer's rule.
fn seen_by_projection(json: &Value, eye: [f64; 3], p: [f64; 3]) -> [f64; 2] {
    let [u, v, o] = [0, 1, 2].map(|k| vec3(&json["projection"][k]));
    let d = [p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]];
    let det = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        a[0] * (b[1] * c[2] - b[2] * c[1]) - b[0] * (a[1] * c[2] - a[2] * c[1])
            + c[0] * (a[1] * b[2] - a[2] * b[1])
    };
    let whole = det(u, v, o);
    let (xs, ys, s) = (
        det(d, v, o) / whole,
        det(u, d, o) / whole,
        det(u, v, d) / whole,
    );
    [xs / s, ys / s]
}

fn png(path: &Path) -> image::RgbImage {
    image::open(path).unwrap().to_rgb8()
}

/// Whether a pixel within `r` of (x, y) has exactly `colour`.
fn has_colour_near(image: &image::RgbImage, (x, y): (i64, i64), r: i64, colour: [u8; 3]) -> bool {
    (-r..=r).any(|dy| {
        (-r..=r).any(|dx| {
            let (px, py) = (x + dx, y + dy);
            px >= 0
                && py >= 0
                && (px as u32) < image.width()
                && (py as u32) < image.height()
                && image.get_pixel(px as u32, py as u32).0 == colour
        })
    })
}

const PRIMARY: [u8; 3] = [255, 214, 0];
const REFLECTED: [u8; 3] = [0, 190, 255];
const BLOCKED: [u8; 3] = [255, 40, 40];
const LIGHT: [u8; 3] = [255, 245, 150];

#[test]
fn a_blocked_shadow_ray_is_drawn_dashed_red_to_the_light_with_its_blocker_where_worked_out() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("wall.toml"), BLOCKED_WALL).unwrap();
    let args = [
        "explain",
        "wall.toml",
        "32",
        "32",
        "--json",
        "--draw",
        "wall.png",
    ];
    let json = explain_json(dir.path(), &args);
    let drawing = &json["drawing"];
    let rays = drawing["rays"].as_array().unwrap();
    assert_eq!(rays.len(), 2, "{drawing}");
    // The primary ray's hit, the origin, is seen at the pixel's centre.
    assert_eq!(rays[0]["kind"], "primary");
    let hit = point(&rays[0]["image"]["end_seen"]);
    assert!(near(hit, [32.5, 32.5], 1e-3), "{hit:?}");
    // Its shadow ray: blocked by the ball, objects[1], at the point worked
    // out by hand, and drawn to the light.
    let shadow = &rays[1];
    assert_eq!(shadow["kind"], "shadow");
    assert_eq!(shadow["parent"], 0);
    assert_eq!(shadow["light"], 0);
    assert_eq!(shadow["blocked"], true);
    assert_eq!(shadow["blocked_by"]["name"], "objects[1]");
    let s = 2.0 - 0.5 / 2f64.sqrt();
    let blocker = vec3(&shadow["blocked_by"]["point"]);
    assert!(
        (blocker[0] - s).abs() < 1e-4 && blocker[1].abs() < 1e-4 && (blocker[2] - s).abs() < 1e-4,
        "{blocker:?}"
    );
    let blocker_seen = point(&shadow["blocked_by"]["seen_at"]);
    let by_hand = [32.5 - 32.5 * s / (10.0 - s), 32.5];
    assert!(
        near(blocker_seen, by_hand, 1e-3),
        "{blocker_seen:?} {by_hand:?}"
    );
    let segment = &shadow["image"];
    assert!(
        near(point(&segment["from"]), [32.5, 32.5], 1e-3),
        "{segment}"
    );
    let light_by_hand = [32.5 - 32.5 * 4.0 / 6.0, 32.5];
    assert!(
        near(point(&segment["to"]), light_by_hand, 1e-3),
        "{segment}"
    );
    assert_eq!(segment["leaves"], false);
    assert!(near(
        point(&drawing["lights"][0]["seen_at"]),
        light_by_hand,
        1e-3
    ));
    // The tree's rays have their ends too: the hit, and the blocker.
    assert_eq!(
        vec3(&json["ray"]["end"]).map(|c| (c * 1e3).round()),
        [0.0; 3]
    );
    assert!(json["ray"]["lights"][0]["blocked_by"]["point"].is_array());

    // The picture: the render, enlarged 8 times (the least whole factor
    // that makes 65 pixels at least 480), with a yellow dot and ring on
    // the clicked pixel, red dashes along the shadow ray, a red X at the
    // blocker, the light.
    let drawn = png(&dir.path().join("wall.png"));
    let k = 8.0;
    assert_eq!(drawn.width(), 520, "65 pixels enlarged 8 times");
    assert!(drawn.height() > 520, "the legend's strip below the image");
    let at = |p: [f64; 2]| ((p[0] * k).floor() as i64, (p[1] * k).floor() as i64);
    // The clicked pixel is the square from (256, 256) to (264, 264): the
    // hit's dot is at its centre.
    assert_eq!(at([32.5, 32.5]), (260, 260));
    assert_eq!(
        drawn.get_pixel(260, 260).0,
        PRIMARY,
        "the hit's dot on the clicked pixel"
    );
    // The ring (radius 6 round the dot) is the primary ray's colour.
    assert!(has_colour_near(&drawn, (260, 254), 1, PRIMARY));
    let (bx, by) = at(by_hand);
    assert_eq!((bx, by), (208, 260));
    assert!(
        has_colour_near(&drawn, (bx, by), 1, BLOCKED),
        "the X at the blocker"
    );
    // Dashes: red between the light and the blocker, and gaps.
    let (lx, _) = at(light_by_hand);
    assert_eq!(lx, 86);
    let on_line: Vec<[u8; 3]> = (lx as u32 + 12..bx as u32 - 8)
        .map(|x| drawn.get_pixel(x, 260).0)
        .collect();
    assert!(on_line.contains(&BLOCKED), "{on_line:?}");
    assert!(on_line.iter().any(|c| *c != BLOCKED), "dashed: {on_line:?}");
    // Nothing red on the other side of the hit, where no ray goes.
    let beyond: Vec<[u8; 3]> = (280..400).map(|x| drawn.get_pixel(x, 260).0).collect();
    assert!(!beyond.contains(&BLOCKED), "{beyond:?}");
    assert!(
        has_colour_near(&drawn, (lx, 260), 2, LIGHT),
        "the light's mark"
    );
    // The render itself is untouched away from the drawing.
    let out = tracer(dir.path(), &["render", "wall.toml", "-o", "plain.png"]);
    assert!(out.status.success());
    let plain = png(&dir.path().join("plain.png"));
    for (x, y) in [(60, 5), (5, 60), (50, 50)] {
        let enlarged = drawn.get_pixel(x * 8 + 4, y * 8 + 4);
        assert_eq!(enlarged, plain.get_pixel(x, y), "({x}, {y})");
    }
}

#[test]
fn a_mirror_rays_hit_is_ringed_where_the_projection_matrix_sees_it() {
    // reflectance2's mirror wall under the red ball: the mirror ray of
    // pixel (250, 330) goes up to the ball.
    let dir = tempfile::tempdir().unwrap();
    let file = scene("reflectance2.toml");
    let args = ["explain", &file, "250", "330", "--json", "--draw", "r.png"];
    let json = explain_json(dir.path(), &args);
    let rays = json["drawing"]["rays"].as_array().unwrap();
    let mirror = rays
        .iter()
        .find(|r| r["kind"] == "reflected")
        .expect("a mirror ray");
    let end = vec3(&mirror["end"]);
    let eye = vec3(&json["ray"]["origin"]);
    let by_matrix = seen_by_projection(&json, eye, end);
    let end_seen = point(&mirror["image"]["end_seen"]);
    assert!(
        near(end_seen, by_matrix, 1e-2),
        "{end_seen:?} {by_matrix:?}"
    );
    // The line starts where the primary ray's hit is seen: the pixel.
    let from = point(&mirror["image"]["from"]);
    assert!(near(from, [250.5, 330.5], 1e-2), "{from:?}");
    let drawn = png(&dir.path().join("r.png"));
    let pixel = (end_seen[0].floor() as i64, end_seen[1].floor() as i64);
    assert_eq!(
        drawn.get_pixel(pixel.0 as u32, pixel.1 as u32).0,
        REFLECTED,
        "the mirror ray's hit's dot at {pixel:?}"
    );
    assert_eq!(drawn.get_pixel(250, 330).0, PRIMARY);
    // Along the mirror ray, half way: its colour.
    let mid = ((from[0] + end_seen[0]) / 2.0, (from[1] + end_seen[1]) / 2.0);
    assert!(has_colour_near(
        &drawn,
        (mid.0 as i64, mid.1 as i64),
        1,
        REFLECTED
    ));
}

#[test]
fn a_path_traced_pixel_draws_its_path_and_a_bad_draw_output_is_refused_first() {
    let dir = tempfile::tempdir().unwrap();
    let cornell = scene("cornell-box.toml");
    let args = ["explain", &cornell, "128", "100", "--sample", "3", "--json"];
    let json = explain_json(dir.path(), &args);
    let rays = json["drawing"]["rays"].as_array().unwrap();
    let events = json["events"].as_array().unwrap();
    // Each bounce ends at the next vertex the events list; each is the
    // event that traced it.
    let vertices: Vec<[f64; 3]> = events
        .iter()
        .filter(|e| e["event"] == "vertex")
        .map(|e| vec3(&e["point"]))
        .collect();
    let bounces: Vec<&Value> = rays.iter().filter(|r| r["kind"] == "bounce").collect();
    assert!(!bounces.is_empty(), "{}", json["drawing"]);
    for (k, bounce) in bounces.iter().enumerate() {
        let event = &events[bounce["event"].as_u64().unwrap() as usize];
        if bounce["end"].is_null() {
            assert_eq!(event["event"], "escaped");
            continue;
        }
        assert_eq!(event["event"], "vertex");
        assert_eq!(vec3(&bounce["end"]), vertices[k + 1]);
        assert_eq!(vec3(&bounce["origin"]), vertices[k]);
    }
    assert_eq!(
        rays.iter().filter(|r| r["kind"] == "shadow").count(),
        events
            .iter()
            .filter(|e| e["event"] == "light_sample"
                && e["f_cos"] != serde_json::json!([0.0, 0.0, 0.0]))
            .count()
    );
    // --draw to a float format is refused before the work, exit 2.
    let out = tracer(
        dir.path(),
        &["explain", &cornell, "1", "1", "--draw", "x.exr"],
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(!dir.path().join("x.exr").exists());
}
