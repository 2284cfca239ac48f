//! A glTF file as a whole scene (`tracer render model.glb`): the model as
//! one `gltf` object, the file's first camera or one that frames the
//! model, its lights or a documented default lighting, path mode.

use super::{GltfData, Pick, IMAGE_WIDTH};
use crate::diagnostic::Diagnostic;
use crate::error::SceneError;
use crate::images::ImageCache;
use crate::include::Origins;
use crate::load::{LoadedScene, SceneKind};
use crate::model::{
    Camera, Environment, Gltf, Handedness, Integrator, Light, Object, Projection, RenderSettings,
    SceneFile,
};
use crate::source::Source;
use crate::{Budget, Format};
use std::path::Path;
use std::sync::Arc;

/// Paths per pixel of a glTF file rendered on its own.
pub const SAMPLES: u32 = 64;

/// The default lighting of a file without lights: a uniform grey sky of
/// this radiance...
pub const SKY: f32 = 0.5;
/// ...and a sun of this irradiance from above, behind the camera's left
/// shoulder, so that the model's shape shows.
pub const SUN: f32 = 2.0;

/// Whether `path` names a glTF file (`.gltf` or `.glb`, any case).
pub fn is_gltf(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// Reads the glTF file at `path` of `source` as a scene.
pub fn load(source: &dyn Source, path: &Path) -> Result<LoadedScene, SceneError> {
    let name = source.name(path);
    let file_name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let mut images = ImageCache::default();
    let data = super::read(
        source,
        path,
        &Pick::default(),
        &mut Budget::default(),
        &mut images,
    )
    .map_err(|e| {
        let text = e.json.clone().unwrap_or_default();
        let d = Diagnostic::new(e.failure.path.clone(), e.failure.message.clone());
        let diagnostics = if text.is_empty() {
            vec![d]
        } else {
            crate::locate::locate_all(&text, Format::Json, vec![d])
        };
        SceneError::Invalid {
            file: name.clone(),
            text,
            diagnostics,
        }
    })?;
    let scene = scene_of(Arc::new(data), &file_name);
    let problems = crate::validate::validate(&scene);
    if !problems.is_empty() {
        return Err(SceneError::Invalid {
            file: name.clone(),
            text: String::new(),
            diagnostics: problems,
        });
    }
    let json_text = source
        .read(path, super::MAX_GLTF_BYTES)
        .ok()
        .filter(|b| !b.starts_with(b"glTF"))
        .and_then(|b| String::from_utf8(b).ok())
        .unwrap_or_default();
    Ok(LoadedScene {
        kind: SceneKind::Scene3d(scene),
        origins: Origins::single(&name, &json_text, Format::Json),
        files_read: source.files_read(),
    })
}

/// The scene that shows `data` (read from `file`, a name relative to the
/// scene's folder): the file's first camera, or one framing its model; its
/// lights, or the default lighting; path mode.
pub fn scene_of(data: Arc<GltfData>, file: &str) -> SceneFile {
    let bounds = data.bounds();
    let camera = match data.cameras.first() {
        Some(c) => c.camera.clone(),
        None => framing(bounds),
    };
    let (lights, environment) = if data.lights.is_empty() {
        default_lighting(&camera)
    } else {
        (Vec::new(), None)
    };
    SceneFile {
        camera,
        render: RenderSettings {
            integrator: Integrator::Path,
            samples: SAMPLES,
            ..RenderSettings::default()
        },
        lights,
        materials: Default::default(),
        objects: vec![Object {
            gltf: Some(Gltf {
                file: file.to_string(),
                scene: None,
                node: None,
                data: Some(data),
            }),
            ..Object::default()
        }],
        environment,
        include: Vec::new(),
        schema: None,
    }
}

/// A camera that frames the box `bounds` (the unit cube around the origin
/// when there is none): looking at its centre from the front (+Z, where
/// glTF models face), to the right and above, far enough that the sphere
/// around the box fills the height of a 40-degree-wide, 4:3 image.
pub fn framing(bounds: Option<([f32; 3], [f32; 3])>) -> Camera {
    let (lo, hi) = bounds.unwrap_or(([-1.0; 3], [1.0; 3]));
    let centre: [f32; 3] = std::array::from_fn(|a| (lo[a] + hi[a]) / 2.0);
    let half: [f32; 3] = std::array::from_fn(|a| (hi[a] - lo[a]) / 2.0);
    let radius = half.iter().map(|x| x * x).sum::<f32>().sqrt().max(1e-3);
    let fov: f32 = 40.0;
    let (width, height) = (IMAGE_WIDTH, IMAGE_WIDTH * 3 / 4);
    let vertical = 2.0 * ((fov.to_radians() / 2.0).tan() * height as f32 / width as f32).atan();
    let distance = radius / (vertical / 2.0).sin() * 1.05;
    let toward = [0.45f32, 0.35, 1.0];
    let length = toward.iter().map(|x| x * x).sum::<f32>().sqrt();
    let eye = std::array::from_fn(|a| centre[a] + toward[a] / length * distance);
    Camera {
        eye,
        look_at: centre,
        up: [0.0, 1.0, 0.0],
        fov,
        width,
        height,
        handedness: Handedness::Right,
        aperture: 0.0,
        focus_distance: None,
        projection: Projection::Perspective,
        view_width: None,
    }
}

/// The default lighting: a uniform sky of `SKY` and a sun of `SUN` coming
/// from above, behind the camera and from its left.
pub fn default_lighting(camera: &Camera) -> (Vec<Light>, Option<Box<Environment>>) {
    let view: [f32; 3] = std::array::from_fn(|a| camera.look_at[a] - camera.eye[a]);
    let flat = (view[0] * view[0] + view[2] * view[2]).sqrt().max(1e-6);
    let (fx, fz) = (view[0] / flat, view[2] / flat);
    // The camera's right on the ground (+x when it looks along -z).
    let (rx, rz) = (-fz, fx);
    // Travelling down, away from the camera, toward its right.
    let direction = [0.5 * rx + fx, -1.2, 0.5 * rz + fz];
    let sun = Light {
        position: None,
        direction: Some(direction),
        cone: None,
        color: [SUN; 3],
        radius: 0.0,
    };
    let sky = Environment {
        image: None,
        color: Some([SKY; 3]),
        strength: 1.0,
        rotate: 0.0,
        data: None,
    };
    (vec![sun], Some(Box::new(sky)))
}

/// The warnings of a glTF file rendered on its own, at their JSON paths.
pub fn warnings(scene: &SceneFile) -> Vec<Diagnostic> {
    scene
        .objects
        .iter()
        .filter_map(|o| o.gltf.as_ref()?.data.as_ref())
        .flat_map(|d| d.warnings.iter())
        .map(|(path, message)| Diagnostic::new(path.clone(), message.clone()))
        .collect()
}
