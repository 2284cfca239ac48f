//! Checks every value of a parsed scene, so the renderer can trust it.

use crate::error::Diagnostic;
use crate::model::*;

/// Largest image side accepted, and largest pixel count (2^28).
pub const MAX_IMAGE_SIDE: u32 = 16384;
pub const MAX_IMAGE_PIXELS: u64 = 1 << 28;
/// Largest `render.max_depth`: deeper mirror recursion only costs time.
pub const MAX_DEPTH_CAP: u32 = 64;

/// All problems found in `scene`, in file order.
pub fn validate(scene: &SceneFile) -> Vec<Diagnostic> {
    let mut v = Validator::default();
    v.camera(&scene.camera);
    v.render(&scene.render);
    for (i, light) in scene.lights.iter().enumerate() {
        let path = format!("lights[{i}]");
        v.finite_vec(&format!("{path}.position"), light.position);
        v.color(&format!("{path}.color"), light.color);
    }
    for (name, material) in &scene.materials {
        v.material(&format!("materials.{name}"), material);
    }
    for (i, object) in scene.objects.iter().enumerate() {
        v.object(&format!("objects[{i}]"), object, scene);
    }
    v.diagnostics
}

#[derive(Default)]
struct Validator {
    diagnostics: Vec<Diagnostic>,
}

impl Validator {
    fn error(&mut self, path: &str, message: impl Into<String>) {
        self.diagnostics.push(Diagnostic::new(path, message));
    }

    fn finite(&mut self, path: &str, x: f32) -> bool {
        if !x.is_finite() {
            self.error(path, format!("expected a finite number, found {x}"));
        }
        x.is_finite()
    }

    fn finite_vec(&mut self, path: &str, v: Vec3) -> bool {
        if v.iter().all(|x| x.is_finite()) {
            return true;
        }
        self.error(path, format!("expected finite numbers, found {v:?}"));
        false
    }

    fn color(&mut self, path: &str, c: Color) {
        if self.finite_vec(path, c) && c.iter().any(|&x| x < 0.0) {
            self.error(
                path,
                format!("expected a colour with channels >= 0, found {c:?}"),
            );
        }
    }

    fn camera(&mut self, c: &Camera) {
        let ok = self.finite_vec("camera.eye", c.eye)
            & self.finite_vec("camera.look_at", c.look_at)
            & self.finite_vec("camera.up", c.up);
        if self.finite("camera.fov", c.fov) && !(c.fov > 0.0 && c.fov < 180.0) {
            self.error(
                "camera.fov",
                format!(
                    "expected degrees between 0 and 180 (exclusive), found {}",
                    c.fov
                ),
            );
        }
        self.image_size(c.width, c.height);
        if !ok {
            return;
        }
        let view = sub(c.look_at, c.eye);
        if length(view) == 0.0 {
            self.error(
                "camera.look_at",
                "expected a point other than `camera.eye`; the camera would look nowhere",
            );
        } else if length(c.up) == 0.0 {
            self.error("camera.up", "expected a non-zero vector");
        } else if length(cross(c.up, view)) <= 1e-6 * length(c.up) * length(view) {
            self.error(
                "camera.up",
                "expected a vector not parallel to the view direction (look_at - eye)",
            );
        }
    }

    fn image_size(&mut self, width: u32, height: u32) {
        for (key, side) in [("camera.width", width), ("camera.height", height)] {
            if side == 0 || side > MAX_IMAGE_SIDE {
                self.error(
                    key,
                    format!("expected 1 to {MAX_IMAGE_SIDE} pixels, found {side}"),
                );
            }
        }
        if u64::from(width) * u64::from(height) > MAX_IMAGE_PIXELS {
            self.error(
                "camera",
                format!(
                    "expected at most {MAX_IMAGE_PIXELS} pixels (2^28), found {width}x{height}"
                ),
            );
        }
    }

    fn render(&mut self, r: &RenderSettings) {
        if r.max_depth > MAX_DEPTH_CAP {
            self.error(
                "render.max_depth",
                format!("expected at most {MAX_DEPTH_CAP}, found {}", r.max_depth),
            );
        }
        if self.finite("render.min_energy", r.min_energy) && r.min_energy < 0.0 {
            self.error(
                "render.min_energy",
                format!("expected a number >= 0, found {}", r.min_energy),
            );
        }
        self.color("render.background", r.background);
        if self.finite("render.gamma", r.gamma) && r.gamma <= 0.0 {
            self.error(
                "render.gamma",
                format!("expected a number > 0, found {}", r.gamma),
            );
        }
    }

