//! What is found about a scene after it has loaded: errors found by its
//! users (the tracer's limits), located like validation's, and warnings
//! about likely mistakes that still make an image.

use crate::error::SceneError;
use crate::locate::locate_all;
use crate::model::{Integrator, RenderSettings, SceneFile, ShapeRef, Vec3};
use crate::obj::mesh_warnings;
use crate::{Diagnostic, Format, KeyPath};
use std::path::Path;

/// Diagnostics found after loading, as a located error of `file`.
pub fn invalid(
    file: &Path,
    text: &str,
    format: Format,
    diagnostics: Vec<Diagnostic>,
) -> SceneError {
    SceneError::Invalid {
        file: file.to_path_buf(),
        text: text.to_string(),
        diagnostics: locate_all(text, format, diagnostics),
    }
}

/// Likely mistakes in a valid scene: each still renders, but probably not
/// what was meant. The meshes' warnings come first.
pub fn warnings(scene: &SceneFile) -> Vec<Diagnostic> {
    let mut warnings = mesh_warnings(scene);
    warnings.extend(crate::gltf::warnings(scene));
    let path_mode = scene.render.integrator == Integrator::Path;
    if path_mode {
        let dark = scene.render.background == [0.0; 3] && scene.environment.is_none();
        if scene.lights.is_empty() && !has_gltf_lights(scene) && !emits(scene) && dark {
            warnings.push(Diagnostic::new(
                "lights",
                "no lights, no emissive material and a black background: nothing gives off light, so the image is black; add [[lights]] or a material with `emission`",
            ));
        }
    } else if scene.lights.is_empty() && !has_gltf_lights(scene) {
        // The lab adds ambient once per light: no light, no light at all.
        let message = if emits(scene) {
            "no lights: in Whitted mode an emissive material is seen but lights nothing else, so every other object renders black; path mode (integrator = \"path\") makes it a light"
        } else {
            "no lights: ambient is added once per light, so every object renders black"
        };
        warnings.push(Diagnostic::new("lights", message));
    }
    if path_mode && scene.render.light_samples != RenderSettings::default().light_samples {
        warnings.push(Diagnostic::new(
            "render.light_samples",
            "not read in path mode: a sphere light is an emitter there, sampled once per bounce; `samples` sets the paths per pixel",
        ));
    }
    units(&mut warnings, scene);
    if scene.objects.is_empty() {
        warnings.push(Diagnostic::new(
            "objects",
            "no objects: the image is the background only",
        ));
    } else if !scene.objects.iter().any(|o| in_front(scene, o)) {
        warnings.push(Diagnostic::new(
            "camera.look_at",
            "nothing is in front of the camera: every object is behind the eye",
        ));
    }
    let root = KeyPath::root();
    let mut materials: Vec<(KeyPath, &crate::Material)> = scene
        .materials
        .iter()
        .map(|(name, m)| (root.key("materials").key(name), m))
        .collect();
    for (i, o) in scene.objects.iter().enumerate() {
        if let Some(crate::MaterialRef::Inline(m)) = &o.material {
            materials.push((root.key("objects").index(i).key("material"), m));
        }
    }
    if path_mode {
        let lab: Vec<(KeyPath, &crate::Material)> = materials
            .iter()
            .filter(|(_, m)| !m.is_physical())
            .map(|(p, m)| (p.clone(), *m))
            .collect();
        path_materials(&mut warnings, &lab);
    }
    environment_shape(&mut warnings, scene);
    if scene.environment.is_some() && scene.render.background != [0.0; 3] {
        warnings.push(Diagnostic::new(
            "render.background",
            "not used: with an [environment], rays that leave the scene see the environment instead",
        ));
    }
    for (path, m) in &materials {
        over_one(&mut warnings, path, m);
        unseen_texture(&mut warnings, path, m);
        if m.fresnel && m.reflectance > 0.0 {
            warnings.push(Diagnostic::new(
                path.key("reflectance"),
                "ignored with `fresnel = true`: the Fresnel equations give the reflection",
            ));
        }
    }
    open_glass(&mut warnings, scene);
    alpha_cutoffs(&mut warnings, scene);
    if path_mode {
        emitters_facing_away(&mut warnings, scene);
    }
    let transparent = materials.iter().any(|(_, m)| m.transmittance > 0.0);
    if transparent && scene.render.max_depth() < 2 {
        warnings.push(Diagnostic::new(
            "render.max_depth",
            format!(
                "{}: a ray can enter a transparent object but not leave it, so glass looks dark; try max_depth = 8",
                scene.render.max_depth()
            ),
        ));
    }
    if scene.render.time_limit.is_some() && !path_mode {
        warnings.push(Diagnostic::new(
            "render.time_limit",
            "ignored in Whitted mode, which renders in one pass; path mode renders in passes that a time limit can stop",
        ));
    }
    if scene.render.denoise && !path_mode {
        warnings.push(Diagnostic::new(
            "render.denoise",
            "ignored in Whitted mode, whose images have no noise to take out; it is for integrator = \"path\"",
        ));
    }
    if scene.render.path_reuse.is_some_and(|n| n > 1) && !path_mode {
        warnings.push(Diagnostic::new(
            "render.path_reuse",
            "ignored in Whitted mode, whose rays have no bounces to share; it is for integrator = \"path\"",
        ));
    }
    if scene.render.camera_rays.is_some_and(|n| n > 1) && !path_mode {
        warnings.push(Diagnostic::new(
            "render.camera_rays",
            "ignored in Whitted mode, whose samples are each one camera ray; it is for integrator = \"path\"",
        ));
    }
    if scene.render.adaptive == Some(true) && !path_mode {
        warnings.push(Diagnostic::new(
            "render.adaptive",
            "ignored in Whitted mode, whose pixels all take `samples` rays; it is for integrator = \"path\"",
        ));
    }
    if path_mode && scene.render.time_limit.is_some() && scene.render.samples == 1 {
        warnings.push(Diagnostic::new(
            "render.time_limit",
            "has nothing to stop with samples = 1 (the default): 1 sample a pixel is one pass; set `samples` to the most you want (up to 65536), and the limit stops the render sooner",
        ));
    }
    if scene.camera.aperture > 0.0 && scene.render.samples < 16 {
        warnings.push(Diagnostic::new(
            "render.samples",
            format!(
                "{}: with an aperture, the blur is made of samples per pixel; below 16 it is grainy",
                scene.render.samples
            ),
        ));
    }
    warnings
}

