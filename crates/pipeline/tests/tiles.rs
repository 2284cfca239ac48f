//! Render-farm tiles: a part's pixels are the whole render's, bit for bit,
//! whatever the threads; tiles merge back to the single render; merge
//! refuses a missing, overlapping or foreign tile, naming it.

use std::path::{Path, PathBuf};
use tracer_pipeline::tiles::{self, TileError};
use tracer_pipeline::{load, render, tile_region, Input, Options, Part, Picture, Region};

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
}

/// Depth of field: a thin lens and several samples per pixel, so every
/// sample's random numbers matter; small, to be quick.
fn options(part: Option<Part>) -> Options {
    Options {
        width: Some(72),
        samples: Some(4),
        part,
        ..Options::default()
    }
}

fn render_on(threads: usize, input: &Input, options: &Options) -> Picture {
    let loaded = load(input).unwrap();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| render(&loaded, options, &|_| {}).unwrap().image)
}

fn bits(picture: &Picture) -> Vec<[u32; 3]> {
    let p = &picture.linear.pixels;
    p.iter()
        .map(|c| [c.x.to_bits(), c.y.to_bits(), c.z.to_bits()])
        .collect()
}

/// The pixels of `region` cut out of the whole image, row by row.
fn cut(full: &Picture, r: Region) -> Vec<[u32; 3]> {
    let all = bits(full);
    let width = full.linear.width;
    (r.y0..r.y1)
        .flat_map(|y| (r.x0..r.x1).map(move |x| (y * width + x) as usize))
        .map(|i| all[i])
        .collect()
}

fn dof() -> Input {
    Input::File(scene("depth-of-field.toml"))
}

#[test]
fn a_region_holds_the_whole_renders_pixels_at_any_thread_count() {
    let full = render_on(2, &dof(), &options(None));
    // 72x45: the view's shape kept (480x300).
    assert_eq!(full.dimensions(), (72, 45));
    let region = Region {
        x0: 5,
        y0: 7,
        x1: 41,
        y1: 30,
    };
    for threads in [1, 2, 3] {
        let part = render_on(threads, &dof(), &options(Some(Part::Region(region))));
        assert_eq!(part.dimensions(), (36, 23));
        assert_eq!(bits(&part), cut(&full, region), "{threads} threads");
    }
}

#[test]
fn tiles_are_bands_of_rows_of_near_equal_height_covering_the_image_once() {
    // 10 rows in 4: floor(i * 10 / 4) = 0, 2, 5, 7, 10.
    let rows: Vec<(u32, u32)> = (0..4)
        .map(|i| tile_region(i, 4, (3, 10)))
        .map(|r| {
            assert_eq!((r.x0, r.x1), (0, 3));
            (r.y0, r.y1)
        })
        .collect();
    assert_eq!(rows, [(0, 2), (2, 5), (5, 7), (7, 10)]);
    let full = Part::Tile { index: 0, count: 1 }.region((3, 10)).unwrap();
    assert_eq!(
        full,
        Region {
            x0: 0,
            y0: 0,
            x1: 3,
            y1: 10
        }
    );
    for bad in [
        Part::Tile {
            index: 0,
            count: 11,
        },
        Part::Region(Region {
            x0: 0,
            y0: 0,
            x1: 4,
            y1: 10,
        }),
        Part::Region(Region {
            x0: 2,
            y0: 0,
            x1: 2,
            y1: 10,
        }),
    ] {
        let err = bad.region((3, 10)).unwrap_err();
        assert!(err.is_bad_input(), "{err}");
    }
}

/// Renders tile `index` of `count` on `threads` threads and writes it.
fn write_tile(dir: &Path, input: &Input, base: &Options, index: u32, count: u32) -> PathBuf {
    let options = Options {
        part: Some(Part::Tile { index, count }),
        ..*base
    };
    let loaded = load(input).unwrap();
    let size = tracer_pipeline::image_size(&loaded, &options).unwrap();
    let region = tile_region(index, count, size);
    let picture = render_on(1 + index as usize % 3, input, &options);
    let digest = tiles::digest(input, &loaded, &options).unwrap();
    let bytes = tiles::encode(&picture, region, size, &digest, Some((index, count)), None).unwrap();
    let path = dir.join(format!("tile-{index}-of-{count}.exr"));
    std::fs::write(&path, bytes).unwrap();
    path
}

fn read_all(paths: &[PathBuf]) -> Vec<(PathBuf, tiles::Tile)> {
    paths
        .iter()
        .map(|p| (p.clone(), tiles::read(p).unwrap()))
        .collect()
}

