//! Textures and the lab's procedural stripes (lab 4.5 and 7); beyond the
//! lab, colour textures (an image, a checkerboard) that colour the ambient
//! and diffuse terms.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// An RGB texture, row 0 at the top (v = 0).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "TextureData")]
pub struct Texture {
    pub width: u32,
    pub height: u32,
    texels: Vec<Vec3>,
}

/// A texture as stored (in a `--cache` entry), checked before it becomes a
/// `Texture`: a lookup assumes at least one texel and `width * height` of
/// them (the cache's fuzz target found an empty one panicking).
#[derive(Deserialize)]
struct TextureData {
    width: u32,
    height: u32,
    texels: Vec<Vec3>,
}

impl TryFrom<TextureData> for Texture {
    type Error = String;

    fn try_from(t: TextureData) -> Result<Texture, String> {
        let count = u64::from(t.width) * u64::from(t.height);
        if count == 0 || count != t.texels.len() as u64 {
            return Err(format!(
                "a texture of {}x{} with {} texels",
                t.width,
                t.height,
                t.texels.len()
            ));
        }
        Ok(Texture {
            width: t.width,
            height: t.height,
            texels: t.texels,
        })
    }
}

/// The textures built into the tracer, by the name a scene file gives them.
/// The one registry: the file format knows the names, this the images, and
/// `prepare` maps one to the other with an exhaustive match.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Builtin {
    /// The lab's `createTexture(400, 400)`: grey stripes.
    LabStripes,
}

impl Builtin {
    /// The texture's image.
    pub fn texture(self) -> Texture {
        match self {
            Builtin::LabStripes => Texture::lab_stripes(400, 400),
        }
    }
}

/// The two greys of the lab's stripes (8-bit values) and the stripe heights.
const STRIPE_DARK: u8 = 10;
const STRIPE_LIGHT: u8 = 200;
const STRIPE_ROWS: u32 = 20;

impl Texture {
    /// `texels` row by row; its length must be `width * height`.
    pub fn new(width: u32, height: u32, texels: Vec<Vec3>) -> Self {
        assert_eq!(texels.len(), (width * height) as usize, "texel count");
        Texture {
            width,
            height,
            texels,
        }
    }

    /// The template's `CImage::createTexture(w, h)`: horizontal stripes of grey
    /// 10 and 200, starting with 10; the first stripe is 21 rows, the rest 20.
    pub fn lab_stripes(width: u32, height: u32) -> Self {
        let texels = (0..height)
            .flat_map(|row| {
                let grey = Vec3::splat(f32::from(lab_stripe_grey(row)) / 255.0);
                std::iter::repeat_n(grey, width as usize)
            })
            .collect();
        Texture::new(width, height, texels)
    }

    /// The lab's `getTexel(u, v)`: column floor(w u), row floor(h v), clamped to
    /// the last texel where the template read out of bounds.
    pub fn texel(&self, uv: Vec2) -> Vec3 {
        let col = index(uv.x, self.width);
        let row = index(uv.y, self.height);
        self.texels[(row * self.width + col) as usize]
    }
}

fn index(coord: f32, size: u32) -> u32 {
    // `as` saturates: negative and NaN give 0.
    ((size as f32 * coord).floor() as u32).min(size - 1)
}

/// The 8-bit grey of row `row` of the lab's stripes.
pub fn lab_stripe_grey(row: u32) -> u8 {
    // Row 0 opens a 21-row stripe; thereafter a new stripe starts every 20 rows.
    let stripe = row.saturating_sub(1) / STRIPE_ROWS;
    if stripe.is_multiple_of(2) {
        STRIPE_DARK
    } else {
        STRIPE_LIGHT
    }
}

/// The linear value of an sRGB-encoded one (0 to 1): the inverse of the
/// sRGB transfer curve of IEC 61966-2-1, linear near black, a 2.4 power
/// above.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// How an image is read outside its 0..1 square.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Wrap {
    /// Tiles the image.
    Repeat,
    /// Extends the edge texels.
    Clamp,
    /// Tiles the image, every other copy flipped.
    Mirror,
}

