//! `tracer pack`: a scene and its archive render the same image, bit for
//! bit; a scene split over included files renders as the same scene in one
//! file; a scene with errors is not packed, and no file is left behind.

use std::path::{Path, PathBuf};
use tracer_pipeline::pack::pack;
use tracer_pipeline::{load, render, Error, Input, Options};

fn repository_scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
}

/// The linear image's bits and the 8-bit image's bytes of `path`, at
/// `width` pixels wide (the height follows).
fn render_bits(path: &Path, width: u32) -> (Vec<u32>, Vec<u8>) {
    let loaded = load(&Input::File(path.to_path_buf())).unwrap();
    let options = Options {
        width: Some(width),
        ..Options::default()
    };
    let picture = render(&loaded, &options, &|_| {}).unwrap().image;
    let linear = picture.to_rgb32f().into_raw();
    (
        linear.iter().map(|x| x.to_bits()).collect(),
        picture.to_rgb8().into_raw(),
    )
}

#[test]
fn the_showcase_and_its_archive_render_the_same_bits() {
    let dir = tempfile::tempdir().unwrap();
    let scene = repository_scene("showcase.toml");
    let archive = dir.path().join("showcase.zip");
    let packed = pack(&scene, &archive).unwrap();
    // Its meshes are in scenes/meshes/ and scenes/bench/: all below scenes/.
    assert_eq!(
        packed.entries,
        [
            "showcase.toml",
            "meshes/checker-light.obj",
            "meshes/checker-dark.obj",
            "bench/bunny.obj"
        ]
    );
    assert_eq!(render_bits(&archive, 125), render_bits(&scene, 125));
}

#[test]
fn a_textured_scene_and_its_archive_render_the_same_bits() {
    // Its images and the MTL file (with its own image) come from the
    // archive too: the render reads nothing else.
    let dir = tempfile::tempdir().unwrap();
    let scene = repository_scene("textures.toml");
    let archive = dir.path().join("textures.zip");
    let packed = pack(&scene, &archive).unwrap();
    for file in [
        "meshes/labelled-box.mtl",
        "meshes/bullseye.png",
        "textures/grid.png",
    ] {
        assert!(
            packed.entries.iter().any(|e| e == file),
            "{file}: {:?}",
            packed.entries
        );
    }
    let loaded = load(&Input::File(archive.clone())).unwrap();
    assert_eq!(loaded.files_read, std::slice::from_ref(&archive));
    assert_eq!(render_bits(&archive, 120), render_bits(&scene, 120));
}

const TRIANGLE: &str = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";

/// The materials, light and objects of the split scene below, in one file.
const WHOLE: &str = r#"
[camera]
eye = [0, 0, 6]
look_at = [0, 0, 0]
width = 64
height = 48

[[lights]]
position = [2, 3, 8]

[[lights]]
position = [-3, 1, 5]
color = [0.3, 0.3, 0.5]

[materials.red]
ambient = [0.1, 0, 0]
diffuse = [0.7, 0.1, 0.1]
specular = [0.5, 0.5, 0.5]
shininess = 20

[materials.mirror]
diffuse = [0.1, 0.1, 0.1]
reflectance = 0.6

[[objects]]
mesh = { obj = "meshes/tri.obj" }
material = "mirror"

[[objects]]
sphere = { center = [0.5, 0, 1], radius = 0.6 }
material = "red"
"#;

/// A scene in `root/scenes/` that includes `lib/look.toml` (materials and
/// the first light) and `lib/stage.json` (the triangle mesh, read from
/// `root/meshes/`, outside the scene's folder).
fn split_scene(root: &Path) -> PathBuf {
    let write = |path: &str, text: &str| {
        let path = root.join(path);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, text).unwrap();
        path
    };
    write("meshes/tri.obj", TRIANGLE);
    write(
        "scenes/lib/look.toml",
        "[[lights]]\nposition = [2, 3, 8]\n\n[materials.red]\nambient = [0.1, 0, 0]\n\
         diffuse = [0.7, 0.1, 0.1]\nspecular = [0.5, 0.5, 0.5]\nshininess = 20\n\n\
         [materials.mirror]\ndiffuse = [0.1, 0.1, 0.1]\nreflectance = 0.6\n",
    );
    write(
        "scenes/lib/stage.json",
        r#"{"objects": [{"mesh": {"obj": "../../meshes/tri.obj"}, "material": "mirror"}]}"#,
    );
    write(
        "scenes/split.toml",
        "include = [\"lib/look.toml\", \"lib/stage.json\"]\n\n\
         [camera]\neye = [0, 0, 6]\nlook_at = [0, 0, 0]\nwidth = 64\nheight = 48\n\n\
         [[lights]]\nposition = [-3, 1, 5]\ncolor = [0.3, 0.3, 0.5]\n\n\
         [[objects]]\nsphere = { center = [0.5, 0, 1], radius = 0.6 }\nmaterial = \"red\"\n",
    )
}

