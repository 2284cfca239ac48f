//! Where an explained pixel's rays are: each ray of its tree (the primary,
//! mirror, refracted and shadow rays; in path mode the path's segments and
//! its light samples) from its origin to its end in the scene, and the
//! part of it seen in the image, projected by the core's camera
//! (`Camera::image_homogeneous`) and clipped to the image. What `tracer
//! explain --draw` draws over the render, what the playground draws over
//! its image and in 3D, and what `--json` gives other tools as `drawing`.

use crate::explain::{Names, PathEvent, PathEventKind, RayKind, RayNode, Trace};
use glam::{DVec2, Vec3};
use serde::Serialize;
use tracer_core::camera::Camera;
use tracer_core::explain::Explanation;
use tracer_core::ray::Ray;
use tracer_core::Scene;

/// An explained pixel's rays and the scene's lights, in the scene and in
/// the image.
#[derive(Debug, Clone, Serialize)]
pub struct Drawing {
    /// The image's size, [width, height], and the pixel explained.
    pub size: [u32; 2],
    pub pixel: [u32; 2],
    /// Every ray of the tree, in the order the explanation tells them:
    /// each ray, then its shadow rays, then its mirror and refracted rays
    /// (in path mode, in the order of the path's events).
    pub rays: Vec<DrawnRay>,
    /// Each light of `[[lights]]`.
    pub lights: Vec<DrawnLight>,
}

/// What a drawn ray is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DrawnKind {
    /// From the eye (or the lens) through the pixel.
    Primary,
    /// A mirror ray.
    Reflected,
    /// Bent into or out of glass.
    Refracted,
    /// From a hit toward a light (path mode: a light sample's).
    Shadow,
    /// Path mode: the ray a BSDF sample sends on to the next vertex.
    Bounce,
}

/// One ray of the tree.
#[derive(Debug, Clone, Serialize)]
pub struct DrawnRay {
    /// Its index in `rays`; `parent`: the ray whose hit it leaves.
    pub id: usize,
    pub parent: Option<usize>,
    pub kind: DrawnKind,
    /// Path mode: the index in `events` of the event that traced it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub event: Option<usize>,
    pub origin: Vec3,
    /// Unit length.
    pub direction: Vec3,
    /// Where it ends: its hit, or the light a shadow ray goes to (past a
    /// blocker); None when it leaves the scene.
    pub end: Option<Vec3>,
    /// A shadow ray's light (its index in `[[lights]]`), when known.
    pub light: Option<usize>,
    /// A shadow ray that something opaque stops, and what does when known.
    pub blocked: bool,
    pub blocked_by: Option<DrawnBlocker>,
    /// The part of it seen in the image, if any.
    pub image: Option<ImageSegment>,
}

/// The first object in a shadow ray's way.
#[derive(Debug, Clone, Serialize)]
pub struct DrawnBlocker {
    pub object: usize,
    /// As the scene file calls it (`objects[1]`).
    pub name: String,
    pub point: Vec3,
    /// Where that point is seen, when in the image.
    pub seen_at: Option<DVec2>,
}

/// A ray's part in the image: from `from` to `to`, in pixels (x from the
/// left, y from the top of the image; pixel (i, j) is the square from (i,
/// j) to (i + 1, j + 1)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ImageSegment {
    pub from: DVec2,
    pub to: DVec2,
    /// Whether the ray starts outside the image (or behind the eye) and
    /// comes in at `from`.
    pub enters: bool,
    /// Whether it goes on out of the image at `to`.
    pub leaves: bool,
    /// Where its end is seen, when it is in the image: `to`, unless the
    /// ray leaves the image first or goes on forever (then `to` is its
    /// vanishing point).
    pub end_seen: Option<DVec2>,
}

