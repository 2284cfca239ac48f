//! Reading the scene: a file, or the scene built in for `tracer render`
//! without one; with the files it read and the warnings it gave.

use crate::limits;
use scene_format::{Diagnostic, Format, KeyPath, Location, Origins, SceneError, SceneKind};
use std::path::{Path, PathBuf};

/// The scene rendered when none is given: the lab's final scene (table
/// 1.10). A copy of `scenes/reflectance2.toml` (a test keeps them equal):
/// a crate reads nothing from outside its folder.
pub(crate) const DEFAULT_SCENE: &str = include_str!("../scenes/reflectance2.toml");

/// The built-in scene's name, as if it were a file in the current folder.
pub const DEFAULT_SCENE_NAME: &str = "reflectance2.toml";

/// Where a scene comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Input {
    File(PathBuf),
    /// The lab's final scene, built in (see [`DEFAULT_SCENE_NAME`]).
    DefaultScene,
}

impl Input {
    /// A scene file when one is given, else the built-in scene.
    pub fn from_arg(path: Option<PathBuf>) -> Input {
        path.map_or(Input::DefaultScene, Input::File)
    }

    /// How messages and the default output name the scene.
    pub fn name(&self) -> PathBuf {
        match self {
            Input::File(path) => path.clone(),
            Input::DefaultScene => PathBuf::from(DEFAULT_SCENE_NAME),
        }
    }
}

/// A scene read and validated, ready to render.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The scene's name for messages: its path, or the built-in scene's name.
    pub name: PathBuf,
    pub kind: SceneKind,
    /// Every file the scene was read from, each once, in the order read: the
    /// scene file, the files it includes, the OBJ files of their meshes;
    /// for a zip archive the archive. Empty for the built-in scene.
    pub files_read: Vec<PathBuf>,
    /// Likely mistakes (mesh faces of zero area, no lights, ...; see
    /// `scene_format::warnings`); worth showing, not errors. Their key
    /// paths are the merged scene's: `origins` tells the file of each.
    pub warnings: Vec<Diagnostic>,
    /// The files the scene was merged from (it and the files it includes).
    pub origins: Origins,
}

/// A likely mistake of a scene, as shown to its user.
#[derive(Debug, Clone, PartialEq)]
pub struct Warning {
    /// `warning: FILE: `KEY`: MESSAGE`, as `tracer render` prints it.
    pub text: String,
    /// The file that holds it, its key path there, and its place in that
    /// file when found.
    pub file: PathBuf,
    pub key: String,
    pub message: String,
    pub location: Option<Location>,
    /// `key` as a path, to place it.
    key_path: KeyPath,
}

impl Loaded {
    /// The warnings of the scene as `options` render it: its own, or those
    /// of the scene as changed by `--integrator` (the path tracer reads
    /// materials differently) and `--samples` (a lens needs many).
    pub fn warnings_for(&self, options: &crate::Options) -> Vec<Diagnostic> {
        let SceneKind::Scene3d(file) = &self.kind else {
            return self.warnings.clone();
        };
        let integrator = options.integrator.unwrap_or(file.render.integrator);
        let samples = options.samples.unwrap_or(file.render.samples);
        let mut list = if (integrator, samples) == (file.render.integrator, file.render.samples) {
            self.warnings.clone()
        } else {
            let mut file = file.clone();
            (file.render.integrator, file.render.samples) = (integrator, samples);
            scene_format::warnings(&file)
        };
        // The browser build has no denoiser (`scene3d::denoise_asked`).
        let path = integrator == scene_format::Integrator::Path;
        if cfg!(target_arch = "wasm32") && file.render.denoise && path {
            list.push(Diagnostic::new(
                "render.denoise",
                "the playground cannot denoise (Open Image Denoise is a native library \
                 with trained weights): the image is shown as rendered; `tracer render` \
                 denoises it",
            ));
        }
        list
    }

