//! `include = ["materials.toml", ...]`: the materials, lights and objects
//! of other files merged into a scene, and where each merged item came
//! from, so that a problem found in the merged scene is shown in the file
//! and at the line that wrote it.

use crate::budget::Budget;
use crate::diagnostic::Diagnostic;
use crate::error::SceneError;
use crate::images::{self, ImageCache};
use crate::key_path::{KeyPath, Segment};
use crate::locate::{locate, locate_all};
use crate::model::{Light, Material, Object, SceneFile};
use crate::source::Source;
use crate::{obj, parse, Format};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// How deep includes may nest (a scene includes a file that includes ...):
/// far more than a library needs, and each level is a frame of recursion.
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// What an included file may hold: materials, lights, objects and its own
/// includes. The camera and the render settings are the scene file's.
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IncludedFile {
    /// Files included in turn, each a path relative to this file; their
    /// items come before this file's. Default: none.
    #[serde(default)]
    pub include: Vec<String>,
    /// Lights joining the scene's. Default: none.
    #[serde(default)]
    pub lights: Vec<Light>,
    /// Materials joining the scene's, by name; a name may be defined once
    /// in all the files of a scene. Default: none.
    #[serde(default)]
    pub materials: BTreeMap<String, Material>,
    /// Objects joining the scene's. Default: none.
    #[serde(default)]
    pub objects: Vec<Object>,
    /// The JSON Schema an editor checks a JSON file against (TOML files
    /// use a `#:schema` comment instead). The tracer ignores it.
    #[serde(rename = "$schema", default, skip_serializing_if = "Option::is_none")]
    pub schema: Option<String>,
}

/// One file read for a scene: its name in messages, its text and syntax.
#[derive(Debug, Clone, PartialEq)]
pub struct SourceText {
    pub name: PathBuf,
    pub text: String,
    pub format: Format,
}

/// The files a scene was merged from (the scene file first), and which
/// file and index each merged light, material and object came from.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Origins {
    pub files: Vec<SourceText>,
    materials: HashMap<String, usize>,
    /// Per merged light: (file, index in that file's `lights`).
    lights: Vec<(usize, usize)>,
    /// Per merged object: (file, index in that file's `objects`).
    objects: Vec<(usize, usize)>,
}

impl Origins {
    /// A scene of one file, including nothing.
    pub fn single(name: &Path, text: &str, format: Format) -> Origins {
        Origins {
            files: vec![SourceText {
                name: name.to_path_buf(),
                text: text.to_string(),
                format,
            }],
            ..Origins::default()
        }
    }

    /// The file (index into `files`) and the path in it of a key path of
    /// the merged scene.
    pub fn origin(&self, path: &KeyPath) -> (usize, KeyPath) {
        let mut local = path.clone();
        let file = match path.0.as_slice() {
            [Segment::Key(k), Segment::Key(name), ..] if k == "materials" => {
                self.materials.get(name).copied().unwrap_or(0)
            }
            [Segment::Key(k), Segment::Index(i), ..] if k == "lights" || k == "objects" => {
                let items = if k == "lights" {
                    &self.lights
                } else {
                    &self.objects
                };
                match items.get(*i) {
                    Some(&(file, j)) => {
                        local.0[1] = Segment::Index(j);
                        file
                    }
                    None => 0,
                }
            }
            _ => 0,
        };
        (file, local)
    }

    /// Diagnostics of the merged scene (validation, the tracer's limits),
    /// each moved to its file and located there.
    pub fn invalid(&self, diagnostics: Vec<Diagnostic>) -> SceneError {
        let mut per_file = vec![Vec::new(); self.files.len().max(1)];
        for mut d in diagnostics {
            let (file, local) = self.origin(&d.path);
            d.path = local;
            let last = per_file.len() - 1;
            per_file[file.min(last)].push(d);
        }
        let errors = per_file
            .into_iter()
            .enumerate()
            .filter(|(_, ds)| !ds.is_empty())
            .map(|(i, ds)| self.file_error(i, Vec::new(), ds))
            .collect();
        SceneError::of_files(errors)
    }