/// A light of the scene.
#[derive(Debug, Clone, Serialize)]
pub struct DrawnLight {
    /// Its index in `[[lights]]`.
    pub light: usize,
    pub position: Vec3,
    /// A sphere light's radius (0 for a point light).
    pub radius: f32,
    /// Where it is seen, when in the image.
    pub seen_at: Option<DVec2>,
}

/// The drawing of `explanation`, a pixel of `scene` (its prepared scene,
/// which holds its objects).
pub fn drawing(
    scene: &Scene,
    explanation: &Explanation,
    pixel: (u32, u32),
    names: &Names,
) -> Drawing {
    let camera = scene.camera();
    let mut rays = Rays {
        camera,
        names,
        scene,
        rays: Vec::new(),
    };
    match &explanation.trace {
        Trace::Whitted { ray } => rays.tree(ray, None),
        Trace::Path { ray, events } => rays.path(ray, events),
    }
    let lights = scene
        .lights()
        .iter()
        .enumerate()
        .map(|(light, l)| {
            use tracer_core::light::{Light, FAR_AWAY};
            let (position, radius) = match l {
                Light::Point(p) => (p.position, 0.0),
                Light::Sphere(s) => (s.centre, s.radius),
                Light::Spot(s) => (s.position, 0.0),
                // Where the lab's shading puts a sun: its shadow rays go there.
                Light::Directional(d) => (-d.direction * FAR_AWAY, 0.0),
            };
            DrawnLight {
                light,
                position,
                radius,
                seen_at: seen_in_image(camera, position),
            }
        })
        .collect();
    Drawing {
        size: [camera.width, camera.height],
        pixel: [pixel.0, pixel.1],
        rays: rays.rays,
        lights,
    }
}

/// The drawn rays, as they are added.
struct Rays<'a> {
    camera: &'a Camera,
    names: &'a Names,
    scene: &'a Scene,
    rays: Vec<DrawnRay>,
}

