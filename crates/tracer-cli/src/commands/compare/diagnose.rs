//! The usual mistakes behind a difference, each tried by undoing it: the
//! image flipped back, re-encoded, resampled, its channels swapped back.
//! A mistake is named only when undoing it clearly explains the difference:
//! at least [`MIN_DIFFERING`] pixels were off, and [`FACTOR`] times fewer
//! are off once it is undone (none, when the image is exactly that mistake).

use super::input::{Reference, CORNERS};
use super::metrics::channel_difference;
use image::RgbImage;

/// Fewer differing pixels than this are a detail, not a mistake to name.
pub const MIN_DIFFERING: u64 = 10;
/// How many times fewer pixels must be off once a mistake is undone.
pub const FACTOR: u64 = 10;
/// The gamma tried when the reference's is not known (an image) or is 1.
const USUAL_GAMMA: f32 = 2.2;
/// The half-pixel test counts only pixels off by more than this many
/// levels, before and after: resampling at the corners only approximates
/// what a render there gives (a smooth or anti-aliased edge comes out a
/// little softer), and a coarser count ignores that.
const HALF_PIXEL_LEVELS: u8 = 16;

/// A mistake that explains a difference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fault {
    /// Left and right swapped.
    Mirror,
    /// Top and bottom swapped.
    UpsideDown,
    /// `c^(1/gamma)` applied once too often.
    GammaTwice(f32),
    /// No gamma: the linear values written.
    GammaMissing(f32),
    /// Encoded with another gamma than the reference's (a display's
    /// measured one, say): `c^(1/image)` where `c^(1/reference)` was due.
    GammaOther { image: f32, reference: f32 },
    /// Sampled at the pixels' corners: the content moved half a pixel
    /// right (`right`) or left, and down (`down`) or up.
    HalfPixel { right: bool, down: bool },
    /// The content moved by one whole pixel (`dx` right, `dy` down).
    OnePixel { dx: i8, dy: i8 },
    /// Red and blue swapped (BGR).
    Swapped,
}

/// A mistake found: pixels off by more than `levels` before and after
/// undoing it (and `with`, a second mistake found together with it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Finding {
    pub fault: Fault,
    pub before: u64,
    pub after: u64,
    pub levels: u8,
    pub with: Option<Fault>,
    /// The reference's camera puts world +x on the image's right
    /// (`handedness = "right"`), not the lab's left.
    pub right_handed: bool,
}

impl Finding {
    /// The word scripts look for, which the message starts with.
    pub fn word(&self) -> &'static str {
        word_of(self.fault)
    }
}

/// A mistake's word.
fn word_of(fault: Fault) -> &'static str {
    match fault {
        Fault::Mirror => "mirror",
        Fault::UpsideDown => "upside down",
        Fault::GammaTwice(_) | Fault::GammaMissing(_) | Fault::GammaOther { .. } => "gamma",
        Fault::HalfPixel { .. } => "half a pixel",
        Fault::OnePixel { .. } => "one pixel",
        Fault::Swapped => "swapped",
    }
}

/// A mistake undone, in words: "with ... too" in a finding of two.
fn undoing(fault: Fault) -> &'static str {
    match fault {
        Fault::Mirror => "the image flipped back",
        Fault::UpsideDown => "the image turned upright",
        Fault::GammaTwice(_) => "one gamma encoding undone",
        Fault::GammaMissing(_) => "the gamma encoding applied",
        Fault::GammaOther { .. } => "the image encoded anew",
        Fault::Swapped => "the channels swapped back",
        Fault::HalfPixel { .. } | Fault::OnePixel { .. } => "the shift undone",
    }
}

impl Finding {
    /// The finding in words: what is wrong, how undoing it fares, and
    /// where the mistake usually is.
    pub fn message(&self) -> String {
        let (what, mut undone, hint) = self.words();
        if let Some(other) = self.with {
            undone = format!("{undone}, and with {} too", undoing(other));
        }
        format!(
            "{}: {what}. {undone}, {} off by more than {} of 255 instead of {}. {hint}",
            self.word(),
            pixels(self.after),
            self.levels,
            self.before
        )
    }

