//! Render-farm tiles as a scheduler runs them: one `tracer render --tile`
//! process per tile, then `tracer merge`.

mod common;

use common::tracer;
use std::path::{Path, PathBuf};
use std::process::Output;

fn scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// A thin lens and 4 samples per pixel, small.
const VIEW: [&str; 4] = ["--width", "64", "--samples", "4"];

fn render(dir: &Path, scene: &Path, extra: &[&str]) -> Output {
    let mut args = vec!["render", scene.to_str().unwrap()];
    args.extend(VIEW);
    args.extend(extra);
    tracer(dir, &args)
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn floats(path: &Path) -> Vec<u32> {
    let image = image::open(path).unwrap().to_rgb32f();
    image.into_raw().into_iter().map(f32::to_bits).collect()
}

/// Tiles 0..count, each in its own process on 1 to 3 threads.
fn tiles(dir: &Path, scene: &Path, count: u32) -> Vec<String> {
    (0..count)
        .map(|i| {
            let name = format!("t{i}-{count}.exr");
            let (tile, threads) = (format!("{i}/{count}"), format!("{}", 1 + i % 3));
            ok(&render(
                dir,
                scene,
                &["--tile", &tile, "--threads", &threads, "-o", &name, "-q"],
            ));
            name
        })
        .collect()
}

fn merge(dir: &Path, tiles: &[String], out: &str) -> Output {
    let mut args = vec!["merge"];
    args.extend(tiles.iter().map(String::as_str));
    args.extend(["-o", out]);
    tracer(dir, &args)
}

#[test]
fn tiles_in_separate_processes_merge_into_the_single_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("depth-of-field.toml");
    ok(&render(dir.path(), &scene, &["-o", "full.png", "-q"]));
    ok(&render(dir.path(), &scene, &["-o", "full.exr", "-q"]));
    for count in [1, 4] {
        let names = tiles(dir.path(), &scene, count);
        ok(&merge(dir.path(), &names, "merged.exr"));
        ok(&merge(dir.path(), &names, "merged.png"));
        let at = |n: &str| dir.path().join(n);
        assert_eq!(
            floats(&at("merged.exr")),
            floats(&at("full.exr")),
            "{count} tiles"
        );
        let (merged, full) = (
            std::fs::read(at("merged.png")),
            std::fs::read(at("full.png")),
        );
        assert!(merged.unwrap() == full.unwrap(), "{count} tiles");
    }
}

#[test]
fn merge_refuses_a_missing_an_overlapping_and_a_foreign_tile_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("depth-of-field.toml");
    let names = tiles(dir.path(), &scene, 3);
    let missing = merge(dir.path(), &[names[0].clone(), names[2].clone()], "m.png");
    assert_eq!(missing.status.code(), Some(2));
    // 40 rows in 3: tile 1 is rows 13..26.
    assert!(
        stderr(&missing).contains("missing tile 1/3 (rows 13..26)"),
        "{}",
        stderr(&missing)
    );
    ok(&render(
        dir.path(),
        &scene,
        &["--region", "0,20,64,30", "-o", "extra.exr", "-q"],
    ));
    let mut overlapping = names.clone();
    overlapping.push("extra.exr".to_string());
    let out = merge(dir.path(), &overlapping, "m.png");
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("extra.exr: overlaps t1-3.exr"),
        "{}",
        stderr(&out)
    );
    // The scene copied with one value edited.
    let copy = dir.path().join("copy");
    std::fs::create_dir_all(copy.join("meshes")).unwrap();
    for mesh in ["checker-light.obj", "checker-dark.obj"] {
        std::fs::copy(
            scenes().join("meshes").join(mesh),
            copy.join("meshes").join(mesh),
        )
        .unwrap();
    }
    let text = std::fs::read_to_string(&scene).unwrap();
    let edited = text.replacen("focus_distance = 6.9", "focus_distance = 7", 1);
    assert_ne!(edited, text);
    std::fs::write(copy.join("dof.toml"), edited).unwrap();
    ok(&render(
        dir.path(),
        &copy.join("dof.toml"),
        &["--tile", "1/3", "-o", "foreign.exr", "-q"],
    ));
    let out = merge(
        dir.path(),
        &[names[0].clone(), "foreign.exr".into(), names[2].clone()],
        "m.png",
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("foreign.exr: a tile of another scene"),
        "{}",
        stderr(&out)
    );
    assert!(!dir.path().join("m.png").exists());
}