impl Rays<'_> {
    /// Adds a ray from `origin` along `direction`, ending at `end` (None:
    /// never); its id.
    fn add(
        &mut self,
        kind: DrawnKind,
        parent: Option<usize>,
        (origin, direction, end): (Vec3, Vec3, Option<Vec3>),
    ) -> usize {
        let id = self.rays.len();
        let length = end.map(|e| f64::from((e - origin).length()));
        self.rays.push(DrawnRay {
            id,
            parent,
            kind,
            event: None,
            origin,
            direction,
            end,
            light: None,
            blocked: false,
            blocked_by: None,
            image: image_segment(self.camera, origin, direction, length),
        });
        id
    }

    /// The blocker of a shadow ray, named.
    fn blocker(&self, object: usize, point: Vec3) -> DrawnBlocker {
        DrawnBlocker {
            object,
            name: self.names.object(object),
            point,
            seen_at: seen_in_image(self.camera, point),
        }
    }

    /// A Whitted tree's ray, its shadow rays, then its children.
    fn tree(&mut self, node: &RayNode, parent: Option<usize>) {
        let kind = match node.kind {
            RayKind::Primary => DrawnKind::Primary,
            RayKind::Reflected => DrawnKind::Reflected,
            RayKind::Refracted => DrawnKind::Refracted,
        };
        let id = self.add(kind, parent, (node.origin, node.direction, node.end));
        for lit in &node.lights {
            let Some(shadow) = lit.term.shadow else {
                continue;
            };
            let end = shadow.origin + shadow.direction * shadow.length;
            let ray = self.add(
                DrawnKind::Shadow,
                Some(id),
                (shadow.origin, shadow.direction, Some(end)),
            );
            let blocked_by = lit.blocked_by.map(|b| self.blocker(b.object, b.point));
            let drawn = &mut self.rays[ray];
            drawn.light = Some(lit.term.light);
            drawn.blocked = shadow.passes.is_none();
            drawn.blocked_by = blocked_by;
        }
        for child in &node.children {
            self.tree(child, Some(id));
        }
    }

    /// A path: the camera's ray, then each bounce and light sample in the
    /// order of its events.
    fn path(&mut self, first: &RayNode, events: &[PathEvent]) {
        let primary = self.add(
            DrawnKind::Primary,
            None,
            (first.origin, first.direction, first.end),
        );
        // The vertex the path is at (its ray), and the direction its BSDF
        // sample sent it on.
        let mut at: Option<(Vec3, usize)> = None;
        let mut onward: Option<Vec3> = None;
        for (k, event) in events.iter().enumerate() {
            match event.kind {
                PathEventKind::Vertex {
                    depth: 0, point, ..
                } => at = Some((point, primary)),
                PathEventKind::Vertex { point, .. } => {
                    if let (Some((from, parent)), Some(dir)) = (at, onward.take()) {
                        let ray =
                            self.add(DrawnKind::Bounce, Some(parent), (from, dir, Some(point)));
                        self.rays[ray].event = Some(k);
                        at = Some((point, ray));
                    }
                }
                PathEventKind::Escaped { .. } => {
                    if let (Some((from, parent)), Some(dir)) = (at, onward.take()) {
                        let ray = self.add(DrawnKind::Bounce, Some(parent), (from, dir, None));
                        self.rays[ray].event = Some(k);
                        at = None;
                    }
                }
                PathEventKind::BsdfSample { wi, .. } => onward = Some(wi),
                PathEventKind::LightSample {
                    wi,
                    distance,
                    f_cos,
                    blocked,
                    ..
                } if f_cos != Vec3::ZERO => {
                    if let Some((from, parent)) = at {
                        self.light_sample(k, (from, parent), wi, distance, blocked);
                    }
                }
                _ => {}
            }
        }
    }

    /// A path's shadow ray toward a light sample (`distance` infinite for
    /// the environment's).
    fn light_sample(
        &mut self,
        event: usize,
        (from, parent): (Vec3, usize),
        wi: Vec3,
        distance: f32,
        blocked: bool,
    ) {
        let end = distance.is_finite().then(|| from + wi * distance);
        let ray = self.add(DrawnKind::Shadow, Some(parent), (from, wi, end));
        // The event says only that it was blocked: what did is found as
        // the recorder finds a Whitted shadow ray's blocker.
        let blocked_by = blocked
            .then(|| {
                self.scene
                    .closest_hit(&Ray::new(from, wi), tracer_core::EPSILON, distance)
            })
            .flatten()
            .map(|hit| self.blocker(hit.object, from + wi * hit.t));
        let drawn = &mut self.rays[ray];
        drawn.event = Some(event);
        drawn.blocked = blocked;
        drawn.blocked_by = blocked_by;
    }
}

/// Where `point` is seen, when it is in the image.
fn seen_in_image(camera: &Camera, point: Vec3) -> Option<DVec2> {
    let seen = camera.seen_at(point)?;
    let inside = (0.0..=f64::from(camera.width)).contains(&seen.x)
        && (0.0..=f64::from(camera.height)).contains(&seen.y);
    inside.then_some(seen)
}

