//! glTF 2.0 files (`.gltf` with its `.bin` files and images, or `.glb`):
//! read into the same plain data a scene file gives (meshes as `MeshData`,
//! materials as `Material`, cameras and lights as the scene file's), so
//! that `prepare` sees no difference. Every problem is an error at the
//! JSON path of the value that has it (`meshes[0].primitives[1].attributes.POSITION`),
//! and every count is checked against the bytes there are before anything
//! is allocated for it.
//!
//! A reader of its own rather than the `gltf` crate: the checks and their
//! messages are the point (the crate reads an accessor's range unchecked
//! and reports no JSON path for it), and serde_json, already here, does the
//! parsing.

mod accessor;
mod buffers;
mod camera;
mod doc;
pub mod glb;
mod material;
mod mesh;
mod nodes;
pub mod scene;

pub use accessor::MAX_ELEMENTS;
pub use buffers::MAX_BUFFER_BYTES;
pub use camera::IMAGE_WIDTH;
pub use material::default_material;

use crate::budget::Budget;
use crate::diagnostic::Diagnostic;
use crate::images::ImageCache;
use crate::key_path::KeyPath;
use crate::model::{Camera, Light, Material, MeshData, Object, SceneFile};
use crate::source::Source;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Largest .gltf or .glb file read (its JSON, or the whole binary file).
pub const MAX_GLTF_BYTES: u64 = crate::read::MAX_OBJ_BYTES;

/// The extensions read; one required by a file and not here is an error.
pub const EXTENSIONS: [&str; 5] = [
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_texture_transform",
];

/// What a glTF file gives a scene: its meshes (those the chosen scene
/// places), materials, and the chosen scene's placed meshes, cameras and
/// lights, in the file's own coordinates (+Y up, right-handed).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GltfData {
    /// Each mesh of the file that is placed, by its index in `meshes`: its
    /// primitives' triangles together, each triangle's material an index
    /// into `materials` (`MeshData::triangle_materials`; `None` is glTF's
    /// default material).
    pub meshes: Vec<Option<Arc<MeshData>>>,
    /// The file's materials in the scene file's terms.
    pub materials: Vec<Material>,
    /// Every node of the chosen scene that has a mesh, in the order a
    /// depth-first walk meets them.
    pub placed: Vec<PlacedMesh>,
    /// The cameras of the chosen scene, placed.
    pub cameras: Vec<PlacedCamera>,
    /// The lights of the chosen scene (`KHR_lights_punctual`), placed.
    pub lights: Vec<Light>,
    /// What was read but not as the file says, or not read: each with the
    /// JSON path it is about.
    pub warnings: Vec<(KeyPath, String)>,
}

/// A mesh placed by a node.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedMesh {
    /// Index into `GltfData::meshes`.
    pub mesh: usize,
    /// The node's index in the file.
    pub node: usize,
    /// The node's world matrix (its own times its parents'), column-major
    /// as glTF writes matrices.
    pub matrix: [f32; 16],
}

/// A camera of the file, as the scene file's `[camera]` would say it.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedCamera {
    /// The node that places it.
    pub node: usize,
    /// The camera's or its node's name, if any.
    pub name: Option<String>,
    pub camera: Camera,
}

impl GltfData {
    /// Triangles the placed meshes make, each placement counted.
    pub fn triangles(&self) -> usize {
        self.placed
            .iter()
            .map(|p| self.mesh(p.mesh).map_or(0, |m| m.triangles.len()))
            .sum()
    }

    /// Placed mesh `index`'s triangles.
    pub fn mesh(&self, index: usize) -> Option<&Arc<MeshData>> {
        self.meshes.get(index).and_then(Option::as_ref)
    }

    /// The box of every placed triangle in the file's coordinates, None
    /// for a file that places none.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let mut b: Option<([f32; 3], [f32; 3])> = None;
        for p in &self.placed {
            let Some(mesh) = self.mesh(p.mesh) else {
                continue;
            };
            for t in &mesh.triangles {
                for v in t {
                    let w = nodes::apply(&p.matrix, *v);
                    let (lo, hi) = b.get_or_insert((w, w));
                    for a in 0..3 {
                        lo[a] = lo[a].min(w[a]);
                        hi[a] = hi[a].max(w[a]);
                    }
                }
            }
        }
        b
    }
}

/// Which part of a file to read: a scene and, in it, one node (with its
/// children), each by index or name.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Pick {
    pub scene: Option<crate::model::GltfPick>,
    pub node: Option<crate::model::GltfPick>,
}

/// Why a glTF file could not be read: where in it (the JSON path; the
/// root for the file as a whole) and what was expected.
#[derive(Debug, Clone, PartialEq)]
pub struct Failure {
    pub path: KeyPath,
    pub message: String,
}

impl Failure {
    pub(crate) fn at(path: KeyPath, message: impl Into<String>) -> Failure {
        Failure {
            path,
            message: message.into(),
        }
    }

