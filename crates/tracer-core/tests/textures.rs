//! Colour textures and OBJ materials against numbers worked out apart from
//! the code: an image seen texel for texel through a camera sized to it
//! (decoded here by the sRGB formula), a checkerboard's squares where the
//! floor's geometry puts them, MTL values in the prepared materials and in
//! the light of a face lit head-on.

mod common;

use common::srgb_decoded;
use glam::Vec3;
use std::path::Path;
use tracer_core::material::{Material, Phong};
use tracer_core::texture::ColorTexture;
use tracer_core::{prepare, render, LinearImage, RenderJob, Scene};

fn write(dir: &Path, name: &str, bytes: &[u8]) {
    let path = dir.join(name);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, bytes).unwrap();
}

/// The scene `text` saved as `scene.toml` in `dir`, loaded with its files.
fn load(dir: &Path, text: &str) -> scene_format::SceneFile {
    write(dir, "scene.toml", text.as_bytes());
    scene_format::load_path(&dir.join("scene.toml")).unwrap_or_else(|e| panic!("{e}"))
}

fn scene(dir: &Path, text: &str) -> Scene {
    prepare(&load(dir, text)).expect("prepare")
}

fn render_linear(scene: &Scene) -> LinearImage {
    render(scene, &RenderJob::full(scene), &|_| {}).image
}

/// A `width` x `height` image of reproducible, uneven pixels.
fn noise_image(width: u32, height: u32) -> image::RgbImage {
    let mut state = 12345u32;
    image::RgbImage::from_fn(width, height, |_, _| {
        image::Rgb(std::array::from_fn(|_| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 24) as u8
        }))
    })
}

fn encoded(image: &image::RgbImage, format: image::ImageFormat) -> Vec<u8> {
    let mut bytes = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut bytes), format)
        .unwrap();
    bytes
}

/// A camera 1 unit from a 2 x 1.5 quad with a 90 degree field of view sees
/// exactly the quad (its half-width over the distance is tan 45 = 1); at
/// 40 x 30 pixels each pixel's centre falls on a texel's centre of a
/// 40 x 30 image, where bilinear filtering returns that texel. Only
/// ambient (1, under one white light) is lit, so each pixel's linear value
/// is the texel's, decoded.
fn image_fills_the_view(file: &str, format: image::ImageFormat) {
    let (w, h) = (40, 30);
    let dir = tempfile::tempdir().unwrap();
    let bytes = encoded(&noise_image(w, h), format);
    write(dir.path(), file, &bytes);
    // What the file holds (a JPEG is lossy): the texels expected.
    let stored = image::load_from_memory(&bytes).unwrap().to_rgb8();
    let scene = scene(
        dir.path(),
        &format!(
            "[camera]\neye = [0, 0, 1]\nlook_at = [0, 0, 0]\nfov = 90\nwidth = {w}\nheight = {h}\n\
             handedness = \"right\"\n[[lights]]\nposition = [0, 0, 5]\n\
             [[objects]]\nquad = {{ corner = [-1, -0.75, 0], edge_u = [2, 0, 0], edge_v = [0, 1.5, 0] }}\n\
             material = {{ ambient = [1, 1, 1], texture = {{ image = \"{file}\" }} }}\n"
        ),
    );
    let linear = render_linear(&scene);
    let mut worst = 0.0f64;
    for j in 0..h {
        for i in 0..w {
            let got = linear.get(i, j).to_array();
            let texel = stored.get_pixel(i, j).0;
            for c in 0..3 {
                worst = worst.max((f64::from(got[c]) - srgb_decoded(texel[c])).abs());
            }
        }
    }
    assert!(worst < 1e-4, "{file}: largest difference {worst}");
}

#[test]
fn a_png_filling_the_view_at_its_resolution_is_reproduced() {
    image_fills_the_view("tex/noise.png", image::ImageFormat::Png);
}

#[test]
fn a_jpeg_filling_the_view_at_its_resolution_is_reproduced() {
    image_fills_the_view("noise.jpg", image::ImageFormat::Jpeg);
}