impl Wrap {
    /// The texel index that index `i` reads, of `n` texels across.
    fn index(self, i: i64, n: i64) -> i64 {
        match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m < n {
                    m
                } else {
                    2 * n - 1 - m
                }
            }
        }
    }

    /// `index` of `i` and of `i + 1` (saturating), with one division: a
    /// bilinear look-up's two columns (or rows).
    #[inline(always)]
    fn pair(self, i: i64, n: i64) -> [i64; 2] {
        let next = i.saturating_add(1);
        match self {
            Wrap::Clamp => [i, next].map(|k| k.clamp(0, n - 1)),
            // At i64::MAX the next index is the same one.
            _ if next == i => [self.index(i, n); 2],
            Wrap::Repeat => {
                let m = i.rem_euclid(n);
                [m, if m + 1 == n { 0 } else { m + 1 }]
            }
            Wrap::Mirror => {
                let m = i.rem_euclid(2 * n);
                let m1 = if m + 1 == 2 * n { 0 } else { m + 1 };
                [m, m1].map(|m| if m < n { m } else { 2 * n - 1 - m })
            }
        }
    }
}

/// An image of linear colours, row 0 at the top, shared by every texture
/// that reads the same file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ImageTexels {
    width: u32,
    height: u32,
    texels: Linear,
    /// Each texel's alpha byte (v / 255), if the image has some below 255:
    /// what an `AlphaMask` reads.
    alpha: Option<Arc<Vec<u8>>>,
}

/// An image's linear texels: an 8-bit image's sRGB bytes, decoded at each
/// look-up by a table (a quarter of the memory of floats, the same
/// values), or floats.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
enum Linear {
    Srgb8(Arc<Vec<[u8; 3]>>),
    Floats(Vec<Vec3>),
    /// An 8-bit image of data, not colour (glTF's metallic-roughness and
    /// normal textures): each byte v is v / 255.
    Raw8(Arc<Vec<[u8; 3]>>),
}

impl Linear {
    fn len(&self) -> usize {
        match self {
            Linear::Srgb8(t) | Linear::Raw8(t) => t.len(),
            Linear::Floats(t) => t.len(),
        }
    }
}

/// srgb_to_linear(v / 255) for each byte v: the values an 8-bit image's
/// floats (v / 255, as the image crate reads them) decode to.
static SRGB8_TO_LINEAR: std::sync::LazyLock<[f32; 256]> =
    std::sync::LazyLock::new(|| std::array::from_fn(|v| srgb_to_linear(v as f32 / 255.0)));

impl ImageTexels {
    /// The image of sRGB-encoded texels (0 to 1, row by row from the top),
    /// decoded to linear. Panics unless there are `width * height` (> 0).
    pub fn from_srgb(width: u32, height: u32, srgb: &[[f32; 3]]) -> Self {
        let texels = srgb
            .iter()
            .map(|c| Vec3::from(c.map(srgb_to_linear)))
            .collect();
        ImageTexels::new(width, height, Linear::Floats(texels))
    }

    /// The image of 8-bit sRGB texels (row by row from the top): the same
    /// as `from_srgb` of their values / 255, in a quarter of the memory.
    /// Shared with the scene's model, not copied. Panics unless there are
    /// `width * height` (> 0).
    pub fn from_srgb8(width: u32, height: u32, srgb: Arc<Vec<[u8; 3]>>) -> Self {
        ImageTexels::new(width, height, Linear::Srgb8(srgb))
    }

    /// The image of 8-bit data texels (v / 255 each, no sRGB curve),
    /// shared with the scene's model. Panics unless there are `width *
    /// height` (> 0).
    pub fn from_raw8(width: u32, height: u32, texels: Arc<Vec<[u8; 3]>>) -> Self {
        ImageTexels::new(width, height, Linear::Raw8(texels))
    }

    /// The image of data texels as they are (no sRGB curve): a 16-bit
    /// image's floats.
    pub fn from_raw(width: u32, height: u32, texels: &[[f32; 3]]) -> Self {
        let texels = texels.iter().map(|&c| Vec3::from(c)).collect();
        ImageTexels::new(width, height, Linear::Floats(texels))
    }

