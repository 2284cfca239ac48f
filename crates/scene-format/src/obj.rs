//! Wavefront OBJ meshes: read (`obj_text.rs`), triangulated, degenerate
//! faces left out and counted.

use crate::budget::Budget;
use crate::diagnostic::Diagnostic;
use crate::images::ImageCache;
use crate::model::{MeshData, MeshFormat, Object, SceneFile, Vec3};
use crate::mtl::Libraries;
use crate::obj_text::{self, Corner, ObjText};
use crate::read::MAX_OBJ_BYTES;
use crate::source::{Folder, Source};
use std::collections::HashMap;
use std::io::{BufRead, Read};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Reads the mesh file (OBJ or PLY) of every mesh of `objects` from
/// `source`, relative to `base` (the folder of the file that lists them).
/// Every file that cannot be read gives a diagnostic at
/// `objects[i].mesh.obj` (or `.ply`), `i` an index of `objects`. The images of their MTL files are read through `images`;
/// the triangles of the files read are taken from `budget`.
pub fn load_object_meshes(
    objects: &mut [Object],
    base: &Path,
    source: &dyn Source,
    (images, budget): (&mut ImageCache, &mut Budget),
) -> Vec<Diagnostic> {
    let mut diagnostics = Vec::new();
    // A file used by several objects is read once and shared; one that
    // failed is not read again (a zip bomb named a thousand times would
    // be inflated a thousand times).
    let mut read: HashMap<PathBuf, Result<Arc<MeshData>, String>> = HashMap::new();
    for (i, object) in objects.iter_mut().enumerate() {
        let Some(mesh) = object.mesh.as_mut() else {
            continue;
        };
        // Neither or both files: validation says so.
        let Some((format, file)) = mesh.file() else {
            continue;
        };
        let path = base.join(file);
        let loaded = read.entry(path).or_insert_with_key(|path| {
            match format {
                MeshFormat::Obj => read_obj_within(source, path, images, budget),
                MeshFormat::Ply => crate::ply::read_ply_within(source, path, budget),
            }
            .map(|mut data| {
                data.skipped_repeated = crate::repeated_faces::drop_repeated(&mut data);
                Arc::new(data)
            })
        });
        match loaded {
            Ok(data) => mesh.data = Some(data.clone()),
            Err(message) => diagnostics.push(Diagnostic::new(
                format!("objects[{i}].mesh.{}", format.key()),
                format!("cannot load `{file}`: {message}"),
            )),
        }
    }
    diagnostics
}

/// Warnings of a loaded scene: meshes with faces left out, and the MTL
/// problems of meshes that take their materials from it (no `material`).
pub fn mesh_warnings(scene: &SceneFile) -> Vec<Diagnostic> {
    let mut warnings = Vec::new();
    for (i, object) in scene.objects.iter().enumerate() {
        let Some(data) = object.mesh.as_ref().and_then(|m| m.data.as_ref()) else {
            continue;
        };
        if object.material.is_none() {
            let key = object.mesh.as_ref().map_or("obj", |m| m.key());
            for message in &data.material_warnings {
                warnings.push(Diagnostic::new(format!("objects[{i}].mesh.{key}"), message));
            }
        }
        if data.skipped_degenerate > 0 {
            let mut message = format!(
                "{} degenerate (zero-area) faces left out",
                data.skipped_degenerate
            );
            if let (Some(line), Some(mesh)) = (data.first_degenerate_line, &object.mesh) {
                let name = Path::new(mesh.path()).file_name().unwrap_or_default();
                message += &format!("; the first at `{}:{line}`", name.to_string_lossy());
            }
            let key = object.mesh.as_ref().map_or("obj", |m| m.key());
            warnings.push(Diagnostic::new(format!("objects[{i}].mesh.{key}"), message));
        }
        if data.skipped_repeated > 0 {
            let key = object.mesh.as_ref().map_or("obj", |m| m.key());
            let message = format!(
                "{} faces left out that repeat an earlier face (the same corners in the same order): every ray through one would test each copy",
                data.skipped_repeated
            );
            warnings.push(Diagnostic::new(format!("objects[{i}].mesh.{key}"), message));
        }
        if let (Some((at, what)), Some(mesh)) = (&data.first_polygon_trouble, &object.mesh) {
            let name = Path::new(mesh.path()).file_name().unwrap_or_default();
            let message = format!(
                "{} faces of more than 3 corners cut as fans from their first corner, which may not be their shape; the first at `{}{at}` is {what}",
                data.polygon_troubles,
                name.to_string_lossy()
            );
            warnings.push(Diagnostic::new(
                format!("objects[{i}].mesh.{}", mesh.key()),
                message,
            ));
        }
    }
    warnings
}