    /// The error of file `i`: `located` diagnostics as they are, `paths`
    /// located by their key paths; all in file order.
    fn file_error(&self, i: usize, located: Vec<Diagnostic>, paths: Vec<Diagnostic>) -> SceneError {
        let Some(file) = self.files.get(i) else {
            return SceneError::Invalid {
                file: PathBuf::new(),
                text: String::new(),
                diagnostics: located.into_iter().chain(paths).collect(),
            };
        };
        let mut diagnostics = located;
        diagnostics.extend(locate_all(&file.text, file.format, paths));
        diagnostics.sort_by_key(|d| d.span.as_ref().map(|s| s.start));
        SceneError::Invalid {
            file: file.name.clone(),
            text: file.text.clone(),
            diagnostics,
        }
    }

    /// "`name`:line:column" of a key path in file `i`, for messages that
    /// point at a second place.
    fn place(&self, i: usize, path: &KeyPath) -> String {
        let Some(file) = self.files.get(i) else {
            return String::new();
        };
        let name = file.name.display();
        match locate(&file.text, file.format, path) {
            Some(found) => {
                let start = found.key.unwrap_or(found.value).start;
                let at = crate::Location::from_offset(&file.text, start);
                format!("{name}:{}:{}", at.line, at.column)
            }
            None => name.to_string(),
        }
    }
}

/// The materials, lights and objects of one file, in the order merged.
struct Part {
    file: usize,
    lights: Vec<Light>,
    materials: BTreeMap<String, Material>,
    objects: Vec<Object>,
}

/// Problems of one file: parse errors come located, the others with a key
/// path to locate.
#[derive(Default)]
struct Problems {
    located: Vec<Diagnostic>,
    paths: Vec<Diagnostic>,
    /// OBJ files and images that could not be read, at
    /// `objects[i].mesh.obj` or a texture's `image`.
    meshes: Vec<Diagnostic>,
}

impl Problems {
    fn is_empty(&self) -> bool {
        self.located.is_empty() && self.paths.is_empty() && self.meshes.is_empty()
    }

    /// The problems to locate by key path: a mesh that failed to load may
    /// also fail a value check (an empty `obj`), and is reported once.
    fn paths(mut self) -> (Vec<Diagnostic>, Vec<Diagnostic>) {
        for d in self.meshes {
            if !self.paths.iter().any(|v| v.path == d.path) {
                self.paths.push(d);
            }
        }
        (self.located, self.paths)
    }
}

/// Reads the included files of a parsed scene file (`origins.files[0]`,
/// at `path`), merges them into `scene`, reads every mesh, and validates
/// the whole; every problem located in the file that holds it.
pub(crate) fn resolve(
    source: &dyn Source,
    path: &Path,
    scene: SceneFile,
    origins: Origins,
) -> Result<(SceneFile, Origins), SceneError> {
    resolve_as(source, path, scene, origins, false)
}

fn resolve_as(
    source: &dyn Source,
    path: &Path,
    mut scene: SceneFile,
    origins: Origins,
    part: bool,
) -> Result<(SceneFile, Origins), SceneError> {
    let mut loader = Loader {
        part,
        source,
        origins,
        problems: vec![Problems::default()],
        stack: vec![source.identity(path)],
        seen: HashMap::new(),
        parts: Vec::new(),
        images: ImageCache::default(),
        budget: Budget::default(),
        first_places: Default::default(),
    };
    let include = std::mem::take(&mut scene.include);
    loader.includes(0, base(path), &include);
    scene.include = include;
    if loader.failed_includes() {
        // Without a file that failed, names it defines would be reported
        // unknown: its own problems are what to fix first.
        return Err(loader.error());
    }
    let own = Part {
        file: 0,
        lights: std::mem::take(&mut scene.lights),
        materials: std::mem::take(&mut scene.materials),
        objects: std::mem::take(&mut scene.objects),
    };
    loader.finish(own, base(path), scene)
}

