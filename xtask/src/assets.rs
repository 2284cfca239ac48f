//! The files the texture scenes read, made here rather than downloaded:
//! `cargo xtask assets` writes them, and a test checks that the committed
//! ones are what this code makes.

use anyhow::{Context, Result};
use image::{Rgb, Rgb32FImage, RgbImage};
use std::fmt::Write;
use std::path::Path;

/// A generated file's contents.
pub enum Asset {
    /// Compared by its pixels: a PNG's bytes may change with the encoder.
    Image(RgbImage),
    /// A Radiance HDR's linear values, compared as its file stores them
    /// (RGBE: an 8-bit mantissa per channel).
    Hdr(Rgb32FImage),
    Text(String),
}

/// Every generated file, by its path from the workspace root.
pub fn all() -> Vec<(&'static str, Asset)> {
    vec![
        ("scenes/textures/grid.png", Asset::Image(grid())),
        ("scenes/textures/studio.hdr", Asset::Hdr(studio())),
        ("scenes/textures/sky.hdr", Asset::Hdr(sky())),
        ("scenes/textures/tiles.png", Asset::Image(tiles())),
        ("scenes/meshes/bullseye.png", Asset::Image(bullseye())),
        ("scenes/meshes/labelled-box.obj", Asset::Text(box_obj())),
        (
            "scenes/meshes/labelled-box.mtl",
            Asset::Text(BOX_MTL.to_string()),
        ),
    ]
}

/// Writes every asset under `root`.
pub fn write_all(root: &Path) -> Result<()> {
    for (path, asset) in all() {
        let path = root.join(path);
        match asset {
            Asset::Image(image) => image.save(&path),
            Asset::Hdr(image) => image.save(&path),
            Asset::Text(text) => std::fs::write(&path, text).map_err(Into::into),
        }
        .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(())
}

/// The assets whose file under `root` is missing or differs.
pub fn stale(root: &Path) -> Vec<&'static str> {
    all()
        .into_iter()
        .filter(|(path, asset)| {
            let path = root.join(path);
            match asset {
                Asset::Image(image) => {
                    image::open(&path).map(|i| i.to_rgb8()).ok().as_ref() != Some(image)
                }
                Asset::Hdr(image) => {
                    let stored = image::open(&path).map(|i| i.to_rgb32f()).ok();
                    stored.as_ref() != Some(&as_stored(image))
                }
                Asset::Text(text) => std::fs::read_to_string(&path).ok().as_ref() != Some(text),
            }
        })
        .map(|(path, _)| path)
        .collect()
}

/// `image` as a Radiance HDR file keeps it.
fn as_stored(image: &Rgb32FImage) -> Rgb32FImage {
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Hdr,
        )
        .expect("an HDR in memory");
    image::load_from_memory(&bytes)
        .expect("the HDR just written")
        .to_rgb32f()
}

/// A photographer's studio as a latitude-longitude environment (512 x 256,
/// linear radiance; row 0 straight up, the centre column toward -z): dim
/// grey walls over a darker floor, a large warm softbox up and to the right
/// (toward +x, radiance 30), a smaller cool one up to the left (8) and a
/// strip light behind the camera (6), so that metals and glass show sharp
/// and blurred reflections of bright shapes on a dark ground.
fn studio() -> Rgb32FImage {
    let (w, h) = (512u32, 256u32);
    Rgb32FImage::from_fn(w, h, |x, y| {
        let (u, v) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
        let inside = |(u0, u1): (f32, f32), (v0, v1): (f32, f32)| {
            (u0..u1).contains(&u) && (v0..v1).contains(&v)
        };
        if inside((0.64, 0.76), (0.16, 0.3)) {
            return Rgb([30.0, 27.0, 23.0]);
        }
        if inside((0.22, 0.29), (0.24, 0.34)) {
            return Rgb([6.5, 7.5, 9.0]);
        }
        if inside((0.96, 1.0), (0.3, 0.44)) || inside((0.0, 0.04), (0.3, 0.44)) {
            return Rgb([6.0, 6.0, 6.0]);
        }
        let up = (std::f32::consts::PI * v).cos();
        if up >= 0.0 {
            // A little lighter toward the ceiling.
            let grey = 0.09 + 0.06 * up;
            Rgb([grey, grey, 1.05 * grey])
        } else {
            let floor = 0.04 + 0.02 * (1.0 + up);
            Rgb([floor, 0.95 * floor, 0.9 * floor])
        }
    })
}

/// A clear sky as a latitude-longitude environment (512 x 256, linear
/// radiance; row 0 straight up, the centre column toward -z): blue at the
/// zenith paling to the horizon, a dull brown ground, and a small warm sun
/// (2.5 degrees across its radius, radiance 1000) 30 degrees up, toward -x
/// and a little -z (for a camera looking along -z: on the left, a little
/// beyond the scene, so shadows fall to the right and toward the camera),
/// which gives two thirds of the light on the ground. Each row is one colour but for
/// the sun's, so the file is small.
fn sky() -> Rgb32FImage {
    use std::f32::consts::PI;
    let (w, h) = (512u32, 256u32);
    let sun = direction(0.32, 60.0 / 180.0);
    let sun_cos = 2.5f32.to_radians().cos();
    Rgb32FImage::from_fn(w, h, |x, y| {
        let (u, v) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
        let d = direction(u, v);
        if d.iter().zip(&sun).map(|(a, b)| a * b).sum::<f32>() >= sun_cos {
            return Rgb([1000.0, 920.0, 800.0]);
        }
        let up = (PI * v).cos();
        if up < 0.0 {
            return Rgb([0.16, 0.14, 0.11]);
        }
        let t = up.sqrt();
        let mix = |horizon: f32, zenith: f32| horizon + (zenith - horizon) * t;
        Rgb([mix(0.75, 0.18), mix(0.85, 0.34), mix(1.0, 0.75)])
    })
}

