//! `include = [...]`: every folder in `tests/include/` is a scene
//! (`scene.toml`) with the files it includes. The good one merges as the
//! book says (docs/src/guide/include-pack.md); each bad one is rejected with the problem in the file that
//! holds it, at the key path, line and column listed here (worked out by
//! reading the files), and its report is snapshotted.

use scene_format::{load_file, Object, SceneError, SceneKind};
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/include")
}

/// One file's first problem: the file below the case's folder, the key
/// path, line, column and a part of the message.
type Expected = (&'static str, &'static str, usize, usize, &'static str);

#[rustfmt::skip]
const CASES: &[(&str, &[Expected])] = &[
    ("value-in-included", &[("lib/materials.toml", "materials.shiny.shininess", 7, 13, "expected a number >= 0, found -30")]),
    ("unknown-key-in-included", &[("materials.toml", "materials.red.difuse", 2, 1, "unknown key `difuse` in [materials.red]; did you mean `diffuse`?")]),
    ("missing-include", &[("scene.toml", "include[1]", 3, 3, "cannot read `lights.toml`: ")]),
    ("cycle", &[("b.toml", "include[0]", 2, 12, "`a.toml` includes itself (a.toml -> b.toml -> a.toml); it is first included at include/cycle/scene.toml:1:12")]),
    ("duplicate-material", &[("scene.toml", "materials.red", 7, 1, "material `red` is defined twice: first at include/duplicate-material/materials.toml:4:12")]),
    ("camera-in-included", &[("view.toml", "camera", 4, 2, "an included file cannot set `camera`")]),
    ("missing-obj-in-included", &[("parts/objects.toml", "objects[1].mesh.obj", 5, 16, "cannot load `missing.obj`: ")]),
    ("json-included", &[("lights.json", "lights[1].color", 4, 38, "expected a colour with channels >= 0")]),
    ("unknown-material-in-included", &[("objects.toml", "objects[1].material", 7, 12, "unknown material `bleu`; did you mean `blue`?")]),
    ("several-files", &[
        ("scene.toml", "camera.fov", 6, 7, "found 0"),
        ("objects.toml", "objects[0].sphere.radius", 2, 41, "expected a radius from 1e-4 to 1e6, found -2"),
    ]),
];

/// What a file's first problem is: file, key path, line and column, message.
type Found = (String, String, Option<(usize, usize)>, String);

fn load_case(case: &str) -> Result<SceneKind, SceneError> {
    load_file(&dir().join(case).join("scene.toml")).map(|l| l.kind)
}

/// The report with the checkout's folder left out.
fn report(error: &SceneError) -> String {
    without_checkout(&error.to_string())
}

/// `text` with the path of the tests' folder left out, so file names read
/// `include/<case>/...` wherever the checkout is.
fn without_checkout(text: &str) -> String {
    let tests = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    text.replace(&format!("{}/", tests.display()), "")
}

#[test]
fn each_problem_is_shown_in_the_file_that_holds_it() {
    let mut failures = Vec::new();
    for (case, expected) in CASES {
        let error = match load_case(case) {
            Ok(_) => panic!("{case}: accepted, expected an error"),
            Err(e) => e,
        };
        let files = error.files();
        let found: Vec<Found> = files
            .iter()
            .map(|e| match e {
                SceneError::Invalid {
                    file, diagnostics, ..
                } => {
                    let d = &diagnostics[0];
                    let name = file.strip_prefix(dir().join(case)).unwrap_or(file);
                    (
                        name.display().to_string(),
                        d.path.to_string(),
                        d.location.map(|l| (l.line, l.column)),
                        without_checkout(&d.message),
                    )
                }
                other => panic!("{case}: {other}"),
            })
            .collect();
        let matches = found.len() == expected.len()
            && found.iter().zip(expected.iter()).all(|(f, e)| {
                f.0 == e.0 && f.1 == e.1 && f.2 == Some((e.2, e.3)) && f.3.contains(e.4)
            });
        if !matches {
            failures.push(format!("{case}: expected {expected:?}\n   got {found:?}"));
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

#[test]
fn every_folder_has_a_case() {
    let mut folders: Vec<String> = std::fs::read_dir(dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|f| f != "good")
        .collect();
    folders.sort();
    let mut listed: Vec<&str> = CASES.iter().map(|c| c.0).collect();
    listed.sort();
    assert_eq!(folders, listed);
}

#[test]
fn reports_name_each_file_with_its_lines() {
    for (case, _) in CASES {
        let error = load_case(case).unwrap_err();
        insta::assert_snapshot!(format!("include-{case}"), report(&error));
    }
}

/// What tells the merged objects apart: the sphere's radius, or the
/// mesh's triangle count.
fn shape(o: &Object) -> String {
    match (&o.sphere, &o.mesh) {
        (Some(s), _) => format!("sphere {}", s.radius),
        (_, Some(m)) => format!(
            "mesh {} triangles",
            m.data.as_ref().map_or(0, |d| d.triangles.len())
        ),
        _ => "other".to_string(),
    }
}

#[test]
fn included_items_come_first_in_list_order_then_the_scenes_own() {
    let SceneKind::Scene3d(scene) = load_case("good").unwrap() else {
        panic!("expected a 3D scene");
    };
    // common.toml includes nested.toml first, then has its own; then
    // more.json; then the scene's own.
    let lights: Vec<[f32; 3]> = scene.lights.iter().map(|l| l.position.unwrap()).collect();
    assert_eq!(lights, [[1.0; 3], [2.0; 3], [3.0; 3]]);
    let objects: Vec<String> = scene.objects.iter().map(shape).collect();
    assert_eq!(
        objects,
        ["sphere 1", "mesh 1 triangles", "sphere 2", "sphere 3"]
    );
    let names: Vec<&str> = scene.materials.keys().map(|k| k.as_str()).collect();
    assert_eq!(names, ["common", "nested", "own"]);
}

#[test]
fn the_files_read_are_the_scene_its_includes_and_their_meshes() {
    let loaded = load_file(&dir().join("good/scene.toml")).unwrap();
    let names: Vec<String> = loaded
        .files_read
        .iter()
        .map(|f| {
            f.strip_prefix(dir().join("good"))
                .unwrap()
                .display()
                .to_string()
        })
        .collect();
    assert_eq!(
        names,
        [
            "scene.toml",
            "lib/common.toml",
            "lib/nested.toml",
            "lib/tri.obj",
            "lib/more.json"
        ]
    );
}

#[test]
fn a_scene_given_as_text_cannot_include() {
    let text = "include = [\"m.toml\"]\n[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n";
    let error =
        scene_format::load_str(text, scene_format::Format::Toml, Path::new("s.toml")).unwrap_err();
    let d = &error.diagnostics()[0];
    assert_eq!(d.path.to_string(), "include");
    assert_eq!(d.location.map(|l| (l.line, l.column)), Some((1, 11)));
}