    fn new(width: u32, height: u32, texels: Linear) -> Self {
        assert!(width > 0 && height > 0, "an empty image");
        assert_eq!(
            texels.len(),
            width as usize * height as usize,
            "texel count"
        );
        ImageTexels {
            width,
            height,
            texels,
            alpha: None,
        }
    }

    /// The same image with `alpha`, a byte per texel (v / 255, row by row
    /// from the top), shared with the scene's model. Panics unless there
    /// are `width * height`.
    pub fn with_alpha(self, alpha: Arc<Vec<u8>>) -> Self {
        assert_eq!(alpha.len(), self.texels.len(), "alpha count");
        ImageTexels {
            alpha: Some(alpha),
            ..self
        }
    }

    /// Whether the image has alpha (some texel below 255).
    pub fn has_alpha(&self) -> bool {
        self.alpha.is_some()
    }

    /// The texel at column `x`, row `y`, wrapped into the image.
    #[cfg(test)]
    fn texel(&self, x: i64, y: i64, wrap: Wrap) -> Vec3 {
        self.texel2(x, y, wrap, wrap)
    }

    /// The texel at column `x`, row `y`, wrapped into the image by `wrap_u`
    /// across and `wrap_v` down.
    fn texel2(&self, x: i64, y: i64, wrap_u: Wrap, wrap_v: Wrap) -> Vec3 {
        let x = wrap_u.index(x, i64::from(self.width));
        let y = wrap_v.index(y, i64::from(self.height));
        self.texel_at((y * i64::from(self.width) + x) as usize)
    }

    /// Texel `i` of the rows, linear.
    #[inline(always)]
    fn texel_at(&self, i: usize) -> Vec3 {
        match &self.texels {
            Linear::Srgb8(t) => Vec3::from(t[i].map(|v| SRGB8_TO_LINEAR[usize::from(v)])),
            Linear::Raw8(t) => Vec3::from(t[i].map(|v| f32::from(v) / 255.0)),
            Linear::Floats(t) => t[i],
        }
    }

    /// The bilinear interpolation of the four texels around `uv`, u from
    /// the left edge, v from the bottom edge; at a texel's centre
    /// ((i + 0.5) / width, 1 - (j + 0.5) / height) it is that texel.
    pub fn bilinear(&self, uv: Vec2, wrap: Wrap) -> Vec3 {
        self.bilinear2(uv, [wrap, wrap])
    }

    /// `bilinear` with a wrap mode along u and another along v.
    pub fn bilinear2(&self, uv: Vec2, wraps: [Wrap; 2]) -> Vec3 {
        let ([i, i1], [j, j1], [fx, fy]) = self.corners(uv, wraps);
        let texel = |x: i64, y: i64| self.texel_at((y * i64::from(self.width) + x) as usize);
        let top = texel(i, j).lerp(texel(i1, j), fx);
        let bottom = texel(i, j1).lerp(texel(i1, j1), fx);
        top.lerp(bottom, fy)
    }

    /// The columns and rows (wrapped into the image) of the four texels
    /// around `uv`, and the weights of the second column and row.
    #[inline(always)]
    fn corners(&self, uv: Vec2, [wrap_u, wrap_v]: [Wrap; 2]) -> ([i64; 2], [i64; 2], [f32; 2]) {
        let x = uv.x * self.width as f32 - 0.5;
        let y = (1.0 - uv.y) * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        // `as` saturates (NaN gives 0): no index overflows.
        let (i, j) = (x0 as i64, y0 as i64);
        (
            wrap_u.pair(i, i64::from(self.width)),
            wrap_v.pair(j, i64::from(self.height)),
            [x - x0, y - y0],
        )
    }

