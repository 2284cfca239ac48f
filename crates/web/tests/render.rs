//! The browser build's render, natively: the same image as `tracer render`,
//! bands merged into the whole image bit for bit, errors located.

use scene_format::source::Memory;
use std::path::{Path, PathBuf};
use tracer_pipeline::{Input, Options, Region};
use tracer_web::{render, render_passes, Request};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// The scene at `name` under scenes/ with the files it reads, in memory.
fn folder(name: &str) -> Memory {
    let path = scenes().join(name);
    let loaded = tracer_pipeline::load(&Input::File(path.clone())).unwrap();
    let mut memory = Memory::new();
    for file in loaded.files_read {
        let relative = file.strip_prefix(scenes()).unwrap();
        memory
            .insert(relative, std::fs::read(&file).unwrap())
            .unwrap();
    }
    memory
}

fn native_rgba(name: &str) -> Vec<u8> {
    let loaded = tracer_pipeline::load(&Input::File(scenes().join(name))).unwrap();
    let rgb = tracer_pipeline::render(&loaded, &Options::default(), &|_| {})
        .unwrap()
        .image
        .to_rgb8();
    rgb.pixels().flat_map(|p| [p[0], p[1], p[2], 255]).collect()
}

#[test]
fn bands_of_a_scene_with_files_merge_into_tracer_render_s_image() {
    let name = "textures.toml";
    let files = folder(name);
    let whole = render(&files, Path::new(name), &Request::default()).unwrap();
    assert_eq!(whole.size, (480, 320));
    assert_eq!(whole.full, (480, 320));
    assert!(whole.rays > 480 * 320, "{}", whole.rays);
    assert!(
        whole.rgba == native_rgba(name),
        "differs from tracer render"
    );
    let mut merged = Vec::new();
    for (y0, y1) in [(0, 100), (100, 101), (101, 320)] {
        let region = Region {
            x0: 0,
            y0,
            x1: 480,
            y1,
        };
        let request = Request {
            region: Some(region),
            ..Request::default()
        };
        let band = render(&files, Path::new(name), &request).unwrap();
        assert_eq!(band.rgba.len(), (480 * (y1 - y0) * 4) as usize);
        merged.extend(band.rgba);
    }
    assert!(merged == whole.rgba, "the merged bands differ");
}

#[test]
fn a_preview_is_the_same_view_narrower_and_a_canvas_is_cropped() {
    let files = folder("reflectance2.toml");
    let request = Request {
        shrink: Some(4),
        samples: Some(1),
        region: None,
    };
    let preview = render(&files, Path::new("reflectance2.toml"), &request).unwrap();
    assert_eq!((preview.size, preview.full), ((125, 100), (500, 400)));
    let files = folder("robot.toml");
    let region = Region {
        x0: 10,
        y0: 20,
        x1: 30,
        y1: 25,
    };
    let request = Request {
        region: Some(region),
        ..Request::default()
    };
    let part = render(&files, Path::new("robot.toml"), &request).unwrap();
    let whole = native_rgba("robot.toml");
    let width = part.full.0 as usize;
    let expected: Vec<u8> = (20..25)
        .flat_map(|y| whole[(y * width + 10) * 4..(y * width + 30) * 4].to_vec())
        .collect();
    assert_eq!(part.rgba, expected);
}

