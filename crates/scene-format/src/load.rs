//! Loading a scene file: bytes or text to a validated `SceneFile` (or
//! `CanvasFile`), every problem located in the text.

use crate::error::SceneError;
use crate::include::{self, Origins};
use crate::locate::locate_all;
use crate::source::{Archive, Folder, Source};
use crate::{canvas, parse, validate, CanvasFile, Diagnostic, Format, SceneFile};
use std::borrow::Cow;
use std::path::{Path, PathBuf};

/// Reads, parses and validates the 3D scene file at `path`, and reads the
/// OBJ files of its meshes and the images of its textures (relative to the
/// scene file's folder).
pub fn load_path(path: &Path) -> Result<SceneFile, SceneError> {
    match load_any(path)? {
        SceneKind::Scene3d(scene) => Ok(scene),
        SceneKind::Canvas(_) => Err(SceneError::Invalid {
            file: path.to_path_buf(),
            text: String::new(),
            diagnostics: vec![Diagnostic::new(
                "canvas",
                "found a 2D canvas scene ([canvas]); expected a 3D scene with a [camera] here",
            )],
        }),
    }
}

/// Parses and validates a scene file's bytes; `file` names it in errors.
/// Bytes that are not UTF-8 text are reported, not read lossily.
pub fn load_bytes(bytes: &[u8], format: Format, file: &Path) -> Result<SceneFile, SceneError> {
    load_str(utf8_text(bytes, file)?, format, file)
}

fn utf8_text<'a>(bytes: &'a [u8], file: &Path) -> Result<&'a str, SceneError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let text = String::from_utf8_lossy(bytes).into_owned();
        let d = parse::not_utf8(bytes, &text, e);
        SceneError::Invalid {
            file: file.to_path_buf(),
            text,
            diagnostics: vec![d],
        }
    })
}

/// Parses and validates scene text; `file` names it in errors. A parse
/// error stops at the first problem; validation reports all it finds.
/// Meshes and images are not read: see `load_path`.
pub fn load_str(text: &str, format: Format, file: &Path) -> Result<SceneFile, SceneError> {
    let read = scene_text(text);
    let text = &*read;
    let invalid = |diagnostics| SceneError::Invalid {
        file: file.to_path_buf(),
        text: text.to_string(),
        diagnostics,
    };
    let scene: SceneFile = parse::parse(text, format).map_err(invalid)?;
    let mut diagnostics = validate::validate(&scene);
    if !scene.include.is_empty() {
        diagnostics.push(Diagnostic::new(
            "include",
            "included files are read only with a scene read from a file; \
             expected no `include` in scene text",
        ));
    }
    if diagnostics.is_empty() {
        Ok(scene)
    } else {
        Err(invalid(locate_all(text, format, diagnostics)))
    }
}

/// A scene file's text as it is read: without a leading UTF-8 byte order
/// mark (Windows editors write one, TOML allows it and serde_json does not,
/// so JSON would fail on it; columns on the first line then count as an
/// editor shows them), and with each line ending in a lone `\r` (old Mac
/// files, which the toml crate refuses) ending in `\n`: the same length,
/// so every offset into it is one into the file.
pub(crate) fn scene_text(text: &str) -> Cow<'_, str> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let bytes = text.as_bytes();
    let lone = |i: usize| bytes[i] == b'\r' && bytes.get(i + 1) != Some(&b'\n');
    if !(0..bytes.len()).any(lone) {
        return Cow::Borrowed(text);
    }
    Cow::Owned(
        text.char_indices()
            .map(|(i, c)| if lone(i) { '\n' } else { c })
            .collect(),
    )
}

/// What a scene file describes: a 3D scene or a 2D canvas.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneKind {
    Scene3d(SceneFile),
    Canvas(CanvasFile),
}

/// Reads, parses and validates the file at `path`, a 3D scene or, when it
/// has a top-level `[canvas]` table, a 2D canvas scene.
/// A 3D scene's included files and meshes are read too.
pub fn load_any(path: &Path) -> Result<SceneKind, SceneError> {
    load_file(path).map(|loaded| loaded.kind)
}

/// A scene read from its files.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    pub kind: SceneKind,
    /// The files it was merged from, to locate problems found later (the
    /// tracer's limits) in the file that holds them.
    pub origins: Origins,
    /// Every file read on the file system, each once: the scene file, the
    /// files it includes, their meshes; for a zip archive, the archive.
    pub files_read: Vec<PathBuf>,
}

/// [`load_any`], with where the scene came from: a scene file (`.toml`,
/// `.json`) and the files it names, or a zip archive made by `tracer pack`.
pub fn load_file(path: &Path) -> Result<LoadedScene, SceneError> {
    let is_zip = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("zip"));
    if !is_zip {
        return load_from(&Folder::new(), path);
    }
    let archive = Archive::open(path).map_err(|source| SceneError::Io {
        file: path.to_path_buf(),
        source,
    })?;
    let mut loaded = load_from(&archive, archive.scene())?;
    loaded.files_read = vec![path.to_path_buf()];
    Ok(loaded)
}

