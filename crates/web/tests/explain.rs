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