    pub(crate) fn file(message: impl Into<String>) -> Failure {
        Failure::at(KeyPath::root(), message)
    }
}

/// A failure with the file's JSON text (to show the line it is at), when
/// the file had one.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfError {
    pub failure: Failure,
    pub json: Option<String>,
}

impl GltfError {
    /// The failure as one line: the JSON path (if any), then what is wrong.
    pub fn message(&self) -> String {
        if self.failure.path.is_root() {
            self.failure.message.clone()
        } else {
            format!("{}: {}", self.failure.path, self.failure.message)
        }
    }
}

/// Reads the glTF file at `path` of `source` (a .glb by its magic bytes,
/// else JSON text), the part `pick` names; its triangles taken from
/// `budget`, its images read through `images`. Also the files it read
/// beside it (buffers, images).
pub fn read(
    source: &dyn Source,
    path: &Path,
    pick: &Pick,
    budget: &mut Budget,
    images: &mut ImageCache,
) -> Result<GltfData, GltfError> {
    let bytes = source.read(path, MAX_GLTF_BYTES).map_err(|e| GltfError {
        failure: Failure::file(format!("cannot read it: {e}")),
        json: None,
    })?;
    let is_glb = bytes.starts_with(b"glTF")
        || path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let (json, bin) = if is_glb {
        let glb = glb::split(&bytes).map_err(|failure| GltfError {
            failure,
            json: None,
        })?;
        (glb.json, glb.bin)
    } else {
        (bytes.as_slice(), None)
    };
    let text = std::str::from_utf8(json).map_err(|e| GltfError {
        failure: Failure::file(format!(
            "its JSON is not UTF-8 text (byte {} is not); expected a glTF file",
            e.valid_up_to() + 1
        )),
        json: None,
    })?;
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let located = |failure| GltfError {
        failure,
        json: Some(text.to_string()),
    };
    let doc = parse(text).map_err(located)?;
    let base = path.parent().unwrap_or(Path::new(""));
    let reading = Reading {
        doc: &doc,
        base,
        source,
        file: path.to_path_buf(),
    };
    reading.read(bin, pick, budget, images).map_err(located)
}

/// The document of a glTF file's JSON text, its version and required
/// extensions checked.
fn parse(text: &str) -> Result<doc::Document, Failure> {
    let mut de = serde_json::Deserializer::from_str(text);
    let doc: doc::Document = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = KeyPath::from_serde(e.path());
        let inner = e.into_inner();
        let what = inner.to_string();
        // serde_json ends its messages with "at line L column C".
        let what = what.split(" at line ").next().unwrap_or(&what).to_string();
        if inner.is_syntax() || inner.is_eof() {
            Failure::file(format!(
                "not valid JSON: {what} (line {}, column {})",
                inner.line(),
                inner.column()
            ))
        } else {
            Failure::at(path, format!("{what}; expected glTF 2.0's JSON"))
        }
    })?;
    de.end()
        .map_err(|e| Failure::file(format!("not valid JSON: {e}")))?;
    let version = &doc.asset.version;
    if !version.starts_with("2.") {
        let found = if version.is_empty() {
            "none".to_string()
        } else {
            format!("{version:?}")
        };
        return Err(Failure::at(
            KeyPath::root().key("asset").key("version"),
            format!("expected a glTF 2.0 file (`asset.version` \"2.0\"), found {found}"),
        ));
    }
    for (i, name) in doc.extensions_required.iter().enumerate() {
        if !EXTENSIONS.contains(&name.as_str()) {
            return Err(Failure::at(
                KeyPath::root().key("extensionsRequired").index(i),
                format!(
                    "the file requires the extension `{name}`, which the tracer does not read; it reads {}",
                    EXTENSIONS.join(", ")
                ),
            ));
        }
    }
    Ok(doc)
}

/// One file being read.
struct Reading<'a> {
    doc: &'a doc::Document,
    base: &'a Path,
    source: &'a dyn Source,
    file: PathBuf,
}

impl Reading<'_> {
    fn read(
        &self,
        bin: Option<&[u8]>,
        pick: &Pick,
        budget: &mut Budget,
        images: &mut ImageCache,
    ) -> Result<GltfData, Failure> {
        let doc = self.doc;
        let (buffers, _) = buffers::load(doc, bin, self.base, self.source)?;
        let reader = accessor::Reader {
            doc,
            buffers: &buffers,
        };
        let walk = nodes::walk(doc, pick)?;
        let mut data = GltfData {
            meshes: vec![None; doc.meshes.len()],
            ..GltfData::default()
        };
        let normal_mapped = material::normal_mapped(doc);
        for placed in &walk.meshes {
            if data.meshes[placed.mesh].is_none() {
                let mesh = mesh::read(
                    &reader,
                    placed.mesh,
                    &normal_mapped,
                    budget,
                    &mut data.warnings,
                )?;
                data.meshes[placed.mesh] = Some(Arc::new(mesh));
            }
        }
        data.placed = walk.meshes;
        let mut textures =
            material::Textures::new(doc, &buffers, self.base, self.source, images, &self.file);
        data.materials = doc
            .materials
            .iter()
            .enumerate()
            .map(|(i, m)| material::read(m, i, &mut textures, &mut data.warnings))
            .collect::<Result<_, _>>()?;
        data.cameras = camera::cameras(doc, &walk.cameras)?;
        data.lights = camera::lights(doc, &walk.lights)?;
        not_read(doc, &mut data.warnings);
        Ok(data)
    }
}

