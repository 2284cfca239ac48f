//! `--cache`: a scene kept after preparing renders bit for bit as the scene
//! prepared from its files; an entry whose files changed, or that is
//! damaged, is refused; a scene with instances is not kept.

use std::path::{Path, PathBuf};
use tracer_pipeline::cache::{CacheError, SceneCache};
use tracer_pipeline::{
    load, prepare_taking, render, render_prepared, tiles, Input, Options, Part, Picture, Region,
};

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
}

fn bits(picture: &Picture) -> Vec<[u32; 3]> {
    let p = &picture.linear.pixels;
    p.iter()
        .map(|c| [c.x.to_bits(), c.y.to_bits(), c.z.to_bits()])
        .collect()
}

/// Prepares `input` and keeps it in `cache`, as a first render does.
fn keep(cache: &SceneCache, input: &Input, options: &Options) -> Result<(), CacheError> {
    let loaded = load(input).unwrap();
    let files_read = loaded.files_read.clone();
    let digest = tiles::digest(input, &loaded, options).unwrap();
    let prepared = prepare_taking(loaded, options, "--cache").unwrap();
    let entry = cache.entry(input, options).unwrap();
    entry.write(&prepared, &files_read, &digest, &["a warning".into()])
}

#[test]
fn a_kept_scene_renders_bit_for_bit_as_one_prepared_from_its_files() {
    let dir = tempfile::tempdir().unwrap();
    let cache = SceneCache::new(dir.path().join("kept"));
    let part = Part::Region(Region {
        x0: 3,
        y0: 5,
        x1: 61,
        y1: 30,
    });
    // Meshes flat and smooth, textures (images and the lab's), glass,
    // sphere lights, a lens, planes, and the built-in scene.
    let inputs = [
        "bench/bunny.toml",
        "smooth-mesh.toml",
        "textures.toml",
        "texture.toml",
        "showcase.toml",
        "glass.toml",
        "soft-shadows.toml",
        "depth-of-field.toml",
        "boxes.toml",
    ]
    .map(|name| Input::File(scene(name)));
    for input in inputs.iter().chain([&Input::DefaultScene]) {
        for part in [None, Some(part)] {
            let options = Options {
                width: Some(64),
                samples: Some(2),
                part,
                ..Options::default()
            };
            let fresh = render(&load(input).unwrap(), &options, &|_| {}).unwrap();
            keep(&cache, input, &options).unwrap();
            let entry = cache.entry(input, &options).unwrap();
            let kept = entry.read(input, &options).unwrap().expect("kept");
            assert_eq!(kept.warnings, ["a warning"]);
            let again = render_prepared(&kept.prepared, &options, &|_| {}).unwrap();
            assert_eq!(bits(&again.image), bits(&fresh.image), "{input:?} {part:?}");
            assert_eq!(again.image.encoding, fresh.image.encoding);
        }
    }
}

/// A scene of one triangle from `tri.obj` beside it.
fn triangle_scene(dir: &Path, obj: &str) -> Input {
    std::fs::write(dir.join("tri.obj"), obj).unwrap();
    let toml = "[camera]\neye = [0, 0, 3]\nlook_at = [0, 0, 0]\nwidth = 16\nheight = 16\n\
        [[lights]]\nposition = [0, 2, 3]\n\
        [[objects]]\nmesh = { obj = \"tri.obj\" }\n";
    std::fs::write(dir.join("tri.toml"), toml).unwrap();
    Input::File(dir.join("tri.toml"))
}

const TRIANGLE: &str = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n";

#[test]
fn an_entry_is_refused_once_a_file_of_its_scene_changed() {
    let dir = tempfile::tempdir().unwrap();
    let input = triangle_scene(dir.path(), TRIANGLE);
    let cache = SceneCache::new(dir.path().join("kept"));
    let options = Options::default();
    keep(&cache, &input, &options).unwrap();
    let entry = cache.entry(&input, &options).unwrap();
    assert!(entry.read(&input, &options).unwrap().is_some());
    // Same size, one vertex moved: only the contents tell.
    std::fs::write(
        dir.path().join("tri.obj"),
        TRIANGLE.replace("v 0 1 0", "v 0 2 0"),
    )
    .unwrap();
    let why = entry.read(&input, &options).unwrap_err();
    assert!(why.contains("has changed"), "{why}");
    std::fs::remove_file(dir.path().join("tri.obj")).unwrap();
    let why = entry.read(&input, &options).unwrap_err();
    assert!(why.contains("tri.obj"), "{why}");
}