/// The triangles of the OBJ file at `path`. When the file is not a valid
/// OBJ, the message names the first offending line as `<file name>:<line>`.
pub fn read_obj(path: &Path) -> Result<MeshData, String> {
    read_obj_from(&Folder::new(), path, &mut ImageCache::default())
}

/// [`read_obj`] from `source`, the images of its MTL files read through
/// `images`.
pub fn read_obj_from(
    source: &dyn Source,
    path: &Path,
    images: &mut ImageCache,
) -> Result<MeshData, String> {
    read_obj_within(source, path, images, &mut Budget::default())
}

/// [`read_obj_from`], its faces' triangles taken from `budget`.
pub fn read_obj_within(
    source: &dyn Source,
    path: &Path,
    images: &mut ImageCache,
    budget: &mut Budget,
) -> Result<MeshData, String> {
    read_obj_lines(source, path, images, budget).map_err(|failure| {
        let name = path.file_name().unwrap_or(path.as_os_str());
        let name = name.to_string_lossy();
        let scanned = bad_line_in(source, path);
        match (failure.line, scanned) {
            // The scan says what is wrong, on the line the parser stopped at.
            (Some(line), Some((at, what))) if at == line => {
                format!("{}; `{name}:{line}`: {what}", failure.message)
            }
            (Some(line), _) => format!("{}; `{name}:{line}`", failure.message),
            (None, Some((line, what))) => format!("{}; `{name}:{line}`: {what}", failure.message),
            (None, None) => failure.message,
        }
    })
}

/// Why an OBJ file was not read, and the line the parser stopped at.
struct ObjFailure {
    message: String,
    line: Option<usize>,
}

impl From<String> for ObjFailure {
    fn from(message: String) -> Self {
        ObjFailure {
            message,
            line: None,
        }
    }
}

fn read_obj_lines(
    source: &dyn Source,
    path: &Path,
    images: &mut ImageCache,
    budget: &mut Budget,
) -> Result<MeshData, ObjFailure> {
    let mut bytes = Vec::new();
    source
        .open(path, MAX_OBJ_BYTES)
        .and_then(|mut file| file.read_to_end(&mut bytes))
        .map_err(|e| e.to_string())?;
    let mut libraries = Libraries::new(path.parent().unwrap_or(Path::new("")), source);
    let parsed = obj_text::parse(&bytes, &mut libraries, budget);
    drop(bytes);
    let text = parsed.map_err(|e| ObjFailure {
        message: format!("not a valid OBJ file: {}", e.what),
        line: Some(e.line),
    })?;
    let found = libraries.finish(images);
    let mut data = MeshData {
        materials: found.materials,
        material_warnings: found.warnings,
        polygon_troubles: text.polygon_troubles,
        first_polygon_trouble: (text.first_polygon_trouble)
            .map(|(line, trouble)| (format!(":{line}"), trouble.says())),
        ..MeshData::default()
    };
    let first_degenerate =
        add_triangles(&text, &mut data).map_err(|what| format!("not a valid OBJ file: {what}"))?;
    if let Some(k) = first_degenerate {
        data.first_degenerate_line = source
            .open(path, MAX_OBJ_BYTES)
            .ok()
            .and_then(|file| line_of_triangle(file, k));
    }
    if data.triangles.is_empty() {
        return Err("expected at least one face of non-zero area"
            .to_string()
            .into());
    }
    Ok(data)
}

