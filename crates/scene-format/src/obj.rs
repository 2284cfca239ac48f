//! Wavefront OBJ meshes: read with `tobj`, triangulated, degenerate faces
//! left out and counted.

use crate::diagnostic::Diagnostic;
use crate::model::{MeshData, SceneFile, Vec3};
use std::collections::HashMap;
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Reads the OBJ file of every mesh object, relative to `base` (the scene
/// file's folder). Every file that cannot be read gives a diagnostic at
/// `objects[i].mesh.obj`.
pub fn load_meshes(scene: &mut SceneFile, base: &Path) -> Vec<Diagnostic> {
    let mut diagnostics = Vec::new();
    // A file used by several objects is read once and shared.
    let mut read: HashMap<PathBuf, Arc<MeshData>> = HashMap::new();
    for (i, object) in scene.objects.iter_mut().enumerate() {
        let Some(mesh) = object.mesh.as_mut() else {
            continue;
        };
        let path = base.join(&mesh.obj);
        if let Some(data) = read.get(&path) {
            mesh.data = Some(data.clone());
            continue;
        }
        match read_obj(&path) {
            Ok(data) => {
                let data = Arc::new(data);
                read.insert(path, data.clone());
                mesh.data = Some(data);
            }
            Err(message) => diagnostics.push(Diagnostic::new(
                format!("objects[{i}].mesh.obj"),
                format!("cannot load `{}`: {message}", mesh.obj),
            )),
        }
    }
    diagnostics
}

/// Warnings of a loaded scene: meshes with faces left out.
pub fn mesh_warnings(scene: &SceneFile) -> Vec<Diagnostic> {
    let mut warnings = Vec::new();
    for (i, object) in scene.objects.iter().enumerate() {
        let Some(data) = object.mesh.as_ref().and_then(|m| m.data.as_ref()) else {
            continue;
        };
        if data.skipped_degenerate > 0 {
            warnings.push(Diagnostic::new(
                format!("objects[{i}].mesh.obj"),
                format!(
                    "{} degenerate (zero-area) faces left out",
                    data.skipped_degenerate
                ),
            ));
        }
    }
    warnings
}

/// The triangles of the OBJ file at `path`.
pub fn read_obj(path: &Path) -> Result<MeshData, String> {
    let file =
        crate::read::open_capped(path, crate::read::MAX_OBJ_BYTES).map_err(|e| e.to_string())?;
    let options = tobj::LoadOptions {
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    // Materials of the OBJ are not used: the scene file gives the material.
    let (models, _) = tobj::load_obj_buf(&mut BufReader::new(file), &options, |_| {
        Err(tobj::LoadError::GenericFailure)
    })
    .map_err(|e| format!("not a valid OBJ file: {e}"))?;
    let mut data = MeshData::default();
    for model in &models {
        add_model(&model.mesh, &mut data)?;
    }
    if data.triangles.is_empty() {
        return Err("expected at least one face of non-zero area".to_string());
    }
    Ok(data)
}

fn add_model(mesh: &tobj::Mesh, data: &mut MeshData) -> Result<(), String> {
    let vertex = |index: u32| -> Result<Vec3, String> {
        let i = index as usize * 3;
        let p = mesh
            .positions
            .get(i..i + 3)
            .ok_or_else(|| format!("face vertex {} does not exist", index + 1))?;
        let v = [p[0], p[1], p[2]];
        if v.iter().all(|x| x.is_finite()) {
            Ok(v)
        } else {
            Err(format!("vertex {} is not finite: {v:?}", index + 1))
        }
    };
    for face in mesh.indices.chunks_exact(3) {
        let triangle = [vertex(face[0])?, vertex(face[1])?, vertex(face[2])?];
        if is_degenerate(&triangle) {
            data.skipped_degenerate += 1;
        } else {
            data.triangles.push(triangle);
        }
    }
    Ok(())
}

fn is_degenerate([a, b, c]: &[Vec3; 3]) -> bool {
    let e1 = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let e2 = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    n == [0.0; 3]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn quads_are_triangulated_and_degenerate_faces_counted() {
        let dir = tempfile::tempdir().unwrap();
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n\
                    f 1 2 3 4\nf 1 2 5\n";
        let data = read_obj(&write(dir.path(), "quad.obj", text)).unwrap();
        assert_eq!(data.triangles.len(), 2);
        assert_eq!(data.skipped_degenerate, 1);
        assert_eq!(data.triangles[0][0], [0.0, 0.0, 0.0]);
        assert_eq!(data.triangles[1][2], [0.0, 1.0, 0.0]);
    }

    #[test]
    fn missing_and_corrupt_files_are_errors() {
        let dir = tempfile::tempdir().unwrap();
        let missing = read_obj(&dir.path().join("none.obj")).unwrap_err();
        assert!(missing.contains("No such file"), "{missing}");
        let corrupt = write(dir.path(), "bad.obj", "v 0 0 zero\nf 1 2 3\n");
        assert!(read_obj(&corrupt).unwrap_err().contains("not a valid OBJ"));
        let out_of_range = write(dir.path(), "range.obj", "v 0 0 0\nf 1 2 3\n");
        assert!(read_obj(&out_of_range).is_err());
        let empty = write(dir.path(), "empty.obj", "v 0 0 0\n");
        assert!(read_obj(&empty).unwrap_err().contains("at least one face"));
    }
}