#[test]
fn errors_are_json_with_the_words_and_places_of_tracer_check() {
    let mut files = Memory::new();
    let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfvo = 50\n";
    files.insert(Path::new("s.toml"), text.into()).unwrap();
    let json = render(&files, Path::new("s.toml"), &Request::default()).unwrap_err();
    let value: serde_json::Value = serde_json::from_str(&json).unwrap();
    let loaded = tracer_pipeline::load_from(&files, Path::new("s.toml")).unwrap_err();
    assert_eq!(value["text"], loaded.to_string());
    assert!(
        value["text"].as_str().unwrap().contains("s.toml:4:1"),
        "{json}"
    );
    let problem = &value["problems"][0];
    assert_eq!(problem["file"], "s.toml");
    assert_eq!(
        (problem["line"].clone(), problem["column"].clone()),
        (4.into(), 1.into())
    );
    assert_eq!(problem["key"], "camera.fvo");
    // The key `fvo` is marked, not the rest of the line.
    assert_eq!(
        (problem["end_line"].clone(), problem["end_column"].clone()),
        (4.into(), 4.into())
    );
    // A region outside the image is refused, not a panic.
    files
        .insert(Path::new("s.toml"), text.replace("fvo", "fov").into())
        .unwrap();
    let request = Request {
        region: Some(Region {
            x0: 0,
            y0: 0,
            x1: 501,
            y1: 1,
        }),
        ..Request::default()
    };
    let json = render(&files, Path::new("s.toml"), &request).unwrap_err();
    assert!(json.contains("outside the 500x400 image"), "{json}");
}

#[test]
fn a_packed_archive_renders_as_its_scene() {
    let dir = tempfile::tempdir().unwrap();
    let zip = dir.path().join("t.zip");
    tracer_pipeline::pack::pack(&scenes().join("textures.toml"), &zip).unwrap();
    let mut files = Memory::new();
    files
        .insert(Path::new("t.zip"), std::fs::read(&zip).unwrap())
        .unwrap();
    let image = render(&files, Path::new("t.zip"), &Request::default()).unwrap();
    assert!(image.rgba == native_rgba("textures.toml"));
}

#[test]
fn a_path_traced_scene_renders_in_passes_whose_last_is_the_image() {
    let name = "cornell-box.toml";
    let files = folder(name);
    let region = Region {
        x0: 0,
        y0: 100,
        x1: 256,
        y1: 140,
    };
    let request = Request {
        region: Some(region),
        ..Request::default()
    };
    let mut passes = Vec::new();
    let whole = render_passes(&files, Path::new(name), &request, &mut |pass| {
        assert_eq!(pass.rgba.len(), 256 * 40 * 4);
        passes.push((pass.samples, pass.total, pass.rgba.to_vec()));
        true
    })
    .unwrap();
    let counts: Vec<u32> = passes.iter().map(|p| p.0).collect();
    assert_eq!(counts, [1, 2, 4, 8, 16, 32, 64]);
    assert!(passes.iter().all(|p| p.1 == 64));
    assert_eq!(whole.samples, (64, 64));
    let native = native_rgba(name);
    let rows = &native[256 * 100 * 4..256 * 140 * 4];
    assert!(whole.rgba == rows, "differs from tracer render");
    assert!(passes[6].2 == whole.rgba, "the last pass is the image");
    assert!(passes[0].2 != whole.rgba, "one sample is noisier");

    // Stopped after the second pass: the image of two samples a pixel.
    let stopped = render_passes(&files, Path::new(name), &request, &mut |pass| {
        pass.samples < 2
    })
    .unwrap();
    assert_eq!(stopped.samples, (2, 64));
    assert!(stopped.rgba == passes[1].2);
}

#[test]
fn warnings_come_with_the_image_at_their_place() {
    let text = std::fs::read_to_string(scenes().join("cornell-box.toml")).unwrap();
    let text = text.replacen(
        "diffuse = [0.885809, 0.698859, 0.666422]",
        "diffuse = [200, 180, 170]",
        1,
    );
    let mut files = Memory::new();
    files
        .insert(Path::new("box.toml"), text.clone().into_bytes())
        .unwrap();
    let request = Request {
        shrink: Some(8),
        samples: Some(1),
        ..Request::default()
    };
    let image = render(&files, Path::new("box.toml"), &request).unwrap();
    let line = 1 + text[..text.find("diffuse = [200").unwrap()]
        .matches('\n')
        .count();
    let warning = image
        .warnings
        .iter()
        .find(|w| w.message.contains("not 0 to 255"))
        .unwrap_or_else(|| panic!("{:?}", image.warnings));
    assert_eq!(warning.location.map(|l| l.line), Some(line));
    assert!(
        warning
            .text
            .starts_with("warning: box.toml: `materials.white"),
        "{}",
        warning.text
    );
}

