//! A scene file as POV-Ray 3.7 SDL: the scene the tracer renders, for
//! timing POV-Ray on the same work. Covers what the bench scenes use: the
//! camera, point lights, spheres, triangles, meshes (as `mesh2`), planes,
//! boxes, quads (as the tracer's two triangles) and the lab's Blinn-Phong
//! materials with mirror reflection.
//!
//! The lab's shading, term by term, in POV-Ray's words (`tracer-core`'s
//! `integrate/whitted.rs` is the reference):
//! - diffuse `kd * cos * light`: `pigment` is the diffuse colour divided
//!   by its largest channel, `diffuse` that channel;
//! - specular `ks * cos^shininess * light` (Blinn's half vector): POV-Ray's
//!   `specular` (the largest channel of `ks`) with `roughness 1/shininess`;
//! - ambient `ka * light`, once per light, never shadowed: `ambient_light`
//!   is the sum of the lights' colours and the finish's `ambient` is `ka`
//!   divided by the pigment (POV-Ray multiplies them);
//! - a mirror adds `reflectance * reflected` to the local colour:
//!   `reflection { reflectance }`; `max_trace_level` is the lab's
//!   `max_depth` + 1 (the primary ray is the first level) and `adc_bailout`
//!   its `min_energy`.
//!
//! Textures, saturation and gamma are left out (they cost POV-Ray nothing
//! worth timing). Like the peers' own files (`mesh2pov.py`, the lab's
//! `reflectance2.pov`: `right -x*W/H` with `look_at`), the picture is the
//! mirror image of the lab's: the lab's camera puts world +x on the
//! image's left, POV-Ray's here on its right. The rays are the same.

use scene_format::{
    Material, MaterialRef, MeshData, Object, SceneFile, ShapeRef, Transform, TransformStep,
};
use std::collections::HashMap;
use std::fmt::Write;

/// Writes `scene` (its meshes loaded) as a POV-Ray 3.7 scene.
pub fn pov_scene(scene: &SceneFile) -> String {
    let mut pov = String::new();
    // Writing to a String cannot fail: the results of write! are ignored.
    let _ = writeln!(
        pov,
        "// Written by `cargo xtask bench` from a scene file; objects: {}.",
        scene.objects.len()
    );
    pov.push_str("#version 3.7;\n");
    let r = &scene.render;
    let ambient_light = scene.lights.iter().fold([0.0f32; 3], |sum, l| {
        [
            sum[0] + l.color[0],
            sum[1] + l.color[1],
            sum[2] + l.color[2],
        ]
    });
    let _ = writeln!(
        pov,
        "global_settings {{ assumed_gamma 1.0 max_trace_level {} adc_bailout {} ambient_light rgb {} }}",
        r.max_depth() + 1,
        num(r.min_energy),
        vec3(ambient_light)
    );
    let _ = writeln!(pov, "background {{ rgb {} }}", vec3(r.background));
    pov.push_str(&camera(&scene.camera));
    pov.push('\n');
    for light in &scene.lights {
        // The bench's scenes have point lights; a spot or sun is left out.
        let Some(position) = light.position.filter(|_| light.direction.is_none()) else {
            let _ = writeln!(pov, "// a spot or directional light left out");
            continue;
        };
        let _ = writeln!(
            pov,
            "light_source {{ {} color rgb {} }}",
            vec3(position),
            vec3(light.color)
        );
    }
    for object in &scene.objects {
        write_object(&mut pov, scene, object);
    }
    pov
}

/// The lab's camera as explicit POV-Ray vectors: `direction` the unit view
/// direction, `right` across the image (2 tan(fov/2) long, so that the
/// horizontal field of view is `fov`), `up` up the image (`right`'s length
/// times height / width).
fn camera(c: &scene_format::Camera) -> String {
    let v = |a: [f32; 3]| a.map(f64::from);
    let (eye, look_at, up) = (v(c.eye), v(c.look_at), v(c.up));
    let look = sub(look_at, eye);
    // The lab's image right (its u: world +x on the left for the default
    // camera) and image up.
    let lab_right = normalize(cross(up, look));
    let image_up = normalize(cross(look, lab_right));
    let width = 2.0 * (f64::from(c.fov).to_radians() / 2.0).tan();
    let height = width * f64::from(c.height) / f64::from(c.width);
    // Mirrored, as the peers' files are (see the module's comment).
    let right = scale(lab_right, -width);
    let f = |a: [f64; 3]| vec3(a.map(|x| x as f32));
    format!(
        "camera {{ perspective location {} direction {} right {} up {} }}",
        f(eye),
        f(normalize(look)),
        f(right),
        f(scale(image_up, height))
    )
}