#[test]
fn other_options_or_the_same_file_elsewhere_are_other_entries() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    std::fs::create_dir_all(&a).unwrap();
    std::fs::create_dir_all(&b).unwrap();
    let (in_a, in_b) = (triangle_scene(&a, TRIANGLE), triangle_scene(&b, TRIANGLE));
    let cache = SceneCache::new(dir.path().join("kept"));
    let options = Options::default();
    let wider = Options {
        width: Some(32),
        ..options
    };
    let path = |input: &Input, options: &Options| cache.entry(input, options).unwrap().path;
    assert_ne!(path(&in_a, &options), path(&in_b, &options));
    assert_ne!(path(&in_a, &options), path(&in_a, &wider));
    // A tile's part is not the scene's: every tile reads one entry.
    let tile = Options {
        part: Some(Part::Tile { index: 1, count: 4 }),
        ..options
    };
    assert_eq!(path(&in_a, &options), path(&in_a, &tile));
    assert!(cache
        .entry(&Input::File(dir.path().join("none.toml")), &options)
        .is_none());
}

#[test]
fn a_damaged_entry_is_refused_and_a_missing_one_is_none() {
    let dir = tempfile::tempdir().unwrap();
    let input = triangle_scene(dir.path(), TRIANGLE);
    let cache = SceneCache::new(dir.path().join("kept"));
    let options = Options::default();
    let entry = cache.entry(&input, &options).unwrap();
    assert!(entry.read(&input, &options).unwrap().is_none());
    keep(&cache, &input, &options).unwrap();
    let bytes = std::fs::read(&entry.path).unwrap();
    let damaged = [
        bytes[..bytes.len() - 1].to_vec(),
        bytes[10..].to_vec(),
        {
            let mut flipped = bytes.clone();
            let last = flipped.len() - 5;
            flipped[last] ^= 1;
            flipped
        },
        Vec::new(),
    ];
    for bytes in damaged {
        std::fs::write(&entry.path, bytes).unwrap();
        let why = entry.read(&input, &options).unwrap_err();
        assert!(why.contains("damaged"), "{why}");
    }
}

#[test]
fn a_scene_with_instances_is_not_kept() {
    let dir = tempfile::tempdir().unwrap();
    let input = triangle_scene(dir.path(), TRIANGLE);
    let Input::File(path) = &input else {
        unreachable!()
    };
    let twice =
        "[[objects]]\nmesh = { obj = \"tri.obj\" }\ntransform = { translate = [1, 0, 0] }\n";
    let mut toml = std::fs::read_to_string(path).unwrap();
    toml.push_str(twice);
    std::fs::write(path, toml).unwrap();
    let cache = SceneCache::new(dir.path().join("kept"));
    let error = keep(&cache, &input, &Options::default()).unwrap_err();
    assert!(matches!(error, CacheError::Instances), "{error}");
    assert!(
        !dir.path().join("kept").exists()
            || std::fs::read_dir(dir.path().join("kept"))
                .unwrap()
                .next()
                .is_none()
    );
}

#[cfg(unix)]
#[test]
fn an_entry_that_is_not_a_regular_file_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let input = triangle_scene(dir.path(), TRIANGLE);
    let cache = SceneCache::new(dir.path().join("kept"));
    let options = Options::default();
    let entry = cache.entry(&input, &options).unwrap();
    std::fs::create_dir_all(dir.path().join("kept")).unwrap();
    // A FIFO would wait for a writer for ever; /dev/zero never ends.
    let made = std::process::Command::new("mkfifo")
        .arg(&entry.path)
        .status()
        .unwrap();
    assert!(made.success());
    let why = entry.read(&input, &options).unwrap_err();
    assert!(why.contains("not a regular file"), "{why}");
    std::fs::remove_file(&entry.path).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &entry.path).unwrap();
    let why = entry.read(&input, &options).unwrap_err();
    assert!(why.contains("not a regular file"), "{why}");
}

#[test]
fn another_scenes_entry_under_this_name_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    std::fs::create_dir_all(&a).unwrap();
    std::fs::create_dir_all(&b).unwrap();
    let in_a = triangle_scene(&a, TRIANGLE);
    let in_b = triangle_scene(&b, &TRIANGLE.replace("v 0 1 0", "v 0 2 0"));
    let cache = SceneCache::new(dir.path().join("kept"));
    let options = Options::default();
    keep(&cache, &in_a, &options).unwrap();
    keep(&cache, &in_b, &options).unwrap();
    let (entry_a, entry_b) = (
        cache.entry(&in_a, &options).unwrap(),
        cache.entry(&in_b, &options).unwrap(),
    );
    // B's entry, whole and with its files unchanged, under A's name.
    std::fs::copy(&entry_b.path, &entry_a.path).unwrap();
    assert!(entry_b.read(&in_b, &options).unwrap().is_some());
    let why = entry_a.read(&in_a, &options).unwrap_err();
    assert!(why.contains("another scene"), "{why}");
}