/// The part of the ray from `origin` along `direction`, `length` long
/// (None: for ever), seen in the image: its points in front of the eye
/// whose image point is in the image. The image coordinates of the ray's
/// points are homogeneous and linear in its t, q(t) = a + t b, so each
/// edge of the image cuts t at one value (Liang-Barsky's clipping).
fn image_segment(
    camera: &Camera,
    origin: Vec3,
    direction: Vec3,
    length: Option<f64>,
) -> Option<ImageSegment> {
    let a = camera.image_homogeneous((origin - camera.eye).as_dvec3());
    let b = camera.image_homogeneous(direction.as_dvec3());
    let (w, h) = (f64::from(camera.width), f64::from(camera.height));
    // Each constraint c0 + t c1 >= 0: in front of the eye, then x >= 0,
    // x <= w, y >= 0, y <= h (times the positive q.z).
    let near = 1e-9 * a.z.abs().max(b.z.abs()).max(1e-30);
    let constraints = [
        (a.z - near, b.z),
        (a.x, b.x),
        (w * a.z - a.x, w * b.z - b.x),
        (a.y, b.y),
        (h * a.z - a.y, h * b.z - b.y),
    ];
    let end = length.unwrap_or(f64::INFINITY);
    let (mut lo, mut hi) = (0.0f64, end);
    for (c0, c1) in constraints {
        if c1 == 0.0 {
            if c0 < 0.0 {
                return None;
            }
            continue;
        }
        let t = -c0 / c1;
        if c1 > 0.0 {
            lo = lo.max(t);
        } else {
            hi = hi.min(t);
        }
    }
    if lo > hi {
        return None;
    }
    let at = |t: f64| -> DVec2 {
        let q = if t.is_infinite() { b } else { a + t * b };
        DVec2::new(q.x / q.z, q.y / q.z)
    };
    let (from, to) = (at(lo), at(hi));
    let leaves = hi < end;
    // A whole ray's vanishing point is where it heads, not where it ends.
    let end_seen = (!leaves && length.is_some()).then_some(to);
    Some(ImageSegment {
        from,
        to,
        enters: lo > 0.0,
        leaves,
        end_seen,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera::new(
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::ZERO,
            Vec3::Y,
            50.0,
            500,
            400,
        )
    }

    #[test]
    fn a_segment_in_view_is_seen_whole_from_end_to_end() {
        let cam = camera();
        let (p, q) = (Vec3::new(-1.0, 0.5, 0.0), Vec3::new(1.5, -1.0, -2.0));
        let dir = (q - p).normalize();
        let length = f64::from((q - p).length());
        let s = image_segment(&cam, p, dir, Some(length)).unwrap();
        let near = |a: DVec2, b: DVec2| (a - b).length() < 1e-3;
        assert!(near(s.from, cam.seen_at(p).unwrap()), "{s:?}");
        assert!(near(s.to, cam.seen_at(q).unwrap()), "{s:?}");
        assert!(!s.enters && !s.leaves);
        assert_eq!(s.end_seen, Some(s.to));
    }

    #[test]
    fn a_segment_out_of_the_image_is_cut_at_its_edge() {
        let cam = camera();
        // From the middle of the view to far off on the left (+x is on the
        // image's left in the lab's camera).
        let (p, q) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(50.0, 0.0, 0.0));
        let length = f64::from((q - p).length());
        let s = image_segment(&cam, p, Vec3::X, Some(length)).unwrap();
        assert!((s.from - DVec2::new(250.0, 200.0)).length() < 1e-3, "{s:?}");
        assert!(
            s.to.x.abs() < 1e-6 && (s.to.y - 200.0).abs() < 1e-3,
            "{s:?}"
        );
        assert!(s.leaves && !s.enters && s.end_seen.is_none());
    }

    #[test]
    fn a_ray_for_ever_ends_at_its_vanishing_point_and_behind_the_eye_is_not_seen() {
        let cam = camera();
        let dir = Vec3::new(0.1, 0.05, -1.0).normalize();
        let s = image_segment(&cam, Vec3::new(0.0, 0.0, 0.0), dir, None).unwrap();
        // Seen through a point one unit along it from the eye (in f32, so
        // to about 1e-4 of a pixel).
        let vanishing = cam.seen_at(cam.eye + dir).unwrap();
        assert!((s.to - vanishing).length() < 1e-3, "{s:?}");
        assert!(!s.leaves && s.end_seen.is_none());
        // Toward the eye and past it: cut where it passes the eye's plane,
        // which is out of the image.
        let back = image_segment(&cam, Vec3::new(0.0, 0.0, 0.0), Vec3::Z, None).unwrap();
        assert!(back.leaves, "{back:?}");
        assert!(image_segment(&cam, Vec3::new(0.0, 0.0, 12.0), Vec3::Z, None).is_none());
    }
}