#[test]
fn a_split_scene_renders_as_the_whole_and_so_does_its_archive() {
    let dir = tempfile::tempdir().unwrap();
    let split = split_scene(dir.path());
    let whole = dir.path().join("whole.toml");
    std::fs::write(&whole, WHOLE).unwrap();
    let archive = dir.path().join("out/split.zip");
    std::fs::create_dir(dir.path().join("out")).unwrap();
    let packed = pack(&split, &archive).unwrap();
    // Stored below the folder holding scenes/ and meshes/: no `..` entry,
    // and `../../meshes/tri.obj` from scenes/lib/ still finds the mesh.
    assert_eq!(
        packed.entries,
        [
            "scenes/split.toml",
            "scenes/lib/look.toml",
            "scenes/lib/stage.json",
            "meshes/tri.obj"
        ]
    );
    let expected = render_bits(&whole, 64);
    // Something is drawn: not every pixel is the background.
    assert!(expected.1.iter().any(|&b| b > 0));
    assert_eq!(render_bits(&split, 64), expected);
    assert_eq!(render_bits(&archive, 64), expected);
}

#[test]
fn a_scene_with_a_missing_mesh_is_not_packed() {
    let dir = tempfile::tempdir().unwrap();
    let split = split_scene(dir.path());
    std::fs::remove_file(dir.path().join("meshes/tri.obj")).unwrap();
    let archive = dir.path().join("split.zip");
    let error = pack(&split, &archive).unwrap_err();
    let Error::Scene(scene_error) = &error else {
        panic!("{error}");
    };
    let d = &scene_error.diagnostics()[0];
    // In stage.json, where the mesh is named: line 1, column 31 (the value of `"obj"`).
    assert_eq!(d.path.to_string(), "objects[0].mesh.obj");
    assert_eq!(d.location.map(|l| (l.line, l.column)), Some((1, 31)));
    assert!(scene_error.to_string().contains("lib/stage.json:1:31"));
    // No archive, and no temporary file left.
    let mut left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    left.sort();
    assert_eq!(left, ["meshes", "scenes"]);
    assert!(!archive.exists());
}

#[test]
fn an_output_that_is_not_a_zip_is_refused_before_loading() {
    let dir = tempfile::tempdir().unwrap();
    let error = pack(&repository_scene("boxes.toml"), &dir.path().join("b.tar")).unwrap_err();
    assert!(error
        .to_string()
        .contains("expected an output ending in .zip"));
    assert!(error.is_bad_input());
}

#[test]
fn a_scene_naming_a_mesh_by_its_absolute_path_is_not_packed_broken() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("tri.obj");
    std::fs::write(&obj, TRIANGLE).unwrap();
    let scene = dir.path().join("s.toml");
    std::fs::write(
        &scene,
        format!(
            "[camera]\neye = [0, 0, 6]\nlook_at = [0, 0, 0]\n\
             [[objects]]\nmesh = {{ obj = {:?} }}\n",
            obj.display().to_string()
        ),
    )
    .unwrap();
    let archive = dir.path().join("s.zip");
    let error = pack(&scene, &archive).unwrap_err();
    // Inside the archive the absolute path leaves it: the check load says so.
    let message = error.to_string();
    assert!(message.contains("would not load"), "{message}");
    assert!(message.contains("leaves the archive"), "{message}");
    assert!(error.is_bad_input());
    assert!(!archive.exists());
}

#[test]
fn an_obj_or_mtl_naming_a_file_outside_the_scene_is_not_packed() {
    let dir = tempfile::tempdir().unwrap();
    let outside = dir.path().join("secret");
    std::fs::create_dir(&outside).unwrap();
    std::fs::write(outside.join("passwd.mtl"), "newmtl m\nKd 1 0 0\n").unwrap();
    let scene_dir = dir.path().join("scene");
    std::fs::create_dir(&scene_dir).unwrap();
    image::RgbImage::new(2, 2)
        .save(outside.join("key.png"))
        .unwrap();
    let lib = outside.join("passwd.mtl");
    let cases = [
        // An absolute `mtllib`, and one that climbs out with `..`.
        (
            format!("mtllib {}\n", lib.display()),
            "own.mtl",
            String::new(),
        ),
        (
            "mtllib ../secret/passwd.mtl\n".to_string(),
            "own.mtl",
            String::new(),
        ),
        // An MTL inside whose `map_Kd` climbs out.
        (
            "mtllib own.mtl\n".to_string(),
            "own.mtl",
            "newmtl m\nmap_Kd ../secret/key.png\n".to_string(),
        ),
    ];
    for (i, (head, mtl_name, mtl)) in cases.iter().enumerate() {
        std::fs::write(scene_dir.join(mtl_name), mtl).unwrap();
        std::fs::write(
            scene_dir.join("m.obj"),
            format!("{head}usemtl m\n{TRIANGLE}"),
        )
        .unwrap();
        let scene = scene_dir.join("s.toml");
        std::fs::write(
            &scene,
            "[camera]\neye = [0, 0, 6]\nlook_at = [0, 0, 0]\n\
             [[objects]]\nmesh = { obj = \"m.obj\" }\n",
        )
        .unwrap();
        let archive = dir.path().join("s.zip");
        let error = pack(&scene, &archive).unwrap_err();
        let message = error.to_string();
        let (file, line, keyword, named) = match i {
            2 => ("own.mtl", 2, "map_Kd", outside.join("key.png")),
            _ => ("m.obj", 1, "mtllib", lib.clone()),
        };
        let at = format!(
            "{}:{line}: `{keyword}` names {}",
            scene_dir.join(file).display(),
            named.display()
        );
        assert!(message.starts_with(&at), "{i}: {message}");
        assert!(message.contains("outside"), "{message}");
        assert!(error.is_bad_input());
        assert!(!archive.exists());
    }
}
