//! Alpha masks (`alpha_cutoff`, glTF's `alphaMode` MASK) against the
//! geometry of the scene worked out here: a 2 x 2 quad cut by a 4 x 4
//! checkerboard of alpha in front of a wall, lit by a point light. Where
//! the camera's ray meets a transparent square it sees the wall; where the
//! light's ray crosses one, the wall is lit (in path mode by the point
//! light's irradiance, I cos / d^2, exactly); through an opaque square it
//! is in shadow. The same from a glTF file made here.

use glam::Vec3;
use std::path::Path;
use tracer_core::{prepare, render, Camera, LinearImage, RenderJob, Scene};

const LIGHT: Vec3 = Vec3::new(0.7, 0.4, 6.0);
const WALL_Z: f32 = -2.0;
/// The wall's Lambert albedo (red channel) and the quad's (green).
const WALL_RED: f32 = 0.8;

/// Whether the checkerboard's texel (column, row from the top) is
/// transparent: alpha 0 where column + row is even.
fn clear(column: u32, row: u32) -> bool {
    (column + row).is_multiple_of(2)
}

/// The 4 x 4 RGBA image: white, alpha 0 or 255.
fn checker_png(dir: &Path) {
    let image = image::RgbaImage::from_fn(4, 4, |x, y| {
        let alpha = if clear(x, y) { 0 } else { 255 };
        image::Rgba([255, 255, 255, alpha])
    });
    image.save(dir.join("checker.png")).unwrap();
}

/// What the camera sees through image point (fx, fy).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Seen {
    Quad,
    /// The wall (a plane: no seam to slip through) at this point, lit or
    /// in the quad's shadow.
    Wall(Vec3, bool),
}

/// Whether the quad z = 0, -1 <= x, y <= 1 is there at (x, y): inside
/// it and on an opaque square (uv = ((x + 1) / 2, (y + 1) / 2), rows of
/// texels counted from the top, v = 1), unless `all_cut`.
fn quad_at(p: Vec3, all_cut: bool) -> bool {
    let inside = p.x.abs() < 1.0 && p.y.abs() < 1.0;
    let column = ((p.x + 1.0) * 2.0).floor() as u32;
    let row = ((1.0 - p.y) * 2.0).floor() as u32;
    inside && !all_cut && !clear(column, row)
}

/// Where the line from `from` toward `to` crosses z = `z`.
fn cross_at(from: Vec3, to: Vec3, z: f32) -> Vec3 {
    from + (to - from) * ((z - from.z) / (to.z - from.z))
}

fn seen(camera: &Camera, fx: f32, fy: f32, all_cut: bool) -> Seen {
    let ray = camera.ray(fx, fy);
    let (eye, ahead) = (ray.origin(), ray.origin() + ray.dir());
    if quad_at(cross_at(eye, ahead, 0.0), all_cut) {
        return Seen::Quad;
    }
    let p = cross_at(eye, ahead, WALL_Z);
    Seen::Wall(p, !quad_at(cross_at(p, LIGHT, 0.0), all_cut))
}

/// The pixels whose centre and corners all see the same thing, with it.
fn clear_pixels(camera: &Camera, all_cut: bool) -> Vec<((u32, u32), Seen)> {
    let mut kept = Vec::new();
    for j in 0..camera.height {
        for i in 0..camera.width {
            let (x, y) = (i as f32, j as f32);
            let centre = seen(camera, x + 0.5, y + 0.5, all_cut);
            let kind = |s: Seen| match s {
                Seen::Wall(_, lit) => (1, lit),
                Seen::Quad => (0, false),
            };
            let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
            let same = corners
                .iter()
                .all(|(dx, dy)| kind(seen(camera, x + dx, y + dy, all_cut)) == kind(centre));
            if same {
                kept.push(((i, j), centre));
            }
        }
    }
    kept
}