/// Adds the file's triangles to `data`, but for degenerate ones, counted;
/// gives the index among all triangles of the first degenerate one.
fn add_triangles(text: &ObjText, data: &mut MeshData) -> Result<Option<usize>, String> {
    let vertex = |c: Corner| -> Result<Vec3, String> {
        let v = *text
            .positions
            .get(c.v as usize)
            .ok_or("face vertex index out of bounds")?;
        if v.iter().all(|x| x.is_finite()) {
            Ok(v)
        } else {
            Err(format!("vertex {} is not finite: {v:?}", c.v + 1))
        }
    };
    data.triangles.reserve(text.triangles.len());
    data.indices.reserve(text.triangles.len());
    let mut first_degenerate = None;
    for (k, corners) in text.triangles.iter().enumerate() {
        let triangle = [
            vertex(corners[0])?,
            vertex(corners[1])?,
            vertex(corners[2])?,
        ];
        if is_degenerate(&triangle) {
            first_degenerate.get_or_insert(k);
            data.skipped_degenerate += 1;
            continue;
        }
        let normal = corner_values(&text.normals, corners.map(|c| c.vn))
            .map_err(|()| "face normal index out of bounds")?;
        let uv = corner_values(&text.texcoords, corners.map(|c| c.vt))
            .map_err(|()| "face texcoord index out of bounds")?;
        push_triangle(data, triangle, corners.map(|c| c.v), normal, uv);
        if let Some(&material) = text.triangle_materials.get(k) {
            data.triangle_materials.push(material);
        }
    }
    Ok(first_degenerate)
}

/// The values at a triangle's three corners: `None` unless every corner
/// names one (a file without any values may name some); an error for an
/// index past the list's end.
fn corner_values<T: Copy>(values: &[T], indices: [u32; 3]) -> Result<Option<[T; 3]>, ()> {
    if values.is_empty() || indices.contains(&obj_text::NONE) {
        return Ok(None);
    }
    let at = |i: u32| values.get(i as usize).copied().ok_or(());
    Ok(Some([at(indices[0])?, at(indices[1])?, at(indices[2])?]))
}

/// Adds a triangle and what its file says of its corners, keeping the
/// normal and uv lists empty until some triangle has one.
pub(crate) fn push_triangle(
    data: &mut MeshData,
    triangle: [Vec3; 3],
    indices: [u32; 3],
    normals: Option<[Vec3; 3]>,
    uvs: Option<[crate::model::Uv; 3]>,
) {
    let before = data.triangles.len();
    if normals.is_some() || !data.normals.is_empty() {
        data.normals.resize(before, None);
        data.normals.push(normals);
    }
    if uvs.is_some() || !data.uvs.is_empty() {
        data.uvs.resize(before, None);
        data.uvs.push(uvs);
    }
    data.triangles.push(triangle);
    data.indices.push(indices);
}

/// Lines scanned for the offending line of a file not read; the scan
/// runs only on failure, on a file already under `MAX_OBJ_BYTES`.
const MAX_SCAN_LINES: usize = 20_000_000;

/// The first offending line of the OBJ file at `path`, if a scan finds one.
fn bad_line_in(source: &dyn Source, path: &Path) -> Option<(usize, String)> {
    first_bad_line(source.open(path, MAX_OBJ_BYTES).ok()?)
}

/// The first line (counted from 1) of OBJ text that is not valid, or whose
/// face cannot be made a triangle, with what is wrong on it. Indices are
/// checked against the vertices defined so far, negative ones counted back
/// from the last, as OBJ defines them.
fn first_bad_line(reader: impl BufRead) -> Option<(usize, String)> {
    // Positions, texture coordinates and normals defined so far.
    let mut counts = [0usize; 3];
    for (i, line) in reader.split(b'\n').take(MAX_SCAN_LINES).enumerate() {
        let number = i + 1;
        let Ok(line) = line else {
            return Some((number, "the file cannot be read".to_string()));
        };
        let Ok(line) = std::str::from_utf8(&line) else {
            return Some((number, "the line is not UTF-8 text".to_string()));
        };
        if let Err(what) = check_line(line, &mut counts) {
            return Some((number, what));
        }
    }
    None
}

/// The line (counted from 1) of the face that holds triangle `k` (counted
/// from 0): faces keep the file's order, and a face of n vertices makes
/// n - 2 triangles.
fn line_of_triangle(reader: impl BufRead, k: usize) -> Option<usize> {
    let mut triangles = 0;
    for (i, line) in reader.split(b'\n').take(MAX_SCAN_LINES).enumerate() {
        let line = line.ok()?;
        let mut words = line
            .split(|b| b.is_ascii_whitespace())
            .filter(|w| !w.is_empty());
        if words.next() == Some(b"f") {
            triangles += words.count().saturating_sub(2);
            if triangles > k {
                return Some(i + 1);
            }
        }
    }
    None
}