    /// [`Loaded::warnings_for`] as shown: each with its line as `tracer
    /// render` prints it, in the file that holds it, at its place there
    /// (each file parsed once, for all of its warnings).
    pub fn warning_list(&self, options: &crate::Options) -> Vec<Warning> {
        let mut list = self.unplaced_warnings(options);
        let mut by_file: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
        for (i, (_, file)) in list.iter().enumerate() {
            by_file.entry(*file).or_default().push(i);
        }
        for (file, mine) in by_file {
            let Some(source) = self.origins.files.get(file) else {
                continue;
            };
            let paths: Vec<KeyPath> = mine.iter().map(|&i| list[i].0.key_path.clone()).collect();
            let found = scene_format::locate::locate_each(&source.text, source.format, &paths);
            for (&i, location) in mine.iter().zip(found) {
                list[i].0.location = location;
            }
        }
        list.into_iter().map(|(w, _)| w).collect()
    }

    /// The lines `tracer render` prints for [`Loaded::warnings_for`] (no
    /// file is read again to place them).
    pub fn warning_lines(&self, options: &crate::Options) -> Vec<String> {
        let list = self.unplaced_warnings(options);
        list.into_iter().map(|(w, _)| w.text).collect()
    }

    /// The warnings, each named in its file but not yet placed in it, with
    /// the index of that file in `origins`.
    fn unplaced_warnings(&self, options: &crate::Options) -> Vec<(Warning, usize)> {
        let name = |file: usize| match self.origins.files.get(file) {
            Some(f) if file > 0 => f.name.clone(),
            _ => self.name.clone(),
        };
        let warning = |w: Diagnostic| {
            // An object of an included file is named in that file.
            let (file, key_path) = self.origins.origin(&w.path);
            let named = name(file);
            let warning = Warning {
                text: format!("warning: {}: `{key_path}`: {}", named.display(), w.message),
                file: named,
                key: key_path.to_string(),
                key_path,
                message: w.message,
                location: None,
            };
            (warning, file)
        };
        self.warnings_for(options)
            .into_iter()
            .map(warning)
            .collect()
    }

    /// Whether `options` render this scene in path mode.
    pub fn is_path_traced(&self, options: &crate::Options) -> bool {
        match &self.kind {
            SceneKind::Scene3d(file) => {
                options.integrator.unwrap_or(file.render.integrator)
                    == scene_format::Integrator::Path
            }
            SceneKind::Canvas(_) => false,
        }
    }

    /// Whether a render with `options` is denoised (`--denoise` or the
    /// scene's `[render] denoise`, in path mode; not an AOV).
    pub fn is_denoised(&self, options: &crate::Options) -> bool {
        match &self.kind {
            SceneKind::Scene3d(file) => {
                (options.denoise || file.render.denoise)
                    && self.is_path_traced(options)
                    && options.aov.is_none()
            }
            SceneKind::Canvas(_) => false,
        }
    }

    /// The scene file's `[render] time_limit`, in seconds.
    pub fn time_limit(&self) -> Option<f64> {
        match &self.kind {
            SceneKind::Scene3d(file) => file.render.time_limit.map(as_written),
            SceneKind::Canvas(_) => None,
        }
    }

    /// The scene's time limit, when a render with `options` would stop at it
    /// but one of every sample (`explain`, `compare`, `watch`) does not.
    pub fn time_limit_not_kept(&self, options: &crate::Options) -> Option<f64> {
        self.time_limit().filter(|_| self.is_path_traced(options))
    }

    /// The image's size in pixels, (width, height).
    pub fn size(&self) -> (u32, u32) {
        match &self.kind {
            SceneKind::Scene3d(file) => (file.camera.width, file.camera.height),
            SceneKind::Canvas(file) => (file.canvas.width, file.canvas.height),
        }
    }
}

/// An f32 of a scene file as the f64 of its shortest decimal: 0.01 stays
/// 0.01 (`f64::from` would make it 0.009999999776482582, which messages
/// then print).
pub fn as_written(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(f64::from(x))
}

/// Reads and validates the scene, a 3D scene (with its included files and
/// meshes) or a 2D canvas; from a scene file or a zip archive made by
/// `tracer pack`.
pub fn load(input: &Input) -> Result<Loaded, SceneError> {
    let name = input.name();
    let loaded = match input {
        Input::File(path) => scene_format::load_file(path)?,
        Input::DefaultScene => scene_format::LoadedScene {
            kind: scene_format::load_any_str(DEFAULT_SCENE, Format::Toml, &name)?,
            origins: Origins::single(&name, DEFAULT_SCENE, Format::Toml),
            files_read: Vec::new(),
        },
    };
    checked(name, loaded)
}