/// Values that look written in another unit: a field of view in radians,
/// or the inverse of a display gamma.
fn units(warnings: &mut Vec<Diagnostic>, scene: &SceneFile) {
    let fov = scene.camera.fov;
    if fov <= std::f32::consts::PI {
        let degrees = format!("{:.0}", fov.to_degrees());
        warnings.push(Diagnostic::new(
            "camera.fov",
            format!(
                "{}: `fov` is in degrees, so this is a very narrow view; if it is in radians, write fov = {degrees}",
                short(fov)
            ),
        ));
    }
    let gamma = scene.render.gamma;
    if gamma < 1.0 {
        warnings.push(Diagnostic::new(
            "render.gamma",
            format!(
                "{}: below 1 the image comes out darker than linear; `gamma` is the display's, usually about 2.2 (0.45 is 1 / 2.2)",
                short(gamma)
            ),
        ));
    }
}

/// An environment image that is not twice as wide as it is high: not a
/// latitude-longitude image, so its directions would come out stretched.
fn environment_shape(warnings: &mut Vec<Diagnostic>, scene: &SceneFile) {
    let Some(data) = scene.environment.as_ref().and_then(|e| e.data.as_ref()) else {
        return;
    };
    if u64::from(data.width) != 2 * u64::from(data.height) {
        warnings.push(Diagnostic::new(
            "environment.image",
            format!(
                "{}x{}: a latitude-longitude image is twice as wide as it is high (360 by 180 degrees); this one is read as one anyway, its directions stretched",
                data.width, data.height
            ),
        ));
    }
}