/// A file a scene includes, read on its own as [`resolve`] reads it in a
/// scene (`tracer check`, `tracer convert`): its includes, meshes and
/// images, and its values; a material it names may be defined by another
/// file of the scene, so an unknown name is not a problem here. The
/// scene made of it has a camera that passes validation, not to render.
pub(crate) fn resolve_part(
    source: &dyn Source,
    path: &Path,
    part: IncludedFile,
    origins: Origins,
) -> Result<(SceneFile, Origins), SceneError> {
    let scene = SceneFile {
        camera: placeholder_camera(),
        render: Default::default(),
        lights: part.lights,
        materials: part.materials,
        objects: part.objects,
        environment: None,
        include: part.include,
        schema: part.schema,
    };
    resolve_as(source, path, scene, origins, true)
}

/// A camera that passes validation, for a file that has none.
fn placeholder_camera() -> crate::model::Camera {
    let text = "eye = [0, 0, 1]\nlook_at = [0, 0, 0]\n";
    toml::from_str(text).expect("a valid camera")
}

/// The folder paths in a file are relative to.
fn base(path: &Path) -> &Path {
    path.parent().unwrap_or(Path::new(""))
}

struct Loader<'s> {
    source: &'s dyn Source,
    /// Whether the file read is one a scene includes, read on its own.
    part: bool,
    origins: Origins,
    /// Per file of `origins.files`.
    problems: Vec<Problems>,
    /// The identities of the files being included, the scene's first.
    stack: Vec<PathBuf>,
    /// Files included so far: identity -> (including file, include index).
    seen: HashMap<PathBuf, (usize, usize)>,
    parts: Vec<Part>,
    /// Texture images read so far, each file once.
    images: ImageCache,
    /// The triangles the meshes not yet read may still make.
    budget: Budget,
    /// Where each file included twice was first included (`first_place`).
    first_places: std::cell::RefCell<HashMap<PathBuf, String>>,
}

