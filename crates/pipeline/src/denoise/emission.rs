//! The light a pixel sees directly (lamps, the sky, through mirrors and
//! glass) kept out of what OIDN filters.
//!
//! That light has no noise but at its edges. OIDN, given it, moves it all
//! the same by a few percent (its network's tolerance, which it keeps in a
//! perceptual, nearly logarithmic scale), and the albedo and normal cannot
//! tell it apart: a lamp that reflects as the ceiling around it has the
//! ceiling's. On the Cornell box at 16 paths a pixel those few percent of
//! a lamp 90 times brighter than the walls outweighed all the noise
//! denoising removed. So OIDN is given the image less this light, and the
//! light is added back after.
//!
//! What is taken out is what the render itself counted
//! (`PathTracer::seen_light`): the light its camera rays met on their
//! first segment, from as many rays as it had (at a lamp's edge, where a
//! path's one ray would be noise, the more camera rays a denoised render
//! takes), so the image less it is exactly the light that bounced, never
//! below 0. A guide of it sampled apart would differ at an edge by its
//! share of lamp, at random, and so did the first version of this, which
//! cut what fell below 0 there and biased edges up: the Cornell box
//! denoised at 16 paths, RMSE 0.0065 then, 0.0031 now. The light met
//! after a mirror or glass (`Aov::ReflectedEmission`) a path's camera ray
//! does not see alone; it is sampled as a guide, both branches of glass
//! followed at the first surfaces and finely at its edges
//! ([`edge_samples`]), and taken out as well, which is not exact there.
//! (Followed one branch at random, as the albedo is, that guide was
//! speckled in glass, and so was the denoised image: the materials scene
//! at 16 paths, RMSE 0.061, 0.060 now.)

use glam::Vec3;
use tracer_core::{LinearImage, Region};

/// Samples per pixel of the guide of the light seen in mirrors and glass
/// where it has an edge (its other pixels have [`crate::GUIDE_SAMPLES`]):
/// this many times the render's paths a pixel, from 64 to 256. The
/// materials scene at 16 paths, denoised: RMSE 0.0600 with these, 0.0589
/// with 16 times the paths (256 to 1024), whose guide took 0.64 s against
/// 0.28 s (2.2 s against 0.6 s at 64 paths, for the same error).
const EDGE_FACTOR: u32 = 4;
const EDGE_SAMPLES: (u32, u32) = (64, 256);

/// Samples per pixel of the emission guide's edges for a render of
/// `paths` a pixel.
pub(crate) fn edge_samples(paths: u32) -> u32 {
    paths
        .saturating_mul(EDGE_FACTOR)
        .clamp(EDGE_SAMPLES.0, EDGE_SAMPLES.1)
}

/// A pixel is at an edge of the light when it or a neighbour differs
/// from the other by more than this share of the larger (each channel):
/// a lamp's outline, an object before the sky; not the gentle change
/// across a sky or a textured lamp.
const EDGE_JUMP: f32 = 0.1;

/// Rows of pixels at an edge of `light`, an image of `wide`, each a
/// region of one row: those of `region` (inside `wide`), each compared
/// with its eight neighbours in `wide` (so a tile, given one pixel more
/// on each side, finds the edges the whole image finds).
pub(crate) fn edge_rows(light: &LinearImage, wide: Region, region: Region) -> Vec<Region> {
    let at = |x: u32, y: u32| light.get(x - wide.x0, y - wide.y0);
    let is_edge = |x: u32, y: u32| {
        let c = at(x, y);
        let (x0, x1) = (x.saturating_sub(1).max(wide.x0), (x + 2).min(wide.x1));
        let (y0, y1) = (y.saturating_sub(1).max(wide.y0), (y + 2).min(wide.y1));
        (y0..y1).any(|j| (x0..x1).any(|i| jumps(c, at(i, j))))
    };
    let mut rows = Vec::new();
    for y in region.y0..region.y1 {
        let mut start = None;
        for x in region.x0..=region.x1 {
            match (start, x < region.x1 && is_edge(x, y)) {
                (None, true) => start = Some(x),
                (Some(x0), false) => {
                    rows.push(Region {
                        x0,
                        y0: y,
                        x1: x,
                        y1: y + 1,
                    });
                    start = None;
                }
                _ => {}
            }
        }
    }
    rows
}

/// Whether `a` and `b` differ by more than [`EDGE_JUMP`] of the larger.
fn jumps(a: Vec3, b: Vec3) -> bool {
    let larger = a.max(b);
    ((a - b).abs() - EDGE_JUMP * larger).max_element() > 0.0
}