/// Whether some material of the scene gives off light.
fn emits(scene: &SceneFile) -> bool {
    let inline = scene.objects.iter().filter_map(|o| match &o.material {
        Some(crate::MaterialRef::Inline(m)) => Some(m),
        _ => None,
    });
    // A mesh without a material of its own takes its MTL's (`Ke` emits).
    let from_mtl = scene
        .objects
        .iter()
        .filter(|o| o.material.is_none())
        .filter_map(|o| o.mesh.as_ref()?.data.as_ref())
        .flat_map(|data| &data.materials);
    // A glTF model without a material of the scene takes its file's.
    let from_gltf = scene
        .objects
        .iter()
        .filter(|o| o.material.is_none())
        .filter_map(|o| o.gltf.as_ref()?.data.as_ref())
        .flat_map(|data| &data.materials);
    scene
        .materials
        .values()
        .chain(inline)
        .chain(from_mtl)
        .chain(from_gltf)
        .any(crate::Material::is_emissive)
}

/// Whether a glTF model of the scene brings lights of its own.
fn has_gltf_lights(scene: &SceneFile) -> bool {
    scene
        .objects
        .iter()
        .filter_map(|o| o.gltf.as_ref()?.data.as_ref())
        .any(|data| !data.lights.is_empty())
}

/// What the path tracer reads differently from the lab: `ambient`, which
/// stands in for light that really bounces there (one warning, at the first
/// material that has it), and materials that would reflect more light than
/// they receive.
fn path_materials(warnings: &mut Vec<Diagnostic>, materials: &[(KeyPath, &crate::Material)]) {
    if let Some((path, _)) = materials.iter().find(|(_, m)| m.ambient != [0.0; 3]) {
        warnings.push(Diagnostic::new(
            path.key("ambient"),
            "ignored in path mode: ambient stands in for light bounced between objects, which the path tracer computes (this warning is given once)",
        ));
    }
    for (path, m) in materials {
        let sum = albedo_sum(m);
        if sum > 1.0 + 1e-6 {
            let sum = short(sum);
            let terms = if m.fresnel {
                "diffuse + specular + 1 for the Fresnel glass"
            } else {
                "diffuse + specular + reflectance + transmittance"
            };
            warnings.push(Diagnostic::new(
                (*path).clone(),
                format!(
                    "{terms} is {sum} (its largest channel), above 1: it would give back more light than it receives, so path mode scales each by 1/{sum}"
                ),
            ));
        }
    }
}

