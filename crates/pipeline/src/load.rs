//! Reading the scene: a file, or the scene built in for `tracer render`
//! without one; with the files it read and the warnings it gave.

use scene_format::{Diagnostic, Format, SceneError, SceneFile, SceneKind};
use std::path::{Path, PathBuf};

/// The scene rendered when none is given: the lab's final scene (table
/// 1.10). A copy of `scenes/reflectance2.toml` (a test keeps them equal):
/// a crate reads nothing from outside its folder.
const DEFAULT_SCENE: &str = include_str!("../scenes/reflectance2.toml");

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
    /// Every file the scene was read from: the scene file, then the OBJ
    /// files of its meshes, each once. Empty for the built-in scene.
    pub files_read: Vec<PathBuf>,
    /// What was read but not used (mesh faces of zero area); worth showing.
    pub warnings: Vec<Diagnostic>,
}

impl Loaded {
    /// The image's size in pixels, (width, height).
    pub fn size(&self) -> (u32, u32) {
        match &self.kind {
            SceneKind::Scene3d(file) => (file.camera.width, file.camera.height),
            SceneKind::Canvas(file) => (file.canvas.width, file.canvas.height),
        }
    }
}

/// Reads and validates the scene, a 3D scene (with its meshes) or a 2D canvas.
pub fn load(input: &Input) -> Result<Loaded, SceneError> {
    let name = input.name();
    let kind = match input {
        Input::File(path) => scene_format::load_any(path)?,
        Input::DefaultScene => scene_format::load_any_str(DEFAULT_SCENE, Format::Toml, &name)?,
    };
    let (files_read, warnings) = match (&kind, input) {
        (SceneKind::Scene3d(file), Input::File(path)) => (files_read(path, file), warnings(file)),
        (SceneKind::Scene3d(file), Input::DefaultScene) => (Vec::new(), warnings(file)),
        (SceneKind::Canvas(_), Input::File(path)) => (vec![path.clone()], Vec::new()),
        (SceneKind::Canvas(_), Input::DefaultScene) => (Vec::new(), Vec::new()),
    };
    Ok(Loaded {
        name,
        kind,
        files_read,
        warnings,
    })
}

fn warnings(file: &SceneFile) -> Vec<Diagnostic> {
    scene_format::mesh_warnings(file)
}

/// The scene file and its meshes' OBJ files, relative to the scene file's
/// folder as the loader reads them.
fn files_read(path: &Path, file: &SceneFile) -> Vec<PathBuf> {
    let base = path.parent().unwrap_or(Path::new(""));
    let mut files = vec![path.to_path_buf()];
    for mesh in file.objects.iter().filter_map(|o| o.mesh.as_ref()) {
        let obj = base.join(&mesh.obj);
        if !files.contains(&obj) {
            files.push(obj);
        }
    }
    files
}

#[cfg(test)]
mod tests {
    use super::*;

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
        assert_eq!(paths, ["objects[0].mesh.obj", "objects[1].mesh.obj"]);
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