/// The direction of the latitude-longitude point (u, v), as the
/// environment reads it: v = 0 straight up, u = 0.5 toward -z, 0.75
/// toward +x.
fn direction(u: f32, v: f32) -> [f32; 3] {
    use std::f32::consts::PI;
    let (theta, phi) = (PI * v, 2.0 * PI * (u - 0.5));
    [
        theta.sin() * phi.sin(),
        theta.cos(),
        -theta.sin() * phi.cos(),
    ]
}

/// Floor tiles (64 x 64, four tiles of 32 x 32 between grout lines 2 texels
/// wide): terracotta and cream in a checkerboard, each tile a little
/// lighter toward one corner so that the bilinear lookup has gradients to
/// follow, not only edges.
fn tiles() -> RgbImage {
    RgbImage::from_fn(64, 64, |x, y| {
        let (i, j) = (x % 32, y % 32);
        if i < 2 || j < 2 {
            return Rgb([70, 66, 60]);
        }
        let shade = (i + j) as f32 / 62.0;
        let [r, g, b] = if (x / 32 + y / 32) % 2 == 0 {
            [176.0, 84.0, 52.0]
        } else {
            [214.0, 200.0, 168.0]
        };
        let lift = |c: f32| (c + 30.0 * shade).min(255.0) as u8;
        Rgb([lift(r), lift(g), lift(b)])
    })
}

/// A 64 x 48 picture that shows its orientation: red grows to the right,
/// green to the top, lines every 8 texels, and a white "F" in the top
/// left corner (an F read the right way round means the image is neither
/// flipped nor mirrored).
fn grid() -> RgbImage {
    let (w, h) = (64u32, 48u32);
    RgbImage::from_fn(w, h, |x, y| {
        let f_stem = (4..8).contains(&x) && (4..24).contains(&y);
        let f_top = (4..20).contains(&x) && (4..8).contains(&y);
        let f_bar = (4..15).contains(&x) && (12..16).contains(&y);
        if f_stem || f_top || f_bar {
            return Rgb([255, 255, 255]);
        }
        if x % 8 == 0 || y % 8 == 0 {
            return Rgb([20, 20, 40]);
        }
        let red = 60 + x * 190 / (w - 1);
        let green = 60 + (h - 1 - y) * 190 / (h - 1);
        Rgb([red as u8, green as u8, 110])
    })
}

/// Rings around the centre of a 64 x 64 image: the same when turned half a
/// turn, so a face's two triangles show it alike whether their uv are the
/// OBJ's texture coordinates or their own barycentrics turned round.
fn bullseye() -> RgbImage {
    RgbImage::from_fn(64, 64, |x, y| {
        let (dx, dy) = (x as f32 - 31.5, y as f32 - 31.5);
        let ring = (dx.hypot(dy) / 6.0) as u32;
        if ring.is_multiple_of(2) {
            Rgb([235, 225, 190])
        } else {
            Rgb([200, 40, 40])
        }
    })
}

/// A face of the box: its corner a, the directions of u and v, its material.
type Face = ([f32; 3], [f32; 3], [f32; 3], &'static str);

/// The unit cube, each face with its own four corners and texture
/// coordinates (0, 0) to (1, 1), cut into the triangles (a, b, d) and
/// (c, d, b) of its corners a, b, c, d (counter-clockwise from the
/// outside): each triangle's barycentrics are then its uv, or the uv
/// turned half a turn. The front (+z) and the top carry the label.
fn box_obj() -> String {
    // Corner a, then the directions of u and v: u x v points outward.
    let faces: [Face; 6] = [
        ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], "label"), // +z
        ([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], "paint"), // -z
        ([1.0, 0.0, 1.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0], "paint"), // +x
        ([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0], "paint"), // -x
        ([0.0, 1.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0], "label"), // +y
        ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], "paint"), // -y
    ];
    let mut obj = String::from(
        "# A unit cube with two materials; made by `cargo xtask assets`.\nmtllib labelled-box.mtl\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n",
    );
    for (a, u, v, _) in &faces {
        for (su, sv) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            let p: Vec<String> = (0..3)
                .map(|k| format!("{}", a[k] + su * u[k] + sv * v[k]))
                .collect();
            writeln!(obj, "v {}", p.join(" ")).unwrap();
        }
    }
    for (i, (_, _, _, material)) in faces.iter().enumerate() {
        let [a, b, c, d] = [1, 2, 3, 4].map(|k| 4 * i + k);
        writeln!(obj, "usemtl {material}").unwrap();
        writeln!(obj, "f {a}/1 {b}/2 {d}/4").unwrap();
        writeln!(obj, "f {c}/3 {d}/4 {b}/2").unwrap();
    }
    obj
}

const BOX_MTL: &str = "# Made by `cargo xtask assets`.\n\
newmtl paint\nKa 0.05 0.08 0.15\nKd 0.15 0.3 0.7\nKs 0.6 0.6 0.6\nNs 60\n\n\
newmtl label\nKa 0.12 0.12 0.12\nKd 0.9 0.9 0.9\nKs 0.2 0.2 0.2\nNs 20\nmap_Kd bullseye.png\n";