/// A camera 10 above a floor, looking straight down with a 90 degree
/// field of view and `up` = -z, sees x from -10 to 10 across 100 pixels
/// (+x to the right) and z growing down the image: pixel (i, j)'s centre
/// is x = (i + 0.5 - 50) 0.2, z = (j + 0.5 - 40) 0.2. The floor's uv is
/// (x, -z); with scale 0.5 the squares are 2 wide, the first colour where
/// floor(x / 2) + floor(-z / 2) is even.
#[test]
fn checker_squares_land_where_the_floor_geometry_puts_them() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene(
        dir.path(),
        "[camera]\neye = [0, 10, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov = 90\n\
         width = 100\nheight = 80\nhandedness = \"right\"\n[[lights]]\nposition = [0, 20, 0]\n\
         [[objects]]\nplane = { point = [0, 0, 0], normal = [0, 1, 0] }\n\
         material = { ambient = [1, 1, 1] }\n\
         texture = { checker = [[1, 0, 0], [0, 0, 1]], scale = 0.5 }\n",
    );
    let linear = render_linear(&scene);
    let (red, blue) = (Vec3::X, Vec3::Z);
    for j in 0..80 {
        for i in 0..100 {
            let x = (f64::from(i) + 0.5 - 50.0) * 0.2;
            let z = (f64::from(j) + 0.5 - 40.0) * 0.2;
            // Centres are 0.05 or more from a square's edge: no ties.
            let even = ((x / 2.0).floor() + (-z / 2.0).floor()) as i64 % 2 == 0;
            let expected = if even { red } else { blue };
            let got = linear.get(i, j);
            assert!(
                (got - expected).length() < 1e-6,
                "pixel ({i}, {j}) at x {x}, z {z}: {got}, expected {expected}"
            );
        }
    }
}

/// A colour texture multiplies ambient and diffuse only: a black checker
/// on a shiny mirror leaves exactly what the same material without ambient
/// and diffuse shows (its highlight and its reflection).
#[test]
fn a_colour_texture_leaves_specular_and_reflection_alone() {
    let dir = tempfile::tempdir().unwrap();
    let text = |material: &str| {
        format!(
            "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nwidth = 100\nheight = 80\n\
             [[lights]]\nposition = [-3, -2, 8]\n\
             [[objects]]\nsphere = {{ center = [0, 0, 0], radius = 2 }}\nmaterial = {material}\n\
             [[objects]]\nsphere = {{ center = [3, 0, 3], radius = 1 }}\n\
             material = {{ ambient = [0.2, 0.2, 0.2], diffuse = [0.8, 0.3, 0.3] }}\n"
        )
    };
    let shiny = "specular = [0.7, 0.7, 0.7], shininess = 30, reflectance = 0.5";
    let textured = scene(
        dir.path(),
        &text(&format!(
            "{{ ambient = [0.3, 0.3, 0.3], diffuse = [0.6, 0.6, 0.6], {shiny}, \
             texture = {{ checker = [[0, 0, 0], [0, 0, 0]] }} }}"
        )),
    );
    let plain = scene(dir.path(), &text(&format!("{{ {shiny} }}")));
    let (a, b) = (render_linear(&textured), render_linear(&plain));
    let mut lit = 0;
    for j in 0..80 {
        for i in 0..100 {
            assert_eq!(a.get(i, j), b.get(i, j), "pixel ({i}, {j})");
            lit += usize::from(a.get(i, j) != Vec3::ZERO);
        }
    }
    assert!(
        lit > 50,
        "the highlight and the reflection show: {lit} pixels"
    );
}

const FACE_OBJ: &str = "mtllib face.mtl\n\
    v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
    usemtl red\nf 1 2 3\nusemtl glassy\nf 1 3 4\nusemtl clear\nf 4 1 3\n";
const FACE_MTL: &str = "newmtl red\nKa 0.1 0.2 0.3\nKd 0.2 0.4 0.6\nKs 0.5 0.5 0.5\nNs 20\n\n\
    newmtl glassy\nKd 0.3 0.3 0.3\nd 0.25\nNi 1.33\nmap_Kd tex/dot.png\n\n\
    newmtl clear\nTr 0.4\n";

/// The square of `FACE_OBJ` (lower-right half `red`, upper-left `glassy`,
/// and `clear` on the same half again) in a folder with its MTL and image.
fn face_dir() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "face.obj", FACE_OBJ.as_bytes());
    write(dir.path(), "face.mtl", FACE_MTL.as_bytes());
    let dot = encoded(&noise_image(2, 2), image::ImageFormat::Png);
    write(dir.path(), "tex/dot.png", &dot);
    dir
}

fn phong(m: &Material) -> &Phong {
    m.surface()
}