#[test]
fn skip_existing_skips_a_valid_tile_and_redoes_one_of_another_digest() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("depth-of-field.toml");
    let tile = ["--tile", "1/2", "-o", "t.exr", "--skip-existing"];
    ok(&render(dir.path(), &scene, &tile));
    let out = render(dir.path(), &scene, &tile);
    ok(&out);
    assert!(
        stderr(&out).contains("skipped: t.exr already holds this tile"),
        "{}",
        stderr(&out)
    );
    // A tile of other options at the path: rendered over.
    ok(&render(
        dir.path(),
        &scene,
        &["--tile", "1/2", "--gamma", "1.8", "-o", "t.exr"],
    ));
    let out = render(dir.path(), &scene, &tile);
    ok(&out);
    assert!(!stderr(&out).contains("skipped"), "{}", stderr(&out));
    assert!(stderr(&out).contains("rendered"), "{}", stderr(&out));
    // Only tiles carry a digest to compare.
    let out = render(dir.path(), &scene, &["-o", "full.png", "--skip-existing"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_region_outside_the_image_or_empty_is_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("depth-of-field.toml");
    for (region, says) in [
        ("0,0,65,10", "outside the 64x40 image"),
        ("0,30,64,41", "outside the 64x40 image"),
        ("3,3,3,9", "empty"),
        ("1,2,3", "four whole numbers"),
    ] {
        let out = render(dir.path(), &scene, &["--region", region, "-o", "r.exr"]);
        assert_eq!(out.status.code(), Some(2), "{region}");
        assert!(stderr(&out).contains(says), "{region}: {}", stderr(&out));
        assert!(!dir.path().join("r.exr").exists());
    }
    let out = render(dir.path(), &scene, &["--tile", "41/50", "-o", "r.exr"]);
    assert_eq!(out.status.code(), Some(2));
    let out = render(dir.path(), &scene, &["--tile", "50/50", "-o", "r.exr"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_gamma_given_to_the_tiles_encodes_the_merged_png() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("depth-of-field.toml");
    let gamma = ["--gamma", "1.8", "-q"];
    ok(&render(
        dir.path(),
        &scene,
        &[&gamma[..], &["-o", "full.png"]].concat(),
    ));
    for i in 0..2 {
        let (tile, name) = (format!("{i}/2"), format!("t{i}.exr"));
        ok(&render(
            dir.path(),
            &scene,
            &[&gamma[..], &["--tile", &tile, "-o", &name]].concat(),
        ));
    }
    ok(&merge(
        dir.path(),
        &["t0.exr".into(), "t1.exr".into()],
        "merged.png",
    ));
    let read = |n: &str| std::fs::read(dir.path().join(n)).unwrap();
    assert!(read("merged.png") == read("full.png"));
    // And not the PNG of the scene's own gamma (2.2).
    ok(&render(dir.path(), &scene, &["-o", "own.png", "-q"]));
    assert!(read("merged.png") != read("own.png"));
}

#[test]
fn tiles_that_read_a_kept_scene_merge_into_the_single_render() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("depth-of-field.toml");
    ok(&render(dir.path(), &scene, &["-o", "full.exr", "-q"]));
    let names: Vec<String> = (0..3).map(|i| format!("c{i}.exr")).collect();
    for (i, name) in names.iter().enumerate() {
        let tile = format!("{i}/3");
        let out = render(
            dir.path(),
            &scene,
            &["--tile", &tile, "--cache", "kept", "-o", name],
        );
        ok(&out);
        let said = if i == 0 {
            "kept the prepared scene in"
        } else {
            "read the prepared scene from"
        };
        assert!(stderr(&out).contains(said), "{}", stderr(&out));
    }
    ok(&merge(dir.path(), &names, "merged.exr"));
    let at = |n: &str| dir.path().join(n);
    assert_eq!(floats(&at("merged.exr")), floats(&at("full.exr")));
}

#[test]
fn a_damaged_kept_scene_is_said_and_prepared_again() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("showcase.toml");
    ok(&render(dir.path(), &scene, &["-o", "full.png", "-q"]));
    ok(&render(
        dir.path(),
        &scene,
        &["--cache", "kept", "-o", "a.png", "-q"],
    ));
    let entries: Vec<PathBuf> = std::fs::read_dir(dir.path().join("kept"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(entries.len(), 1, "{entries:?}");
    std::fs::write(&entries[0], b"tracer prepared scene 1\nnot a scene").unwrap();
    let out = render(dir.path(), &scene, &["--cache", "kept", "-o", "b.png"]);
    ok(&out);
    assert!(
        stderr(&out).contains("not used (it is damaged"),
        "{}",
        stderr(&out)
    );
    let read = |n: &str| std::fs::read(dir.path().join(n)).unwrap();
    assert!(read("a.png") == read("full.png") && read("b.png") == read("full.png"));
    // Prepared again, and kept again.
    let out = render(dir.path(), &scene, &["--cache", "kept", "-o", "c.png"]);
    assert!(
        stderr(&out).contains("read the prepared scene"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn cache_with_an_aov_or_a_canvas_is_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("showcase.toml");
    let out = render(dir.path(), &scene, &["--aov", "depth", "--cache", "kept"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let canvas = scenes().join("robot.toml");
    let out = tracer(
        dir.path(),
        &[
            "render",
            canvas.to_str().unwrap(),
            "--cache",
            "kept",
            "-o",
            "r.png",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("--cache"), "{}", stderr(&out));
    assert!(!dir.path().join("r.png").exists());
}

#[test]
fn a_cache_that_cannot_be_written_is_a_warning_and_the_render_goes_on() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("showcase.toml");
    std::fs::write(dir.path().join("taken"), b"a file, not a folder").unwrap();
    let out = render(
        dir.path(),
        &scene,
        &["--cache", "taken/kept", "-o", "a.png"],
    );
    ok(&out);
    assert!(
        stderr(&out).contains("warning: --cache:"),
        "{}",
        stderr(&out)
    );
    assert!(dir.path().join("a.png").exists());
}

#[test]
fn skip_existing_renders_a_damaged_tile_again() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scenes().join("depth-of-field.toml");
    let tile = ["--tile", "1/2", "-o", "t.exr", "--skip-existing"];
    ok(&render(dir.path(), &scene, &tile));
    let path = dir.path().join("t.exr");
    let good = std::fs::read(&path).unwrap();
    // A byte of the pixels flipped, as a bad disk or copy would.
    let mut bytes = good.clone();
    let at = bytes.len() - 20;
    bytes[at] ^= 0x10;
    std::fs::write(&path, &bytes).unwrap();
    let out = render(dir.path(), &scene, &tile);
    ok(&out);
    assert!(!stderr(&out).contains("skipped"), "{}", stderr(&out));
    // Rendered again: the same pixels as first written.
    std::fs::write(dir.path().join("good.exr"), &good).unwrap();
    assert_eq!(floats(&path), floats(&dir.path().join("good.exr")));
    assert!(std::fs::read(&path).unwrap() != bytes);
}

#[test]
fn merge_of_a_folder_is_exit_2_with_the_reason_once() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("tiles.exr")).unwrap();
    let out = merge(dir.path(), &["tiles.exr".to_string()], "m.png");
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let message = stderr(&out);
    assert_eq!(message.matches("is a folder").count(), 1, "{message}");
    assert!(message.contains("tiles.exr"), "{message}");
    assert!(!dir.path().join("m.png").exists());
}
