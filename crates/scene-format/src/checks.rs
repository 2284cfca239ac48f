//! What is found about a scene after it has loaded: errors found by its
//! users (the tracer's limits), located like validation's, and warnings
//! about likely mistakes that still make an image.

use crate::error::SceneError;
use crate::locate::locate_all;
use crate::model::{SceneFile, ShapeRef, Vec3};
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
    if scene.lights.is_empty() {
        // The lab adds ambient once per light: no light, no light at all.
        warnings.push(Diagnostic::new(
            "lights",
            "no lights: ambient is added once per light, so every object renders black",
        ));
    }
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
    for (path, m) in &materials {
        over_one(&mut warnings, path, m);
        if m.fresnel && m.reflectance > 0.0 {
            warnings.push(Diagnostic::new(
                path.key("reflectance"),
                "ignored with `fresnel = true`: the Fresnel equations give the reflection",
            ));
        }
    }
    open_glass(&mut warnings, scene);
    let transparent = materials.iter().any(|(_, m)| m.transmittance > 0.0);
    if transparent && scene.render.max_depth < 2 {
        warnings.push(Diagnostic::new(
            "render.max_depth",
            format!(
                "{}: a ray can enter a transparent object but not leave it, so glass looks dark; try max_depth = 8",
                scene.render.max_depth
            ),
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

/// Glass on a lone triangle: a ray enters it and never leaves, so
/// everything behind is seen bent as from inside glass.
fn open_glass(warnings: &mut Vec<Diagnostic>, scene: &SceneFile) {
    for (i, o) in scene.objects.iter().enumerate() {
        let material = match &o.material {
            Some(crate::MaterialRef::Inline(m)) => Some(m),
            Some(crate::MaterialRef::Named(name)) => scene.materials.get(name),
            None => None,
        };
        if o.triangle.is_some() && material.is_some_and(|m| m.transmittance > 0.0) {
            warnings.push(Diagnostic::new(
                KeyPath::root().key("objects").index(i).key("material"),
                "a transparent material on a single triangle: a ray enters it and never leaves; glass needs a closed shape (a sphere, a closed mesh)",
            ));
        }
    }
}

/// Colour channels above 1: 0-255 habits (`diffuse = [200, 0, 0]`).
fn over_one(warnings: &mut Vec<Diagnostic>, path: &KeyPath, m: &crate::Material) {
    for (key, c) in [
        ("ambient", m.ambient),
        ("diffuse", m.diffuse),
        ("specular", m.specular),
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
        // A mesh is placed by the core; its extent is not known here.
        _ => true,
    }
}

fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: Vec3, b: Vec3) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn length(v: Vec3) -> f32 {
    dot(v, v).sqrt()
}
