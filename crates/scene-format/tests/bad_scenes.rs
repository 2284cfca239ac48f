//! Every file in `tests/bad/` is a scene with a mistake a student could
//! make. Each is rejected with the key path, line, column and message
//! listed here (worked out by reading the file, not by running the code),
//! and the full report is snapshotted so its wording gets reviewed.

use scene_format::{Format, SceneError};
use std::path::{Path, PathBuf};

struct Case {
    file: &'static str,
    /// The key path of the first diagnostic; empty for the whole file.
    path: &'static str,
    line: usize,
    column: usize,
    /// A part of the first diagnostic's message.
    message: &'static str,
}

const fn case(
    file: &'static str,
    path: &'static str,
    line: usize,
    column: usize,
    message: &'static str,
) -> Case {
    Case {
        file,
        path,
        line,
        column,
        message,
    }
}

#[rustfmt::skip]
const CASES: &[Case] = &[
    case("big-number.toml", "camera.fov", 4, 7, "expected a finite number, found inf"),
    case("huge-number.json", "camera.eye[2]", 1, 27, "number out of range; expected a finite number"),
    case("binary.toml", "", 1, 1, "found byte 0x89, which is not UTF-8 text"),
    case("bom.json", "camera.fov", 2, 62, "expected degrees between 0 and 180 (exclusive), found 0"),
    case("canvas-transform-two-keys.toml", "shapes[0].transform[0]", 7, 14, "expected a table with exactly one key, found several"),
    case("comments-only.toml", "camera", 1, 1, "missing key `camera` at the top level"),
    case("control-characters.toml", "objects[0].material", 10, 12, "[31mred`; expected one of `red`"),
    case("cr-line-endings.json", "camera.fov", 5, 12, "found 500"),
    case("cr-line-endings.toml", "camera.fov", 5, 7, "found 500"),
    case("degenerate-triangle.toml", "objects[0].triangle", 6, 12, "the triangle is degenerate"),
    case("duplicate-key.json", "camera.eye", 5, 5, "duplicate key `eye` in [camera] (first defined at line 3, column 5)"),
    case("duplicate-key.toml", "camera.fov", 5, 1, "duplicate key `fov` in [camera]; expected each key once"),
    case("duplicate-key-second-object.toml", "objects[1].material", 19, 1, "duplicate key `material` in `objects[1]`"),
    case("duplicate-material.json", "materials.red", 5, 5, "duplicate key `red` in [materials] (first defined at line 4, column 5)"),
    case("duplicate-table.toml", "camera", 5, 2, "duplicate table [camera]; expected each table once"),
    case("empty.json", "", 1, 1, "the file is empty"),
    case("empty.toml", "", 1, 1, "the file is empty"),
    case("center-huge.toml", "objects[0].sphere.center", 6, 21, "expected coordinates from -1e6 to 1e6, found [1e19, 0, 0]; single-precision tracing cannot handle larger ones"),
    case("eye-far.toml", "camera.eye", 2, 7, "expected coordinates from -1e6 to 1e6, found [0, 0, 3e38]"),
    case("eye-equals-look-at.toml", "camera.look_at", 3, 11, "expected a point other than `camera.eye`"),
    case("float-width.toml", "camera.width", 4, 9, "expected a whole number of pixels from 1 to 16384, found 640.5"),
    case("fov-180.toml", "camera.fov", 4, 7, "expected degrees between 0 and 180 (exclusive), found 180"),
    case("fov-zero.toml", "camera.fov", 4, 7, "found 0"),
    case("fov-tiny.toml", "camera.fov", 4, 7, "expected at least 1 degree, found 1e-20; below it neighbouring pixels get the same single-precision ray"),
    case("gamma-zero.toml", "render.gamma", 6, 9, "expected a number > 0, found 0"),
    case("width-past-64-bits.toml", "camera.width", 4, 9, "expected a whole number of pixels from 1 to 16384, found 99999999999999999999"),
    case("height-too-large.toml", "camera.height", 4, 10, "expected 1 to 16384 pixels, found 20000"),
    case("inf-radius.toml", "objects[0].sphere.radius", 6, 41, "expected a finite number, found inf"),
    case("latin1.json", "", 1, 72, "found byte 0xfc, which is not UTF-8 text"),
    case("light-far.json", "lights[0].position", 3, 27, "expected coordinates from -1e6 to 1e6, found [0, -2e7, 8]"),
    case("many-errors.toml", "camera.fov", 4, 7, "found 200"),
    case("max-depth-too-deep.toml", "render.max_depth", 6, 13, "expected at most 64, found 1000"),
    case("min-energy-negative.toml", "render.min_energy", 6, 14, "expected a number >= 0, found -0.01"),
    case("mesh-scale-tiny.toml", "objects[0].transform.scale", 7, 23, "expected factors from 1e-6 to 1e6 (or their negatives), found [1e-30, 1e-30, 1e-30]"),
    case("minified.json", "objects[0].material.reflectance", 1, 299, "expected a number from 0 to 1, found 3"),
    case("missing-camera.toml", "camera", 1, 1, "missing key `camera` at the top level"),
    case("missing-eye.toml", "camera.eye", 1, 2, "missing key `eye` in [camera]"),
    case("missing-light-position.toml", "lights[0].position", 5, 1, "missing key `position` in `lights[0]`"),
    case("missing-look-at.json", "camera.look_at", 2, 3, "missing key `look_at` in [camera]"),
    case("missing-sphere-radius.toml", "objects[0].sphere.radius", 6, 1, "missing key `radius` in `objects[0].sphere`"),
    case("nan-eye.toml", "camera.eye", 2, 7, "expected finite numbers"),
    case("negative-background.toml", "render.background", 6, 14, "expected a colour with channels >= 0"),
    case("negative-diffuse.toml", "materials.red.diffuse", 6, 11, "expected a colour with channels >= 0"),
    case("negative-light-colour.toml", "lights[0].color", 7, 9, "expected a colour with channels >= 0"),
    case("negative-width.toml", "camera.width", 4, 9, "expected a whole number of pixels from 1 to 16384, found -5"),
    case("no-materials-defined.toml", "objects[0].material", 7, 12, "unknown material `red`; expected a name from [materials], but none are defined"),
    case("not-an-object.json", "", 1, 1, "expected a JSON object"),
    case("nul-byte.toml", "", 2, 17, "found a NUL byte"),
    case("object-two-shapes.toml", "objects[0]", 5, 1, "expected exactly one shape per object"),
    case("object-without-shape.toml", "objects[0]", 5, 1, "expected a shape: one of `sphere`, `triangle`, `mesh`, `plane`, `box`, `quad`"),
    case("plane-zero-normal.toml", "objects[0].plane.normal", 6, 40, "expected a non-zero vector, found [0, 0, 0]; a plane needs the side it faces"),
    case("box-flat.toml", "objects[0].box.max", 6, 34, "expected `max` above `min` on every axis, found min [-1, 0, -1] and max [1, 0, 1]"),
    case("box-huge.toml", "objects[0].box.max", 6, 35, "expected coordinates from -1e6 to 1e6, found [1, 1, 2e7]"),
    case("quad-parallel-edges.toml", "objects[0].quad.edge_v", 6, 59, "expected an edge not parallel to `edge_u` ([1, 2, 0]), found [-2, -4, 0]; the quad is degenerate"),
    case("quad-zero-edge.toml", "objects[0].quad.edge_u", 6, 39, "expected a non-zero edge, found [0, 0, 0]"),
    case("quad-corner-far.toml", "objects[0].quad", 6, 8, "expected corners with coordinates from -1e6 to 1e6, found [1100000, 0, 0]"),
    case("obj-bad-vertex.toml", "objects[0].mesh.obj", 6, 16, "`obj-bad-vertex.obj:3`: expected numbers in a `v` line, found `O`"),
    case("ply-truncated.toml", "objects[0].mesh.ply", 6, 16, "`ply-truncated.ply`: not a valid PLY file: it ends before the data its header declares"),
    case("mesh-obj-and-ply.toml", "objects[0].mesh.ply", 6, 34, "expected one mesh file, `obj` or `ply`; found both"),
    case("uv-on-sphere.toml", "objects[0].uv", 7, 6, "expected `uv` only on a `triangle` object"),
    case("obj-index-out-of-range.toml", "objects[1].mesh.obj", 9, 16, "`obj-index-out-of-range.obj:5`: vertex index 4 in `4`, but only 3 defined before this line"),
    case("radius-huge.toml", "objects[0].sphere.radius", 6, 41, "expected a radius from 1e-4 to 1e6, found 1e19"),
    case("radius-negative.json", "objects[1].sphere.radius", 5, 48, "expected a radius from 1e-4 to 1e6, found -2"),
    case("radius-negative.toml", "objects[1].sphere.radius", 9, 41, "expected a radius from 1e-4 to 1e6, found -1.5"),
    case("radius-tiny.toml", "objects[0].sphere.radius", 6, 41, "expected a radius from 1e-4 to 1e6, found 1e-7"),
    case("radius-zero.toml", "objects[0].sphere.radius", 6, 41, "expected a radius from 1e-4 to 1e6, found 0"),
    case("reflectance-above-one.toml", "materials.mirror.reflectance", 6, 15, "expected a number from 0 to 1, found 1.5"),
    case("saturation-number.toml", "render.saturation", 5, 14, "expected a name in quotes or a table with one key"),
    case("saturation-typo.toml", "render.saturation", 6, 14, "unknown value `clmap`; did you mean `clamp`?"),
    case("shininess-negative.toml", "materials.shiny.shininess", 6, 13, "expected a number >= 0, found -30"),
    case("syntax-missing-equals.toml", "", 2, 5, "expected `=`"),
    case("syntax-single-quotes.json", "", 2, 3, "key must be a string"),
    case("syntax-trailing-comma.json", "", 5, 3, "trailing comma"),
    case("syntax-unclosed-array.toml", "", 3, 1, "expected `,`"),
    case("syntax-unclosed-string.toml", "", 6, 23, "expected `\"`"),
    case("tabs-and-unicode.toml", "materials.\"grün\".shininess", 8, 14, "expected a number >= 0, found -1"),
    case("too-long-colour.json", "lights[0].color", 4, 38, "expected 3 numbers, found 4"),
    case("too-long-eye.toml", "camera.eye", 2, 7, "expected 3 numbers, found 4"),
    case("too-long-translate-2d.toml", "shapes[0].transform[0].translate", 8, 28, "expected 2 numbers, found 3"),
    case("too-wide.toml", "camera.width", 4, 9, "expected 1 to 16384 pixels, found 16385"),
    case("trailing-garbage.json", "", 2, 1, "trailing characters"),
    case("triangle-four-vertices.toml", "objects[0].triangle", 6, 12, "expected 3 vertices, found 4"),
    case("unknown-camera-key.toml", "camera.fvo", 4, 1, "unknown key `fvo` in [camera]; did you mean `fov`?"),
    case("unknown-inline-material-key.toml", "objects[0].material.specullar", 7, 37, "unknown key `specullar` in `objects[0].material`; did you mean `specular`?"),
    case("unknown-key-no-suggestion.toml", "camera.zoom", 4, 1, "unknown key `zoom` in [camera]; expected one of `eye`, `look_at`, `up`, `fov`, `width`, `height`, `handedness`, `aperture`, `focus_distance`"),
    case("unknown-key.json", "camera.fvo", 5, 5, "unknown key `fvo` in [camera]; did you mean `fov`?"),
    case("unknown-material-key.toml", "materials.red.difuse", 6, 1, "unknown key `difuse` in [materials.red]; did you mean `diffuse`?"),
    case("unknown-material-name.toml", "objects[0].material", 10, 12, "unknown material `bleu`; did you mean `blue`?"),
    case("unknown-material-texture.toml", "materials.wood.texture", 6, 11, "unknown texture `wood`; expected one of `lab-stripes`"),
    case("unknown-sphere-key.toml", "objects[0].sphere.raduis", 6, 32, "unknown key `raduis` in `objects[0].sphere`; did you mean `radius`?"),
    case("unknown-table.toml", "lihgts", 5, 3, "unknown key `lihgts` at the top level; did you mean `lights`?"),
    case("unknown-texture.toml", "objects[0].texture", 7, 11, "unknown texture `lab-stripe`; did you mean `lab-stripes`?"),
    case("up-parallel.toml", "camera.up", 4, 6, "expected a vector not parallel to the view direction"),
    case("up-zero.toml", "camera.up", 4, 6, "expected a non-zero vector"),
    case("width-zero.toml", "camera.width", 4, 9, "expected 1 to 16384 pixels, found 0"),
    case("wrong-length-eye.toml", "camera.eye", 2, 7, "expected an array of 3 elements, found 2 elements"),
    case("wrong-type-eye.toml", "camera.eye", 2, 7, "expected an array of 3 elements, found 5"),
    case("wrong-type-fov.toml", "camera.fov", 4, 7, "expected a number, found the string \"wide\""),
    case("wrong-type-lights.toml", "lights", 1, 10, "expected an array, found 5"),
    case("wrong-type-material.toml", "objects[0].material", 7, 12, "expected a material name (a string) or an inline material table, found 5"),
    case("samples-zero.toml", "render.samples", 6, 11, "expected 1 to 4096 samples, found 0"),
    case("light-samples-too-many.toml", "render.light_samples", 7, 17, "expected 1 to 4096 samples, found 5000"),
    case("ior-zero.toml", "materials.glass.ior", 7, 7, "expected an index of refraction > 0"),
    case("transmittance-above-one.toml", "materials.glass.transmittance", 6, 17, "expected a number from 0 to 1, found 1.2"),
    case("reflectance-plus-transmittance.toml", "materials.glass.transmittance", 7, 17, "found 0.6 + 0.7 = 1.3"),
    case("light-radius-negative.toml", "lights[0].radius", 7, 10, "expected a radius >= 0, found -0.5"),
    case("aperture-negative.toml", "camera.aperture", 4, 12, "expected a lens radius >= 0, found -0.1"),
    case("focus-distance-zero.toml", "camera.focus_distance", 4, 18, "expected a distance > 0, found 0"),
    case("focus-distance-negative.json", "camera.focus_distance", 2, 73, "expected a distance > 0, found -4"),
    case("image-missing.toml", "materials.wood.texture.image", 7, 21, "cannot load `textures/wood.png`: No such file or directory"),
    case("texture-unknown-key.toml", "objects[0].texture.wrapp", 7, 33, "unknown key `wrapp` in `objects[0].texture`; did you mean `wrap`?"),
    case("texture-wrong-type.toml", "objects[0].texture", 7, 11, "expected a texture name (a string) or a texture table (`image` or `checker`), found 5"),
    case("checker-negative.toml", "objects[0].texture.checker[1]", 7, 35, "expected a colour with channels >= 0, found [0, -0.5, 0]"),
    case("checker-wrap.toml", "objects[0].texture", 7, 11, "expected `wrap` only with `image`"),
    case("wrong-type.json", "camera.width", 2, 64, "expected a whole number of pixels from 1 to 16384, found the string \"640\""),
    case("emission-negative.toml", "materials.lamp.emission", 6, 12, "expected a colour with channels >= 0, found [4, -1, 4]"),
    case("integrator-typo.toml", "render.integrator", 6, 14, "unknown value `pth`; did you mean `path`?"),
    case("emissive-plane.toml", "objects[0].material", 10, 12, "an infinite plane cannot be sampled as a light; use a `quad`"),
    case("samples-whitted-too-many.toml", "render.samples", 6, 11, "expected 1 to 4096 samples, found 8192; more are allowed with integrator = \"path\""),
    case("samples-path-too-many.toml", "render.samples", 7, 11, "expected 1 to 65536 samples, found 100000"),
    case("time-limit-negative.toml", "render.time_limit", 7, 14, "expected seconds > 0, found -5"),
    case("metallic-above-one.toml", "materials.gold.metallic", 7, 12, "expected a number from 0 to 1, found 1.5"),
    case("roughness-negative.toml", "materials.paint.roughness", 6, 13, "expected a number from 0 to 1, found -0.2"),
    case("transmission-above-one.toml", "materials.glass.transmission", 6, 16, "expected a number from 0 to 1, found 2"),
    case("material-two-kinds.toml", "materials.odd.metallic", 7, 12, "expected one kind of material: physically based (`base_color`, `metallic`, `roughness`, `transmission`) or the lab's Blinn-Phong"),
    case("environment-image-and-color.toml", "environment.color", 6, 9, "expected either `image` or `color`, found both"),
    case("environment-image-missing.toml", "environment.image", 6, 9, "cannot load `no-such-sky.hdr`"),
    case("environment-image-empty.toml", "environment.image", 6, 9, "cannot load `empty-sky.hdr`: 0x0 texels: the image is empty; expected at least 1x1"),
    case("environment-empty.toml", "environment", 5, 1, "expected `image` (a latitude-longitude .hdr or .exr file) or `color`; found neither"),
    case("camera-as-array.toml", "camera", 3, 10, "expected a table of named keys (`{ key = value, ... }` or a `[header]`), found an array"),
    case("sphere-as-long-array.json", "objects[0].sphere", 4, 26, "expected an object of named keys ({\"key\": value, ...}), found an array"),
    case("material-as-array.json", "materials.red", 4, 24, "expected an object of named keys ({\"key\": value, ...}), found an array"),
    case("alpha-cutoff-above-one.toml", "materials.leaf.alpha_cutoff", 7, 16, "expected a number from 0 to 1, found 128"),
    case("alpha-cutoff-sphere.toml", "objects[1].material", 15, 12, "expected a material without `alpha_cutoff` on a sphere: alpha masks cut triangles only"),
    case("normal-texture-lab.toml", "materials.bumpy.normal_texture", 7, 18, "expected `normal_texture` on a physically based material"),
    case("alpha-cutoff-plane.toml", "objects[0].material", 7, 12, "expected a material without `alpha_cutoff` on a plane"),
    case("alpha-cutoff-checker.toml", "materials.leaf.alpha_cutoff", 8, 16, "expected an image `texture` to read alpha from, found a checker, which has none"),
    case("physical-lab-texture.toml", "materials.striped.texture", 7, 11, "expected an image or checker texture table on a physically based material"),
];