    fn words(&self) -> (String, String, String) {
        match self.fault {
            Fault::Mirror if self.right_handed => (
                "the image is the reference's mirror image (left and right swapped)".into(),
                "Flipped back".into(),
                "This scene's camera (handedness = \"right\") puts world +x on the image's \
                 right, where the lab's puts it on the left: check the camera's horizontal \
                 axis."
                    .into(),
            ),
            Fault::Mirror => (
                "the image is the reference's mirror image (left and right swapped)".into(),
                "Flipped back".into(),
                "The lab's camera puts world +x on the image's left, where most other \
                 renderers put it on the right: check the camera's horizontal axis."
                    .into(),
            ),
            Fault::UpsideDown => (
                "the image is the reference upside down".into(),
                "Turned upright".into(),
                "Image rows run from the top (y = 0 is the top row): check the sign of \
                 the camera's vertical axis."
                    .into(),
            ),
            Fault::GammaTwice(g) => (
                "gamma is applied twice".into(),
                format!("With one c^(1/{g}) undone"),
                format!("Encode once, as the last step: c^(1/{g}) before the 8-bit truncation."),
            ),
            Fault::GammaMissing(g) => (
                "no gamma is applied, the image holds the linear values".into(),
                format!("Encoded with c^(1/{g})"),
                format!("Encode with c^(1/{g}) before the 8-bit truncation."),
            ),
            Fault::GammaOther { image, reference } => (
                format!("the image is encoded with gamma {image}, the reference with {reference}"),
                format!("Encoded anew with c^(1/{reference})"),
                format!(
                    "Encode with the scene's gamma, c^(1/{reference}); to see the scene with \
                     your display's gamma, tracer render --gamma {image}."
                ),
            ),
            Fault::HalfPixel { right, down } => (
                format!(
                    "the image is shifted by half a pixel ({} and {}), as when its rays go \
                     through the pixels' corners, not their centres",
                    if right { "right" } else { "left" },
                    if down { "down" } else { "up" }
                ),
                "Against the reference moved to the corners".into(),
                "Aim each ray at the pixel's centre, (x + 0.5, y + 0.5).".into(),
            ),
            Fault::OnePixel { dx, dy } => (
                format!("the image is shifted by one pixel ({})", direction(dx, dy)),
                "Shifted back".into(),
                "Look for an off-by-one in the pixel loops or the ray's pixel coordinates.".into(),
            ),
            Fault::Swapped => (
                "the red and blue channels are swapped (BGR instead of RGB)".into(),
                "Swapped back".into(),
                "Write the channels in the order red, green, blue.".into(),
            ),
        }
    }
}

/// "1 pixel", "2 pixels".
pub fn pixels(n: u64) -> String {
    format!("{n} pixel{}", if n == 1 { "" } else { "s" })
}

fn direction(dx: i8, dy: i8) -> String {
    let horizontal = match dx {
        1 => Some("right"),
        -1 => Some("left"),
        _ => None,
    };
    let vertical = match dy {
        1 => Some("down"),
        -1 => Some("up"),
        _ => None,
    };
    let words: Vec<&str> = [horizontal, vertical].into_iter().flatten().collect();
    words.join(" and ")
}

/// The message for images of different sizes, which are compared no further.
pub fn size_message((w, h): (u32, u32), (rw, rh): (u32, u32)) -> String {
    let relation = if (w, h) == (rh, rw) {
        " (width and height swapped)".to_string()
    } else if u64::from(w) * 2 == u64::from(rw) && u64::from(h) * 2 == u64::from(rh) {
        " (half its width and height)".to_string()
    } else if u64::from(w) == u64::from(rw) * 2 && u64::from(h) == u64::from(rh) * 2 {
        " (twice its width and height)".to_string()
    } else {
        String::new()
    };
    format!(
        "size: the image is {w}x{h} pixels, the reference {rw}x{rh}{relation}; images of \
         different sizes are compared no further. Render at the reference's size \
         (tracer render --width {rw} --height {rh})."
    )
}

/// The images as functions of (x, y), clamped at the borders.
#[derive(Clone, Copy)]
struct Pair<'a> {
    image: &'a RgbImage,
    reference: &'a RgbImage,
    tolerance: u8,
}