    /// The alpha at `uv` (0 to 1), interpolated as `bilinear2` interpolates
    /// colours; 1 for an image without alpha.
    pub fn alpha2(&self, uv: Vec2, wraps: [Wrap; 2]) -> f32 {
        let Some(alpha) = &self.alpha else {
            return 1.0;
        };
        let ([i, i1], [j, j1], [fx, fy]) = self.corners(uv, wraps);
        let texel = |x: i64, y: i64| {
            let k = y * i64::from(self.width) + x;
            f32::from(alpha[k as usize]) / 255.0
        };
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let top = lerp(texel(i, j), texel(i1, j), fx);
        let bottom = lerp(texel(i, j1), texel(i1, j1), fx);
        lerp(top, bottom, fy)
    }

    /// The mean colour of the texels: what a texture that covers a
    /// surface evenly gives off on average (an emission texture's share
    /// of its light's power).
    pub fn mean(&self) -> Vec3 {
        let (w, h) = (i64::from(self.width), i64::from(self.height));
        let mut sum = glam::DVec3::ZERO;
        for y in 0..h {
            for x in 0..w {
                sum += self.texel2(x, y, Wrap::Clamp, Wrap::Clamp).as_dvec3();
            }
        }
        (sum / (w * h) as f64).as_vec3()
    }
}

/// A colour over a surface's uv that multiplies the ambient and diffuse
/// colours of its material (not the specular, not the reflection).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum ColorTexture {
    /// An image, sampled at (u * scale.x, v * scale.y), turned by `turn`
    /// and moved by `offset` when it has `place`.
    Image {
        texels: Arc<ImageTexels>,
        scale: Vec2,
        wrap: Wrap,
        /// How uv is placed beyond `scale`, and a wrap along v of its own:
        /// None for most textures.
        place: Option<Box<Place>>,
    },
    /// Squares 1 / scale wide in uv, `colors[0]` on the square at the origin.
    Checker { colors: [Vec3; 2], scale: Vec2 },
}

/// A texture's uv turned and moved after its scale (a glTF file's
/// `KHR_texture_transform`), and its wrap mode along v.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Place {
    /// (cos, sin) of the counter-clockwise turn.
    pub turn: Vec2,
    pub offset: Vec2,
    pub wrap_v: Wrap,
}

impl Place {
    /// Where the texture is read for scaled uv `s`: turned, then moved.
    fn at(&self, s: Vec2) -> Vec2 {
        let (c, n) = (self.turn.x, self.turn.y);
        Vec2::new(c * s.x - n * s.y, n * s.x + c * s.y) + self.offset
    }
}

impl ColorTexture {
    /// The texture's alpha at `uv` (0 to 1): an image's, read where
    /// `color` reads its colour; 1 where there is none (a checker, an
    /// image without alpha).
    pub fn alpha(&self, uv: Vec2) -> f32 {
        match self {
            ColorTexture::Image {
                texels,
                scale,
                wrap,
                place: None,
            } => texels.alpha2(uv * *scale, [*wrap, *wrap]),
            ColorTexture::Image {
                texels,
                scale,
                wrap,
                place: Some(p),
            } => texels.alpha2(p.at(uv * *scale), [*wrap, p.wrap_v]),
            ColorTexture::Checker { .. } => 1.0,
        }
    }

    /// Whether some of the texture's alpha is below 1.
    pub fn has_alpha(&self) -> bool {
        matches!(self, ColorTexture::Image { texels, .. } if texels.has_alpha())
    }

    /// The mean of its colours: an image's texels' mean, a checker's two
    /// colours' (each covers half of any whole number of squares).
    pub fn mean(&self) -> Vec3 {
        match self {
            ColorTexture::Image { texels, .. } => texels.mean(),
            ColorTexture::Checker { colors, .. } => (colors[0] + colors[1]) / 2.0,
        }
    }

    /// The texture's colour at `uv`.
    pub fn color(&self, uv: Vec2) -> Vec3 {
        match self {
            ColorTexture::Image {
                texels,
                scale,
                wrap,
                place: None,
            } => texels.bilinear(uv * *scale, *wrap),
            ColorTexture::Image {
                texels,
                scale,
                wrap,
                place: Some(p),
            } => texels.bilinear2(p.at(uv * *scale), [*wrap, p.wrap_v]),
            ColorTexture::Checker { colors, scale } => {
                let cell = (uv * *scale).floor();
                let parity = (cell.x as i64).wrapping_add(cell.y as i64).rem_euclid(2);
                colors[parity as usize]
            }
        }
    }
}