    fn material(&mut self, path: &str, m: &Material) {
        self.color(&format!("{path}.ambient"), m.ambient);
        self.color(&format!("{path}.diffuse"), m.diffuse);
        self.color(&format!("{path}.specular"), m.specular);
        let shin = format!("{path}.shininess");
        if self.finite(&shin, m.shininess) && m.shininess < 0.0 {
            self.error(
                &shin,
                format!("expected a number >= 0, found {}", m.shininess),
            );
        }
        let refl = format!("{path}.reflectance");
        if self.finite(&refl, m.reflectance) && !(0.0..=1.0).contains(&m.reflectance) {
            self.error(
                &refl,
                format!("expected a number from 0 to 1, found {}", m.reflectance),
            );
        }
        if let Some(t) = &m.texture {
            self.texture_name(&format!("{path}.texture"), t);
        }
    }

    fn texture_name(&mut self, path: &str, name: &str) {
        if !TEXTURE_NAMES.contains(&name) {
            self.error(
                path,
                format!(
                    "unknown texture `{name}`; expected one of: {}",
                    TEXTURE_NAMES.join(", ")
                ),
            );
        }
    }

    fn object(&mut self, path: &str, o: &Object, scene: &SceneFile) {
        match o.shapes().as_slice() {
            [] => self.error(
                path,
                "expected a shape: one of `sphere`, `triangle`, `mesh`",
            ),
            [shape] => self.shape(path, shape),
            _ => self.error(
                path,
                "expected exactly one shape per object; found several of `sphere`, `triangle`, `mesh`",
            ),
        }
        if let Some(t) = &o.transform {
            self.transform(&format!("{path}.transform"), t, o.mesh.is_some());
        }
        match &o.material {
            Some(MaterialRef::Named(name)) if !scene.materials.contains_key(name) => {
                let known: Vec<&str> = scene.materials.keys().map(String::as_str).collect();
                let expected = if known.is_empty() {
                    "no [materials] are defined".to_string()
                } else {
                    format!("expected one of: {}", known.join(", "))
                };
                self.error(
                    &format!("{path}.material"),
                    format!("unknown material `{name}`; {expected}"),
                );
            }
            Some(MaterialRef::Inline(m)) => self.material(&format!("{path}.material"), m),
            _ => {}
        }
        if let Some(t) = &o.texture {
            self.texture_name(&format!("{path}.texture"), t);
        }
    }

    fn transform(&mut self, path: &str, t: &Transform, on_mesh: bool) {
        if !on_mesh {
            self.error(path, "expected `transform` only on a `mesh` object");
        }
        self.finite_vec(&format!("{path}.translate"), t.translate);
        self.finite_vec(&format!("{path}.rotate"), t.rotate);
        let scale = format!("{path}.scale");
        let s = t.scale.per_axis();
        if self.finite_vec(&scale, s) && s.contains(&0.0) {
            self.error(&scale, format!("expected non-zero factors, found {s:?}"));
        }
    }

    fn shape(&mut self, path: &str, shape: &ShapeRef) {
        match shape {
            ShapeRef::Mesh(m) => {
                if m.obj.trim().is_empty() {
                    self.error(
                        &format!("{path}.mesh.obj"),
                        "expected the path of an OBJ file",
                    );
                }
            }
            ShapeRef::Sphere(s) => {
                self.finite_vec(&format!("{path}.sphere.center"), s.center);
                let r = format!("{path}.sphere.radius");
                if self.finite(&r, s.radius) && s.radius <= 0.0 {
                    self.error(&r, format!("expected a radius > 0, found {}", s.radius));
                }
            }
            ShapeRef::Triangle(t) => {
                let p = format!("{path}.triangle");
                if t.iter().all(|v| self.finite_vec(&p, *v)) {
                    let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
                    if length(n) == 0.0 {
                        self.error(&p, "expected three vertices not on one line; the triangle is degenerate (zero area)");
                    }
                }
            }
        }
    }
}

fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn length(v: Vec3) -> f32 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}