/// Reads the scene file at `path` of `source`, a 3D scene with its
/// included files and meshes, or a 2D canvas.
pub fn load_from(source: &dyn Source, path: &Path) -> Result<LoadedScene, SceneError> {
    if crate::gltf::scene::is_gltf(path) {
        return crate::gltf::scene::load(source, path);
    }
    let name = source.name(path);
    let format =
        Format::from_path(path).ok_or_else(|| SceneError::UnknownFormat { file: name.clone() })?;
    let bytes = source
        .read(path, crate::read::MAX_SCENE_BYTES)
        .map_err(|e| SceneError::Io {
            file: name.clone(),
            source: e,
        })?;
    let read = scene_text(utf8_text(&bytes, &name)?);
    let text = &*read;
    let origins = Origins::single(&name, text, format);
    let (kind, origins) = if has_canvas_table(text, format) {
        (load_any_str(text, format, &name)?, origins)
    } else {
        let scene: SceneFile =
            parse::parse(text, format).map_err(|diagnostics| SceneError::Invalid {
                file: name.clone(),
                text: text.to_string(),
                diagnostics,
            })?;
        let (scene, origins) = include::resolve(source, path, scene, origins)?;
        (SceneKind::Scene3d(scene), origins)
    };
    Ok(LoadedScene {
        kind,
        origins,
        files_read: source.files_read(),
    })
}

/// What `tracer check` and `tracer convert` read: a whole scene, or a
/// file a scene includes, read on its own.
#[derive(Debug, Clone)]
pub enum Checked {
    Whole(Box<LoadedScene>),
    /// A file of no other top-level keys than `include`, `materials`,
    /// `lights`, `objects` (and `$schema`): a scene of its items, with a
    /// camera only to pass validation, not to render.
    Part(Box<LoadedScene>),
}

/// [`load_file`], or for a file a scene includes (no other top-level
/// keys than `include`, `materials`, `lights`, `objects`), that file with
/// its includes, meshes and images, its values validated; a material it
/// names may be defined by another file of the scene.
pub fn load_file_or_part(path: &Path) -> Result<Checked, SceneError> {
    let folder = Folder::new();
    let part = match Format::from_path(path) {
        Some(format) => folder
            .read(path, crate::read::MAX_SCENE_BYTES)
            .ok()
            .and_then(|bytes| String::from_utf8(bytes).ok())
            .filter(|text| is_part(&scene_text(text), format))
            .map(|text| (text, format)),
        None => None,
    };
    let Some((text, format)) = part else {
        // Errors, a zip archive and whole scenes: as a scene.
        return load_file(path).map(|loaded| Checked::Whole(Box::new(loaded)));
    };
    let read = scene_text(&text);
    let text = &*read;
    let name = folder.name(path);
    let included: include::IncludedFile =
        parse::parse(text, format).map_err(|diagnostics| SceneError::Invalid {
            file: name.clone(),
            text: text.to_string(),
            diagnostics,
        })?;
    let origins = Origins::single(&name, text, format);
    let (scene, origins) = include::resolve_part(&folder, path, included, origins)?;
    Ok(Checked::Part(Box::new(LoadedScene {
        kind: SceneKind::Scene3d(scene),
        origins,
        files_read: folder.files_read(),
    })))
}

/// Whether text parses to a table of an included file's keys only, some
/// of them (an empty file, or one with `[camra]`, is a scene whose
/// mistake its own checks name).
fn is_part(text: &str, format: Format) -> bool {
    const PART: [&str; 4] = ["include", "materials", "lights", "objects"];
    let keys: Vec<String> = match format {
        Format::Toml => toml::from_str::<toml::Table>(text)
            .map(|t| t.keys().cloned().collect())
            .unwrap_or_default(),
        Format::Json => serde_json::from_str::<serde_json::Value>(text)
            .ok()
            .and_then(|v| {
                // A part's own keys valued null are keys left out; any
                // other key, null or not, makes the file a scene.
                let left_out = |(k, v): &(&String, &serde_json::Value)| {
                    v.is_null() && PART.contains(&k.as_str())
                };
                let members = v.as_object()?.iter().filter(|m| !left_out(m));
                Some(members.map(|(k, _)| k.clone()).collect())
            })
            .unwrap_or_default(),
    };
    let of_part = |k: &String| PART.contains(&k.as_str()) || k == "$schema";
    keys.iter().any(|k| PART.contains(&k.as_str())) && keys.iter().all(of_part)
}

