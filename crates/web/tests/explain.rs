//! The browser build's explain, natively: the text `tracer explain` prints
//! (the pipeline's one formatter), ending in the rendered pixel's value.

use scene_format::source::Memory;
use std::path::{Path, PathBuf};
use tracer_pipeline::{Input, Options};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// The scene `name` of scenes/ (one that reads no other file), and a
/// folder in memory holding it.
fn alone(name: &str) -> (PathBuf, Memory) {
    let path = scenes().join(name);
    let mut files = Memory::new();
    files
        .insert(Path::new(name), std::fs::read(&path).unwrap())
        .unwrap();
    (path, files)
}

#[test]
fn a_pixel_s_tree_is_tracer_explain_s_text_with_the_rendered_value() {
    let name = "illumination.toml";
    let (path, files) = alone(name);
    // A pixel on the sphere (the image's centre), one of the background.
    let loaded = tracer_pipeline::load(&Input::File(path)).unwrap();
    let rgb = tracer_pipeline::render(&loaded, &Options::default(), &|_| {})
        .unwrap()
        .image
        .to_rgb8();
    for (x, y) in [(rgb.width() / 2, rgb.height() / 2), (0, 0)] {
        let shown = tracer_web::explain(&files, Path::new(name), (x, y), 0).unwrap();
        let pixel =
            tracer_pipeline::explain::explain(&loaded, &Options::default(), (x, y), 0).unwrap();
        // `tracer explain` names the scene as given; here, by the folder's path.
        let expected = tracer_pipeline::explain_text::text(&pixel, (x, y), name);
        assert_eq!(shown, expected);
        assert!(
            shown.starts_with(&format!("pixel ({x}, {y}) of {name} (")),
            "{shown}"
        );
        let [r, g, b] = rgb.get_pixel(x, y).0;
        assert!(
            shown.contains(&format!(
                "(int)(c * 255) = ({r}, {g}, {b}), the rendered pixel"
            )),
            "({r}, {g}, {b}) not in\n{shown}"
        );
    }
    // The image's centre is on the sphere: a hit, not the background.
    let centre = tracer_web::explain(&files, Path::new(name), (250, 200), 0).unwrap();
    assert!(centre.contains("nearest hit: object"), "{centre}");
}

#[test]
fn a_pixel_outside_the_image_is_a_located_error() {
    let name = "illumination.toml";
    let mut files = Memory::new();
    files
        .insert(Path::new(name), std::fs::read(scenes().join(name)).unwrap())
        .unwrap();
    let json = tracer_web::explain(&files, Path::new(name), (100_000, 0), 0).unwrap_err();
    let value: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert!(value["text"].as_str().unwrap().contains("100000"), "{json}");
    // A scene's own mistake is placed at its line, as a render's is.
    files
        .insert(Path::new(name), "[camera]\nfvo = 50\n".into())
        .unwrap();
    let json = tracer_web::explain(&files, Path::new(name), (0, 0), 0).unwrap_err();
    let value: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(value["problems"][0]["line"], 2, "{json}");
}

#[test]
fn any_sample_of_a_path_traced_pixel_is_explained_as_tracer_explain_does() {
    let name = "cornell-box.toml";
    let (path, files) = alone(name);
    let loaded = tracer_pipeline::load(&Input::File(path)).unwrap();
    let (x, y) = (128, 64);
    let mut texts = Vec::new();
    for sample in [0, 5] {
        let shown = tracer_web::explain(&files, Path::new(name), (x, y), sample).unwrap();
        let pixel = tracer_pipeline::explain::explain(&loaded, &Options::default(), (x, y), sample)
            .unwrap();
        assert_eq!(
            shown,
            tracer_pipeline::explain_text::text(&pixel, (x, y), name)
        );
        assert!(shown.contains(&format!("sample {sample} of 64")), "{shown}");
        texts.push(shown);
    }
    assert_ne!(texts[0], texts[1], "another sample traces another path");
    let json = tracer_web::explain(&files, Path::new(name), (x, y), 64).unwrap_err();
    assert!(json.contains("64"), "{json}");
}

#[test]
fn a_time_limit_the_explanation_does_not_keep_is_noted() {
    let name = "cornell-box.toml";
    let text = std::fs::read_to_string(scenes().join(name))
        .unwrap()
        .replace("samples = 64", "samples = 64\ntime_limit = 2");
    let mut files = Memory::new();
    files.insert(Path::new(name), text.into_bytes()).unwrap();
    let said = tracer_web::explain(&files, Path::new(name), (128, 128), 0).unwrap();
    assert!(
        said.starts_with("note: the scene's time_limit (2 s) is not used here"),
        "{said}"
    );
    // Without a limit, the text is `tracer explain`'s alone.
    let (_, files) = alone(name);
    let said = tracer_web::explain(&files, Path::new(name), (128, 128), 0).unwrap();
    assert!(said.starts_with("pixel (128, 128)"), "{said}");
}

/// The page's view of pixel (x, y) of scenes/`name`: its lines and drawing.
fn view(name: &str, (x, y): (u32, u32), sample: u32) -> (String, serde_json::Value) {
    let (_, files) = alone(name);
    let text = tracer_web::explain(&files, Path::new(name), (x, y), sample).unwrap();
    let json = tracer_web::explain_view(&files, Path::new(name), (x, y), sample).unwrap();
    (text, serde_json::from_str(&json).unwrap())
}