fn write_object(pov: &mut String, scene: &SceneFile, object: &Object) {
    let mut look = appearance(&material(scene, object));
    if let Some(t) = &object.transform {
        look += &pov_transform(t);
    }
    if let Some(texture) = object.texture.as_ref() {
        let _ = writeln!(pov, "// texture {texture:?} left out");
    }
    for shape in object.shapes() {
        match shape {
            ShapeRef::Sphere(s) => {
                let _ = writeln!(
                    pov,
                    "sphere {{ {}, {} {look} }}",
                    vec3(s.center),
                    num(s.radius)
                );
            }
            ShapeRef::Triangle([a, b, c]) => {
                let _ = writeln!(
                    pov,
                    "triangle {{ {}, {}, {} {look} }}",
                    vec3(*a),
                    vec3(*b),
                    vec3(*c)
                );
            }
            ShapeRef::Plane(p) => {
                // POV-Ray's plane is `n . P = d` with n taken as given:
                // the unit normal, and d the point's distance along it.
                let n = normalize(p.normal.map(f64::from));
                let d: f64 = (0..3).map(|a| n[a] * f64::from(p.point[a])).sum();
                let n = vec3(n.map(|x| x as f32));
                let _ = writeln!(pov, "plane {{ {n}, {} {look} }}", num(d as f32));
            }
            ShapeRef::Box(b) => {
                let _ = writeln!(pov, "box {{ {}, {} {look} }}", vec3(b.min), vec3(b.max));
            }
            ShapeRef::Quad(q) => {
                // The tracer's two triangles (`prepare.rs`), the same surface.
                let at = |s: f32, t: f32| {
                    let p: [f32; 3] =
                        std::array::from_fn(|a| q.corner[a] + s * q.edge_u[a] + t * q.edge_v[a]);
                    vec3(p)
                };
                let (c, u, v, far) = (at(0.0, 0.0), at(1.0, 0.0), at(0.0, 1.0), at(1.0, 1.0));
                let _ = writeln!(pov, "triangle {{ {c}, {u}, {v} {look} }}");
                let _ = writeln!(pov, "triangle {{ {far}, {v}, {u} {look} }}");
            }
            ShapeRef::Mesh(m) => match &m.data {
                Some(data) => write_mesh2(pov, data, &look),
                None => {
                    let _ = writeln!(pov, "// mesh {:?} not loaded: left out", m.obj);
                }
            },
            ShapeRef::Gltf(g) => {
                let _ = writeln!(pov, "// glTF model {:?} left out", g.file);
            }
        }
    }
}

/// A mesh as `mesh2`: each distinct vertex once, faces by index, in the
/// file's vertex order; `look` ends with the object's transform.
fn write_mesh2(pov: &mut String, data: &MeshData, look: &str) {
    let mut index: HashMap<[u32; 3], usize> = HashMap::new();
    let mut vertices = Vec::new();
    let faces: Vec<[usize; 3]> = data
        .triangles
        .iter()
        .map(|t| {
            t.map(|p| {
                *index.entry(p.map(f32::to_bits)).or_insert_with(|| {
                    vertices.push(p);
                    vertices.len() - 1
                })
            })
        })
        .collect();
    let _ = writeln!(pov, "mesh2 {{\n  vertex_vectors {{ {},", vertices.len());
    for (i, p) in vertices.iter().enumerate() {
        let comma = if i + 1 < vertices.len() { "," } else { "" };
        let _ = writeln!(pov, "    {}{comma}", vec3(*p));
    }
    let _ = writeln!(pov, "  }}\n  face_indices {{ {},", faces.len());
    for (i, [a, b, c]) in faces.iter().enumerate() {
        let comma = if i + 1 < faces.len() { "," } else { "" };
        let _ = writeln!(pov, "    <{a}, {b}, {c}>{comma}");
    }
    let _ = writeln!(pov, "  }}\n  {look}");
    pov.push_str("}\n");
}