/// `region` grown by one pixel on each side, inside an image of `size`.
pub(crate) fn widened(region: Region, (width, height): (u32, u32)) -> Region {
    Region {
        x0: region.x0.saturating_sub(1),
        y0: region.y0.saturating_sub(1),
        x1: (region.x1 + 1).min(width),
        y1: (region.y1 + 1).min(height),
    }
}

/// The image OIDN is given: `colour` less the light seen directly (each
/// channel at least 0: the rounding of that difference, and where the
/// render caught less of a reflection's edge than its guide, are cut).
/// The playground's WebAssembly does not denoise.
#[cfg(not(target_arch = "wasm32"))]
pub(crate) fn without(colour: &[Vec3], light: &[Vec3]) -> Vec<Vec3> {
    colour
        .iter()
        .zip(light)
        .map(|(c, e)| (*c - *e).max(Vec3::ZERO))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, lit: impl Fn(u32, u32) -> f32) -> LinearImage {
        let mut image = LinearImage::new(width, height);
        for y in 0..height {
            for x in 0..width {
                image.pixels[(y * width + x) as usize] = Vec3::splat(lit(x, y));
            }
        }
        image
    }

    fn pixels(rows: &[Region]) -> Vec<(u32, u32)> {
        rows.iter()
            .flat_map(|r| (r.x0..r.x1).map(move |x| (x, r.y0)))
            .collect()
    }

    #[test]
    fn a_lamps_outline_is_its_edge_and_its_inside_and_a_gentle_sky_are_not() {
        // A lamp of 18 over columns 2..7, rows 1..5, of a 10x7 image whose
        // sky brightens by 5 % a column.
        let lamp = |x: u32, y: u32| (2..7).contains(&x) && (1..5).contains(&y);
        let lit = |x: u32, y: u32| {
            if lamp(x, y) {
                18.0
            } else {
                1.0 + 0.05 * x as f32
            }
        };
        let light = image(10, 7, lit);
        let whole = Region::full(10, 7);
        let found = pixels(&edge_rows(&light, whole, whole));
        let inside = |x: u32, y: u32| (3..6).contains(&x) && (2..4).contains(&y);
        let expected: Vec<(u32, u32)> = (0..6)
            .flat_map(|y| (1..8).map(move |x| (x, y)))
            .filter(|&(x, y)| !inside(x, y))
            .collect();
        assert_eq!(found, expected);
    }

    #[test]
    fn a_tile_widened_by_a_pixel_finds_the_edges_the_whole_image_finds() {
        // A lamp's bottom row is the last row of the tile above it.
        let light = image(6, 6, |x, y| if y < 3 && x > 1 { 10.0 } else { 0.0 });
        let whole = Region::full(6, 6);
        let all = pixels(&edge_rows(&light, whole, whole));
        let mut parts = Vec::new();
        for (y0, y1) in [(0, 3), (3, 6)] {
            let tile = Region {
                x0: 0,
                y0,
                x1: 6,
                y1,
            };
            let wide = widened(tile, (6, 6));
            let mut part = LinearImage::new(wide.width(), wide.height());
            for y in wide.y0..wide.y1 {
                for x in wide.x0..wide.x1 {
                    part.pixels[((y - wide.y0) * wide.width() + x - wide.x0) as usize] =
                        light.get(x, y);
                }
            }
            parts.extend(pixels(&edge_rows(&part, wide, tile)));
        }
        assert_eq!(parts, all);
        assert!(all.contains(&(3, 3)), "the row below the lamp: {all:?}");
    }

    #[test]
    fn edges_get_4_times_the_renders_paths_from_64_to_256() {
        assert_eq!(edge_samples(1), 64);
        assert_eq!(edge_samples(16), 64);
        assert_eq!(edge_samples(32), 128);
        assert_eq!(edge_samples(64), 256);
        assert_eq!(edge_samples(65536), 256);
    }

    #[test]
    fn what_oidn_is_given_is_the_colour_less_the_light_and_never_negative() {
        let colour = [Vec3::new(18.5, 1.0, 0.2), Vec3::new(0.3, 0.3, 0.3)];
        let light = [Vec3::new(18.0, 0.5, 0.0), Vec3::new(4.5, 0.0, 0.0)];
        assert_eq!(
            without(&colour, &light),
            [Vec3::new(0.5, 0.5, 0.2), Vec3::new(0.0, 0.3, 0.3)]
        );
    }
}