/// The scene, with `cutter` the objects table of the masked quad.
fn scene_text(path_mode: bool, cutter: &str) -> String {
    let (render, light) = if path_mode {
        ("integrator = \"path\"\nmax_depth = 1\nsamples = 8\n", 40.0)
    } else {
        ("", 1.0)
    };
    format!(
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfov = 30\nwidth = 64\nheight = 64\n\
         handedness = \"right\"\n[render]\n{render}\
         [[lights]]\nposition = [{}, {}, {}]\ncolor = [{light}, {light}, {light}]\n\
         [[objects]]\nplane = {{ point = [0, 0, {WALL_Z}], normal = [0, 0, 1] }}\n\
         material = {{ ambient = [0.1, 0.02, 0.02], diffuse = [{WALL_RED}, 0.2, 0.2] }}\n{cutter}",
        LIGHT.x, LIGHT.y, LIGHT.z
    )
}

const TOML_QUAD: &str = "[[objects]]\nquad = { corner = [-1, -1, 0], edge_u = [2, 0, 0], edge_v = [0, 2, 0] }\n\
     material = { ambient = [0, 0.1, 0], diffuse = [0.2, 0.8, 0.2], texture = { image = \"checker.png\" }, alpha_cutoff = 0.5 }\n";

fn load(dir: &Path, text: &str) -> scene_format::SceneFile {
    std::fs::write(dir.join("scene.toml"), text).unwrap();
    scene_format::load_path(&dir.join("scene.toml")).unwrap_or_else(|e| panic!("{e}"))
}

fn render_linear(scene: &Scene) -> LinearImage {
    render(scene, &RenderJob::full(scene), &|_| {}).image
}

/// Every clear pixel of a Whitted render against what is there: the
/// quad's green, the wall's lit red (ambient plus diffuse) or its ambient
/// alone in shadow. Returns how many of each kind were checked.
fn check_whitted(image: &LinearImage, camera: &Camera, all_cut: bool) -> [u32; 3] {
    let mut counts = [0; 3];
    for ((i, j), s) in clear_pixels(camera, all_cut) {
        let c = image.pixels[(j * image.width + i) as usize];
        match s {
            Seen::Quad => {
                assert!(c.y > 0.5 && c.x < 0.3, "({i}, {j}) the quad: {c}");
                counts[0] += 1;
            }
            Seen::Wall(_, true) => {
                assert!(c.x > 0.6 && c.y < 0.3, "({i}, {j}) the lit wall: {c}");
                counts[1] += 1;
            }
            Seen::Wall(_, false) => {
                assert!(
                    (c - Vec3::new(0.1, 0.02, 0.02)).abs().max_element() < 1e-3,
                    "({i}, {j}) the wall in shadow: {c}"
                );
                counts[2] += 1;
            }
        }
    }
    counts
}

/// Every clear pixel of a path-mode render (direct light only) against
/// the radiance worked out here: on the lit wall the Lambert albedo over
/// pi times the point light's irradiance, I cos / d^2 (within 2 %: the
/// pixel's samples spread over its area); black in shadow.
fn check_path(image: &LinearImage, camera: &Camera, all_cut: bool) -> [u32; 3] {
    let mut counts = [0; 3];
    for ((i, j), s) in clear_pixels(camera, all_cut) {
        let c = image.pixels[(j * image.width + i) as usize];
        match s {
            Seen::Quad => {
                assert!(c.y > 2.0 * c.x && c.y > 0.05, "({i}, {j}) the quad: {c}");
                counts[0] += 1;
            }
            Seen::Wall(p, true) => {
                let to = LIGHT - p;
                let irradiance = 40.0 * to.normalize().z / to.length_squared();
                let expected = WALL_RED / std::f32::consts::PI * irradiance;
                assert!(
                    (c.x / expected - 1.0).abs() < 0.02,
                    "({i}, {j}) the lit wall: {c}, expected red {expected}"
                );
                counts[1] += 1;
            }
            Seen::Wall(_, false) => {
                assert_eq!(c, Vec3::ZERO, "({i}, {j}) the wall in shadow");
                counts[2] += 1;
            }
        }
    }
    counts
}