fn bad_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad")
}

/// Loads `tests/bad/<name>`, naming it `bad/<name>` so reports do not
/// depend on where the checkout is. A scene with an OBJ or PLY of its own
/// name beside it, or with an image texture, is loaded from its path, so
/// its meshes and images are read too.
fn load_bad(name: &str) -> SceneError {
    let path = bad_dir().join(name);
    let reads_files = path.with_extension("obj").exists()
        || path.with_extension("ply").exists()
        || std::fs::read_to_string(&path).is_ok_and(|t| t.contains("image ="));
    if reads_files {
        return match scene_format::load_any(&path) {
            Ok(_) => panic!("{name}: accepted, expected an error"),
            Err(e) => e,
        };
    }
    let bytes = std::fs::read(bad_dir().join(name)).unwrap();
    let format = Format::from_path(Path::new(name)).unwrap();
    let file = Path::new("bad").join(name);
    // Text may be a 3D or a 2D canvas scene; bytes that are not text go
    // through the byte loader, which says so.
    let result = match std::str::from_utf8(&bytes) {
        Ok(text) => scene_format::load_any_str(text, format, &file).map(drop),
        Err(_) => scene_format::load_bytes(&bytes, format, &file).map(drop),
    };
    match result {
        Ok(()) => panic!("{name}: accepted, expected an error"),
        Err(e) => e,
    }
}