/// `x` with at most 3 decimals, trailing zeros dropped: 1.4000001 -> 1.4.
fn short(x: f32) -> String {
    let text = format!("{x:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The largest channel of the share of light a material sends back in path
/// mode, before any scaling: its Lambertian, Blinn-Phong, mirror and
/// transmitted shares (the Fresnel split's reflected and transmitted
/// shares add up to at most 1).
pub fn albedo_sum(m: &crate::Material) -> f32 {
    let interface = if m.fresnel {
        1.0
    } else {
        m.reflectance + m.transmittance
    };
    (0..3)
        .map(|c| m.diffuse[c] + m.specular[c] + interface)
        .fold(0.0, f32::max)
}

/// A one-sided emitter (a quad or a triangle) whose front side faces away
/// from both the camera and the middle of the scene: its light goes
/// nowhere the image shows (a ceiling panel turned to the ceiling).
/// Objects with a transform are left alone (their sides are not read
/// here).
fn emitters_facing_away(warnings: &mut Vec<Diagnostic>, scene: &SceneFile) {
    let Some(middle) = middle(scene) else {
        return;
    };
    for (i, o) in scene.objects.iter().enumerate() {
        let emissive = match &o.material {
            Some(crate::MaterialRef::Inline(m)) => m.is_emissive(),
            Some(crate::MaterialRef::Named(name)) => scene
                .materials
                .get(name)
                .is_some_and(crate::Material::is_emissive),
            None => false,
        };
        if !emissive || o.transform.is_some() {
            continue;
        }
        let (key, point, normal, fix) = match o.shapes().as_slice() {
            [ShapeRef::Quad(q)] => (
                "quad",
                q.corner,
                cross(q.edge_u, q.edge_v),
                "swap `edge_u` and `edge_v` to turn it over",
            ),
            [ShapeRef::Triangle([a, b, c])] => (
                "triangle",
                *a,
                cross(sub(*b, *a), sub(*c, *a)),
                "swap two of its vertices to turn it over",
            ),
            _ => continue,
        };
        let behind = |p: Vec3| dot(sub(p, point), normal) < 0.0;
        if behind(scene.camera.eye) && behind(middle) {
            warnings.push(Diagnostic::new(
                KeyPath::root().key("objects").index(i).key(key),
                format!("emits from its front side only, which faces away from the camera and from the middle of the scene, so its light goes where the image does not show; {fix}"),
            ));
        }
    }
}

/// The mean of the objects' middles (spheres, triangles, quads, boxes;
/// not planes or meshes), if there are any.
fn middle(scene: &SceneFile) -> Option<Vec3> {
    let scale = |v: Vec3, s: f32| [v[0] * s, v[1] * s, v[2] * s];
    let points: Vec<Vec3> = scene
        .objects
        .iter()
        .filter(|o| o.transform.is_none())
        .filter_map(|o| match o.shapes().as_slice() {
            [ShapeRef::Sphere(s)] => Some(s.center),
            [ShapeRef::Triangle([a, b, c])] => Some(scale(add(add(*a, *b), *c), 1.0 / 3.0)),
            [ShapeRef::Quad(q)] => Some(add(q.corner, scale(add(q.edge_u, q.edge_v), 0.5))),
            [ShapeRef::Box(b)] => Some(scale(add(b.min, b.max), 0.5)),
            _ => None,
        })
        .collect();
    let sum = points.iter().fold([0.0; 3], |s, p| add(s, *p));
    (!points.is_empty()).then(|| scale(sum, 1.0 / points.len() as f32))
}

/// Glass on a lone triangle: a ray enters it and never leaves, so
/// everything behind is seen bent as from inside glass.
fn open_glass(warnings: &mut Vec<Diagnostic>, scene: &SceneFile) {
    for (i, o) in scene.objects.iter().enumerate() {
        let material = match &o.material {
            Some(crate::MaterialRef::Inline(m)) => Some(m),
            Some(crate::MaterialRef::Named(name)) => scene.materials.get(name),
            None => None,
        };
        // A plane or a quad is as open as a triangle.
        let open = match o.shapes().as_slice() {
            [ShapeRef::Triangle(_)] => "a single triangle",
            [ShapeRef::Quad(_)] => "a quad",
            [ShapeRef::Plane(_)] => "a plane",
            _ => continue,
        };
        if material.is_some_and(|m| m.transmittance > 0.0) {
            warnings.push(Diagnostic::new(
                KeyPath::root().key("objects").index(i).key("material"),
                format!("a transparent material on {open}: a ray enters it and never leaves; glass needs a closed shape (a sphere, a box, a closed mesh)"),
            ));
        }
    }
}

/// A colour texture on a material with neither ambient nor diffuse: it
/// multiplies them, so it shows nothing (keys left out are 0).
fn unseen_texture(warnings: &mut Vec<Diagnostic>, path: &KeyPath, m: &crate::Material) {
    let colour_texture = matches!(
        m.texture,
        Some(crate::TextureRef::Image(_) | crate::TextureRef::Checker(_))
    );
    if colour_texture && m.ambient == [0.0; 3] && m.diffuse == [0.0; 3] {
        warnings.push(Diagnostic::new(
            path.key("texture"),
            "shows nothing: a texture table multiplies `ambient` and `diffuse`, and both are 0; try diffuse = [1, 1, 1]",
        ));
    }
}

/// Objects whose material has an `alpha_cutoff` that cuts nothing: no
/// image texture to read alpha from, or an image without alpha below 255
/// (on a sphere or a plane, which it cannot cut, it is an error).
fn alpha_cutoffs(warnings: &mut Vec<Diagnostic>, scene: &SceneFile) {
    for (i, o) in scene.objects.iter().enumerate() {
        let material = match &o.material {
            Some(crate::MaterialRef::Inline(m)) => Some(m),
            Some(crate::MaterialRef::Named(name)) => scene.materials.get(name),
            None => None,
        };
        let Some(m) = material.filter(|m| m.alpha_cutoff.is_some()) else {
            continue;
        };
        let object = KeyPath::root().key("objects").index(i);
        let (key, texture) = match (&o.texture, &m.texture) {
            (Some(t), _) => (object.key("texture"), Some(t)),
            (None, t) => (object.key("material"), t.as_ref()),
        };
        let Some(crate::TextureRef::Image(image)) = texture else {
            warnings.push(Diagnostic::new(
                key,
                "drawn whole: its material's `alpha_cutoff` reads the alpha of an image `texture`, and it has none",
            ));
            continue;
        };
        let opaque = image.data.as_ref().is_some_and(|d| d.alpha.is_none());
        if opaque {
            warnings.push(Diagnostic::new(
                key,
                format!("drawn whole: `{}` has no alpha below 255 (no alpha channel, or opaque everywhere), so its material's `alpha_cutoff` cuts nothing", image.image),
            ));
        }
    }
}

/// Colour channels above 1: 0-255 habits (`diffuse = [200, 0, 0]`).
fn over_one(warnings: &mut Vec<Diagnostic>, path: &KeyPath, m: &crate::Material) {
    let base_color = m.base_color.unwrap_or_default();
    for (key, c) in [
        ("ambient", m.ambient),
        ("diffuse", m.diffuse),
        ("specular", m.specular),
        ("base_color", base_color),
    ] {
        if c.iter().any(|&x| x > 1.0) {
            warnings.push(Diagnostic::new(
                path.key(key),
                format!(
                    "a channel above 1 in [{}, {}, {}]: colours run from 0 to 1, not 0 to 255",
                    c[0], c[1], c[2]
                ),
            ));
        }
    }
}

/// Whether some point of the object lies in front of the eye (positive
/// depth along the view direction).
fn in_front(scene: &SceneFile, o: &crate::Object) -> bool {
    let eye = scene.camera.eye;
    let view = sub(scene.camera.look_at, eye);
    let depth = |p: Vec3| dot(sub(p, eye), view);
    match o.shapes().as_slice() {
        [ShapeRef::Sphere(s)] => depth(s.center) + s.radius * length(view) > 0.0,
        [ShapeRef::Triangle(t)] => t.iter().any(|&p| depth(p) > 0.0),
        [ShapeRef::Quad(q)] => {
            let (u, v) = (q.edge_u, q.edge_v);
            let far = add(add(q.corner, u), v);
            [q.corner, add(q.corner, u), add(q.corner, v), far]
                .into_iter()
                .any(|p| depth(p) > 0.0)
        }
        [ShapeRef::Box(b)] => (0..8).any(|k| {
            let pick = |a: usize| if k >> a & 1 == 0 { b.min[a] } else { b.max[a] };
            depth([pick(0), pick(1), pick(2)]) > 0.0
        }),
        // A plane reaches every depth unless it faces along the view (it
        // is then at one depth, that of its point).
        [ShapeRef::Plane(p)] => {
            let (n, across) = (p.normal, cross(p.normal, view));
            length(across) > 1e-6 * length(n) * length(view) || depth(p.point) > 0.0
        }
        // A mesh is placed by the core; its extent is not known here.
        _ => true,
    }
}

fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: Vec3, b: Vec3) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn length(v: Vec3) -> f32 {
    dot(v, v).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{load_str, Format};

    /// The warnings' messages for a scene with a camera at z = 10 looking
    /// down -z, one light and `objects`.
    fn messages(objects: &str) -> Vec<String> {
        let text = format!(
            "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n[render]\nmax_depth = 4\n[[lights]]\nposition = [0, 5, 5]\n{objects}"
        );
        let scene = load_str(&text, Format::Toml, Path::new("t.toml")).expect("loads");
        warnings(&scene).into_iter().map(|d| d.message).collect()
    }

    const BEHIND: &str = "nothing is in front of the camera";

    #[test]
    fn an_mtls_emission_counts_as_a_light() {
        let dir = tempfile::tempdir().unwrap();
        let obj = "mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n";
        std::fs::write(dir.path().join("lamp.obj"), obj).unwrap();
        let scene = |integrator: &str, ke: &str| {
            std::fs::write(
                dir.path().join("lamp.mtl"),
                format!("newmtl lamp\nKd 0.5 0.5 0.5\n{ke}"),
            )
            .unwrap();
            let text = format!(
                "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n[render]\nintegrator = \"{integrator}\"\n\
                 [[objects]]\nmesh = {{ obj = \"lamp.obj\" }}\n"
            );
            let path = dir.path().join("s.toml");
            std::fs::write(&path, text).unwrap();
            let scene = crate::load_path(&path).expect("loads");
            let found: Vec<String> = warnings(&scene).into_iter().map(|d| d.message).collect();
            found.join("\n")
        };
        let lit = scene("path", "Ke 3 2 1\n");
        assert!(!lit.contains("nothing gives off light"), "{lit}");
        let dark = scene("path", "");
        assert!(dark.contains("nothing gives off light"), "{dark}");
        let whitted = scene("whitted", "Ke 3 2 1\n");
        assert!(
            whitted.contains("an emissive material is seen but lights nothing else"),
            "{whitted}"
        );
    }

    #[test]
    fn planes_boxes_and_quads_behind_the_eye_are_found() {
        let behind = [
            // Facing along the view, at z = 11: behind the eye everywhere.
            "plane = { point = [0, 0, 11], normal = [0, 0, 1] }",
            "box = { min = [-1, -1, 11], max = [1, 1, 12] }",
            "quad = { corner = [0, 0, 11], edge_u = [1, 0, 0], edge_v = [0, 1, 0.5] }",
        ];
        for shape in behind {
            let found = messages(&format!("[[objects]]\n{shape}\n"));
            assert!(
                found.iter().any(|m| m.contains(BEHIND)),
                "{shape}: {found:?}"
            );
        }
        let seen = [
            // A floor reaches in front of the eye whatever its height.
            "plane = { point = [0, -1, 50], normal = [0, 1, 0] }",
            "plane = { point = [0, 0, -5], normal = [0, 0, 1] }",
            "box = { min = [-1, -1, 9], max = [1, 1, 12] }",
            "quad = { corner = [0, 0, 11], edge_u = [1, 0, 0], edge_v = [0, 1, -2] }",
        ];
        for shape in seen {
            let found = messages(&format!("[[objects]]\n{shape}\n"));
            assert!(
                !found.iter().any(|m| m.contains(BEHIND)),
                "{shape}: {found:?}"
            );
        }
    }

    #[test]
    fn glass_on_a_quad_or_plane_is_open_and_on_a_box_closed() {
        let glass = "material = { transmittance = 1 }";
        for (shape, open) in [
            (
                "quad = { corner = [0, 0, 0], edge_u = [1, 0, 0], edge_v = [0, 1, 0] }",
                Some("a quad"),
            ),
            (
                "plane = { point = [0, 0, 0], normal = [0, 0, 1] }",
                Some("a plane"),
            ),
            ("box = { min = [0, 0, 0], max = [1, 1, 1] }", None),
        ] {
            let found = messages(&format!("[[objects]]\n{shape}\n{glass}\n"));
            let warned = found.iter().find(|m| m.contains("never leaves"));
            match open {
                Some(what) => assert!(warned.is_some_and(|m| m.contains(what)), "{found:?}"),
                None => assert!(warned.is_none(), "{found:?}"),
            }
        }
    }

    #[test]
    fn a_texture_table_without_ambient_or_diffuse_shows_nothing() {
        let sphere = "[[objects]]\nsphere = { center = [0, 0, 0], radius = 1 }\n";
        let checker = "texture = { checker = [[1, 1, 1], [0, 0, 0]] }";
        let unseen = |material: &str| {
            messages(&format!("{sphere}material = {{ {material} }}\n"))
                .iter()
                .any(|m| m.starts_with("shows nothing"))
        };
        assert!(unseen(&format!("specular = [1, 1, 1], {checker}")));
        assert!(!unseen(&format!("diffuse = [1, 1, 1], {checker}")));
        assert!(!unseen(&format!("ambient = [0.1, 0, 0], {checker}")));
        // The lab's stripes multiply the specular too.
        assert!(!unseen("specular = [1, 1, 1], texture = \"lab-stripes\""));
    }

    #[test]
    fn an_alpha_cutoff_that_cannot_cut_is_warned_about() {
        let quad = "quad = { corner = [-1, -1, 0], edge_u = [2, 0, 0], edge_v = [0, 2, 0] }";
        let image = ", texture = { image = \"leaf.png\" }";
        let whole = |shape: &str, rest: &str| -> Vec<String> {
            let material = format!("{{ diffuse = [1, 1, 1], alpha_cutoff = 0.5{rest} }}");
            let found = messages(&format!("[[objects]]\n{shape}\nmaterial = {material}\n"));
            found
                .into_iter()
                .filter(|m| m.starts_with("drawn whole"))
                .collect()
        };
        assert!(whole(quad, "")[0].contains("and it has none"));
        assert!(whole(quad, image).is_empty());
        // An image read without alpha below 255.
        let dir = tempfile::tempdir().unwrap();
        image::RgbImage::new(2, 2)
            .save(dir.path().join("leaf.png"))
            .unwrap();
        let text = format!(
            "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [0, 5, 5]\n\
             [[objects]]\n{quad}\nmaterial = {{ diffuse = [1, 1, 1], alpha_cutoff = 0.5{image} }}\n"
        );
        std::fs::write(dir.path().join("s.toml"), text).unwrap();
        let scene = crate::load_path(&dir.path().join("s.toml")).expect("loads");
        let found: Vec<_> = warnings(&scene)
            .into_iter()
            .map(|d| (d.path.to_string(), d.message))
            .collect();
        let opaque = found
            .iter()
            .find(|(_, m)| m.contains("has no alpha below 255"));
        assert_eq!(
            opaque.map(|(k, _)| k.as_str()),
            Some("objects[0].material"),
            "{found:?}"
        );
    }

    /// The warnings' (key, message) of a scene of `camera`, `render` and
    /// `rest` tables' lines.
    fn warned(camera: &str, render: &str, rest: &str) -> Vec<(String, String)> {
        let text = format!(
            "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n{camera}\n[render]\n{render}\n{rest}\n[[objects]]\nsphere = {{ center = [0, 0, 0], radius = 1 }}\n"
        );
        let scene = load_str(&text, Format::Toml, Path::new("t.toml")).expect("loads");
        let list = warnings(&scene).into_iter();
        list.map(|d| (d.path.to_string(), d.message)).collect()
    }

    fn has(found: &[(String, String)], key: &str, start: &str) -> bool {
        found.iter().any(|(k, m)| k == key && m.starts_with(start))
    }

    #[test]
    fn a_ceiling_panel_turned_to_the_ceiling_is_warned_about() {
        let room = "[materials.lamp]\nemission = [10, 10, 10]\n\
                    [[objects]]\nbox = { min = [-2, -1, -2], max = [2, -0.9, 2] }\n";
        let panel = |edges: &str| {
            format!("{room}[[objects]]\nquad = {{ corner = [-0.5, 2, -0.5], {edges} }}\nmaterial = \"lamp\"\n")
        };
        let path = "integrator = \"path\"";
        let down = warned("", path, &panel("edge_u = [1, 0, 0], edge_v = [0, 0, 1]"));
        assert!(
            !down.iter().any(|(k, _)| k == "objects[1].quad"),
            "{down:?}"
        );
        let up = warned("", path, &panel("edge_u = [0, 0, 1], edge_v = [1, 0, 0]"));
        assert!(
            has(&up, "objects[1].quad", "emits from its front side only"),
            "{up:?}"
        );
        assert!(up
            .iter()
            .any(|(_, m)| m.ends_with("swap `edge_u` and `edge_v` to turn it over")));
        // Whitted mode lights nothing with it: no word.
        let whitted = warned("", "", &panel("edge_u = [0, 0, 1], edge_v = [1, 0, 0]"));
        assert!(
            !whitted.iter().any(|(k, _)| k == "objects[1].quad"),
            "{whitted:?}"
        );
    }

    #[test]
    fn a_time_limit_with_one_sample_has_nothing_to_stop() {
        let path = "integrator = \"path\"\ntime_limit = 20";
        let lights = "[[lights]]\nposition = [0, 5, 5]";
        assert!(has(
            &warned("", path, lights),
            "render.time_limit",
            "has nothing to stop"
        ));
        let many = format!("{path}\nsamples = 256");
        assert!(!has(
            &warned("", &many, lights),
            "render.time_limit",
            "has nothing"
        ));
    }

    #[test]
    fn light_samples_are_said_unread_in_path_mode() {
        let lights = "[[lights]]\nposition = [0, 5, 5]";
        let set = "light_samples = 4";
        let path = format!("integrator = \"path\"\n{set}");
        assert!(has(
            &warned("", &path, lights),
            "render.light_samples",
            "not read in path mode"
        ));
        assert!(!has(
            &warned("", set, lights),
            "render.light_samples",
            "not read"
        ));
    }

    #[test]
    fn an_emitter_without_lights_in_whitted_mode_points_to_path_mode() {
        let lamp = "[materials.lamp]\nemission = [4, 4, 4]";
        let found = warned("", "", lamp);
        assert!(has(
            &found,
            "lights",
            "no lights: in Whitted mode an emissive material is seen but lights nothing else"
        ));
        assert!(has(
            &warned("", "", ""),
            "lights",
            "no lights: ambient is added once per light"
        ));
    }

    #[test]
    fn radians_for_fov_and_an_inverse_gamma_are_warned_about() {
        let lights = "[[lights]]\nposition = [0, 5, 5]";
        let found = warned("fov = 1.05", "gamma = 0.45", lights);
        assert!(
            has(&found, "camera.fov", "1.05: `fov` is in degrees"),
            "{found:?}"
        );
        assert!(
            found.iter().any(|(_, m)| m.ends_with("write fov = 60")),
            "{found:?}"
        );
        assert!(has(
            &found,
            "render.gamma",
            "0.45: below 1 the image comes out darker"
        ));
        let fine = warned("fov = 20", "gamma = 1", lights);
        assert!(
            !fine
                .iter()
                .any(|(k, _)| k == "camera.fov" || k == "render.gamma"),
            "{fine:?}"
        );
    }

    #[test]
    fn a_background_beside_an_environment_is_said_to_be_unused() {
        let text = |background: &str| {
            format!(
                "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n[render]\nbackground = {background}\n[environment]\ncolor = [1, 1, 1]\n[[objects]]\nsphere = {{ center = [0, 0, 0], radius = 1 }}\n"
            )
        };
        let unused = |background: &str| {
            let scene =
                load_str(&text(background), Format::Toml, Path::new("t.toml")).expect("loads");
            warnings(&scene)
                .iter()
                .any(|d| d.path == "render.background" && d.message.starts_with("not used"))
        };
        assert!(unused("[0.2, 0.3, 0.4]"));
        assert!(!unused("[0, 0, 0]"), "the default is not the user's");
    }
}