/// Enough pixels of each kind for the check to mean something: through
/// the holes the wall is both lit and in shadow; with `all_cut`, no quad
/// and no shadow, the wall lit all over.
fn enough(counts: [u32; 3], all_cut: bool) {
    let fine = match all_cut {
        false => counts.iter().all(|&n| n >= 30),
        true => counts[0] == 0 && counts[1] >= 30 && counts[2] == 0,
    };
    assert!(fine, "{counts:?}");
}

#[test]
fn a_checkerboard_of_alpha_cuts_a_quad_for_the_camera_and_for_the_light() {
    let dir = tempfile::tempdir().unwrap();
    checker_png(dir.path());
    for path_mode in [false, true] {
        let scene = prepare(&load(dir.path(), &scene_text(path_mode, TOML_QUAD))).unwrap();
        let image = render_linear(&scene);
        let counts = match path_mode {
            false => check_whitted(&image, scene.camera(), false),
            true => check_path(&image, scene.camera(), false),
        };
        enough(counts, false);
    }
}

/// A quad as glTF writes it: four corners with TEXCOORD_0 (v down the
/// image: the corner at (-1, 1) reads the top left texel), two triangles,
/// its material `material` (JSON) with the checkerboard as base colour.
fn gltf_quad(dir: &Path, material: &str) {
    let positions: [[f32; 3]; 4] = [
        [-1.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, -1.0, 0.0],
        [-1.0, -1.0, 0.0],
    ];
    let uvs: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    // Counter-clockwise seen from +z, as glTF's front faces are.
    let indices: [u16; 6] = [0, 3, 2, 0, 2, 1];
    let mut bin: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    bin.extend(uvs.iter().flatten().flat_map(|x| x.to_le_bytes()));
    bin.extend(indices.iter().flat_map(|x| x.to_le_bytes()));
    std::fs::write(dir.join("quad.bin"), &bin).unwrap();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
        "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 1}}, "indices": 2, "material": 0}}]}}],
        "materials": [{material}],
        "textures": [{{"source": 0}}], "images": [{{"uri": "checker.png"}}],
        "accessors": [
          {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]}},
          {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}},
          {{"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}}],
        "bufferViews": [
          {{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
          {{"buffer": 0, "byteOffset": 48, "byteLength": 32}},
          {{"buffer": 0, "byteOffset": 80, "byteLength": 12}}],
        "buffers": [{{"byteLength": {}, "uri": "quad.bin"}}]}}"#,
        bin.len()
    );
    std::fs::write(dir.join("quad.gltf"), json).unwrap();
}

fn gltf_material(mode: &str, alpha: f32) -> String {
    format!(
        r#"{{"name": "leaves", "pbrMetallicRoughness": {{"baseColorFactor": [0.2, 0.8, 0.2, {alpha}],
        "baseColorTexture": {{"index": 0}}, "metallicFactor": 0, "roughnessFactor": 1}}, "alphaMode": "{mode}", "alphaCutoff": 0.5}}"#
    )
}

const GLTF_OBJECT: &str = "[[objects]]\ngltf = { file = \"quad.gltf\" }\n";

#[test]
fn a_gltf_mask_cuts_as_the_texture_s_alpha_times_the_factor_s_says() {
    let dir = tempfile::tempdir().unwrap();
    checker_png(dir.path());
    // MASK; BLEND, read as MASK at 0.5 (with a warning naming the
    // material); MASK with a factor alpha of 0.4, below the cutoff even
    // where the texture's alpha is 1: all of the quad is cut.
    for (mode, alpha, all_cut) in [
        ("MASK", 1.0, false),
        ("BLEND", 1.0, false),
        ("MASK", 0.4, true),
    ] {
        gltf_quad(dir.path(), &gltf_material(mode, alpha));
        let file = load(dir.path(), &scene_text(false, GLTF_OBJECT));
        let warned = scene_format::warnings(&file)
            .iter()
            .any(|w| w.message.contains("\"leaves\": BLEND is read as MASK"));
        assert_eq!(warned, mode == "BLEND", "{mode}");
        let scene = prepare(&file).unwrap();
        let image = render_linear(&scene);
        enough(check_whitted(&image, scene.camera(), all_cut), all_cut);
        let scene = prepare(&load(dir.path(), &scene_text(true, GLTF_OBJECT))).unwrap();
        let image = render_linear(&scene);
        enough(check_path(&image, scene.camera(), all_cut), all_cut);
    }
}