/// An object's transform as POV-Ray's statements, which act in the order
/// written: the list's steps from the last (the one acting first). POV-Ray's
/// `rotate <x, y, z>` turns about x, then y, then z, as the tracer's does.
fn pov_transform(t: &Transform) -> String {
    let mut out = String::new();
    for step in t.steps().iter().rev() {
        let _ = match *step {
            TransformStep::Translate(v) => write!(out, " translate {}", vec3(v)),
            TransformStep::Rotate(v) => write!(out, " rotate {}", vec3(v)),
            TransformStep::Scale(s) => write!(out, " scale {}", vec3(s.per_axis())),
        };
    }
    out
}

/// The object's material, as the tracer resolves it (validation has made
/// sure a named one exists); without one, the tracer's matte grey.
fn material(scene: &SceneFile, object: &Object) -> Material {
    let grey = || Material {
        ambient: [0.1; 3],
        diffuse: [0.7; 3],
        ..Material::default()
    };
    match &object.material {
        Some(MaterialRef::Inline(m)) => m.clone(),
        Some(MaterialRef::Named(name)) => scene.materials.get(name).cloned().unwrap_or_else(grey),
        None => grey(),
    }
}

/// `pigment { ... } finish { ... }` for a lab material (see the module's
/// comment for the translation).
fn appearance(m: &Material) -> String {
    let largest = |c: [f32; 3]| c.iter().copied().fold(0.0f32, f32::max);
    let kd = largest(m.diffuse);
    // The pigment's hue: the diffuse colour's, else the ambient's, else white.
    let base = if kd > 0.0 { m.diffuse } else { m.ambient };
    let pigment = match largest(base) {
        l if l > 0.0 => base.map(|c| c / l),
        _ => [1.0; 3],
    };
    // An ambient channel where the pigment has none cannot be written.
    let ambient = [0, 1, 2].map(|i| match pigment[i] {
        p if p > 0.0 => m.ambient[i] / p,
        _ => 0.0,
    });
    let mut finish = format!("ambient rgb {} diffuse {}", vec3(ambient), num(kd));
    let ks = largest(m.specular);
    if ks > 0.0 {
        // POV-Ray's roughness lies in (0, 1].
        let roughness = if m.shininess > 1.0 {
            1.0 / m.shininess
        } else {
            1.0
        };
        let _ = write!(finish, " specular {} roughness {}", num(ks), num(roughness));
    }
    if m.reflectance > 0.0 {
        let _ = write!(finish, " reflection {{ {} }}", num(m.reflectance));
    }
    if let Some(texture) = &m.texture {
        let _ = write!(finish, " /* texture {texture:?} left out */");
    }
    format!("pigment {{ rgb {} }} finish {{ {finish} }}", vec3(pigment))
}

/// A number as POV-Ray reads it: the shortest text that reads back as the
/// same f32, and 0 for -0.
fn num(x: f32) -> String {
    if x == 0.0 {
        "0".to_string()
    } else {
        x.to_string()
    }
}