impl Loader<'_> {
    /// Whether a file failed to be included (unreadable, not parsed, a
    /// cycle): then the merged scene is not validated.
    fn failed_includes(&self) -> bool {
        self.problems
            .iter()
            .any(|p| !p.located.is_empty() || !p.paths.is_empty())
    }

    fn error(mut self) -> SceneError {
        let problems = std::mem::take(&mut self.problems);
        let errors = problems
            .into_iter()
            .enumerate()
            .filter(|(_, p)| !p.is_empty())
            .map(|(i, p)| {
                let (located, paths) = p.paths();
                self.origins.file_error(i, located, paths)
            })
            .collect();
        SceneError::of_files(errors)
    }

    fn problem(&mut self, file: usize, path: KeyPath, message: String) {
        self.problems[file]
            .paths
            .push(Diagnostic::new(path, message));
    }

    /// Reads the files `list` of file `file` (in folder `base`) includes,
    /// depth first, adding their parts in order.
    fn includes(&mut self, file: usize, base: &Path, list: &[String]) {
        for (k, entry) in list.iter().enumerate() {
            let at = KeyPath::root().key("include").index(k);
            if entry.trim().is_empty() {
                self.problem(file, at, "expected a file path, found an empty text".into());
                continue;
            }
            if self.stack.len() > MAX_INCLUDE_DEPTH {
                let m = format!(
                    "cannot include `{entry}`: includes are nested more than \
                     {MAX_INCLUDE_DEPTH} deep; expected a shallower chain"
                );
                self.problem(file, at, m);
                continue;
            }
            let path = base.join(entry);
            let identity = self.source.identity(&path);
            if let Some(message) = self.repeated(&identity, entry) {
                self.problem(file, at, message);
                continue;
            }
            self.seen.insert(identity.clone(), (file, k));
            if let Some(included) = self.read(file, &at, entry, &path) {
                self.stack.push(identity);
                self.include(included, &path);
                self.stack.pop();
            }
        }
    }

    /// Why `entry` may not be included here: it includes itself, or it is
    /// included already.
    fn repeated(&self, identity: &PathBuf, entry: &str) -> Option<String> {
        if let Some(pos) = self.stack.iter().position(|s| s == identity) {
            let chain: Vec<String> = self.stack[pos..]
                .iter()
                .map(|s| file_name(s))
                .chain([file_name(identity)])
                .collect();
            let first = match self.seen.get(identity) {
                Some(&(including, k)) => format!(
                    "it is first included at {}",
                    self.origins
                        .place(including, &KeyPath::root().key("include").index(k))
                ),
                // Only the file read is on the stack without being included.
                None if self.part => "it is the file being checked".to_string(),
                None => "it is the scene file".to_string(),
            };
            return Some(format!(
                "`{entry}` includes itself ({}); {first}",
                chain.join(" -> ")
            ));
        }
        Some(format!(
            "`{entry}` is included already, at {}; a file is included once",
            self.first_place(identity)?
        ))
    }

    /// "`name`:line:column" of the entry that first included `identity`,
    /// worked out once: each costs a walk of the including file's text, so
    /// a file named 10,000 times would take quadratic time.
    fn first_place(&self, identity: &PathBuf) -> Option<String> {
        let &(including, k) = self.seen.get(identity)?;
        let mut places = self.first_places.borrow_mut();
        let place = places.entry(identity.clone()).or_insert_with(|| {
            self.origins
                .place(including, &KeyPath::root().key("include").index(k))
        });
        Some(place.clone())
    }

    /// Reads and parses an included file; its problems are reported at
    /// `at` in file `file` (not readable) or in the included file itself.
    fn read(
        &mut self,
        file: usize,
        at: &KeyPath,
        entry: &str,
        path: &Path,
    ) -> Option<(usize, IncludedFile)> {
        let Some(format) = Format::from_path(path) else {
            let m = format!("cannot include `{entry}`: expected a .toml or .json file");
            self.problem(file, at.clone(), m);
            return None;
        };
        let bytes = match self.source.read(path, crate::read::MAX_SCENE_BYTES) {
            Ok(bytes) => bytes,
            Err(e) => {
                self.problem(file, at.clone(), format!("cannot read `{entry}`: {e}"));
                return None;
            }
        };
        let index = self.origins.files.len();
        self.problems.push(Problems::default());
        let text = match std::str::from_utf8(&bytes) {
            Ok(text) => crate::load::scene_text(text).into_owned(),
            Err(e) => {
                let text = String::from_utf8_lossy(&bytes).into_owned();
                let d = parse::not_utf8(&bytes, &text, e);
                self.add_file(path, text, format);
                self.problems[index].located.push(d);
                return None;
            }
        };
        self.add_file(path, text.clone(), format);
        if let Some(d) = scene_only_keys(&text, format) {
            self.problems[index].located.extend(d);
            return None;
        }
        match parse::parse::<IncludedFile>(&text, format) {
            Ok(included) => Some((index, included)),
            Err(ds) => {
                self.problems[index].located.extend(ds);
                None
            }
        }
    }

    fn add_file(&mut self, path: &Path, text: String, format: Format) {
        self.origins.files.push(SourceText {
            name: self.source.name(path),
            text,
            format,
        });
    }

    /// Adds an included file's includes, then its own part, with its meshes
    /// and images read relative to its folder.
    fn include(&mut self, (index, included): (usize, IncludedFile), path: &Path) {
        self.includes(index, base(path), &included.include);
        let mut part = Part {
            file: index,
            lights: included.lights,
            materials: included.materials,
            objects: included.objects,
        };
        self.read_files(&mut part, base(path));
        self.parts.push(part);
    }

    /// Reads the meshes and texture images of `part`, relative to `base`.
    fn read_files(&mut self, part: &mut Part, base: &Path) {
        let images = &mut self.images;
        let read = (&mut *images, &mut self.budget);
        let meshes = obj::load_object_meshes(&mut part.objects, base, self.source, read);
        let read = (&mut *images, &mut self.budget);
        let models = crate::gltf::load_objects(&mut part.objects, base, self.source, read);
        let items = (&mut part.materials, part.objects.as_mut_slice());
        let textures = images::load_part_images(items, base, self.source, images);
        let problems = &mut self.problems[part.file].meshes;
        problems.extend(meshes);
        problems.extend(models);
        problems.extend(textures);
    }

    /// The scene's own part read (its meshes) and added last, everything
    /// merged into `scene` and validated.
    fn finish(
        mut self,
        mut own: Part,
        base: &Path,
        mut scene: SceneFile,
    ) -> Result<(SceneFile, Origins), SceneError> {
        self.read_files(&mut own, base);
        if let Some(environment) = scene.environment.as_mut() {
            let problems = images::load_environment(environment, base, self.source);
            self.problems[own.file].meshes.extend(problems);
        }
        self.parts.push(own);
        self.merge(&mut scene);
        let merged = if self.part {
            crate::validate::validate_part(&scene)
        } else {
            crate::validate::validate(&scene)
        };
        for d in merged {
            let (i, local) = self.origins.origin(&d.path);
            self.problems[i].paths.push(Diagnostic { path: local, ..d });
        }
        if self.problems.iter().any(|p| !p.is_empty()) {
            return Err(self.error());
        }
        Ok((scene, self.origins))
    }

    /// The parts into `scene`, in order, recording each item's origin; a
    /// material name defined twice is a problem at the second definition.
    fn merge(&mut self, scene: &mut SceneFile) {
        for part in std::mem::take(&mut self.parts) {
            for (j, light) in part.lights.into_iter().enumerate() {
                self.origins.lights.push((part.file, j));
                scene.lights.push(light);
            }
            for (j, object) in part.objects.into_iter().enumerate() {
                self.origins.objects.push((part.file, j));
                scene.objects.push(object);
            }
            for (name, material) in part.materials {
                let path = KeyPath::root().key("materials").key(&name);
                if let Some(&first) = self.origins.materials.get(&name) {
                    let m = format!(
                        "material `{name}` is defined twice: first at {}; \
                         a scene and the files it includes share one set of names",
                        self.origins.place(first, &path)
                    );
                    self.problem(part.file, path, m);
                    continue;
                }
                self.origins.materials.insert(name.clone(), part.file);
                scene.materials.insert(name, material);
            }
        }
    }
}

