//! What a pixel sees directly, sampled by more camera rays than paths
//! (`render.camera_rays`). Where a lamp or the sky shows through part of a
//! pixel, its value is mostly how much of the pixel the lamp covers: a
//! path's one camera ray finds that out slowly, and on the Cornell box the
//! lamp's edges were half the error left after path reuse. A pixel whose
//! corners and centre see lights far apart (by a quarter of the brighter)
//! takes, for each path,
//! `camera_rays` camera rays of their own sequence (stratified together
//! over the pixel's samples) and counts their mean in place of what the
//! path's own camera ray saw: the same expectation, so the image converges
//! to the same one. Other pixels, seeing one light or none across them (or
//! a sky that changes gently), are left as they are, at no cost.

use crate::ray::Ray;
use crate::sampler::PixelSampler;
use crate::scene::Scene;
use glam::{Vec2, Vec3};

/// The most camera rays a path may have: each is a nearest hit.
pub const MAX_CAMERA_RAYS: u32 = scene_format::validate::MAX_CAMERA_RAYS;

/// The request number of the extra camera rays' points in the pixel (and
/// on the lens): far beyond any path's own, so their numbers are
/// independent of the paths'.
const SEEN_REQUEST: u32 = 1 << 12;

/// What a camera ray sees directly: the light a path's first segment adds
/// (an emitter's front, the sky or background), as the path tracer adds
/// it, which gives it (a path of depth 0).
pub(super) type See<'s> = &'s mut dyn FnMut(Ray) -> Vec3;

/// What the camera rays through pixel (i, j)'s centre and four corners
/// (and the lens's centre) see directly, the centre first.
pub(super) fn looks(scene: &Scene, (i, j): (u32, u32), see: See) -> [Vec3; 5] {
    let camera = scene.camera();
    let (x, y) = (i as f32, j as f32);
    let points = [(0.5, 0.5), (0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
    points.map(|(dx, dy)| see(camera.lens_ray(x + dx, y + dy, Vec2::ZERO)))
}

/// Whether what a pixel shows directly changes sharply across it, by its
/// `looks`: its corners see lights apart from its centre's by more than
/// `EDGE` of the brighter (the edge of a lamp, an object against the
/// sky), not the gentle change of a sky across a pixel, which one ray a
/// path finds well enough.
pub(super) fn varies([centre, corners @ ..]: &[Vec3; 5]) -> bool {
    corners.iter().any(|corner| apart(*corner, *centre))
}

/// Whether a pixel's `looks` see no light directly (a wall of a room lit
/// by its lamps).
pub(super) fn dark(looks: &[Vec3; 5]) -> bool {
    looks.iter().all(|&light| light == Vec3::ZERO)
}

/// How far apart, relative to the brighter, two lights seen in a pixel
/// make it an edge.
const EDGE: f32 = 0.25;

/// Whether lights `a` and `b` are apart by more than `EDGE` of the
/// brighter in some channel (or either is not a number).
fn apart(a: Vec3, b: Vec3) -> bool {
    let brighter = a.abs().max(b.abs()).max_element();
    let close = (a - b).abs().max_element() <= EDGE * brighter;
    !close
}

/// What `rays` camera rays of pixel (i, j)'s sample `s` see directly, in
/// the mean, less what the sample's own camera ray saw: added to the
/// sample's value, its directly seen light is theirs (`extra`).
pub(super) fn correction(
    scene: &Scene,
    (seed, rays): (u32, u32),
    (i, j, s): (u32, u32, u32),
    see: See,
) -> Vec3 {
    let own = own(scene, seed, (i, j, s), &mut *see);
    extra(scene, (seed, rays), (i, j, s), see) - own
}

/// What the camera ray of pixel (i, j)'s sample `s` sees directly.
pub(super) fn own(scene: &Scene, seed: u32, (i, j, s): (u32, u32, u32), see: See) -> Vec3 {
    let mut sampler = PixelSampler::new(i, j, seed);
    sampler.start(s);
    see(scene.camera().sampled_ray(&mut sampler, (i, j)))
}

/// What `rays` camera rays of pixel (i, j)'s sample `s` see directly, in
/// the mean: samples `rays s` to `rays (s + 1) - 1` of their own
/// sequence, so that a pixel's samples put `rays` times as many points in
/// it, stratified together.
pub(super) fn extra(
    scene: &Scene,
    (seed, rays): (u32, u32),
    (i, j, s): (u32, u32, u32),
    see: See,
) -> Vec3 {
    let camera = scene.camera();
    let mut sampler = PixelSampler::new(i, j, seed);
    let mut sum = Vec3::ZERO;
    for m in 0..rays {
        sampler.start(s.wrapping_mul(rays).wrapping_add(m));
        sampler.skip(SEEN_REQUEST);
        sum += see(camera.sampled_ray(&mut sampler, (i, j)));
    }
    sum / rays as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_edge_is_a_jump_of_a_quarter_of_the_brighter_light() {
        let lamp = Vec3::new(17.0, 12.0, 4.0);
        assert!(apart(lamp, Vec3::ZERO));
        assert!(apart(Vec3::ZERO, lamp));
        assert!(!apart(lamp, lamp * 0.9));
        assert!(!apart(Vec3::ZERO, Vec3::ZERO));
        // A sky a little bluer at one corner.
        assert!(!apart(Vec3::new(0.5, 0.6, 0.9), Vec3::new(0.5, 0.6, 1.0)));
        assert!(apart(Vec3::splat(f32::NAN), Vec3::ONE));
    }
}
