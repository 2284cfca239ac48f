//! Mesh objects in scene files: the OBJ path is relative to the scene file,
//! and a file that cannot be read is an error at `objects[i].mesh.obj`.

use scene_format::{load_path, mesh_warnings, SceneError};
use std::path::Path;

const HEAD: &str = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n";

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(&path, text).unwrap();
    path
}

fn diagnostics(e: SceneError) -> Vec<(String, String)> {
    e.diagnostics()
        .iter()
        .map(|d| (d.path.to_string(), d.message.clone()))
        .collect()
}

#[test]
fn obj_path_is_relative_to_the_scene_file() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "models/tri.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 2 2\nf 1 2 3\nf 1 1 2\n",
    );
    let scene = format!(
        "{HEAD}[[objects]]\nmesh = {{ obj = \"models/tri.obj\" }}\n\
         transform = {{ translate = [1, 2, 3], rotate = [0, 90, 0], scale = 2 }}\n\
         [[objects]]\nmesh = {{ obj = \"models/tri.obj\" }}\n"
    );
    let path = write(dir.path(), "scene.toml", &scene);
    let file = load_path(&path).unwrap_or_else(|e| panic!("{e}"));
    let mesh = file.objects[0].mesh.as_ref().unwrap();
    let data = mesh.data.as_ref().expect("the OBJ was read");
    let again = file.objects[1]
        .mesh
        .as_ref()
        .unwrap()
        .data
        .as_ref()
        .unwrap();
    assert!(std::sync::Arc::ptr_eq(data, again), "read once, shared");
    assert_eq!(
        data.triangles,
        vec![[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]]
    );
    let warnings = mesh_warnings(&file);
    assert_eq!(warnings.len(), 2);
    assert_eq!(warnings[0].path, "objects[0].mesh.obj");
    assert_eq!(
        warnings[0].message,
        "1 degenerate (zero-area) faces left out; the first at `tri.obj:6`"
    );
}

#[test]
fn a_missing_obj_is_located() {
    let dir = tempfile::tempdir().unwrap();
    let scene = format!(
        "{HEAD}[[objects]]\nsphere = {{ center = [0, 0, 0], radius = 1 }}\n\
         [[objects]]\nmesh = {{ obj = \"nowhere.obj\" }}\n"
    );
    let path = write(dir.path(), "scene.toml", &scene);
    let found = diagnostics(load_path(&path).unwrap_err());
    assert_eq!(found.len(), 1);
    assert_eq!(found[0].0, "objects[1].mesh.obj");
    assert!(found[0].1.contains("nowhere.obj"), "{}", found[0].1);
}

#[test]
fn every_shape_takes_a_transform_and_a_sphere_an_uneven_scale_too() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "tri.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let scene = format!(
        "{HEAD}[[objects]]\nsphere = {{ center = [0, 0, 0], radius = 1 }}\n\
         transform = [{{ translate = [1, 0, 0] }}, {{ scale = -2 }}, {{ rotate = [0, 90, 0] }}]\n\
         [[objects]]\nsphere = {{ center = [0, 0, 0], radius = 1 }}\n\
         transform = [{{ rotate = [0, 90, 0] }}, {{ scale = [1, 2, 1] }}]\n\
         [[objects]]\nmesh = {{ obj = \"tri.obj\" }}\n\
         transform = {{ scale = [1, 0, 1] }}\n\
         [[objects]]\nplane = {{ point = [0, 0, 0], normal = [0, 1, 0] }}\n\
         transform = [{{ scale = [1, 3, 1] }}, {{ translate = [0, 1e9, 0] }}]\n\
         [[objects]]\nbox = {{ min = [0, 0, 0], max = [1, 1, 1] }}\n\
         transform = {{ rotate = [0, 45, 0], scale = [1, 2, 3] }}\n"
    );
    let path = write(dir.path(), "scene.toml", &scene);
    let found = diagnostics(load_path(&path).unwrap_err());
    let paths: Vec<&str> = found.iter().map(|(p, _)| p.as_str()).collect();
    // The sphere scaled unevenly is an ellipsoid: no error.
    assert_eq!(
        paths,
        [
            "objects[2].transform.scale",
            "objects[3].transform[1].translate"
        ]
    );
}

#[test]
fn a_transform_step_of_the_wrong_kind_says_what_is_expected() {
    let scene = format!(
        "{HEAD}[[objects]]\nsphere = {{ center = [0, 0, 0], radius = 1 }}\n\
         transform = [{{ shear = 1 }}]\n"
    );
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "scene.toml", &scene);
    let found = diagnostics(load_path(&path).unwrap_err());
    assert_eq!(found.len(), 1);
    assert!(found[0].0.starts_with("objects[0].transform"), "{found:?}");
    assert!(found[0].1.contains("translate"), "{found:?}");
}

#[test]
fn a_scale_of_the_wrong_type_says_what_is_expected() {
    let text = format!(
        "{HEAD}[[objects]]\nmesh = {{ obj = \"m.obj\" }}\ntransform = {{ scale = \"big\" }}\n"
    );
    let e =
        scene_format::load_str(&text, scene_format::Format::Toml, Path::new("s.toml")).unwrap_err();
    let message = e.to_string();
    assert!(message.contains("a number (one factor"), "{message}");
    assert!(message.contains("s.toml:6:"), "{message}");
}

#[test]
fn a_self_intersecting_face_is_a_warning_naming_its_line() {
    let dir = tempfile::tempdir().unwrap();
    // A bow tie on line 6: fanned, and said.
    write(
        dir.path(),
        "tie.obj",
        "v 0 0 0\nv 1 1 0\nv 1 0 0\nv 0 1 0\nv -0.5 0.5 0\nf 1 2 3 4 5\n",
    );
    let scene = format!("{HEAD}[[objects]]\nmesh = {{ obj = \"tie.obj\" }}\n");
    let file = load_path(&write(dir.path(), "scene.toml", &scene)).unwrap();
    let warnings = mesh_warnings(&file);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!(warnings[0].path.to_string(), "objects[0].mesh.obj");
    assert_eq!(
        warnings[0].message,
        "1 faces of more than 3 corners cut as fans from their first corner, which may not be \
         their shape; the first at `tie.obj:6` is self-intersecting"
    );
}

#[test]
fn faces_a_file_repeats_are_left_out_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    // One face written 1000 times, once from another corner (kept: it
    // rounds otherwise), once under other vertex numbers, and another.
    let mut obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n".to_string();
    obj += &"f 1 2 3\n".repeat(1000);
    obj += "f 2 3 1\nf 4 5 6\nf 1 2 7\n";
    write(dir.path(), "copies.obj", &obj);
    let scene = format!("{HEAD}[[objects]]\nmesh = {{ obj = \"copies.obj\" }}\n");
    let path = write(dir.path(), "scene.toml", &scene);
    let file = load_path(&path).unwrap_or_else(|e| panic!("{e}"));
    let data = file.objects[0]
        .mesh
        .as_ref()
        .unwrap()
        .data
        .as_ref()
        .unwrap();
    assert_eq!(data.triangles.len(), 3);
    assert_eq!(data.skipped_repeated, 1000);
    let warnings: Vec<String> = mesh_warnings(&file)
        .into_iter()
        .map(|d| d.message)
        .collect();
    assert_eq!(
        warnings,
        ["1000 faces left out that repeat an earlier face (the same corners in the same order): every ray through one would test each copy"]
    );
}
