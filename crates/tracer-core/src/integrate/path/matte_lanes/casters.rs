//! Which triangles can stand between a light and the scene: a shadow ray
//! toward a light is tested against those alone. A triangle is left out
//! for a light when the whole scene lies on one side of its plane and
//! every point of the light well inside that side: a segment from a
//! point of the scene to the light then meets the plane at its start at
//! most (a wall, a floor, a box's face on the floor), which the test's
//! `t > EPSILON` refuses. "Well inside" is far enough that the test's own
//! rounding cannot find a distance above `EPSILON` there either, so the
//! answer of every shadow ray is the one testing all triangles gives.

use super::Tri;
use crate::light::area::AreaShape;
use crate::light::lights::Lights;
use crate::EPSILON;
use glam::{DVec3, Vec3};

/// For each light of the table (points, then areas), the triangles of
/// `tris` its shadow rays are tested against, in their order.
pub(super) fn shadow_casters(tris: &[Tri], lights: &Lights) -> Vec<Vec<Tri>> {
    let scene: Vec<DVec3> = tris.iter().flat_map(corners).collect();
    let lights_points: Vec<Vec<DVec3>> = lights
        .points()
        .iter()
        .map(|p| vec![p.position.as_dvec3()])
        .chain(lights.areas().iter().map(|a| area_corners(&a.shape)))
        .collect();
    let extent = diagonal(scene.iter().chain(lights_points.iter().flatten()));
    lights_points
        .iter()
        .map(|light| {
            let apart = |t: &&Tri| !separates(t, &scene, light, extent);
            tris.iter().filter(apart).copied().collect()
        })
        .collect()
}

/// Whether `tri`'s plane has every point of `scene` on one side (or on
/// it) and every corner of `light` inside that side by more than the
/// test's rounding can cross: no shadow ray toward the light hits it.
fn separates(tri: &Tri, scene: &[DVec3], light: &[DVec3], extent: f64) -> bool {
    let Some((n, v0, side, sin)) = scene_side(tri, scene, extent) else {
        return false;
    };
    let height = |x: &DVec3| n.dot(*x - v0);
    light.iter().all(|x| side * height(x) > margin(extent, sin))
}

/// The triangles of `tris` a segment between two points of the scene can
/// meet: those whose plane has some of the scene on each side. A segment
/// between two points on one side of a plane meets it at an end at most,
/// which the test's `t > EPSILON` and the segment's shortened reach
/// refuse.
pub(super) fn connection_casters(tris: &[Tri]) -> Vec<Tri> {
    let scene: Vec<DVec3> = tris.iter().flat_map(corners).collect();
    let extent = diagonal(scene.iter());
    let cuts = |t: &&Tri| scene_side(t, &scene, extent).is_none();
    tris.iter().filter(cuts).copied().collect()
}

/// `tri`'s unit normal and first corner, the side of its plane (1 or -1
/// along the normal) every point of `scene` lies on (or on the plane, off
/// it by rounding), and the sine of its corner: None when the scene lies
/// on both sides, or the triangle is a sliver (or NaN).
fn scene_side(tri: &Tri, scene: &[DVec3], extent: f64) -> Option<(DVec3, DVec3, f64, f64)> {
    let (v0, e1, e2) = (tri.v0.as_dvec3(), tri.e1.as_dvec3(), tri.e2.as_dvec3());
    let cross = e1.cross(e2);
    let sin = cross.length() / (e1.length() * e2.length());
    // A sliver (or NaN) triangle, or a scene of no size, is kept.
    if sin.is_nan() || sin <= 0.0 || !extent.is_finite() {
        return None;
    }
    let n = cross / cross.length();
    let height = |x: &DVec3| n.dot(*x - v0);
    // Points of the scene on the plane may be off it by their rounding.
    let on = 1e-6 * extent;
    if scene.iter().all(|x| height(x) >= -on) {
        Some((n, v0, 1.0, sin))
    } else if scene.iter().all(|x| height(x) <= on) {
        Some((n, v0, -1.0, sin))
    } else {
        None
    }
}