/// Diagnostics at a top-level `camera` or `render` of an included file:
/// only the scene file sets them.
fn scene_only_keys(text: &str, format: Format) -> Option<Vec<Diagnostic>> {
    let tree = crate::span_tree::tree(text, format)?;
    let found: Vec<Diagnostic> = ["camera", "render", "environment"]
        .iter()
        .filter_map(|key| {
            let at = tree.locate(&KeyPath::root().key(key));
            let span = at.key.filter(|_| at.exact)?;
            let d = Diagnostic::new(
                KeyPath::root().key(key),
                format!(
                    "an included file cannot set `{key}`; expected only include, \
                     materials, lights and objects (the scene file sets {key})"
                ),
            );
            Some(d.at(text, span))
        })
        .collect();
    (!found.is_empty()).then_some(found)
}

/// A file's name for a chain of includes.
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::load::load_file;

    const CAMERA: &str = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n";

    fn first(error: &SceneError) -> (String, String, String) {
        let SceneError::Invalid {
            file, diagnostics, ..
        } = error
        else {
            panic!("{error}");
        };
        let d = &diagnostics[0];
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        (name, d.path.to_string(), d.message.clone())
    }

    #[test]
    fn a_file_including_the_scene_is_a_cycle_through_the_scene() {
        let dir = tempfile::tempdir().unwrap();
        let scene = dir.path().join("s.toml");
        std::fs::write(&scene, format!("include = [\"a.toml\"]\n{CAMERA}")).unwrap();
        std::fs::write(dir.path().join("a.toml"), "include = [\"./s.toml\"]\n").unwrap();
        let (file, path, message) = first(&load_file(&scene).unwrap_err());
        assert_eq!((file.as_str(), path.as_str()), ("a.toml", "include[0]"));
        assert_eq!(
            message,
            "`./s.toml` includes itself (s.toml -> a.toml -> s.toml); it is the scene file"
        );
    }

    #[test]
    fn a_checked_part_in_a_cycle_is_named_as_the_file_being_checked() {
        let dir = tempfile::tempdir().unwrap();
        let part = dir.path().join("p.toml");
        std::fs::write(&part, "include = [\"a.toml\"]\n").unwrap();
        std::fs::write(dir.path().join("a.toml"), "include = [\"p.toml\"]\n").unwrap();
        let (file, path, message) = first(&crate::load_file_or_part(&part).unwrap_err());
        assert_eq!((file.as_str(), path.as_str()), ("a.toml", "include[0]"));
        assert_eq!(
            message,
            "`p.toml` includes itself (p.toml -> a.toml -> p.toml); it is the file being checked"
        );
    }

    #[test]
    fn a_file_named_many_times_is_reported_in_linear_time() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("a.toml"),
            "[materials.m]\ndiffuse = [1, 1, 1]\n",
        )
        .unwrap();
        let names = vec!["\"a.toml\""; 10_000].join(", ");
        let scene = dir.path().join("s.toml");
        std::fs::write(&scene, format!("include = [{names}]\n{CAMERA}")).unwrap();
        let start = std::time::Instant::now();
        let (file, path, message) = first(&load_file(&scene).unwrap_err());
        assert!(start.elapsed().as_secs() < 2, "{:?}", start.elapsed());
        assert_eq!((file.as_str(), path.as_str()), ("s.toml", "include[1]"));
        assert!(message.contains("included already, at"), "{message}");
        assert!(message.contains("s.toml:1:12"), "{message}");
    }

    #[test]
    fn includes_nest_at_most_the_limit() {
        let dir = tempfile::tempdir().unwrap();
        // f0 includes f1 includes ... f40: the scene is level 0, f0 level
        // 1, f31 level 32, the deepest allowed: its include of f32 is refused.
        for i in 0..40 {
            let text = format!("include = [\"f{}.toml\"]\n", i + 1);
            std::fs::write(dir.path().join(format!("f{i}.toml")), text).unwrap();
        }
        let scene = dir.path().join("s.toml");
        std::fs::write(&scene, format!("include = [\"f0.toml\"]\n{CAMERA}")).unwrap();
        let (file, path, message) = first(&load_file(&scene).unwrap_err());
        assert_eq!((file.as_str(), path.as_str()), ("f31.toml", "include[0]"));
        assert!(message.contains("more than 32 deep"), "{message}");
    }

    #[test]
    fn merged_paths_map_back_to_their_file_and_index() {
        let origins = Origins {
            files: Vec::new(),
            materials: HashMap::from([("red".to_string(), 2)]),
            lights: vec![(1, 0), (0, 0)],
            objects: vec![(2, 0), (2, 1), (0, 0)],
        };
        let at = |p: &str| {
            let (file, local) = origins.origin(&KeyPath::from(p));
            (file, local.to_string())
        };
        assert_eq!(
            at("objects[1].sphere.radius"),
            (2, "objects[1].sphere.radius".into())
        );
        assert_eq!(at("objects[2].material"), (0, "objects[0].material".into()));
        assert_eq!(at("lights[0].color"), (1, "lights[0].color".into()));
        assert_eq!(
            at("materials.red.diffuse"),
            (2, "materials.red.diffuse".into())
        );
        assert_eq!(at("camera.fov"), (0, "camera.fov".into()));
        // A whole list (a warning about it) is the scene file's.
        assert_eq!(at("lights"), (0, "lights".into()));
    }
}