#[test]
fn mtl_values_land_in_the_faces_materials() {
    let dir = face_dir();
    let scene = scene(
        dir.path(),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n[[objects]]\nmesh = { obj = \"face.obj\" }\n",
    );
    let materials: Vec<&Material> = scene
        .objects()
        .iter()
        .map(|o| scene.material(o.material))
        .collect();
    assert_eq!(materials.len(), 3);
    let red = phong(materials[0]);
    assert!(
        matches!(materials[0], Material::Phong(_)),
        "d absent: opaque"
    );
    assert_eq!(red.ambient, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(red.diffuse, Vec3::new(0.2, 0.4, 0.6));
    assert_eq!(red.specular, Vec3::splat(0.5));
    assert_eq!(red.shininess, 20.0);
    assert!(red.color_texture.is_none() && red.texture.is_none());
    let Material::Glass(glassy) = materials[1] else {
        panic!("d 0.25 lets 0.75 through: glass, found {:?}", materials[1]);
    };
    assert_eq!(glassy.transmittance, 0.75);
    assert_eq!(glassy.ior, 1.33);
    assert_eq!(glassy.surface.diffuse, Vec3::splat(0.3));
    assert!(matches!(
        glassy.surface.color_texture,
        Some(ColorTexture::Image { .. })
    ));
    let Material::Glass(clear) = materials[2] else {
        panic!("Tr 0.4: glass, found {:?}", materials[2]);
    };
    assert_eq!(clear.transmittance, 0.4);
    assert_eq!(clear.ior, 1.5, "no Ni: the default");
}

/// Light and eye straight above a point of the `red` half: cos = 1 for
/// diffuse and for the half vector, so the pixel is Ka + Kd + Ks exactly.
#[test]
fn a_face_lit_head_on_shows_its_mtl_colours() {
    let dir = face_dir();
    let scene = scene(
        dir.path(),
        "[camera]\neye = [0.5, -0.5, 10]\nlook_at = [0.5, -0.5, 0]\nwidth = 11\nheight = 11\n\
         [[lights]]\nposition = [0.5, -0.5, 10]\n[[objects]]\nmesh = { obj = \"face.obj\" }\n",
    );
    let got = render_linear(&scene).get(5, 5);
    let expected = Vec3::new(0.1 + 0.2 + 0.5, 0.2 + 0.4 + 0.5, 0.3 + 0.6 + 0.5);
    assert!(
        (got - expected).length() < 1e-5,
        "{got}, expected {expected}"
    );
}

#[test]
fn an_object_material_overrides_the_mtl() {
    let dir = face_dir();
    let file = load(
        dir.path(),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [0, 0, 5]\n\
         [[objects]]\nmesh = { obj = \"face.obj\" }\nmaterial = { diffuse = [0, 1, 0] }\n",
    );
    let scene = prepare(&file).unwrap();
    for o in scene.objects() {
        assert_eq!(scene.material(o.material), scene.material(0));
        assert_eq!(phong(scene.material(o.material)).diffuse, Vec3::Y);
    }
    // The MTL is not used, so its problems are not reported either.
    assert!(scene_format::warnings(&file).is_empty());
}

#[test]
fn a_missing_mtl_or_map_is_a_warning_and_the_faces_stay_grey_or_plain() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "face.obj", FACE_OBJ.as_bytes());
    let text =
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [0, 0, 5]\n\
                [[objects]]\nmesh = { obj = \"face.obj\" }\n";
    let file = load(dir.path(), text);
    let warnings = scene_format::warnings(&file);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!(warnings[0].path.to_string(), "objects[0].mesh.obj");
    assert!(
        warnings[0]
            .message
            .contains("material library `face.mtl` cannot be read"),
        "{}",
        warnings[0].message
    );
    let scene = prepare(&file).unwrap();
    for o in scene.objects() {
        assert_eq!(
            scene.material(o.material),
            &Material::Phong(Phong::default_grey())
        );
    }
    // With the MTL but not its image: the material without its texture.
    write(dir.path(), "face.mtl", FACE_MTL.as_bytes());
    let file = load(dir.path(), text);
    let warnings = scene_format::warnings(&file);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0]
            .message
            .contains("`face.mtl`: material `glassy`: cannot load `map_Kd` image `tex/dot.png`"),
        "{}",
        warnings[0].message
    );
    let scene = prepare(&file).unwrap();
    assert!(phong(scene.material(scene.objects()[1].material))
        .color_texture
        .is_none());
}

#[test]
fn bad_mtl_values_are_replaced_by_their_defaults_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "face.obj", FACE_OBJ.as_bytes());
    write(
        dir.path(),
        "face.mtl",
        b"newmtl red\nKd -1 0.5 0.5\nKs 0.5 0.5 0.5\nd 1.5\n",
    );
    let file = load(
        dir.path(),
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [0, 0, 5]\n\
         [[objects]]\nmesh = { obj = \"face.obj\" }\n",
    );
    let messages: Vec<String> = scene_format::warnings(&file)
        .into_iter()
        .map(|d| d.message)
        .collect();
    assert_eq!(messages.len(), 2, "{messages:?}");
    assert!(
        messages[0]
            .starts_with("`face.mtl`: material `red`, `Kd`: expected a colour with channels >= 0"),
        "{}",
        messages[0]
    );
    assert!(
        messages[1].starts_with("`face.mtl`: material `red`, `d` or `Tr`: as transmittance (1 - d, or Tr) expected a number from 0 to 1, found -0.5"),
        "{}",
        messages[1]
    );
    let scene = prepare(&file).unwrap();
    let red = scene.material(scene.objects()[0].material);
    assert_eq!(phong(red).diffuse, Vec3::ZERO);
    assert_eq!(phong(red).specular, Vec3::splat(0.5));
    assert!(matches!(red, Material::Phong(_)), "transmittance back to 0");
}