#[test]
fn an_opaque_gltf_material_ignores_alpha() {
    let dir = tempfile::tempdir().unwrap();
    checker_png(dir.path());
    gltf_quad(dir.path(), &gltf_material("OPAQUE", 1.0));
    let scene = prepare(&load(dir.path(), &scene_text(false, GLTF_OBJECT))).unwrap();
    let image = render_linear(&scene);
    // Every texel's square is there: the quad's centre of each is green.
    for (column, row) in (0..4).flat_map(|c| (0..4).map(move |r| (c, r))) {
        let point = Vec3::new(-0.75 + 0.5 * column as f32, 0.75 - 0.5 * row as f32, 0.0);
        let at = scene.camera().seen_at(point).expect("in view").as_vec2();
        let (i, j) = (at.x as u32, at.y as u32);
        let c = image.pixels[(j * image.width + i) as usize];
        assert!(c.y > 0.5, "square ({column}, {row}) at ({i}, {j}): {c}");
    }
}

/// A 2 x 2 quad in z = 0 as an OBJ, uv = ((x + 1) / 2, (y + 1) / 2).
const QUAD_OBJ: &str = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
                        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";

/// Whether a ray down -z through `at` (a cell's centre of a quad placed
/// at `offset`) meets something.
fn blocked(scene: &Scene, at: Vec3) -> bool {
    let ray = tracer_core::Ray::new(at + Vec3::Z * 5.0, -Vec3::Z);
    scene.closest_hit(&ray, 1e-4, f32::INFINITY).is_some()
}

/// The centres of the quad's 16 squares (at z = 0, placed by `offset`),
/// each with whether its texel is opaque.
fn squares(offset: Vec3) -> impl Iterator<Item = (Vec3, bool)> {
    (0..16).map(move |k| {
        let (column, row) = (k % 4, k / 4);
        let at = Vec3::new(-0.75 + 0.5 * column as f32, 0.75 - 0.5 * row as f32, 0.0);
        (at + offset, !clear(column, row))
    })
}