/// How far inside a light must lie for the test of a ray from the plane
/// toward it to keep its distance below `EPSILON / 4`: the distance's
/// rounding is a few units in the last place of the scene's size squared
/// over the ray's height gain, and 16 of them are allowed for.
fn margin(extent: f64, sin: f64) -> f64 {
    let rounding = 16.0 * f64::from(f32::EPSILON) / 2.0;
    rounding * extent * extent / (sin * f64::from(EPSILON) / 4.0)
}

/// A triangle's corners.
fn corners(t: &Tri) -> [DVec3; 3] {
    let v0 = t.v0.as_dvec3();
    [v0, v0 + t.e1.as_dvec3(), v0 + t.e2.as_dvec3()]
}

/// A flat light's corners: every point of it is a mix of them.
fn area_corners(shape: &AreaShape) -> Vec<DVec3> {
    let d = |v: &Vec3| v.as_dvec3();
    match shape {
        AreaShape::Triangle { v0, e1, e2, .. } => {
            vec![d(v0), d(v0) + d(e1), d(v0) + d(e2)]
        }
        AreaShape::Parallelogram { corner, e1, e2, .. } => {
            let (c, e1, e2) = (d(corner), d(e1), d(e2));
            vec![c, c + e1, c + e2, c + e1 + e2]
        }
        // Only flat lights are sampled in lanes; a point-free list keeps
        // every triangle (nothing is proven inside).
        _ => vec![DVec3::splat(f64::NAN)],
    }
}

/// The diagonal of the box around `points`.
fn diagonal<'a>(points: impl Iterator<Item = &'a DVec3>) -> f64 {
    let (lo, hi) = points.fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    (hi - lo).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::lights::PointSource;

    /// Triangle `id` (kept in its material).
    fn tri(id: u32, v0: [f32; 3], e1: [f32; 3], e2: [f32; 3]) -> Tri {
        let (e1, e2) = (Vec3::from(e1), Vec3::from(e2));
        Tri {
            v0: Vec3::from(v0),
            e1,
            e2,
            edge_scale: 0.0,
            normal: e1.cross(e2).normalize(),
            material: id,
        }
    }

    /// A floor (0), a wall standing on it (1) and a tilted panel over
    /// both (2).
    fn room() -> Vec<Tri> {
        vec![
            tri(0, [-1.0, 0.0, -1.0], [2.0, 0.0, 0.0], [0.0, 0.0, 2.0]),
            tri(1, [-1.0, 0.0, -1.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]),
            tri(2, [-0.5, 1.0, -0.5], [1.0, 0.2, 0.0], [0.0, 0.0, 1.0]),
        ]
    }

    /// The triangles a point light at `position` keeps, by id.
    fn kept_for_a_point_at(position: [f32; 3]) -> Vec<u32> {
        let point = PointSource::point(Vec3::from(position), Vec3::ONE);
        let lights = Lights::new(vec![point], Vec::new(), &[], None);
        let casters = shadow_casters(&room(), &lights);
        casters[0].iter().map(|t| t.material).collect()
    }

    #[test]
    fn the_planes_with_the_scene_and_the_light_on_one_side_are_left_out() {
        // Above the panel: the panel can shade, the floor and wall cannot.
        assert_eq!(kept_for_a_point_at([0.0, 1.9, 0.0]), vec![2]);
    }

    #[test]
    fn connections_are_tested_against_the_planes_with_the_scene_on_both_sides() {
        let kept: Vec<u32> = connection_casters(&room())
            .iter()
            .map(|t| t.material)
            .collect();
        // The floor and the wall have the whole room on one side.
        assert_eq!(kept, vec![2]);
        let mut room = room();
        // A wall through the middle of the floor cuts the room.
        room[1].v0 = Vec3::new(0.0, 0.0, -1.0);
        let kept: Vec<u32> = connection_casters(&room)
            .iter()
            .map(|t| t.material)
            .collect();
        assert_eq!(kept, vec![1, 2]);
    }

    #[test]
    fn a_plane_near_the_light_or_between_it_and_the_scene_is_kept() {
        // Too near the floor for the test's rounding to be ruled out.
        assert_eq!(kept_for_a_point_at([0.0, 1e-3, 0.0]), vec![0, 2]);
        // Behind the wall: the wall is between the light and the floor.
        assert_eq!(kept_for_a_point_at([-2.0, 1.0, 0.0]), vec![1, 2]);
    }
}
