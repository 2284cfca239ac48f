//! The scene as the core prepared it, for the playground's 3D view beside
//! an explained pixel: each object of the file as its own spheres and
//! triangles (a plane cut to a square round the scene's bounds), its
//! colour, and the camera with its image plane and the clicked pixel on
//! it. No second scene reader: these are the shapes the rays were traced
//! against.

use glam::Vec3;
use serde::Serialize;
use tracer_core::geometry::Shape;
use tracer_core::material::Material;
use tracer_core::names::Names;
use tracer_core::Scene;

/// At most this many triangles are sent (a mesh of millions would make a
/// page's JSON of hundreds of megabytes); the rest are counted.
pub const MAX_TRIANGLES: usize = 200_000;

/// What the 3D view draws.
#[derive(Debug, Clone, Serialize)]
pub struct SceneView {
    /// One per object of the file's `objects` that made shapes.
    pub objects: Vec<ViewObject>,
    /// Triangles past [`MAX_TRIANGLES`], not sent.
    pub left_out: usize,
    pub camera: ViewCamera,
    /// The box of the finite shapes and the eye, [min, max].
    pub bounds: [Vec3; 2],
}

/// One object of the file, as its shapes.
#[derive(Debug, Clone, Serialize)]
pub struct ViewObject {
    /// As the explanation names it (`objects[2]`).
    pub name: String,
    /// Its material's diffuse colour plus ambient (the lab's), for the view.
    pub colour: Vec3,
    pub glass: bool,
    /// Centre and radius of each sphere.
    pub spheres: Vec<(Vec3, f32)>,
    pub triangles: Vec<[Vec3; 3]>,
}

/// The camera: its eye, the image plane's corners (top-left, top-right,
/// bottom-right, bottom-left as the image is seen) at a distance that
/// suits the scene's size, and the clicked pixel's centre on that plane.
#[derive(Debug, Clone, Serialize)]
pub struct ViewCamera {
    pub eye: Vec3,
    pub corners: [Vec3; 4],
    pub pixel: Vec3,
}

/// The view of `scene`, named by `names`, pixel `pixel` clicked.
pub fn scene_view(scene: &Scene, names: &Names, pixel: (u32, u32)) -> SceneView {
    let camera = scene.camera();
    let (lo, hi) = scene.bounds().unwrap_or((camera.eye, camera.eye));
    let (lo, hi) = (lo.min(camera.eye), hi.max(camera.eye));
    let size = (hi - lo).length().max(1e-3);
    let mut objects: Vec<ViewObject> = Vec::new();
    let mut sent = 0;
    let mut left_out = 0;
    for (k, object) in scene.objects().iter().enumerate() {
        let name = file_object(&names.object(k));
        if objects.last().is_none_or(|o| o.name != name) {
            let material = scene.material(object.material);
            let surface = material.surface();
            objects.push(ViewObject {
                name,
                colour: (surface.diffuse + surface.ambient).min(Vec3::ONE),
                glass: matches!(material.lab(), Material::Glass(_)),
                spheres: Vec::new(),
                triangles: Vec::new(),
            });
        }
        let view = objects.last_mut().expect("just pushed");
        let mut add = |t: [Vec3; 3]| {
            if sent < MAX_TRIANGLES {
                view.triangles.push(t);
                sent += 1;
            } else {
                left_out += 1;
            }
        };
        match &object.shape {
            Shape::Sphere(s) => view.spheres.push((s.center, s.radius)),
            Shape::Triangle(t) => add([t.v0, t.v1, t.v2]),
            Shape::Plane(p) => {
                // A square on the plane round the scene's centre, a little
                // wider than the scene: enough to see it is a floor or a
                // wall without hiding the rest.
                let centre = (lo + hi) / 2.0;
                let on = centre - p.normal * (centre - p.point).dot(p.normal);
                let half = 0.6 * size;
                let (u, v) = (p.u_axis.normalize() * half, p.v_axis.normalize() * half);
                let c = [on - u - v, on + u - v, on + u + v, on - u + v];
                add([c[0], c[1], c[2]]);
                add([c[0], c[2], c[3]]);
            }
            Shape::Instance(i) => {
                for o in i.mesh().objects() {
                    if let Shape::Triangle(t) = &o.shape {
                        add(i.world_triangle(t));
                    }
                }
            }
        }
    }
    SceneView {
        objects,
        left_out,
        camera: view_camera(scene, size, pixel),
        bounds: [lo, hi],
    }
}

/// The file's object a shape's name is of: `objects[5]` of `objects[5]
/// triangle 3 of 12`.
fn file_object(name: &str) -> String {
    match name.find(']') {
        Some(end) => name[..=end].to_string(),
        None => name.to_string(),
    }
}

fn view_camera(scene: &Scene, size: f32, (x, y): (u32, u32)) -> ViewCamera {
    let camera = scene.camera();
    let forward = camera.view_direction();
    // The image plane a tenth of the scene's size in front of the eye.
    let distance = size / 10.0;
    let at = |fx: f32, fy: f32| {
        let dir = camera.ray(fx, fy).dir();
        camera.eye + dir * (distance / dir.dot(forward))
    };
    let (w, h) = (camera.width as f32, camera.height as f32);
    ViewCamera {
        eye: camera.eye,
        corners: [at(0.0, 0.0), at(w, 0.0), at(w, h), at(0.0, h)],
        pixel: at(x as f32 + 0.5, y as f32 + 0.5),
    }
}