/// Checks one OBJ line, counting the vertices it defines.
fn check_line(line: &str, counts: &mut [usize; 3]) -> Result<(), String> {
    let mut words = line.split_whitespace();
    let keyword = words.next().unwrap_or("");
    let values: Vec<&str> = words.collect();
    // The first `n` values as numbers; what follows them is not read.
    let numbers = |what: &str, n: usize| -> Result<Vec<f32>, String> {
        values[..n]
            .iter()
            .map(|v| {
                v.parse::<f32>()
                    .map_err(|_| format!("expected numbers in a `{what}` line, found `{v}`"))
            })
            .collect()
    };
    match keyword {
        "v" => {
            if !matches!(values.len(), 3 | 4 | 6) {
                return Err(format!(
                    "expected a vertex of 3 coordinates (and a weight or an RGB colour), \
                     found {} values",
                    values.len()
                ));
            }
            // A colour (6 values) is not read, nor checked.
            let v = numbers("v", if values.len() == 4 { 4 } else { 3 })?;
            if values.len() == 4 && v[3] == 0.0 {
                return Err("expected a non-zero vertex weight, found 0".to_string());
            }
            if let Some(x) = v[..3].iter().find(|x| !x.is_finite()) {
                return Err(format!("expected finite coordinates, found {x}"));
            }
            counts[0] += 1;
        }
        "vt" | "vn" => {
            let need = if keyword == "vt" { 2 } else { 3 };
            if values.len() < need {
                return Err(format!(
                    "expected {need} numbers in a `{keyword}` line, found {}",
                    values.len()
                ));
            }
            numbers(keyword, need)?;
            counts[if keyword == "vt" { 1 } else { 2 }] += 1;
        }
        "f" => {
            if values.len() < 3 {
                return Err(format!(
                    "expected a face of at least 3 vertices, found {}",
                    values.len()
                ));
            }
            for value in &values {
                check_face_vertex(value, counts)?;
            }
        }
        _ => {}
    }
    Ok(())
}

/// Checks a face vertex `v`, `v/vt`, `v//vn` or `v/vt/vn`. Texture
/// coordinates and normals are checked only when the file has some (a
/// file without any may name them: they are not used).
fn check_face_vertex(value: &str, counts: &[usize; 3]) -> Result<(), String> {
    const NAMES: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    let parts: Vec<&str> = value.split('/').collect();
    if parts.len() > 3 {
        return Err(format!(
            "expected `v`, `v/vt`, `v//vn` or `v/vt/vn`, found `{value}`"
        ));
    }
    for (k, part) in parts.iter().enumerate() {
        if part.is_empty() && k > 0 {
            continue;
        }
        let Ok(index) = part.parse::<i64>() else {
            return Err(format!(
                "expected a {} index, found `{part}` in `{value}`",
                NAMES[k]
            ));
        };
        if index == 0 {
            return Err(format!(
                "{} index 0 in `{value}`; OBJ indices start at 1",
                NAMES[k]
            ));
        }
        let count = counts[k] as i64;
        if k > 0 && count == 0 {
            continue;
        }
        if index > count || -index > count {
            return Err(format!(
                "{} index {index} in `{value}`, but only {count} defined before this line",
                NAMES[k]
            ));
        }
    }
    Ok(())
}