/// `load_any` on text; `file` names it in errors.
pub fn load_any_str(text: &str, format: Format, file: &Path) -> Result<SceneKind, SceneError> {
    let read = scene_text(text);
    let text = &*read;
    if !has_canvas_table(text, format) {
        return load_str(text, format, file).map(SceneKind::Scene3d);
    }
    let invalid = |diagnostics| SceneError::Invalid {
        file: file.to_path_buf(),
        text: text.to_string(),
        diagnostics,
    };
    let canvas: CanvasFile = parse::parse(text, format).map_err(invalid)?;
    let diagnostics = canvas::validate(&canvas);
    if diagnostics.is_empty() {
        Ok(SceneKind::Canvas(canvas))
    } else {
        Err(invalid(locate_all(text, format, diagnostics)))
    }
}

/// Whether the text has a top-level `canvas` key. Text that does not parse
/// is left to the 3D loader, whose error says where.
fn has_canvas_table(text: &str, format: Format) -> bool {
    match format {
        Format::Toml => toml::from_str::<toml::Table>(text).is_ok_and(|t| t.contains_key("canvas")),
        Format::Json => {
            // A null member is a key left out.
            serde_json::from_str::<serde_json::Value>(text)
                .is_ok_and(|v| v.get("canvas").is_some_and(|c| !c.is_null()))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Location;

    const CAMERA: &str = r#""camera": {"eye": [0, 0, 10], "look_at": [0, 0, 0]}"#;

    #[test]
    fn json_scenes_may_name_their_schema() {
        let text = format!(r#"{{"$schema": "./schema.json", {CAMERA}}}"#);
        let scene = load_str(&text, Format::Json, Path::new("s.json")).unwrap();
        assert_eq!(scene.schema.as_deref(), Some("./schema.json"));
    }

    #[test]
    fn a_null_canvas_is_no_canvas() {
        // Read as a 3D scene, where `canvas` is a key it does not know.
        let text = format!(r#"{{"canvas": null, {CAMERA}}}"#);
        let err = load_any_str(&text, Format::Json, Path::new("s.json")).unwrap_err();
        let message = &err.diagnostics()[0].message;
        assert!(
            message.starts_with("unknown key `canvas` at the top level"),
            "{message}"
        );
        // A part's null keys are left out; another key makes a scene.
        assert!(is_part(r#"{"lights": null, "objects": []}"#, Format::Json));
        assert!(!is_part(r#"{"camera": null, "objects": []}"#, Format::Json));
    }

    #[test]
    fn a_missing_obj_is_reported_with_the_value_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.toml");
        let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nfov = 0\n\n\
                    [[objects]]\nmesh = { obj = \"none.obj\" }\n";
        std::fs::write(&path, text).unwrap();
        let err = load_any(&path).unwrap_err();
        let paths: Vec<String> = err
            .diagnostics()
            .iter()
            .map(|d| d.path.to_string())
            .collect();
        assert_eq!(paths, ["camera.fov", "objects[0].mesh.obj"]);
    }

    #[test]
    fn a_mesh_needs_one_file_and_uv_belong_to_triangles() {
        let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
                    [[objects]]\nmesh = { smooth = true }\n\
                    [[objects]]\nmesh = { ply = \" \" }\n\
                    [[objects]]\nmesh = { obj = \"a.obj\", ply = \"a.ply\" }\n\
                    [[objects]]\nsphere = { center = [0, 0, 0], radius = 1 }\nuv = [[0, 0], [1, 0], [0, 1]]\n\
                    [[objects]]\ntriangle = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\nuv = [[0, 0], [1, nan], [0, 1]]\n\
                    [[objects]]\ntriangle = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\nuv = [[0, 0], [1, 0], [0, 1]]\n";
        let err = load_str(text, Format::Toml, Path::new("s.toml")).unwrap_err();
        let found: Vec<(String, usize)> = err
            .diagnostics()
            .iter()
            .map(|d| (d.path.to_string(), d.location.unwrap().line))
            .collect();
        let expected = [
            ("objects[0].mesh", 5),
            ("objects[1].mesh.ply", 7),
            ("objects[2].mesh.ply", 9),
            ("objects[3].uv", 12),
            ("objects[4].uv[1]", 15),
        ];
        let expected: Vec<(String, usize)> =
            expected.iter().map(|(p, l)| (p.to_string(), *l)).collect();
        assert_eq!(found, expected);
    }

    #[test]
    fn other_extensions_are_refused() {
        let err = load_path(Path::new("scene.yaml")).unwrap_err();
        assert!(matches!(err, SceneError::UnknownFormat { .. }));
    }

    #[test]
    fn a_defaulted_value_that_fails_points_at_its_table() {
        // `up` is not in the file; its default [0, 1, 0] is parallel to
        // the view direction here.
        let text = "[camera]\neye = [0, 5, 0]\nlook_at = [0, 0, 0]\n";
        let err = load_str(text, Format::Toml, Path::new("s.toml")).unwrap_err();
        let d = &err.diagnostics()[0];
        assert_eq!(d.path.to_string(), "camera.up");
        assert_eq!(d.location, Some(Location { line: 1, column: 2 }));
    }
}
