//! What `tracer check` says of a 3D scene beside "ok": its objects,
//! triangles, lights, cameras and bounds (`--json` prints them as JSON). A
//! glTF file's in its own coordinates (+Y up), as its nodes place them;
//! another scene's as prepared.

use crate::load::Loaded;
use scene_format::{SceneFile, SceneKind};
use serde::Serialize;
use tracer_core::geometry::Shape;

/// A scene's size in numbers.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneSummary {
    /// Objects: a glTF file's nodes that place a mesh, a scene file's
    /// `objects`.
    pub objects: usize,
    /// Triangles, each placement of a mesh counted (a scene file's
    /// spheres and planes are not triangles).
    pub triangles: usize,
    pub lights: usize,
    /// Cameras: a glTF file's, or a scene file's one.
    pub cameras: usize,
    /// The box of every placed triangle and shape (planes left out); None
    /// for a scene of none.
    pub bounds: Option<Bounds>,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Bounds {
    pub min: [f32; 3],
    pub max: [f32; 3],
}

impl SceneSummary {
    /// The one line `tracer check` prints.
    pub fn line(&self) -> String {
        let plural = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
        let bounds = match &self.bounds {
            Some(b) => format!("bounds {:?} to {:?}", b.min, b.max),
            None => "no bounds".to_string(),
        };
        format!(
            "{}, {}, {}, {}, {bounds}",
            plural(self.objects, "object"),
            plural(self.triangles, "triangle"),
            plural(self.lights, "light"),
            plural(self.cameras, "camera"),
        )
    }
}

/// The summary of a loaded 3D scene; None for a canvas.
pub fn summary(loaded: &Loaded) -> Option<SceneSummary> {
    let SceneKind::Scene3d(file) = &loaded.kind else {
        return None;
    };
    if scene_format::gltf::scene::is_gltf(&loaded.name) {
        let data = file.objects.first()?.gltf.as_ref()?.data.as_ref()?;
        return Some(SceneSummary {
            objects: data.placed.len(),
            triangles: data.triangles(),
            lights: data.lights.len(),
            cameras: data.cameras.len(),
            bounds: data.bounds().map(|(min, max)| Bounds { min, max }),
        });
    }
    Some(prepared_summary(file))
}

/// A scene file's summary, from the scene as prepared.
fn prepared_summary(file: &SceneFile) -> SceneSummary {
    let (objects, lights) = (file.objects.len(), file.lights.len());
    let Ok(parts) = tracer_core::prepare::parts(file) else {
        return SceneSummary {
            objects,
            triangles: 0,
            lights,
            cameras: 1,
            bounds: None,
        };
    };
    let triangles = parts
        .objects
        .iter()
        .map(|o| match &o.shape {
            Shape::Triangle(_) => 1,
            Shape::Instance(i) => i.mesh().objects().len(),
            _ => 0,
        })
        .sum();
    let lights = parts.lights.len();
    let scene = tracer_core::Scene::new(parts);
    SceneSummary {
        objects,
        triangles,
        lights,
        cameras: 1,
        bounds: scene.bounds().map(|(lo, hi)| Bounds {
            min: lo.to_array(),
            max: hi.to_array(),
        }),
    }
}