impl Pair<'_> {
    fn size(&self) -> (u32, u32) {
        self.image.dimensions()
    }

    fn reference_at(&self, x: i64, y: i64) -> [u8; 3] {
        let (w, h) = self.size();
        let x = x.clamp(0, i64::from(w) - 1) as u32;
        let y = y.clamp(0, i64::from(h) - 1) as u32;
        self.reference.get_pixel(x, y).0
    }

    /// How many pixels `error` (of x, y) puts beyond the tolerance.
    fn count(&self, error: impl Fn(u32, u32) -> u8) -> u64 {
        let (w, h) = self.size();
        let mut count = 0;
        for y in 0..h {
            for x in 0..w {
                count += u64::from(error(x, y) > self.tolerance);
            }
        }
        count
    }

    /// Pixels off once the image is mapped pixel by pixel through `undo`.
    fn off_after(&self, undo: impl Fn(u32, u32) -> [u8; 3]) -> u64 {
        self.count(|x, y| channel_difference(undo(x, y), self.reference.get_pixel(x, y).0))
    }
}

/// The mistakes that explain the difference of `image` and `reference`
/// (of one size), `before` pixels being off.
pub fn diagnose(
    image: &RgbImage,
    reference_read: &Reference,
    tolerance: u8,
    before: u64,
) -> Vec<Finding> {
    if before < MIN_DIFFERING {
        return Vec::new();
    }
    // A scene's gamma other than 1: another gamma can be told from it.
    let known = reference_read.gamma.filter(|g| (g - 1.0).abs() > 0.05);
    let gamma = known.unwrap_or(USUAL_GAMMA);
    let pair = Pair {
        image,
        reference: &reference_read.image,
        tolerance,
    };
    let finding = |(fault, after)| Finding {
        fault,
        before,
        after,
        levels: tolerance,
        with: None,
        right_handed: false,
    };
    let table = decoding(gamma);
    let undone = |fault| Undo::of(fault, &table).off(&pair);
    let (after_one_pixel, one_pixel) = one_pixel(&pair);
    let mut found: Vec<Finding> = [
        (Fault::Mirror, undone(Fault::Mirror)),
        (Fault::UpsideDown, undone(Fault::UpsideDown)),
        (Fault::GammaTwice(gamma), undone(Fault::GammaTwice(gamma))),
        (
            Fault::GammaMissing(gamma),
            undone(Fault::GammaMissing(gamma)),
        ),
        (one_pixel, after_one_pixel),
        (Fault::Swapped, undone(Fault::Swapped)),
    ]
    .into_iter()
    // Only against a scene's gamma, which is known (an image's is not).
    .chain(known.map(|_| other_gamma(&pair, gamma)))
    .map(finding)
    .filter(Finding::explains)
    .collect();
    if found.is_empty() {
        found = two_at_once(&pair, gamma, &table, before);
    }
    // A whole pixel's shift also passes the half-pixel test: name it alone.
    // So is a mistake that leaves (next to) nothing off once undone.
    let whole = |f: &Finding| matches!(f.fault, Fault::OnePixel { .. }) || f.after < MIN_DIFFERING;
    if !found.iter().any(whole) {
        // The renders through the corners cost four renders of the scene:
        // only when nothing else explained the difference.
        let rendered = || rendered_half_pixel(&pair, reference_read, before);
        let half = if found.is_empty() { rendered() } else { None };
        found.extend(half.or_else(|| half_pixel(&pair)).filter(Finding::explains));
    }
    for f in &mut found {
        f.right_handed = reference_read.right_handed;
    }
    found
}

/// The usual gammas of displays and of other renderers' defaults: one the
/// image may be encoded with instead of the reference's.
const OTHER_GAMMAS: [f32; 6] = [1.6, 1.8, 2.0, 2.2, 2.4, 2.6];

/// The other gamma that best explains the image (as if encoded with it
/// where the reference has `gamma`), and the pixels off once the image is
/// encoded anew.
fn other_gamma(pair: &Pair, gamma: f32) -> (Fault, u64) {
    OTHER_GAMMAS
        .into_iter()
        .filter(|g| (g - gamma).abs() > 0.05)
        .map(|g| {
            let table = reencoding(g, gamma);
            let undo = Undo {
                image_decoding: Some(&table),
                ..Undo::default()
            };
            let fault = Fault::GammaOther {
                image: g,
                reference: gamma,
            };
            (fault, undo.off(pair))
        })
        .min_by_key(|&(_, after)| after)
        .expect("some gamma differs from any one")
}

/// An 8-bit level encoded with `c^(1/from)` (taken at the level's middle,
/// as the tracer truncates) encoded anew with `c^(1/to)`.
fn reencoding(from: f32, to: f32) -> [u8; 256] {
    std::array::from_fn(|v| {
        let c = (v as f32 + 0.5) / 255.0;
        (255.0 * c.powf(from / to)).min(255.0) as u8
    })
}