/// What `tracer check` and `tracer convert` read: a scene file as
/// [`load`] reads it, or a file a scene includes, read on its own.
pub enum Checked {
    Whole(Box<Loaded>),
    /// A scene of the file's items (its camera only passes validation),
    /// with the warnings of its items.
    Part(Box<Loaded>),
}

/// [`load`] of the file at `path`, or, when its top-level keys are only
/// those of a file a scene includes, that file as a scene includes it
/// ([`scene_format::load_file_or_part`]).
pub fn load_or_part(path: &Path) -> Result<Checked, SceneError> {
    match scene_format::load_file_or_part(path)? {
        scene_format::Checked::Whole(loaded) => {
            checked(path.to_path_buf(), *loaded).map(|l| Checked::Whole(Box::new(l)))
        }
        scene_format::Checked::Part(part) => {
            let mut loaded = checked(path.to_path_buf(), *part)?;
            // Of its items only: "no lights" is the scene's to say.
            loaded.warnings.retain(|w| w.path.0.len() > 1);
            Ok(Checked::Part(Box::new(loaded)))
        }
    }
}

/// [`load`] of the scene file at `path` in `source` (a folder held in
/// memory: the browser build), named by its path in messages.
pub fn load_from(
    source: &dyn scene_format::source::Source,
    path: &Path,
) -> Result<Loaded, SceneError> {
    let loaded = scene_format::load_from(source, path)?;
    checked(source.name(path), loaded)
}