/// The line of `view` that starts with `start` (after its indentation).
fn line<'a>(view: &'a serde_json::Value, start: &str) -> &'a serde_json::Value {
    view["lines"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["text"].as_str().unwrap().starts_with(start))
        .unwrap_or_else(|| panic!("no line {start:?} in {view}"))
}

/// The drawn ray a line tells of.
fn ray_of<'a>(view: &'a serde_json::Value, line: &serde_json::Value) -> &'a serde_json::Value {
    &view["drawing"]["rays"][line["ray"].as_u64().expect("a ray") as usize]
}

#[test]
fn the_page_s_lines_are_the_text_in_steps_each_linked_to_its_drawn_ray() {
    let (text, view) = view("shadows.toml", (100, 150), 0);
    let lines = view["lines"].as_array().unwrap();
    // The text itself, line by line, its indentation as depth.
    let rejoined: String = lines
        .iter()
        .map(|l| {
            let depth = l["depth"].as_u64().unwrap() as usize;
            format!("{}{}\n", "  ".repeat(depth), l["text"].as_str().unwrap())
        })
        .collect();
    assert_eq!(rejoined, text);
    // Steps in order from 0, the primary ray's formula (three lines) one.
    let steps: Vec<u64> = lines.iter().map(|l| l["step"].as_u64().unwrap()).collect();
    assert_eq!(steps[0], 0);
    assert!(steps.windows(2).all(|w| w[1] == w[0] || w[1] == w[0] + 1));
    assert_eq!(steps[1..4], [1, 1, 1], "{view}");
    assert_eq!(*steps.last().unwrap() as usize, lines.len() - 3);
    // The primary ray, its hit, its blocked shadow ray and the gamma.
    let primary = line(&view, "primary ray from");
    assert_eq!(
        (primary["section"].as_str(), primary["ray"].as_u64()),
        (Some("1.2.3"), Some(0))
    );
    assert_eq!(line(&view, "nearest hit:")["section"], "1.3");
    let shadow_line = line(&view, "shadow ray from");
    assert_eq!(shadow_line["section"], "1.4");
    let shadow = ray_of(&view, shadow_line);
    assert_eq!(shadow["kind"], "shadow");
    assert_eq!(shadow["blocked_by"]["name"], "objects[1]");
    assert!(shadow_line["text"]
        .as_str()
        .unwrap()
        .ends_with("blocked by objects[1] at t = 5.5422"));
    assert_eq!(line(&view, "gamma 2.2")["section"], "gamma");
    assert!(line(&view, "gamma 2.2")["ray"].is_null());
}

#[test]
fn a_mirror_ray_s_line_and_a_path_s_events_are_linked_to_their_drawn_rays() {
    let (_, mirror) = view("reflectance2.toml", (250, 330), 0);
    let line_of_mirror = line(&mirror, "mirror ray from");
    assert_eq!(line_of_mirror["section"], "1.5");
    assert_eq!(line_of_mirror["depth"], 1);
    let ray = ray_of(&mirror, line_of_mirror);
    assert_eq!(ray["kind"], "reflected");
    assert_eq!(ray["parent"], 0);
    // Path mode: vertex 1 is where the first bounce ends; a light sample's
    // line is its shadow ray's.
    let (_, path) = view("cornell-box.toml", (128, 100), 3);
    let vertex = line(&path, "vertex 1:");
    assert_eq!(vertex["section"], "path");
    let bounce = ray_of(&path, vertex);
    assert_eq!(bounce["kind"], "bounce");
    assert_eq!(bounce["parent"], 0);
    assert_eq!(line(&path, "vertex 0:")["ray"], 0);
    assert_eq!(
        ray_of(&path, line(&path, "light sample toward"))["kind"],
        "shadow"
    );
}

#[test]
fn the_3d_view_holds_each_object_of_the_file_and_the_pixel_on_the_image_plane() {
    for (name, pixel) in [
        ("reflectance2.toml", (250, 330)),
        ("cornell-box.toml", (128, 100)),
    ] {
        let (_, view) = view(name, pixel, 0);
        let scene = &view["scene"];
        let file = std::fs::read_to_string(scenes().join(name)).unwrap();
        let objects = scene["objects"].as_array().unwrap();
        assert_eq!(
            objects.len(),
            file.lines().filter(|l| l.trim() == "[[objects]]").count(),
            "{name}"
        );
        for (k, o) in objects.iter().enumerate() {
            assert_eq!(o["name"], format!("objects[{k}]"));
            let shapes =
                o["spheres"].as_array().unwrap().len() + o["triangles"].as_array().unwrap().len();
            assert!(shapes > 0, "{name} {o}");
        }
        // The clicked pixel on the image plane is along the primary ray.
        let v = |j: &serde_json::Value| [0, 1, 2].map(|k| j[k].as_f64().unwrap());
        let (eye, at) = (v(&scene["camera"]["eye"]), v(&scene["camera"]["pixel"]));
        let d = [at[0] - eye[0], at[1] - eye[1], at[2] - eye[2]];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let primary = v(&view["drawing"]["rays"][0]["direction"]);
        // Sample 0 of a path-traced pixel is jittered: within the pixel.
        let cos = (0..3).map(|k| d[k] / len * primary[k]).sum::<f64>();
        assert!(cos > 0.99999, "{name}: {cos}");
    }
    // reflectance2: three balls and a plane (two triangles).
    let (_, view) = view("reflectance2.toml", (250, 330), 0);
    let spheres: usize = view["scene"]["objects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["spheres"].as_array().unwrap().len())
        .sum();
    assert_eq!(spheres, 3);
}
