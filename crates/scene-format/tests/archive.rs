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

/// The message of a scene that fails to load.
fn failure(path: &Path) -> String {
    load_file(path).unwrap_err().to_string()
}

#[test]
fn an_archive_cut_short_says_so() {
    let (dir, path) = packed("[materials.red]\ndiffuse = [1, 0, 0]\n");
    let bytes = std::fs::read(&path).unwrap();
    for keep in [bytes.len() - 5, bytes.len() / 2, 30] {
        let cut = dir.path().join("cut.zip");
        std::fs::write(&cut, &bytes[..keep]).unwrap();
        let message = failure(&cut);
        assert!(
            message.contains("damaged or cut short"),
            "{keep}: {message}"
        );
    }
}

/// A zip archive of `entries` (name, bytes), deflated.
fn deflated(dir: &Path, entries: &[(&str, &[u8])]) -> PathBuf {
    let path = dir.join("bomb.zip");
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    for (entry, bytes) in entries {
        zip.start_file(*entry, options).unwrap();
        zip.write_all(bytes).unwrap();
    }
    zip.finish().unwrap();
    path
}

#[test]
fn an_entry_is_never_inflated_past_its_declared_size() {
    let dir = tempfile::tempdir().unwrap();
    let scene = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
                 [[objects]]\nmesh = { obj = \"m.obj\" }\n";
    let junk = vec![b'#'; 50 << 20];
    let path = deflated(
        dir.path(),
        &[("s.toml", scene.as_bytes()), ("m.obj", &junk)],
    );
    // The entry's sizes (local header and central directory) say 100 bytes.
    let mut bytes = std::fs::read(&path).unwrap();
    let size = (50u32 << 20).to_le_bytes();
    let mut patched = 0;
    for at in 0..bytes.len() - 4 {
        if bytes[at..at + 4] == size {
            bytes[at..at + 4].copy_from_slice(&100u32.to_le_bytes());
            patched += 1;
        }
    }
    assert_eq!(patched, 2);
    std::fs::write(&path, bytes).unwrap();
    let start = std::time::Instant::now();
    let message = failure(&path);
    assert!(message.contains("more than its declared size"), "{message}");
    assert!(start.elapsed().as_millis() < 500, "{:?}", start.elapsed());
}

#[test]
fn a_bomb_named_by_many_files_is_inflated_a_few_times_at_most() {
    let dir = tempfile::tempdir().unwrap();
    // 200 OBJ files, each naming one 32 MiB MTL of comments: 6 GiB to
    // inflate if each read it.
    let mut scene = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n".to_string();
    let obj = format!("mtllib bomb.mtl\n{TRIANGLE}");
    let names: Vec<String> = (0..200).map(|i| format!("m{i}.obj")).collect();
    for name in &names {
        scene += &format!("[[objects]]\nmesh = {{ obj = \"{name}\" }}\n");
    }
    // Comments that pack 10 times, not the thousand of one character
    // repeated (refused at once: see the next test).
    let mut seed = 1u32;
    let bomb: Vec<u8> = (0..32 << 20)
        .map(|i| match i % 1024 {
            0 => b'#',
            1023 => b'\n',
            k if k < 100 => {
                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                b'a' + (seed >> 24) as u8 % 26
            }
            _ => b' ',
        })
        .collect();
    let mut entries: Vec<(&str, &[u8])> = vec![("s.toml", scene.as_bytes()), ("bomb.mtl", &bomb)];
    entries.extend(names.iter().map(|n| (n.as_str(), obj.as_bytes())));
    let path = deflated(dir.path(), &entries);
    let start = std::time::Instant::now();
    let loaded = load_file(&path);
    assert!(start.elapsed().as_secs() < 10, "{:?}", start.elapsed());
    let SceneKind::Scene3d(scene) = loaded.unwrap().kind else {
        panic!("expected a 3D scene");
    };
    // The MTL is a warning of the later objects: read no more.
    let last = scene.objects[199]
        .mesh
        .as_ref()
        .unwrap()
        .data
        .as_ref()
        .unwrap();
    let warning = last.material_warnings.join("\n");
    assert!(warning.contains("more than 4 times over"), "{warning}");
}

/// A pack in `dir` of a scene whose OBJ is 20 MiB of one comment and a
/// triangle (packed a thousand times); the OBJ's length.
fn comment_bomb(dir: &Path) -> (PathBuf, usize) {
    let scene = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
                 [[objects]]\nmesh = { obj = \"m.obj\" }\n";
    let mut obj = vec![b'#'; 20 << 20];
    obj.extend_from_slice(format!("\n{TRIANGLE}").as_bytes());
    let path = deflated(dir, &[("s.toml", scene.as_bytes()), ("m.obj", &obj)]);
    (path, obj.len())
}

#[test]
fn a_large_entry_packed_a_thousand_times_is_refused_before_it_is_inflated() {
    let dir = tempfile::tempdir().unwrap();
    let (path, _) = comment_bomb(dir.path());
    assert!(std::fs::metadata(&path).unwrap().len() < 100_000);
    let message = failure(&path);
    assert!(message.contains("over 200 times"), "{message}");
    assert!(message.contains("objects[0].mesh.obj"), "{message}");
}

#[test]
fn a_bad_manifest_is_named_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = zip(
        dir.path(),
        "m.zip",
        &[
            ("tracer-pack.toml", "# made by hand\nscene = 5\n"),
            ("s.toml", ""),
        ],
    );
    let message = failure(&path);
    assert!(
        message.contains("tracer-pack.toml, line 2: invalid type"),
        "{message}"
    );
}

#[test]
fn a_header_claiming_more_packed_bytes_than_the_archive_has_does_not_pass() {
    let dir = tempfile::tempdir().unwrap();
    let (path, obj_len) = comment_bomb(dir.path());
    // The OBJ's packed size, in its local header and the central
    // directory, claimed to be a hundredth of its size.
    let mut bytes = std::fs::read(&path).unwrap();
    let archive = zip::ZipArchive::new(std::io::Cursor::new(bytes.clone())).unwrap();
    let packed = archive.clone().by_name("m.obj").unwrap().compressed_size() as u32;
    let claimed = (obj_len / 100) as u32;
    let mut patched = 0;
    for at in 0..bytes.len() - 4 {
        if bytes[at..at + 4] == packed.to_le_bytes() {
            bytes[at..at + 4].copy_from_slice(&claimed.to_le_bytes());
            patched += 1;
        }
    }
    assert_eq!(patched, 2);
    std::fs::write(&path, bytes).unwrap();
    let message = failure(&path);
    assert!(message.contains("over 200 times"), "{message}");
}

#[test]
fn two_entries_of_one_name_refuse_the_archive() {
    let dir = tempfile::tempdir().unwrap();
    let path = zip(
        dir.path(),
        "twice.zip",
        &[
            (
                "scene.toml",
                "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n",
            ),
            ("red.obj", TRIANGLE),
            ("blu.obj", "v 0 0 0\n"),
        ],
    );
    // The zip writer refuses a repeated name: the second renamed in its
    // local header and in the central directory.
    let mut bytes = std::fs::read(&path).unwrap();
    let mut renamed = 0;
    for at in 0..bytes.len() - 7 {
        if &bytes[at..at + 7] == b"blu.obj" {
            bytes[at..at + 7].copy_from_slice(b"red.obj");
            renamed += 1;
        }
    }
    assert_eq!(renamed, 2);
    std::fs::write(&path, bytes).unwrap();
    let message = failure(&path);
    assert!(
        message.contains("two entries named `red.obj`; expected each file once"),
        "{message}"
    );
    // Before the renaming it opened.
    let fine = zip(
        dir.path(),
        "fine.zip",
        &[("s.toml", ""), ("red.obj", TRIANGLE)],
    );
    assert!(Archive::open(&fine).is_ok());
}