impl ImageTexels {
    /// Whether an image read back from a file (`--cache`) has the texels
    /// its size says.
    pub(crate) fn is_whole(&self) -> bool {
        let count = u64::from(self.width) * u64::from(self.height);
        self.width > 0
            && self.height > 0
            && self.texels.len() as u64 == count
            && self.alpha.as_ref().is_none_or(|a| a.len() as u64 == count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stored_texture_without_texels_or_of_another_count_is_refused() {
        let stored = |width: u32, height: u32, count: usize| {
            let t = TextureData {
                width,
                height,
                texels: vec![Vec3::ONE; count],
            };
            Texture::try_from(t)
        };
        assert!(stored(0, 1, 0).is_err());
        assert!(stored(1, 0, 0).is_err());
        assert!(stored(2, 2, 3).is_err());
        assert!(stored(u32::MAX, u32::MAX, 1).is_err());
        let t = stored(2, 1, 2).unwrap();
        assert_eq!(t.texel(Vec2::new(0.9, 0.5)), Vec3::ONE);
    }

    #[test]
    fn stripes_have_the_exact_row_layout() {
        let expected = |row: u32| -> u8 {
            // Written out from lab section 7, independently of lab_stripe_grey.
            let mut bounds = vec![(0, 20, 10u8)];
            let mut start = 21;
            let mut grey = 200;
            while start < 400 {
                bounds.push((start, (start + 19).min(399), grey));
                start += 20;
                grey = if grey == 200 { 10 } else { 200 };
            }
            bounds
                .iter()
                .find(|(a, b, _)| (*a..=*b).contains(&row))
                .unwrap()
                .2
        };
        let tex = Texture::lab_stripes(400, 400);
        for row in 0..400 {
            let v = (row as f32 + 0.5) / 400.0;
            for u in [0.0, 0.37, 0.999] {
                let texel = tex.texel(Vec2::new(u, v));
                assert_eq!(
                    texel,
                    Vec3::splat(expected(row) as f32 / 255.0),
                    "row {row}"
                );
            }
        }
        assert_eq!(lab_stripe_grey(20), 10);
        assert_eq!(lab_stripe_grey(21), 200);
        assert_eq!(lab_stripe_grey(381), 200);
        assert_eq!(lab_stripe_grey(399), 200);
        assert_eq!(lab_stripe_grey(380), 10);
    }

    #[test]
    fn lookups_at_and_past_the_edges_are_clamped() {
        let tex = Texture::lab_stripes(400, 400);
        assert_eq!(tex.texel(Vec2::new(1.0, 1.0)), Vec3::splat(200.0 / 255.0));
        assert_eq!(tex.texel(Vec2::new(-0.5, -0.1)), Vec3::splat(10.0 / 255.0));
        assert_eq!(
            tex.texel(Vec2::new(f32::NAN, 0.0)),
            Vec3::splat(10.0 / 255.0)
        );
    }

    #[test]
    fn srgb_decodes_by_the_standard_curve() {
        // Reference values of IEC 61966-2-1: black, the linear segment's
        // end, mid grey 0.5 and 128/255 (0.2140, 0.2159 in published
        // tables), white.
        let cases = [
            (0.0, 0.0),
            (0.04045, 0.003_130_805),
            (0.5, 0.214_041_14),
            (128.0 / 255.0, 0.215_860_5),
            (1.0, 1.0),
        ];
        for (encoded, linear) in cases {
            let got = srgb_to_linear(encoded);
            assert!(
                (got - linear).abs() < 1e-6,
                "{encoded}: {got}, expected {linear}"
            );
        }
    }

    #[test]
    fn an_8_bit_image_reads_as_its_floats_bit_for_bit() {
        let bytes: Vec<[u8; 3]> = (0..=255u8).map(|v| [v, 255 - v, v / 2]).collect();
        let floats: Vec<[f32; 3]> = bytes
            .iter()
            .map(|b| b.map(|v| f32::from(v) / 255.0))
            .collect();
        let (eight, float) = (
            ImageTexels::from_srgb8(256, 1, Arc::new(bytes)),
            ImageTexels::from_srgb(256, 1, &floats),
        );
        for x in 0..256 {
            let (a, b) = (
                eight.texel(x, 0, Wrap::Clamp),
                float.texel(x, 0, Wrap::Clamp),
            );
            assert_eq!(
                a.to_array().map(f32::to_bits),
                b.to_array().map(f32::to_bits),
                "{x}"
            );
        }
    }

    /// Four texels in a row, greys 0.1 to 0.4 (linear: `from_srgb` decodes,
    /// so the texels are given encoded).
    fn four_in_a_row() -> ImageTexels {
        let encoded: Vec<[f32; 3]> = [0.1, 0.2, 0.3, 0.4]
            .iter()
            .map(|&g| [linear_to_srgb(g); 3])
            .collect();
        ImageTexels::from_srgb(4, 1, &encoded)
    }

    /// The sRGB curve itself, written from the standard for the tests.
    fn linear_to_srgb(l: f32) -> f32 {
        if l <= 0.003_130_8 {
            l * 12.92
        } else {
            1.055 * l.powf(1.0 / 2.4) - 0.055
        }
    }

    fn grey_at(image: &ImageTexels, u: f32, wrap: Wrap) -> f32 {
        image.bilinear(Vec2::new(u, 0.5), wrap).x
    }

    #[test]
    fn alpha_is_read_where_the_colour_is_whatever_the_placement() {
        // Data texels whose red is the alpha byte: the two lookups, by
        // one placement, must agree everywhere.
        let bytes: Vec<u8> = (0..12u8).map(|k| k * 21).collect();
        let texels = bytes.iter().map(|&a| [a, 0, 0]).collect();
        let image = ImageTexels::from_raw8(4, 3, Arc::new(texels)).with_alpha(Arc::new(bytes));
        let placed = |place| ColorTexture::Image {
            texels: Arc::new(image.clone()),
            scale: Vec2::new(1.5, 0.75),
            wrap: Wrap::Mirror,
            place,
        };
        let turned = Some(Box::new(Place {
            turn: Vec2::new(0.6, 0.8),
            offset: Vec2::new(0.3, -0.2),
            wrap_v: Wrap::Clamp,
        }));
        for texture in [placed(None), placed(turned)] {
            for k in 0..200 {
                let uv = Vec2::new(k as f32 * 0.037 - 2.0, (k * 7 % 23) as f32 * 0.11 - 1.0);
                let (alpha, red) = (texture.alpha(uv), texture.color(uv).x);
                assert!((alpha - red).abs() < 1e-6, "{uv}: {alpha} against {red}");
            }
        }
        // At a texel's centre, its own byte.
        let plain = placed(None);
        let centre = Vec2::new(2.5 / 4.0 / 1.5, (1.0 - 1.5 / 3.0) / 0.75);
        assert!((plain.alpha(centre) - 6.0 * 21.0 / 255.0).abs() < 1e-6);
        // A checker, or an image without alpha: 1.
        let checker = ColorTexture::Checker {
            colors: [Vec3::ZERO; 2],
            scale: Vec2::ONE,
        };
        assert_eq!(checker.alpha(Vec2::splat(0.3)), 1.0);
        assert!(!checker.has_alpha() && plain.has_alpha());
    }

    #[test]
    fn bilinear_returns_texels_at_their_centres_and_blends_between() {
        let image = four_in_a_row();
        for (i, grey) in [0.1, 0.2, 0.3, 0.4].into_iter().enumerate() {
            let u = (i as f32 + 0.5) / 4.0;
            assert!(
                (grey_at(&image, u, Wrap::Clamp) - grey).abs() < 1e-5,
                "texel {i}"
            );
        }
        // Halfway between the centres of texels 1 and 2 (u = 0.5).
        assert!((grey_at(&image, 0.5, Wrap::Clamp) - 0.25).abs() < 1e-5);
        // A quarter of the way from texel 0's centre to texel 1's.
        assert!((grey_at(&image, 0.125 + 0.0625, Wrap::Clamp) - 0.125).abs() < 1e-5);
    }

    #[test]
    fn wrap_modes_beyond_the_edges() {
        let image = four_in_a_row();
        let at = |u, wrap| grey_at(&image, u, wrap);
        // Texel i's centre is at x = u * 4 - 0.5 = i. u = -0.25 is x = -1.5,
        // halfway between texels -2 and -1.
        // Repeat: they are texels 2 and 3 of the copy to the left.
        assert!((at(-0.25, Wrap::Repeat) - 0.35).abs() < 1e-5);
        // Clamp: everything left of the first centre is texel 0.
        assert!((at(-0.25, Wrap::Clamp) - 0.1).abs() < 1e-5);
        // Mirror: flipped over the left edge, -1 is texel 0 and -2 texel 1.
        assert!((at(-0.25, Wrap::Mirror) - 0.15).abs() < 1e-5);
        // u = 1.25 is x = 4.5, between texels 4 and 5: repeat 0 and 1;
        // clamp 3; mirror 3 and 2.
        assert!((at(1.25, Wrap::Repeat) - 0.15).abs() < 1e-5);
        assert!((at(1.25, Wrap::Clamp) - 0.4).abs() < 1e-5);
        assert!((at(1.25, Wrap::Mirror) - 0.35).abs() < 1e-5);
        // Across the seam: repeat blends the last texel with the first.
        assert!((at(1.0, Wrap::Repeat) - 0.25).abs() < 1e-5);
        assert!((at(1.0, Wrap::Mirror) - 0.4).abs() < 1e-5);
    }

    #[test]
    fn a_pair_of_indices_is_each_wrapped_alone() {
        let edges = [i64::MIN, i64::MIN + 1, -1, 0, 1, i64::MAX - 1, i64::MAX];
        for wrap in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
            for n in [1, 2, 3, 7, 512] {
                let near = (-3 * n - 2..=3 * n + 2).chain(edges);
                for i in near {
                    let expected = [i, i.saturating_add(1)].map(|k| wrap.index(k, n));
                    assert_eq!(wrap.pair(i, n), expected, "{wrap:?}, i {i}, n {n}");
                }
            }
        }
    }

    #[test]
    fn v_runs_up_the_image() {
        // Two rows: top (row 0) white, bottom black.
        let image = ImageTexels::from_srgb(1, 2, &[[1.0; 3], [0.0; 3]]);
        assert_eq!(image.bilinear(Vec2::new(0.5, 0.75), Wrap::Clamp), Vec3::ONE);
        assert_eq!(
            image.bilinear(Vec2::new(0.5, 0.25), Wrap::Clamp),
            Vec3::ZERO
        );
    }

    #[test]
    fn far_and_nan_coordinates_read_a_texel_without_panicking() {
        let image = four_in_a_row();
        for u in [1e30, -1e30, f32::NAN, f32::INFINITY] {
            for wrap in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
                let _ = grey_at(&image, u, wrap);
            }
        }
        let checker = ColorTexture::Checker {
            colors: [Vec3::ZERO, Vec3::ONE],
            scale: Vec2::ONE,
        };
        let _ = checker.color(Vec2::new(f32::NAN, 1e30));
    }

    #[test]
    fn checker_squares_are_one_over_scale_wide() {
        let (a, b) = (Vec3::X, Vec3::Z);
        let checker = ColorTexture::Checker {
            colors: [a, b],
            scale: Vec2::splat(4.0),
        };
        let at = |u, v| checker.color(Vec2::new(u, v));
        // Squares 0.25 wide: [0, 0.25) x [0, 0.25) is the first colour.
        assert_eq!(at(0.1, 0.1), a);
        assert_eq!(at(0.3, 0.1), b);
        assert_eq!(at(0.3, 0.3), a);
        assert_eq!(at(0.1, 0.26), b);
        // Below zero the pattern goes on: [-0.25, 0) x [0, 0.25) is the second.
        assert_eq!(at(-0.1, 0.1), b);
        assert_eq!(at(-0.1, -0.1), a);
    }
}