/// One warning naming what the file has that the tracer does not read.
fn not_read(doc: &doc::Document, warnings: &mut Vec<(KeyPath, String)>) {
    let mut skipped = Vec::new();
    if !doc.animations.is_empty() {
        skipped.push(format!("{} animations", doc.animations.len()));
    }
    if !doc.skins.is_empty() {
        skipped.push(format!("{} skins", doc.skins.len()));
    }
    let morphed = doc
        .meshes
        .iter()
        .filter(|m| m.primitives.iter().any(|p| !p.targets.is_empty()))
        .count();
    if morphed > 0 {
        skipped.push(format!("morph targets on {morphed} meshes"));
    }
    let others: Vec<&str> = doc
        .extensions_used
        .iter()
        .map(String::as_str)
        .filter(|e| !EXTENSIONS.contains(e))
        .collect();
    if !others.is_empty() {
        skipped.push(format!("the extensions {}", others.join(", ")));
    }
    if !skipped.is_empty() {
        warnings.push((
            KeyPath::root(),
            format!(
                "not read (the model is rendered as it stands, without them): {}",
                skipped.join("; ")
            ),
        ));
    }
}

impl GltfError {
    /// The failure as a message naming the file: its JSON path, what is
    /// wrong, and (for a text file) the line and column it is at.
    pub fn describe(&self, file: &str) -> String {
        let place = self
            .json
            .as_deref()
            .filter(|_| !self.failure.path.is_root())
            .and_then(|text| {
                crate::locate::locate(text, crate::Format::Json, &self.failure.path).map(|found| {
                    let start = found.key.unwrap_or(found.value).start;
                    let at = crate::Location::from_offset(text, start);
                    format!(" (line {}, column {})", at.line, at.column)
                })
            })
            .unwrap_or_default();
        format!("`{file}`: {}{place}", self.message())
    }
}

/// Reads the glTF file of every `gltf` object of `objects` from `source`,
/// relative to `base`, each file (and part of it) once however many
/// objects name it. A file that cannot be read gives a diagnostic at
/// `objects[i].gltf.file`.
pub fn load_objects(
    objects: &mut [Object],
    base: &Path,
    source: &dyn Source,
    (images, budget): (&mut ImageCache, &mut Budget),
) -> Vec<Diagnostic> {
    let mut diagnostics = Vec::new();
    let mut read: HashMap<(PathBuf, String), Result<Arc<GltfData>, String>> = HashMap::new();
    for (i, object) in objects.iter_mut().enumerate() {
        let Some(g) = object.gltf.as_mut() else {
            continue;
        };
        if g.file.trim().is_empty() {
            continue;
        }
        let pick = Pick {
            scene: g.scene.clone(),
            node: g.node.clone(),
        };
        let path = base.join(&g.file);
        let key = (path.clone(), format!("{:?}", (&pick.scene, &pick.node)));
        let loaded = read.entry(key).or_insert_with(|| {
            read_file(source, &path, &pick, budget, images)
                .map(Arc::new)
                .map_err(|e| e.describe(&g.file))
        });
        match loaded {
            Ok(data) => g.data = Some(Arc::clone(data)),
            Err(message) => diagnostics.push(Diagnostic::new(
                format!("objects[{i}].gltf.file"),
                format!("cannot load {message}"),
            )),
        }
    }
    diagnostics
}

/// [`read`], its texture keys named after the file.
fn read_file(
    source: &dyn Source,
    path: &Path,
    pick: &Pick,
    budget: &mut Budget,
    images: &mut ImageCache,
) -> Result<GltfData, GltfError> {
    read(source, path, pick, budget, images)
}

/// Warnings of the glTF files of a loaded scene: what each read but not
/// as the file says, at its object's `gltf.file`.
pub fn warnings(scene: &SceneFile) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    for (i, object) in scene.objects.iter().enumerate() {
        let Some(g) = &object.gltf else { continue };
        let Some(data) = &g.data else { continue };
        for (path, message) in &data.warnings {
            let at = if path.is_root() {
                String::new()
            } else {
                format!("{path}: ")
            };
            out.push(Diagnostic::new(
                format!("objects[{i}].gltf.file"),
                format!("`{}`: {at}{message}", g.file),
            ));
        }
    }
    out
}