#[test]
fn an_image_larger_than_the_page_renders_is_a_mistake_at_its_width() {
    let mut files = Memory::new();
    let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nwidth = 8192\nheight = 4096\n";
    files.insert(Path::new("s.toml"), text.into()).unwrap();
    let preview = Request {
        shrink: Some(4),
        samples: Some(1),
        ..Request::default()
    };
    let json = render(&files, Path::new("s.toml"), &preview).unwrap_err();
    let value: serde_json::Value = serde_json::from_str(&json).unwrap();
    let problem = &value["problems"][0];
    assert_eq!(problem["key"], "camera.width", "{json}");
    assert_eq!(problem["line"], 4, "{json}");
    assert!(
        problem["message"]
            .as_str()
            .unwrap()
            .contains("at most 4096x4096"),
        "{json}"
    );
    // 4096 x 4096 is still rendered (a preview of it, quickly).
    let fits = text.replace("8192", "4096");
    files.insert(Path::new("s.toml"), fits.into()).unwrap();
    assert!(render(&files, Path::new("s.toml"), &preview).is_ok());
    // A canvas the same.
    let canvas = "[canvas]\nwidth = 16384\nheight = 16384\n";
    files.insert(Path::new("c.toml"), canvas.into()).unwrap();
    let json = render(&files, Path::new("c.toml"), &preview).unwrap_err();
    assert!(json.contains("\"key\":\"canvas.width\""), "{json}");
}

#[test]
fn a_previews_one_sample_brings_no_warning_of_the_scenes_samples() {
    // Through a lens, below 16 samples is warned about: the scene has 64,
    // its preview 1.
    let name = "depth-of-field.toml";
    let files = folder(name);
    let preview = Request {
        shrink: Some(4),
        samples: Some(1),
        ..Request::default()
    };
    let image = render(&files, Path::new(name), &preview).unwrap();
    assert!(
        !image.warnings.iter().any(|w| w.key == "render.samples"),
        "{:?}",
        image.warnings
    );
}

#[test]
fn a_gltf_model_renders_as_tracer_render_renders_it() {
    let name = "khronos/BoxTextured.gltf";
    let mut files = Memory::new();
    let bytes = std::fs::read(scenes().join(name)).unwrap();
    files.insert(Path::new("BoxTextured.gltf"), bytes).unwrap();
    let image = render(&files, Path::new("BoxTextured.gltf"), &Request::default()).unwrap();
    let expected = native_rgba(name);
    assert_eq!(image.rgba.len(), expected.len());
    assert!(image.rgba == expected, "differs from tracer render");
    // Not a blank image: the textured box is there.
    assert!(image.rgba.chunks(4).any(|p| p != &image.rgba[..4]));
}

#[test]
fn a_broken_gltf_model_s_error_names_its_json_path() {
    let mut files = Memory::new();
    let text = r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [3]}]}"#;
    files.insert(Path::new("m.gltf"), text.into()).unwrap();
    let json = render(&files, Path::new("m.gltf"), &Request::default()).unwrap_err();
    let value: serde_json::Value = serde_json::from_str(&json).unwrap();
    let loaded = tracer_pipeline::load_from(&files, Path::new("m.gltf")).unwrap_err();
    assert_eq!(value["text"], loaded.to_string());
    assert_eq!(value["problems"][0]["file"], "m.gltf", "{json}");
    assert!(
        value["text"]
            .as_str()
            .unwrap()
            .contains("scenes[0].nodes[0]"),
        "{json}"
    );
}
