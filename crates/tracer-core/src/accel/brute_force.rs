//! The reference the BVH is tested against: every ray tests every object,
//! in list order.

use crate::geometry::{Object, SurfaceHit};
use crate::ray::Ray;

/// The nearest hit in (t_min, t_max); of hits at the same distance, the
/// object listed first.
pub fn closest_hit(objects: &[Object], ray: &Ray, t_min: f32, t_max: f32) -> Option<SurfaceHit> {
    let mut best: Option<SurfaceHit> = None;
    for (index, object) in objects.iter().enumerate() {
        let limit = best.map_or(t_max, |hit| hit.t);
        if let Some(hit) = object.surface_hit(index, ray, t_min, limit) {
            best = Some(hit);
        }
    }
    best
}

/// Whether any object lies on the ray within (t_min, t_max).
pub fn occluded(objects: &[Object], ray: &Ray, t_min: f32, t_max: f32) -> bool {
    objects
        .iter()
        .any(|o| o.shape.intersect(ray, t_min, t_max).is_some())
}