#[test]
fn tiles_merge_into_the_single_render_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let full = render_on(2, &dof(), &options(None));
    for count in [1, 4, 7] {
        let paths: Vec<PathBuf> = (0..count)
            .map(|i| write_tile(dir.path(), &dof(), &options(None), i, count))
            .collect();
        let merged = tiles::merge(&read_all(&paths)).unwrap();
        assert_eq!(bits(&merged), bits(&full), "{count} tiles");
        assert_eq!(merged.encoding, full.encoding);
        assert!(merged.to_rgb8() == full.to_rgb8(), "{count} tiles");
    }
}

#[test]
fn a_tile_is_an_exr_whose_data_window_is_its_region() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_tile(dir.path(), &dof(), &options(None), 2, 4);
    let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
    let header = &meta.headers[0];
    // Tile 2 of 4 of 45 rows: rows floor(90 / 4) = 22 to floor(135 / 4) = 33.
    assert_eq!(header.own_attributes.layer_position, exr::math::Vec2(0, 22));
    assert_eq!(header.layer_size, exr::math::Vec2(72, 11));
    let display = header.shared_attributes.display_window;
    assert_eq!(display.size, exr::math::Vec2(72, 45));
}

#[test]
fn merge_names_a_missing_an_overlapping_and_a_foreign_tile() {
    let dir = tempfile::tempdir().unwrap();
    let paths: Vec<PathBuf> = (0..4)
        .map(|i| write_tile(dir.path(), &dof(), &options(None), i, 4))
        .collect();
    let tiles = read_all(&paths);

    let missing = [tiles[0].clone(), tiles[1].clone(), tiles[3].clone()];
    let err = tiles::merge(&missing).unwrap_err();
    assert!(matches!(err, TileError::Missing { y: 22, .. }), "{err}");
    assert!(err.to_string().contains("tile 2/4 (rows 22..33)"), "{err}");

    let mut overlapping = tiles.clone();
    let other = dir.path().join("rows-20-to-25.exr");
    let region = Region {
        x0: 10,
        y0: 20,
        x1: 20,
        y1: 25,
    };
    let part = render_on(1, &dof(), &options(Some(Part::Region(region))));
    let loaded = load(&dof()).unwrap();
    let digest = tiles::digest(&dof(), &loaded, &options(None)).unwrap();
    std::fs::write(
        &other,
        tiles::encode(&part, region, (72, 45), &digest, None, None).unwrap(),
    )
    .unwrap();
    overlapping.push((other.clone(), tiles::read(&other).unwrap()));
    let err = tiles::merge(&overlapping).unwrap_err();
    assert!(err.is_bad_input());
    // Pixel (10, 20) is in tile 1 (rows 11..22).
    assert_eq!(
        err.to_string(),
        format!(
            "{}: overlaps {} (both hold pixel (10, 20)); every pixel must be in exactly one tile",
            other.display(),
            paths[1].display()
        )
    );

    // The same scene with one value edited: another digest.
    let text = std::fs::read_to_string(scene("depth-of-field.toml")).unwrap();
    let edited = text.replacen("aperture = 0.25", "aperture = 0.26", 1);
    assert_ne!(edited, text);
    let edited_path = dir.path().join("depth-of-field.toml");
    std::fs::create_dir(dir.path().join("meshes")).unwrap();
    for mesh in ["checker-light.obj", "checker-dark.obj"] {
        let from = scene("meshes").join(mesh);
        std::fs::copy(from, dir.path().join("meshes").join(mesh)).unwrap();
    }
    std::fs::write(&edited_path, edited).unwrap();
    let foreign_dir = dir.path().join("foreign");
    std::fs::create_dir(&foreign_dir).unwrap();
    let foreign = write_tile(
        &foreign_dir,
        &Input::File(edited_path),
        &options(None),
        2,
        4,
    );
    let mut mixed = tiles.clone();
    mixed[2] = (foreign.clone(), tiles::read(&foreign).unwrap());
    let err = tiles::merge(&mixed).unwrap_err();
    assert!(err.is_bad_input());
    let message = err.to_string();
    assert!(
        message.starts_with(&format!("{}: a tile of another scene", foreign.display())),
        "{message}"
    );
}

#[test]
fn the_digest_follows_the_scene_and_options_but_not_the_part() {
    let loaded = load(&dof()).unwrap();
    let digest = |o: &Options| tiles::digest(&dof(), &loaded, o).unwrap();
    let base = digest(&options(None));
    assert_eq!(base.len(), 64);
    let tile = options(Some(Part::Tile { index: 1, count: 3 }));
    assert_eq!(digest(&tile), base);
    let more_samples = Options {
        samples: Some(5),
        ..options(None)
    };
    assert_ne!(digest(&more_samples), base);
    let gamma = Options {
        gamma: Some(tracer_pipeline::Gamma::new(1.8).unwrap()),
        ..options(None)
    };
    assert_ne!(digest(&gamma), base);
}