fn vec3([x, y, z]: [f32; 3]) -> String {
    format!("<{}, {}, {}>", num(x), num(y), num(z))
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    a.map(|x| x * s)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let length = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    scale(a, 1.0 / length)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// Worked out by hand: the eye on +z looking at the origin, fov 90
    /// (tan 45 = 1: the image plane at distance 1 is 2 wide), 200x100.
    const TINY: &str = r#"
        [camera]
        eye = [0, 0, 5]
        look_at = [0, 0, 0]
        fov = 90
        width = 200
        height = 100

        [[lights]]
        position = [1, 2, 3]
        color = [0.5, 0.25, 0.5]

        [[lights]]
        position = [-1, 2, 3]
        color = [0.5, 0.5, 0.5]

        [materials.red]
        ambient = [0.1, 0, 0]
        diffuse = [0.5, 0, 0]
        specular = [0.7, 0.7, 0.7]
        shininess = 20
        reflectance = 0.25

        [[objects]]
        sphere = { center = [1, -2, 0.5], radius = 0.75 }
        material = "red"

        [[objects]]
        triangle = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]

        [[objects]]
        plane = { point = [0, -1, 0], normal = [0, 2, 0] }

        [[objects]]
        box = { min = [-1, -1, -1], max = [1, 0.5, 2] }

        [[objects]]
        quad = { corner = [0, 0, -3], edge_u = [2, 0, 0], edge_v = [0, 1, 0] }
    "#;

    fn tiny() -> String {
        let scene = scene_format::load_str(TINY, scene_format::Format::Toml, Path::new("tiny"))
            .expect("the tiny scene loads");
        pov_scene(&scene)
    }

    #[test]
    fn plane_box_and_quad_as_pov_ray_shapes() {
        let pov = tiny();
        // y = -1 facing +y: unit normal, distance -1 along it.
        assert!(pov.contains("plane { <0, 1, 0>, -1 pigment"), "{pov}");
        assert!(
            pov.contains("box { <-1, -1, -1>, <1, 0.5, 2> pigment"),
            "{pov}"
        );
        assert!(pov.contains("triangle { <0, 0, -3>, <2, 0, -3>, <0, 1, -3> pigment"));
        assert!(pov.contains("triangle { <2, 1, -3>, <0, 1, -3>, <2, 0, -3> pigment"));
    }

    #[test]
    fn camera_vectors_match_the_lab_camera_mirrored_as_the_peers_files() {
        // Looking down -z with up +y, the lab's image right is world -x (+x
        // on the left); POV-Ray's right is its mirror, +x, 2 long; up is +y,
        // 2 * 100/200 = 1 long; direction the unit view direction.
        let pov = tiny();
        assert!(
            pov.contains(
                "camera { perspective location <0, 0, 5> direction <0, 0, -1> \
                 right <2, 0, 0> up <0, 1, 0> }\n"
            ),
            "{pov}"
        );
    }

    #[test]
    fn lights_ambient_and_depth_are_global_settings() {
        let pov = tiny();
        // Ambient once per light: the lights' sum; max_depth 1 (default) + 1.
        assert!(pov.contains(
            "global_settings { assumed_gamma 1.0 max_trace_level 2 adc_bailout 0.01 \
             ambient_light rgb <1, 0.75, 1> }\n"
        ));
        assert!(pov.contains("background { rgb <0, 0, 0> }\n"));
        assert!(pov.contains("light_source { <1, 2, 3> color rgb <0.5, 0.25, 0.5> }\n"));
    }

    #[test]
    fn sphere_and_triangle_with_their_finishes() {
        let pov = tiny();
        // Diffuse (0.5, 0, 0): pigment red, diffuse 0.5; ambient 0.1 / 1;
        // specular 0.7, roughness 1/20; a quarter mirror.
        assert!(
            pov.contains(
                "sphere { <1, -2, 0.5>, 0.75 pigment { rgb <1, 0, 0> } finish { ambient rgb \
                 <0.1, 0, 0> diffuse 0.5 specular 0.7 roughness 0.05 reflection { 0.25 } } }\n"
            ),
            "{pov}"
        );
        // No material: the tracer's matte grey (ambient 0.1, diffuse 0.7).
        assert!(pov.contains(
            "triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0> pigment { rgb <1, 1, 1> } \
             finish { ambient rgb <0.1, 0.1, 0.1> diffuse 0.7 } }\n"
        ));
    }

    #[test]
    fn a_mesh_shares_its_vertices() {
        let data = MeshData {
            triangles: vec![
                [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            ],
            ..MeshData::default()
        };
        let mut pov = String::new();
        write_mesh2(&mut pov, &data, "LOOK");
        assert_eq!(
            pov,
            "mesh2 {\n  vertex_vectors { 4,\n    <0, 0, 0>,\n    <1, 0, 0>,\n    <0, 1, 0>,\n    \
             <1, 1, 0>\n  }\n  face_indices { 2,\n    <0, 1, 2>,\n    <1, 3, 2>\n  }\n  LOOK\n}\n"
        );
    }
}