/// A scene read, checked against the tracer's limits, with its warnings.
fn checked(name: PathBuf, loaded: scene_format::LoadedScene) -> Result<Loaded, SceneError> {
    if let SceneKind::Scene3d(file) = &loaded.kind {
        let diagnostics = limits::check(file);
        if !diagnostics.is_empty() {
            // Located in the file that holds each object.
            return Err(loaded.origins.invalid(diagnostics));
        }
    }
    let warnings = match &loaded.kind {
        // A model rendered on its own: its warnings at their JSON paths.
        SceneKind::Scene3d(file) if scene_format::gltf::scene::is_gltf(&name) => {
            scene_format::gltf::scene::warnings(file)
        }
        SceneKind::Scene3d(file) => scene_format::warnings(file),
        SceneKind::Canvas(_) => Vec::new(),
    };
    Ok(Loaded {
        name,
        kind: loaded.kind,
        files_read: loaded.files_read,
        warnings,
        origins: loaded.origins,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_files_decimal_is_kept_as_written() {
        assert_eq!(as_written(0.01), 0.01);
        assert_eq!(as_written(3.0), 3.0);
        assert_eq!(as_written(1e-30), 1e-30);
        // The same f32 either way.
        assert_eq!(as_written(f32::MAX) as f32, f32::MAX);
    }

    fn repository_scene(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenes")
            .join(name)
    }

    #[test]
    fn the_built_in_scene_is_the_lab_final_scene_file() {
        let file = std::fs::read_to_string(repository_scene("reflectance2.toml")).unwrap();
        assert!(
            DEFAULT_SCENE == file,
            "crates/pipeline/scenes/reflectance2.toml differs from scenes/reflectance2.toml: copy it over"
        );
    }

    #[test]
    fn the_built_in_scene_loads_under_its_name() {
        let loaded = load(&Input::DefaultScene).unwrap();
        assert_eq!(loaded.name, Path::new("reflectance2.toml"));
        assert!(matches!(loaded.kind, SceneKind::Scene3d(_)));
        assert!(loaded.files_read.is_empty());
        assert_eq!(loaded.size(), (500, 400));
    }

    #[test]
    fn the_files_read_are_the_scene_and_each_obj_once() {
        let dir = tempfile::tempdir().unwrap();
        let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n";
        std::fs::write(dir.path().join("t.obj"), obj).unwrap();
        let scene = dir.path().join("s.toml");
        std::fs::write(
            &scene,
            "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
             [[objects]]\nmesh = { obj = \"t.obj\" }\n\
             [[objects]]\nmesh = { obj = \"t.obj\" }\n",
        )
        .unwrap();
        let loaded = load(&Input::File(scene.clone())).unwrap();
        assert_eq!(loaded.files_read, [scene, dir.path().join("t.obj")]);
        // The second face has its three vertices on the x axis.
        let paths: Vec<String> = loaded.warnings.iter().map(|w| w.path.to_string()).collect();
        assert_eq!(
            paths,
            ["objects[0].mesh.obj", "objects[1].mesh.obj", "lights"]
        );
    }

    #[test]
    fn the_files_read_include_texture_images_and_the_mtl_files_with_their_maps() {
        let path = repository_scene("textures.toml");
        let loaded = load(&Input::File(path.clone())).unwrap();
        let scenes = path.parent().unwrap();
        let expected = [
            path.clone(),
            scenes.join("meshes/labelled-box.obj"),
            scenes.join("meshes/labelled-box.mtl"),
            scenes.join("meshes/bullseye.png"),
            // Named by a material and by an object: once.
            scenes.join("textures/grid.png"),
        ];
        assert_eq!(loaded.files_read, expected);
        assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    }

    /// A scene in a temporary folder: `obj` as `m.obj`, `scene` as `s.toml`.
    fn scene_with_obj(obj: &str, scene: &str) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("m.obj"), obj).unwrap();
        let path = dir.path().join("s.toml");
        std::fs::write(&path, scene).unwrap();
        (dir, path)
    }

    const HEAD: &str =
        "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [0, 0, 10]\n";

    fn first_diagnostic(path: &Path) -> (String, Option<(usize, usize)>, String) {
        let err = load(&Input::File(path.to_path_buf())).unwrap_err();
        let d = &err.diagnostics()[0];
        (
            d.path.to_string(),
            d.location.map(|l| (l.line, l.column)),
            d.message.clone(),
        )
    }

    #[test]
    fn a_mesh_named_1001_times_counts_its_triangles_once() {
        // 20,000 triangles named by 1,001 objects: 20,020,000 triangles
        // placed, past the 20M limit, but one shared mesh of 20,000 and
        // 1,001 instances held. (The refusal at the object that crosses the
        // limit is tested in `limits`, with a smaller limit.)
        let mut obj = String::new();
        for k in 0..20_000 {
            obj.push_str(&format!("v {k} 0 0\nv {k} 1 0\nv {k} 0 1\n"));
            obj.push_str(&format!("f {} {} {}\n", 3 * k + 1, 3 * k + 2, 3 * k + 3));
        }
        let mut scene = HEAD.to_string();
        for k in 0..1001 {
            scene.push_str(&format!(
                "[[objects]]\nmesh = {{ obj = \"m.obj\" }}\ntransform = {{ translate = [0, {k}, 0] }}\n"
            ));
        }
        let (_dir, path) = scene_with_obj(&obj, &scene);
        if let Err(e) = load(&Input::File(path)) {
            panic!("refused: {}", e.diagnostics()[0].message);
        }
    }

    #[test]
    fn a_mesh_scaled_to_nothing_is_an_error_at_the_mesh() {
        // Edges of 1e-3 scaled by 1e-6 and moved to 1000, where f32's step
        // is 6e-5: every vertex lands on the same point.
        let obj = "v 0 0 0\nv 0.001 0 0\nv 0 0.001 0\nf 1 2 3\n";
        let scene = format!(
            "{HEAD}[[objects]]\nmesh = {{ obj = \"m.obj\" }}\n\
             transform = {{ scale = 1e-6, translate = [1000, 0, 0] }}\n"
        );
        let (_dir, path) = scene_with_obj(obj, &scene);
        let (key, location, message) = first_diagnostic(&path);
        assert_eq!(key, "objects[0].mesh");
        assert_eq!(location, Some((7, 8)));
        assert!(
            message.starts_with("no triangle of `m.obj` is left once placed"),
            "{message}"
        );
    }

    #[test]
    fn a_shared_mesh_scaled_to_nothing_is_an_error_at_each_mesh() {
        // As above, the mesh named twice (shared): its box's placed corners
        // all land on one point, so no triangle keeps an area.
        let obj = "v 0 0 0\nv 0.001 0 0\nv 0 0.001 0\nf 1 2 3\n";
        let object = "[[objects]]\nmesh = { obj = \"m.obj\" }\n\
             transform = { scale = 1e-6, translate = [1000, 0, 0] }\n";
        let (_dir, path) = scene_with_obj(obj, &format!("{HEAD}{object}{object}"));
        let err = load(&Input::File(path)).unwrap_err();
        let paths: Vec<String> = err
            .diagnostics()
            .iter()
            .map(|d| d.path.to_string())
            .collect();
        assert_eq!(paths, ["objects[0].mesh", "objects[1].mesh"]);
        let message = &err.diagnostics()[1].message;
        assert!(
            message.starts_with("no triangle of `m.obj` is left once placed"),
            "{message}"
        );
    }

    #[test]
    fn a_limit_broken_by_an_included_object_is_shown_in_its_file() {
        let obj = "v 0 0 0\nv 0.001 0 0\nv 0 0.001 0\nf 1 2 3\n";
        let scene = format!("include = [\"first.toml\", \"parts.toml\"]\n{HEAD}");
        let (dir, path) = scene_with_obj(obj, &scene);
        // Merged, the mesh is objects[2] (after first.toml's sphere and
        // parts.toml's); in parts.toml it is objects[1], on line 5.
        let sphere = "[[objects]]\nsphere = { center = [0, 0, 0], radius = 1 }\n";
        std::fs::write(dir.path().join("first.toml"), sphere).unwrap();
        std::fs::write(
            dir.path().join("parts.toml"),
            "[[objects]]\nsphere = { center = [0, 0, 0], radius = 1 }\n\n\
             [[objects]]\nmesh = { obj = \"m.obj\" }\n\
             transform = { scale = 1e-6, translate = [1000, 0, 0] }\n",
        )
        .unwrap();
        let err = load(&Input::File(path)).unwrap_err();
        let SceneError::Invalid {
            file, diagnostics, ..
        } = &err
        else {
            panic!("{err}");
        };
        assert_eq!(*file, dir.path().join("parts.toml"));
        let d = &diagnostics[0];
        assert_eq!(d.path.to_string(), "objects[1].mesh");
        assert_eq!(d.location.map(|l| (l.line, l.column)), Some((5, 8)));
    }

    #[test]
    fn a_mesh_placed_beyond_the_coordinate_bound_is_an_error() {
        let obj = "v 0 0 0\nv 1e5 0 0\nv 0 1 0\nf 1 2 3\n";
        let scene = format!(
            "{HEAD}[[objects]]\nmesh = {{ obj = \"m.obj\" }}\ntransform = {{ scale = 100 }}\n"
        );
        let (_dir, path) = scene_with_obj(obj, &scene);
        let (key, _, message) = first_diagnostic(&path);
        assert_eq!(key, "objects[0].mesh");
        assert!(message.contains("reaches a coordinate of 1e7"), "{message}");
    }

    #[test]
    fn a_folder_or_a_device_as_the_scene_is_bad_input() {
        let dir = tempfile::tempdir().unwrap();
        let folder = dir.path().join("folder.toml");
        std::fs::create_dir(&folder).unwrap();
        let err = load(&Input::File(folder)).unwrap_err();
        assert!(crate::scene_error_is_bad_input(&err), "{err}");
        #[cfg(unix)]
        {
            let zero = dir.path().join("zero.json");
            std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
            let err = load(&Input::File(zero)).unwrap_err();
            assert!(crate::scene_error_is_bad_input(&err), "{err}");
        }
    }

    #[test]
    fn a_canvas_scene_is_one_file() {
        let path = repository_scene("robot.toml");
        let loaded = load(&Input::File(path.clone())).unwrap();
        assert!(matches!(loaded.kind, SceneKind::Canvas(_)));
        assert_eq!(loaded.files_read, [path]);
        assert!(loaded.warnings.is_empty());
    }
}