pub(crate) fn is_degenerate([a, b, c]: &[Vec3; 3]) -> bool {
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
    fn normals_and_uv_are_kept_per_corner_from_the_first_face_on() {
        let dir = tempfile::tempdir().unwrap();
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 2\nvn 0 1 0\nvt 0.5 0.25\nvt 1 1\n\
                    f 1/1/1 2/2/1 3/1/2\nf 2 4 3\n";
        let data = read_obj(&write(dir.path(), "n.obj", text)).unwrap();
        assert_eq!(data.indices, [[0, 1, 2], [1, 3, 2]]);
        let n = [[0.0, 0.0, 2.0], [0.0, 0.0, 2.0], [0.0, 1.0, 0.0]];
        assert_eq!(data.normals[0], Some(n));
        assert_eq!(data.uvs[0], Some([[0.5, 0.25], [1.0, 1.0], [0.5, 0.25]]));
        // A face without them has none, even in a file with some.
        assert_eq!(data.normals.len(), 2);
        assert_eq!((data.normals[1], data.uvs[1]), (None, None));
    }

    #[test]
    fn a_file_without_normals_or_uv_has_none() {
        let dir = tempfile::tempdir().unwrap();
        let data = read_obj(&write(
            dir.path(),
            "p.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        ))
        .unwrap();
        assert!(data.normals.is_empty() && data.uvs.is_empty());
        assert_eq!(data.indices, [[0, 1, 2]]);
    }

    #[test]
    fn quads_are_triangulated_and_degenerate_faces_counted() {
        let dir = tempfile::tempdir().unwrap();
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n\
                    f 1 2 3 4\nf 1 2 5\n";
        let data = read_obj(&write(dir.path(), "quad.obj", text)).unwrap();
        assert_eq!(data.triangles.len(), 2);
        assert_eq!(data.skipped_degenerate, 1);
        assert_eq!(data.first_degenerate_line, Some(7));
        assert_eq!(data.triangles[0][0], [0.0, 0.0, 0.0]);
        assert_eq!(data.triangles[1][2], [0.0, 1.0, 0.0]);
    }

    fn bad(text: &str) -> Option<(usize, String)> {
        first_bad_line(text.as_bytes())
    }

    #[test]
    fn the_scan_finds_the_first_offending_line() {
        let ok = "# a comment\nv 0 0 0\nv 1 0 0 1\nv 0 1 0 0.5 0.5 0.5\nvt 0 0\nvn 0 0 1\n\
                  o thing\nf 1/1/1 2//1 3\nf -3 -2 -1\nl 1 2\nusemtl x\n";
        assert_eq!(bad(ok), None);
        // A vertex colour is not read, so not checked.
        assert_eq!(bad("v 0 1 0 x 0.5 0.5\n"), None);
        // A bad vertex.
        let (line, what) = bad("v 0 0 0\nv 0 0\n").unwrap();
        assert_eq!(line, 2);
        assert!(what.contains("found 2 values"), "{what}");
        let (line, what) = bad("v 0 0 0\n\nv 0 zero 0\n").unwrap();
        assert_eq!(
            (line, what.as_str()),
            (3, "expected numbers in a `v` line, found `zero`")
        );
        assert!(bad("v 0 0 inf\n").unwrap().1.contains("finite"));
        assert!(bad("v 0 0 0 0\n").unwrap().1.contains("weight"));
        assert_eq!(bad("v 0 0 0\nvn 0 1\n").unwrap().0, 2);
        assert_eq!(bad("vt x 0\n").unwrap().0, 1);
        // Bad face indices.
        let three = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
        let (line, what) = bad(&format!("{three}f 1 2 x\n")).unwrap();
        assert_eq!(
            (line, what.as_str()),
            (4, "expected a vertex index, found `x` in `x`")
        );
        let (line, what) = bad(&format!("{three}f 0 1 2\n")).unwrap();
        assert_eq!(line, 4);
        assert!(what.contains("index 0"), "{what}");
        assert!(bad(&format!("{three}f 1 2\n"))
            .unwrap()
            .1
            .contains("found 2"));
        assert!(bad(&format!("{three}f 1/2/3/4 2 3\n")).is_some());
        // Out of range of the vertices defined so far.
        let (line, what) = bad(&format!("f 1 2 3\n{three}")).unwrap();
        assert_eq!(line, 1);
        assert!(
            what.contains("vertex index 1 in `1`, but only 0 defined"),
            "{what}"
        );
        assert_eq!(bad(&format!("{three}f 1 2 4\n")).unwrap().0, 4);
        assert_eq!(bad(&format!("{three}vt 0 0\nf 1/2 2 3\n")).unwrap().0, 5);
        // Negative indices count back from the last vertex defined.
        assert_eq!(bad(&format!("{three}f -1 -2 -3\n")), None);
        let (line, what) = bad(&format!("{three}f -1 -2 -4\n")).unwrap();
        assert_eq!(line, 4);
        assert!(what.contains("vertex index -4"), "{what}");
        assert_eq!(first_bad_line(&b"v 0 0 0\n\xff\n"[..]).unwrap().0, 2);
    }

    #[test]
    fn the_first_degenerate_face_is_found_past_polygons_and_lines() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                    f 1 2 3 4 1\nl 1 2\nf 1 2\n\
                    o other\nf 1 2 3\nl 1 3 4\nf 1 3 3\nf 1 1 2\n";
        // Triangles: 3 from line 5, 1 from line 9, then lines 11 and 12
        // (lines are not faces).
        assert_eq!(line_of_triangle(text.as_bytes(), 0), Some(5));
        assert_eq!(line_of_triangle(text.as_bytes(), 3), Some(9));
        assert_eq!(line_of_triangle(text.as_bytes(), 4), Some(11));
        assert_eq!(line_of_triangle(text.as_bytes(), 5), Some(12));
        assert_eq!(line_of_triangle(text.as_bytes(), 6), None);
        let dir = tempfile::tempdir().unwrap();
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4 1\nf 1 2 3\nf 1 3 3\n";
        let data = read_obj(&write(dir.path(), "fan.obj", text)).unwrap();
        // The fan's last triangle (1 4 1) is degenerate, before line 7's.
        assert_eq!(data.skipped_degenerate, 2);
        assert_eq!(data.first_degenerate_line, Some(5));
    }

    /// Every OBJ of `scenes/`, read by tobj (which read them before): the
    /// same triangles, corner normals, uv and materials.
    #[test]
    fn the_scenes_meshes_read_as_tobj_reads_them() {
        let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
        let files = ["meshes/cube.obj", "meshes/star.obj", "meshes/icosphere.obj"];
        let files = files
            .iter()
            .chain(&["meshes/labelled-box.obj", "bench/bunny.obj"]);
        for file in files {
            let path = scenes.join(file);
            let ours = read_obj(&path).unwrap();
            let options = tobj::LoadOptions {
                triangulate: true,
                ..Default::default()
            };
            let (models, materials) = tobj::load_obj(&path, &options).unwrap();
            let mut triangles = Vec::new();
            for m in &models {
                let mesh = &m.mesh;
                let at = |values: &[f32], n: usize, i: u32| values[i as usize * n..][..n].to_vec();
                for (k, face) in mesh.indices.chunks(3).enumerate() {
                    let corner = |c: usize| {
                        let normal = (!mesh.normals.is_empty())
                            .then(|| at(&mesh.normals, 3, mesh.normal_indices[3 * k + c]));
                        let uv = (!mesh.texcoords.is_empty())
                            .then(|| at(&mesh.texcoords, 2, mesh.texcoord_indices[3 * k + c]));
                        (at(&mesh.positions, 3, face[c]), normal, uv)
                    };
                    triangles.push(([corner(0), corner(1), corner(2)], mesh.material_id));
                }
            }
            assert_eq!(ours.triangles.len(), triangles.len(), "{file}");
            assert_eq!(ours.materials.len(), materials.unwrap().len(), "{file}");
            for (k, (corners, material)) in triangles.iter().enumerate() {
                for (c, (position, normal, uv)) in corners.iter().enumerate() {
                    assert_eq!(ours.triangles[k][c].to_vec(), *position, "{file} {k}");
                    let ours_normal = ours
                        .normals
                        .get(k)
                        .copied()
                        .flatten()
                        .map(|n| n[c].to_vec());
                    assert_eq!(ours_normal, *normal, "{file} {k}");
                    let ours_uv = ours.uvs.get(k).copied().flatten().map(|n| n[c].to_vec());
                    assert_eq!(ours_uv, *uv, "{file} {k}");
                }
                let ours_material = ours.triangle_material(k).map(|m| m as usize);
                assert_eq!(ours_material, *material, "{file} {k}");
            }
        }
    }

    /// Lines put together from OBJ words, numbers and junk: each file is
    /// read or refused, never a panic.
    #[test]
    fn any_jumble_of_obj_words_is_read_or_refused() {
        let words = [
            "v",
            "vt",
            "vn",
            "f",
            "l",
            "o",
            "g",
            "usemtl",
            "mtllib",
            "#",
            "1",
            "-1",
            "0",
            "2/1",
            "3//2",
            "-2/-1/-1",
            "1/2/3/4",
            "/",
            "//",
            "1e38",
            "-1e39",
            "nan",
            "inf",
            "0.5",
            "99999999999",
            "-4294967296",
            "4294967295",
            "\u{e9}",
            "\t",
            "\r",
        ];
        let mut below = obj_text::below(0x2545_F491_4F6C_DD1D);
        let mut next = |n: usize| below(n as u64) as usize;
        let (mut read, mut refused) = (0, 0);
        for _ in 0..4_000 {
            let mut obj = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
            for _ in 0..next(8) {
                for _ in 0..next(6) {
                    obj += words[next(words.len())];
                    obj += " ";
                }
                obj += "\n";
            }
            // The faces' vertices are checked when the triangles are made.
            let mut data = MeshData::default();
            match obj_text::parse(
                obj.as_bytes(),
                &mut obj_text::NoLibraries,
                &mut Budget::default(),
            ) {
                Ok(text) if add_triangles(&text, &mut data).is_ok() => read += 1,
                _ => refused += 1,
            }
        }
        // Both kinds of file came up, so both paths ran.
        assert!(
            read > 100 && refused > 100,
            "{read} read, {refused} refused"
        );
    }

    /// A folder that counts the files opened.
    #[derive(Default)]
    struct Counting {
        folder: Folder,
        opened: std::cell::Cell<usize>,
    }

    impl Source for Counting {
        fn open(&self, path: &Path, cap: u64) -> std::io::Result<Box<dyn BufRead + '_>> {
            self.opened.set(self.opened.get() + 1);
            self.folder.open(path, cap)
        }
        fn name(&self, path: &Path) -> PathBuf {
            self.folder.name(path)
        }
        fn identity(&self, path: &Path) -> PathBuf {
            self.folder.identity(path)
        }
        fn files_read(&self) -> Vec<PathBuf> {
            self.folder.files_read()
        }
    }

    #[test]
    fn a_file_that_failed_is_not_read_again_for_each_object() {
        let dir = tempfile::tempdir().unwrap();
        write(dir.path(), "bad.obj", "v 0 0 0\nf 1 2 3\n");
        let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n".to_string()
            + &"[[objects]]\nmesh = { obj = \"bad.obj\" }\n".repeat(50);
        let mut scene = crate::load_str(&text, crate::Format::Toml, Path::new("s.toml")).unwrap();
        let source = Counting::default();
        let read = (&mut ImageCache::default(), &mut Budget::default());
        let diagnostics = load_object_meshes(&mut scene.objects, dir.path(), &source, read);
        // Each object is told, but the file was read once (and scanned
        // once more for its bad line).
        assert_eq!(diagnostics.len(), 50);
        assert!(source.opened.get() <= 2, "{} opens", source.opened.get());
    }

    #[test]
    fn polygons_are_counted_against_the_budget_before_they_are_built() {
        let dir = tempfile::tempdir().unwrap();
        let corners: String = (1..=1000).map(|i| format!(" {}", i % 3 + 1)).collect();
        let path = write(
            dir.path(),
            "many.obj",
            &format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nf{corners}\n"),
        );
        let (source, images) = (Folder::new(), &mut ImageCache::default());
        let error = read_obj_within(&source, &path, images, &mut Budget::of(997)).unwrap_err();
        assert!(error.contains(crate::budget::TOO_MANY), "{error}");
        assert!(error.contains("`many.obj:4`"), "{error}");
        assert!(read_obj_within(&source, &path, images, &mut Budget::of(998)).is_ok());
    }

    #[test]
    fn errors_name_the_file_and_line() {
        let dir = tempfile::tempdir().unwrap();
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 -7\n";
        let error = read_obj(&write(dir.path(), "bunny.obj", text)).unwrap_err();
        assert!(error.contains("`bunny.obj:5`: vertex index -7"), "{error}");
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

#[cfg(test)]
mod polygon_tests {
    use super::*;

    #[test]
    fn a_concave_face_keeps_its_shape_and_a_crossed_one_is_said_with_its_line() {
        let dir = tempfile::tempdir().unwrap();
        // An L (area 3, its notch the square (1..2, 1..2)) from a corner
        // whose fan covered the notch; then a bow tie on line 14.
        let text = "v 0 2 0\nv 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nf 1 2 3 4 5 6\n\
                    v 0 0 1\nv 1 1 1\nv 1 0 1\nv 0 1 1\nv -0.5 0.5 1\n\n\
                    f 7 8 9 10 11\n";
        let path = dir.path().join("l.obj");
        std::fs::write(&path, text).unwrap();
        let data = read_obj(&path).unwrap();
        assert_eq!(data.triangles.len(), 4 + 3);
        assert_eq!(crate::polygon::flat_area(&data.triangles[..4]), 3.0);
        assert_eq!(data.polygon_troubles, 1);
        assert_eq!(
            data.first_polygon_trouble,
            Some((":14".to_string(), "self-intersecting"))
        );
    }
}
