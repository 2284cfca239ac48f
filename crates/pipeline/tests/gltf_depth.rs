//! Khronos samples seen by the tracer and by Blender's own glTF importer:
//! the depth (distance from the camera to the nearest surface) of each
//! pixel against `tests/data/gltf_depth.json`, which
//! `xtask/peers/gltf_reference.py` made with bpy (Blender as a Python
//! module), casting each pixel's ray into the scene Blender imported. A
//! model turned the wrong way, mirrored, or a camera read otherwise than
//! Blender reads it would move the silhouettes and the distances.

use std::path::{Path, PathBuf};
use tracer_pipeline::{load, render, Aov, Input, Options};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

/// The tracer's depth image of a case: the model rendered on its own (its
/// own camera), or in a scene of the case's camera.
fn tracer_depth(case: &serde_json::Value, dir: &Path) -> (u32, u32, Vec<f32>) {
    let model = repo("scenes/khronos").join(case["model"].as_str().unwrap());
    let [width, height] = [0, 1].map(|k| case["size"][k].as_u64().unwrap() as u32);
    let input = match &case["camera"] {
        serde_json::Value::String(s) if s == "file" => Input::File(model),
        camera => {
            let list = |key: &str| camera[key].to_string();
            let projection = match camera.get("view_width") {
                Some(w) => format!("projection = \"orthographic\"\nview_width = {w}\n"),
                None => format!("fov = {}\n", camera["fov"]),
            };
            let text = format!(
                "[camera]\neye = {}\nlook_at = {}\nhandedness = \"right\"\nwidth = {width}\nheight = {height}\n{projection}\n\
                 [[lights]]\nposition = [0, 5, 5]\n\n[[objects]]\ngltf = {{ file = {:?} }}\n",
                list("eye"),
                list("look_at"),
                model.to_str().unwrap()
            );
            let scene = dir.join("scene.toml");
            std::fs::write(&scene, text).unwrap();
            Input::File(scene)
        }
    };
    let loaded = load(&input).unwrap();
    let options = Options {
        aov: Some(Aov::Depth),
        raw_depth: true,
        width: Some(width),
        height: Some(height),
        samples: Some(1),
        ..Options::default()
    };
    let image = render(&loaded, &options, &|_| {}).unwrap().image.linear;
    assert_eq!((image.width, image.height), (width, height));
    let values = (0..height)
        .flat_map(|j| (0..width).map(move |i| (i, j)))
        .map(|(i, j)| image.get(i, j).x)
        .collect();
    (width, height, values)
}

#[test]
fn depth_images_agree_with_blenders_importer() {
    let text = std::fs::read_to_string(repo("crates/pipeline/tests/data/gltf_depth.json")).unwrap();
    let reference: serde_json::Value = serde_json::from_str(&text).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let cases = reference.as_object().unwrap();
    let mut compared = 0;
    for (name, case) in cases.iter().filter(|(k, _)| *k != "blender") {
        let (width, height, ours) = tracer_depth(case, dir.path());
        let theirs: Vec<f32> = case["depth"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap() as f32)
            .collect();
        assert_eq!(ours.len(), theirs.len(), "{name}");
        // Pixels where one sees the model and the other not: only along
        // the silhouette, where a ray grazes an edge (a few in a hundred).
        let coverage = |d: &[f32]| d.iter().filter(|&&x| x > 0.0).count();
        let differ = ours
            .iter()
            .zip(&theirs)
            .filter(|(a, b)| (**a > 0.0) != (**b > 0.0))
            .count();
        assert!(coverage(&theirs) > 50, "{name}: Blender sees little");
        assert!(
            differ * 50 <= coverage(&theirs),
            "{name}: {differ} pixels of {width}x{height} hit in one image only (Blender covers {}, the tracer {})",
            coverage(&theirs),
            coverage(&ours)
        );
        // Where both hit, the same distance (single precision, 1e-4).
        for (k, (a, b)) in ours.iter().zip(&theirs).enumerate() {
            if *a > 0.0 && *b > 0.0 {
                let (i, j) = (k as u32 % width, k as u32 / width);
                assert!(
                    (a - b).abs() < 1e-4 * b.max(1.0),
                    "{name} ({i}, {j}): {a} against {b}"
                );
            }
        }
        compared += 1;
    }
    assert_eq!(compared, 4);
}