#[test]
fn a_mesh_shared_by_objects_is_cut_by_each_object_s_own_mask() {
    let dir = tempfile::tempdir().unwrap();
    checker_png(dir.path());
    std::fs::write(dir.path().join("quad.obj"), QUAD_OBJ).unwrap();
    let object = |x: f32, y: f32, material: &str| {
        format!("[[objects]]\nmesh = {{ obj = \"quad.obj\" }}\nmaterial = {material}\ntransform = {{ translate = [{x}, {y}, 0] }}\n")
    };
    let leaf =
        "{ diffuse = [0.2, 0.8, 0.2], texture = { image = \"checker.png\" }, alpha_cutoff = 0.5 }";
    let text = format!(
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [0, 0, 10]\n\
         [materials.leaf]\ndiffuse = [0.2, 0.8, 0.2]\ntexture = {{ image = \"checker.png\" }}\nalpha_cutoff = 0.5\n\
         [materials.plain]\ndiffuse = [0.5, 0.5, 0.5]\n{}{}{}{}{}",
        object(-3.0, 0.0, "\"leaf\""),
        object(3.0, 0.0, "\"plain\""),
        object(-3.0, 3.0, "\"leaf\""),
        object(3.0, 3.0, "\"plain\""),
        object(0.0, -3.0, leaf),
    );
    let file = load(dir.path(), &text);
    // The masked objects share one mesh, the plain ones another; the
    // inline material is the object's alone.
    let groups = tracer_core::prepare::shared_meshes(&file);
    assert_eq!(groups, [Some(0), Some(1), Some(0), Some(1), None]);
    let scene = prepare(&file).unwrap();
    assert!(scene.has_instances());
    for (x, y, masked) in [
        (-3.0, 0.0, true),
        (3.0, 0.0, false),
        (-3.0, 3.0, true),
        (3.0, 3.0, false),
        (0.0, -3.0, true),
    ] {
        for (at, opaque) in squares(Vec3::new(x, y, 0.0)) {
            assert_eq!(blocked(&scene, at), opaque || !masked, "{at}");
        }
    }
}

#[test]
fn a_gltf_mesh_placed_twice_is_cut_where_each_object_s_materials_say() {
    let dir = tempfile::tempdir().unwrap();
    checker_png(dir.path());
    gltf_quad(dir.path(), &gltf_material("MASK", 1.0));
    // Two nodes place the one mesh: it is instanced.
    let path = dir.path().join("quad.gltf");
    let json = std::fs::read_to_string(&path).unwrap().replace(
        r#""scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}]"#,
        r#""scenes": [{"nodes": [0, 1]}], "nodes": [{"mesh": 0}, {"mesh": 0, "translation": [0, 3, 0]}]"#,
    );
    std::fs::write(&path, json).unwrap();
    // The file's materials (masked); a material standing for them that
    // cuts nothing; one that cuts where the file's is whole.
    let inverted = image::RgbaImage::from_fn(4, 4, |x, y| {
        image::Rgba([255, 255, 255, if clear(x, y) { 255 } else { 0 }])
    });
    inverted.save(dir.path().join("inverted.png")).unwrap();
    let object = |x: f32, material: &str| {
        format!("[[objects]]\ngltf = {{ file = \"quad.gltf\" }}\n{material}transform = {{ translate = [{x}, 0, 0] }}\n")
    };
    let text = format!(
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [0, 0, 10]\n{}{}{}",
        object(-3.0, ""),
        object(0.0, "material = { diffuse = [0.5, 0.5, 0.5] }\n"),
        object(3.0, "material = { diffuse = [0.5, 0.5, 0.5], texture = { image = \"inverted.png\" }, alpha_cutoff = 0.5 }\n"),
    );
    let scene = prepare(&load(dir.path(), &text)).unwrap();
    assert!(scene.has_instances());
    for (x, expected) in [(-3.0, "file"), (0.0, "whole"), (3.0, "inverted")] {
        for node_y in [0.0, 3.0] {
            for (at, opaque) in squares(Vec3::new(x, node_y, 0.0)) {
                let there = match expected {
                    "file" => opaque,
                    "whole" => true,
                    _ => !opaque,
                };
                assert_eq!(blocked(&scene, at), there, "{expected} at {at}");
            }
        }
    }
}

#[test]
fn explain_names_a_triangle_met_in_a_hole() {
    use tracer_core::explain::{explain, Outcome, Trace};
    let dir = tempfile::tempdir().unwrap();
    checker_png(dir.path());
    let scene = prepare(&load(dir.path(), &scene_text(false, TOML_QUAD))).unwrap();
    let camera = scene.camera();
    // A pixel that sees the wall through a hole of the quad, off the
    // diagonal its two halves share (x = -y, on pixels i = j).
    let ((i, j), _) = clear_pixels(camera, false)
        .into_iter()
        .find(|&((i, j), s)| {
            let through = |p: Vec3| p.x.abs() < 1.0 && p.y.abs() < 1.0;
            i != j && matches!(s, Seen::Wall(p, _) if through(p))
        })
        .expect("a hole in view");
    let explained = explain(&scene, (i, j), 1, 0);
    let Trace::Whitted { ray } = &explained.trace else {
        panic!("Whitted")
    };
    let tested = ray.tested.as_ref().expect("a few objects");
    // The plane is the nearest; one of the quad's halves is met in a hole.
    assert!(
        matches!(tested[0].outcome, Outcome::Nearest { .. }),
        "{tested:?}"
    );
    let cut = tested
        .iter()
        .filter(|t| matches!(t.outcome, Outcome::Cutout { .. }));
    assert_eq!(cut.count(), 1, "{tested:?}");
}
