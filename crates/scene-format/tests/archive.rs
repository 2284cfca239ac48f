//! Scenes read from a zip archive (`tracer pack`'s): as from a folder,
//! errors named `archive.zip:entry`, and nothing read from outside the
//! archive's folder.

use scene_format::source::{Archive, Source};
use scene_format::{load_file, SceneError, SceneKind};
use std::io::Write;
use std::path::{Path, PathBuf};

const SCENE: &str = "include = [\"lib/materials.toml\"]\n\
                     [camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
                     [[objects]]\nmesh = { obj = \"../meshes/tri.obj\" }\nmaterial = \"red\"\n";
const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// A zip archive at `dir/name` holding `entries` (name, text).
fn zip(dir: &Path, name: &str, entries: &[(&str, &str)]) -> PathBuf {
    let path = dir.join(name);
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
    let options = zip::write::SimpleFileOptions::default();
    for (entry, text) in entries {
        zip.start_file(*entry, options).unwrap();
        zip.write_all(text.as_bytes()).unwrap();
    }
    zip.finish().unwrap();
    path
}

fn packed(materials: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = zip(
        dir.path(),
        "s.zip",
        &[
            ("tracer-pack.toml", "scene = \"scenes/s.toml\"\n"),
            ("scenes/s.toml", SCENE),
            ("scenes/lib/materials.toml", materials),
            ("meshes/tri.obj", TRIANGLE),
        ],
    );
    (dir, path)
}

#[test]
fn a_packed_scene_reads_its_includes_and_meshes_from_the_archive() {
    let (_dir, path) = packed("[materials.red]\ndiffuse = [1, 0, 0]\n");
    let loaded = load_file(&path).unwrap();
    let SceneKind::Scene3d(scene) = loaded.kind else {
        panic!("expected a 3D scene");
    };
    let mesh = scene.objects[0].mesh.as_ref().unwrap();
    assert_eq!(mesh.data.as_ref().unwrap().triangles.len(), 1);
    assert_eq!(scene.materials["red"].diffuse, [1.0, 0.0, 0.0]);
    // The archive is the one file read on the file system.
    assert_eq!(loaded.files_read, [path]);
}

#[test]
fn errors_inside_name_the_archive_and_the_entry() {
    let (_dir, path) = packed("[materials.red]\ndiffuse = [1, 0, 0]\nshininess = -1\n");
    let error = load_file(&path).unwrap_err();
    let SceneError::Invalid {
        file, diagnostics, ..
    } = &error
    else {
        panic!("{error}");
    };
    assert_eq!(
        *file,
        PathBuf::from(format!("{}:scenes/lib/materials.toml", path.display()))
    );
    let d = &diagnostics[0];
    assert_eq!(d.path.to_string(), "materials.red.shininess");
    assert_eq!(d.location.map(|l| (l.line, l.column)), Some((3, 13)));
}

#[test]
fn an_entry_that_climbs_out_refuses_the_archive() {
    let dir = tempfile::tempdir().unwrap();
    for evil in ["../evil.toml", "scenes/../../evil.obj", "/etc/evil.toml"] {
        let path = zip(dir.path(), "evil.zip", &[("s.toml", SCENE), (evil, "x")]);
        let error = load_file(&path).unwrap_err();
        let SceneError::Io { source, .. } = &error else {
            panic!("{evil}: {error}");
        };
        assert_eq!(source.kind(), std::io::ErrorKind::InvalidData, "{evil}");
        assert!(
            error.to_string().contains("outside the archive's folder"),
            "{error}"
        );
    }
}

#[test]
fn a_path_from_the_scene_that_climbs_out_is_not_found() {
    let dir = tempfile::tempdir().unwrap();
    let scene = SCENE.replace("../meshes/tri.obj", "../../tri.obj");
    let path = zip(
        dir.path(),
        "s.zip",
        &[
            ("s.toml", &scene),
            ("lib/materials.toml", "[materials.red]\n"),
        ],
    );
    let error = load_file(&path).unwrap_err();
    let d = &error.diagnostics()[0];
    assert_eq!(d.path.to_string(), "objects[0].mesh.obj");
    assert!(d.message.contains("leaves the archive"), "{}", d.message);
}

#[test]
fn without_a_manifest_the_one_top_level_scene_is_read() {
    let dir = tempfile::tempdir().unwrap();
    let one = zip(
        dir.path(),
        "one.zip",
        &[("a.toml", "[camera]\neye = [0, 0, 1]\nlook_at = [0, 0, 0]\n")],
    );
    assert!(load_file(&one).is_ok());
    let two = zip(dir.path(), "two.zip", &[("a.toml", ""), ("b.json", "")]);
    let error = load_file(&two).unwrap_err();
    assert!(error.to_string().contains("found 2 top-level"), "{error}");
}

#[test]
fn entries_are_read_up_to_the_cap() {
    let (_dir, path) = packed("");
    let archive = Archive::open(&path).unwrap();
    let obj = Path::new("meshes/tri.obj");
    assert_eq!(archive.read(obj, 100).unwrap(), TRIANGLE.as_bytes());
    let error = archive.read(obj, 10).unwrap_err();
    assert_eq!(error.kind(), std::io::ErrorKind::InvalidInput);
}