#[test]
fn every_bad_file_names_the_key_line_column_and_problem() {
    let mut failures = Vec::new();
    for case in CASES {
        let error = load_bad(case.file);
        let d = &error.diagnostics()[0];
        let location = d.location.map(|l| (l.line, l.column));
        let ok = d.path == case.path
            && location == Some((case.line, case.column))
            && d.message.contains(case.message);
        if !ok {
            failures.push(format!(
                "{}: expected `{}` at {}:{} with {:?}\n   got `{}` at {:?} with {:?}",
                case.file,
                case.path,
                case.line,
                case.column,
                case.message,
                d.path,
                location,
                d.message
            ));
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

#[test]
fn every_bad_file_has_a_case_and_there_are_at_least_40() {
    let mut files: Vec<String> = std::fs::read_dir(bad_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|f| ![".obj", ".ply", ".hdr"].iter().any(|e| f.ends_with(e)))
        .collect();
    files.sort();
    let listed: Vec<&str> = CASES.iter().map(|c| c.file).collect();
    for f in &files {
        assert!(listed.contains(&f.as_str()), "{f} has no case in CASES");
    }
    assert_eq!(files.len(), CASES.len(), "a case names a missing file");
    assert!(files.len() >= 40);
}

#[test]
fn validation_reports_every_problem_in_file_order() {
    let error = load_bad("many-errors.toml");
    let found: Vec<(String, usize)> = error
        .diagnostics()
        .iter()
        .map(|d| (d.path.to_string(), d.location.unwrap().line))
        .collect();
    let expected = [
        ("camera.fov", 4),
        ("camera.width", 5),
        ("materials.red.reflectance", 8),
        ("objects[0].sphere.radius", 11),
        ("objects[0].material", 12),
    ];
    let expected: Vec<(String, usize)> =
        expected.iter().map(|(p, l)| (p.to_string(), *l)).collect();
    assert_eq!(found, expected);
}

#[test]
fn reports_show_the_source_line_and_a_caret() {
    for case in CASES {
        let full = bad_dir().join(case.file).display().to_string();
        let short = Path::new("bad").join(case.file).display().to_string();
        let report = load_bad(case.file).to_string().replace(&full, &short);
        insta::assert_snapshot!(case.file, report);
    }
}