#[test]
fn a_file_that_is_not_a_tile_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain.exr");
    let picture = render_on(1, &dof(), &options(None));
    tracer_pipeline::output::PendingOutput::create(&plain)
        .unwrap()
        .write_picture(&picture, tracer_pipeline::output::BitDepth::Eight)
        .unwrap();
    let err = tiles::read(&plain).unwrap_err();
    assert!(err.is_bad_input());
    assert!(
        err.to_string()
            .starts_with(&format!("{}: not a tile", plain.display())),
        "{err}"
    );
}

/// A tile of `size` holding `region`, every pixel `value`, written to
/// `dir/name`.
fn made_tile(dir: &Path, name: &str, size: (u32, u32), region: Region, value: f32) -> PathBuf {
    let mut linear =
        tracer_pipeline::LinearImage::new(region.x1 - region.x0, region.y1 - region.y0);
    linear.pixels.fill(glam::Vec3::splat(value));
    let picture = Picture {
        linear,
        encoding: tracer_core::image::Encoding::default(),
    };
    let digest = "d".repeat(64);
    let bytes = tiles::encode(&picture, region, size, &digest, None, None).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn region(x0: u32, y0: u32, x1: u32, y1: u32) -> Region {
    Region { x0, y0, x1, y1 }
}

#[test]
fn windows_beyond_the_largest_image_are_refused_from_the_header() {
    let dir = tempfile::tempdir().unwrap();
    // 100000 x 100000 would take 120 GB as floats.
    let huge = made_tile(
        dir.path(),
        "huge.exr",
        (100_000, 100_000),
        region(0, 0, 2, 2),
        0.5,
    );
    let err = tiles::read(&huge).unwrap_err();
    assert!(err.is_bad_input());
    assert!(
        err.to_string().contains("display window is 100000x100000"),
        "{err}"
    );
    let wide = made_tile(
        dir.path(),
        "wide.exr",
        (20_000, 1),
        region(0, 0, 20_000, 1),
        0.5,
    );
    let err = tiles::read(&wide).unwrap_err();
    assert!(err.to_string().contains("window is 20000x1"), "{err}");
}

#[test]
fn tiles_of_one_digest_and_other_sizes_are_refused_not_merged() {
    let dir = tempfile::tempdir().unwrap();
    let a = made_tile(dir.path(), "a.exr", (4, 4), region(0, 0, 4, 2), 0.5);
    let b = made_tile(dir.path(), "b.exr", (8, 8), region(0, 2, 8, 8), 0.5);
    let err = tiles::merge(&read_all(&[a, b.clone()])).unwrap_err();
    assert!(matches!(err, TileError::OtherSize { .. }), "{err}");
    assert!(err
        .to_string()
        .starts_with(&format!("{}: a tile of a 8x8 image", b.display())));
}

#[test]
fn tiles_with_values_that_are_not_finite_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for value in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let path = made_tile(dir.path(), "bad.exr", (4, 4), region(0, 0, 4, 4), value);
        let err = tiles::read(&path).unwrap_err();
        assert!(err.to_string().contains("not finite"), "{value}: {err}");
        assert!(err.is_bad_input());
    }
}

#[test]
fn a_tile_with_a_byte_changed_is_refused_and_rendered_again() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_tile(dir.path(), &dof(), &options(None), 1, 3);
    let good = tiles::read(&path).unwrap();
    assert!(tiles::is_done(&path, &good.digest, good.region));
    let bytes = std::fs::read(&path).unwrap();
    let (mut damaged, mut other) = (0, 0);
    // Every byte past the header's first part, flipped in turn: never read
    // back as a tile.
    for at in (bytes.len() / 3..bytes.len()).step_by(7) {
        let mut flipped = bytes.clone();
        flipped[at] ^= 0x10;
        std::fs::write(&path, &flipped).unwrap();
        match tiles::read(&path) {
            Ok(_) => panic!("byte {at} flipped, read as a tile"),
            Err(TileError::Damaged { .. }) => damaged += 1,
            Err(_) => other += 1,
        }
        assert!(!tiles::is_done(&path, &good.digest, good.region));
    }
    assert!(damaged > 0, "{damaged} damaged, {other} unreadable");
}

#[cfg(unix)]
#[test]
fn a_tile_that_is_not_a_regular_file_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo.exr");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let zero = dir.path().join("zero.exr");
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    for path in [fifo, zero, dir.path().to_path_buf()] {
        let err = tiles::read(&path).unwrap_err();
        assert!(err.is_bad_input(), "{err}");
        let message = err.to_string();
        assert!(
            message.contains("not a regular file") || message.contains("is a folder"),
            "{message}"
        );
    }
}