impl Finding {
    fn explains(&self) -> bool {
        self.before >= MIN_DIFFERING && self.after * FACTOR <= self.before
    }
}

/// `c^gamma` of each 8-bit level, taken at the level's middle (the tracer
/// truncates), rounded: it undoes one encoding and, unlike `c^(1/gamma)`,
/// does not blow up the 8-bit steps of dark values.
fn decoding(gamma: f32) -> [u8; 256] {
    std::array::from_fn(|v| {
        let c = (v as f32 + 0.5) / 255.0;
        (255.0 * c.powf(gamma)).round().min(255.0) as u8
    })
}

/// What undoing some of the mistakes does: the image read mirrored or
/// upside down, decoded once (gamma applied twice) or its channels swapped
/// back, the reference decoded (gamma missing: the image holds linear
/// values). Each undoes one `Fault`; two together undo two mistakes made
/// at once. The parts commute: the order they are undone in is no matter.
#[derive(Clone, Copy, Default)]
struct Undo<'t> {
    mirror: bool,
    upside_down: bool,
    swap: bool,
    image_decoding: Option<&'t [u8; 256]>,
    reference_decoding: Option<&'t [u8; 256]>,
}

impl<'t> Undo<'t> {
    /// The undoing of `fault` (`table` decodes one gamma encoding); the
    /// shifts are no pixel-by-pixel map: nothing for them.
    fn of(fault: Fault, table: &'t [u8; 256]) -> Undo<'t> {
        let none = Undo::default();
        match fault {
            Fault::Mirror => Undo {
                mirror: true,
                ..none
            },
            Fault::UpsideDown => Undo {
                upside_down: true,
                ..none
            },
            Fault::Swapped => Undo { swap: true, ..none },
            Fault::GammaTwice(_) => Undo {
                image_decoding: Some(table),
                ..none
            },
            Fault::GammaMissing(_) => Undo {
                reference_decoding: Some(table),
                ..none
            },
            // Tried on its own only (`other_gamma`).
            Fault::HalfPixel { .. } | Fault::OnePixel { .. } | Fault::GammaOther { .. } => none,
        }
    }

    /// Both undone.
    fn and(self, other: Undo<'t>) -> Undo<'t> {
        Undo {
            mirror: self.mirror || other.mirror,
            upside_down: self.upside_down || other.upside_down,
            swap: self.swap || other.swap,
            image_decoding: self.image_decoding.or(other.image_decoding),
            reference_decoding: self.reference_decoding.or(other.reference_decoding),
        }
    }

    /// Pixels still off once undone.
    fn off(&self, p: &Pair) -> u64 {
        let (w, h) = p.size();
        let decode = |c: [u8; 3], table: Option<&[u8; 256]>| match table {
            Some(t) => c.map(|v| t[usize::from(v)]),
            None => c,
        };
        p.count(|x, y| {
            let from_x = if self.mirror { w - 1 - x } else { x };
            let from_y = if self.upside_down { h - 1 - y } else { y };
            let mut pixel = decode(p.image.get_pixel(from_x, from_y).0, self.image_decoding);
            if self.swap {
                pixel.swap(0, 2);
            }
            let reference = decode(p.reference.get_pixel(x, y).0, self.reference_decoding);
            channel_difference(pixel, reference)
        })
    }
}

/// Two mistakes made at once, where neither alone explains the
/// difference: the pair whose undoing leaves fewest pixels off, named as
/// two findings (each `with` the other) if it explains the difference.
/// Gamma twice and gamma missing exclude each other.
fn two_at_once(p: &Pair, gamma: f32, table: &[u8; 256], before: u64) -> Vec<Finding> {
    let faults = [
        Fault::Mirror,
        Fault::UpsideDown,
        Fault::GammaTwice(gamma),
        Fault::GammaMissing(gamma),
        Fault::Swapped,
    ];
    let both_gammas = |a, b| matches!((a, b), (Fault::GammaTwice(_), Fault::GammaMissing(_)));
    let mut best: Option<(u64, Fault, Fault)> = None;
    for (i, &a) in faults.iter().enumerate() {
        for &b in faults[i + 1..].iter().filter(|&&b| !both_gammas(a, b)) {
            let after = Undo::of(a, table).and(Undo::of(b, table)).off(p);
            if best.is_none_or(|(least, ..)| after < least) {
                best = Some((after, a, b));
            }
        }
    }
    let Some((after, a, b)) = best else {
        return Vec::new();
    };
    let finding = |fault, with| Finding {
        fault,
        before,
        after,
        levels: p.tolerance,
        with: Some(with),
        right_handed: false,
    };
    [finding(a, b), finding(b, a)]
        .into_iter()
        .filter(Finding::explains)
        .collect()
}

/// The best of the eight shifts by one pixel, and the shift.
fn one_pixel(p: &Pair) -> (u64, Fault) {
    let shifts = (-1i8..=1).flat_map(|dy| (-1i8..=1).map(move |dx| (dx, dy)));
    shifts
        .filter(|&shift| shift != (0, 0))
        .map(|(dx, dy)| {
            let after = p.count(|x, y| {
                let moved =
                    p.reference_at(i64::from(x) - i64::from(dx), i64::from(y) - i64::from(dy));
                channel_difference(p.image.get_pixel(x, y).0, moved)
            });
            (after, Fault::OnePixel { dx, dy })
        })
        .min_by_key(|&(after, _)| after)
        .expect("eight shifts")
}

/// The image against the reference scene rendered through each corner of
/// the pixels: exact for any image, textured or anti-aliased as it may
/// be. None for a reference image or canvas (`half_pixel` then
/// approximates those renders).
fn rendered_half_pixel(p: &Pair, reference: &Reference, before: u64) -> Option<Finding> {
    let mut best: Option<(u64, usize)> = None;
    for k in 0..CORNERS.len() {
        let corner = reference.through_corner(k)?;
        if corner.dimensions() != p.image.dimensions() {
            return None;
        }
        let after =
            p.count(|x, y| channel_difference(p.image.get_pixel(x, y).0, corner.get_pixel(x, y).0));
        if best.is_none_or(|(least, _)| after < least) {
            best = Some((after, k));
        }
    }
    let (after, k) = best?;
    // Aimed at the corner left of the centre (x - 0.5), a pixel shows what
    // the reference shows left of it: the content moved right.
    let [x, y] = CORNERS[k];
    Some(Finding {
        fault: Fault::HalfPixel {
            right: x < 0.0,
            down: y < 0.0,
        },
        before,
        after,
        levels: p.tolerance,
        with: None,
        right_handed: false,
    })
}

/// A pixel sampled at a corner, against the reference's four pixels
/// around that corner: their mean (smooth or anti-aliased images), or the
/// nearest of them (one sample a pixel: a hard edge keeps one side's
/// colour). The best of the four corners, counted at [`HALF_PIXEL_LEVELS`].
fn half_pixel(p: &Pair) -> Option<Finding> {
    let p = Pair {
        tolerance: p.tolerance.max(HALF_PIXEL_LEVELS),
        ..*p
    };
    let before = p.off_after(|x, y| p.image.get_pixel(x, y).0);
    let (after, fault) = [(-1, -1), (0, -1), (-1, 0), (0, 0)]
        .into_iter()
        .map(|(ox, oy)| {
            let after = p.count(|x, y| {
                let (x0, y0) = (i64::from(x) + ox, i64::from(y) + oy);
                let block =
                    [(0, 0), (1, 0), (0, 1), (1, 1)].map(|(i, j)| p.reference_at(x0 + i, y0 + j));
                corner_error(p.image.get_pixel(x, y).0, &block)
            });
            // The block's centre is half a pixel left of the pixel's for ox = -1:
            // the image shows there what the reference shows left of it.
            (
                after,
                Fault::HalfPixel {
                    right: ox == -1,
                    down: oy == -1,
                },
            )
        })
        .min_by_key(|&(after, _)| after)?;
    Some(Finding {
        fault,
        before,
        after,
        levels: p.tolerance,
        with: None,
        right_handed: false,
    })
}

fn corner_error(pixel: [u8; 3], block: &[[u8; 3]; 4]) -> u8 {
    let mean: [u8; 3] = std::array::from_fn(|c| {
        let sum: u16 = block.iter().map(|b| u16::from(b[c])).sum();
        ((sum + 2) / 4) as u8
    });
    let nearest = block
        .iter()
        .map(|&b| channel_difference(pixel, b))
        .min()
        .unwrap_or(0);
    nearest.min(channel_difference(pixel, mean))
}
