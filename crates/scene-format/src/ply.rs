//! PLY meshes (the Stanford format scanners write, ASCII or binary), read
//! with `ply-rs-bw`: vertices with optional normals (`nx ny nz`) and texture
//! coordinates (`u v`, `s t` or `texture_u texture_v`), faces made fans of
//! triangles, degenerate ones left out and counted.

use crate::model::{MeshData, Uv, Vec3};
use crate::obj::{is_degenerate, push_triangle};
use crate::source::Source;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{Header, Property, PropertyAccess, PropertyAccessResult};
use std::path::Path;

/// The triangles of the PLY file at `path`, or what is wrong with it.
pub fn read_ply(path: &Path) -> Result<MeshData, String> {
    read_ply_from(&crate::source::Folder::new(), path)
}

/// [`read_ply`] from `source`.
pub fn read_ply_from(source: &dyn Source, path: &Path) -> Result<MeshData, String> {
    let file = source
        .open(path, crate::read::MAX_OBJ_BYTES)
        .map_err(|e| e.to_string())?;
    let mut reader = Reader::new(file);
    let (vertices, faces) = read_elements(&mut reader).map_err(|e| {
        // The parser's first line says what and where; the rest repeats
        // the I/O error beneath it.
        let text = e.to_string();
        let what = text
            .lines()
            .next()
            .unwrap_or_default()
            .trim_end_matches('.');
        if e.kind() == std::io::ErrorKind::UnexpectedEof {
            format!("not a valid PLY file: it ends before the data its header declares ({what})")
        } else {
            format!("not a valid PLY file: {what}")
        }
    })?;
    let vertices = vertices.ok_or("expected a `vertex` element with x, y, z")?;
    let faces = faces.ok_or("expected a `face` element with `vertex_indices`")?;
    triangles(&vertices, &faces)
}

type Elements = (Option<Vec<PlyVertex>>, Option<Vec<PlyFace>>);

/// The `vertex` and `face` elements of the file; other elements (edges,
/// materials) are read past.
fn read_elements<R: std::io::BufRead>(
    reader: &mut Reader<R>,
) -> Result<Elements, ply_rs_bw::parser::ParseError> {
    let header: Header = Parser::<Skipped>::new().read_header(reader)?;
    let (mut vertices, mut faces) = (None, None);
    for (name, element) in &header.elements {
        match name.as_str() {
            "vertex" => {
                let parser = Parser::<PlyVertex>::new();
                let read = parser.read_payload_for_element(reader, element, &header)?;
                let has = |p: &str| element.properties.contains_key(p);
                if ["x", "y", "z"].iter().all(|p| has(p)) {
                    vertices = Some(read);
                }
            }
            "face" => {
                let parser = Parser::<PlyFace>::new();
                faces = Some(parser.read_payload_for_element(reader, element, &header)?);
            }
            _ => {
                Parser::<Skipped>::new().read_payload_for_element(reader, element, &header)?;
            }
        }
    }
    Ok((vertices, faces))
}

/// The mesh of the file's vertices and faces, each face a fan from its
/// first vertex (a convex polygon's triangulation).
fn triangles(vertices: &[PlyVertex], faces: &[PlyFace]) -> Result<MeshData, String> {
    let position = |i: u32| -> Result<&PlyVertex, String> {
        let v = vertices.get(i as usize).ok_or_else(|| {
            format!(
                "vertex index {i} in a face, but only {} vertices",
                vertices.len()
            )
        })?;
        if v.position.iter().all(|x| x.is_finite()) {
            Ok(v)
        } else {
            Err(format!("vertex {i} is not finite: {:?}", v.position))
        }
    };
    let mut data = MeshData::default();
    for (f, face) in faces.iter().enumerate() {
        if face.indices.len() < 3 {
            return Err(format!(
                "face {f}: expected at least 3 vertices, found {}",
                face.indices.len()
            ));
        }
        for k in 1..face.indices.len() - 1 {
            let ids = [face.indices[0], face.indices[k], face.indices[k + 1]];
            let corners = [position(ids[0])?, position(ids[1])?, position(ids[2])?];
            let triangle = corners.map(|v| v.position);
            if is_degenerate(&triangle) {
                data.skipped_degenerate += 1;
                continue;
            }
            let normals = corners.iter().all(|v| v.normal.is_some());
            let uvs = corners.iter().all(|v| v.uv.is_some());
            push_triangle(
                &mut data,
                triangle,
                ids,
                normals.then(|| corners.map(|v| v.normal.unwrap_or_default())),
                uvs.then(|| corners.map(|v| v.uv.unwrap_or_default())),
            );
        }
    }
    if data.triangles.is_empty() {
        return Err("expected at least one face of non-zero area".to_string());
    }
    Ok(data)
}

/// One vertex: its position, and its normal and uv when it has all of them.
#[derive(Debug, Default)]
struct PlyVertex {
    position: Vec3,
    normal: Option<Vec3>,
    uv: Option<Uv>,
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        PlyVertex::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        let Some(x) = property.to_f32_lossy() else {
            return PropertyAccessResult::Ignored;
        };
        let (normal, uv) = (&mut self.normal, &mut self.uv);
        match name {
            "x" => self.position[0] = x,
            "y" => self.position[1] = x,
            "z" => self.position[2] = x,
            "nx" => normal.get_or_insert_with(Default::default)[0] = x,
            "ny" => normal.get_or_insert_with(Default::default)[1] = x,
            "nz" => normal.get_or_insert_with(Default::default)[2] = x,
            "u" | "s" | "texture_u" => uv.get_or_insert_with(Default::default)[0] = x,
            "v" | "t" | "texture_v" => uv.get_or_insert_with(Default::default)[1] = x,
            _ => return PropertyAccessResult::Ignored,
        }
        PropertyAccessResult::Set
    }
}

/// One face: its vertex indices.
#[derive(Debug, Default)]
struct PlyFace {
    indices: Vec<u32>,
}

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        PlyFace::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        if name != "vertex_indices" && name != "vertex_index" {
            return PropertyAccessResult::Ignored;
        }
        // A negative index is no vertex: made out of range, so reported.
        let index = |i: i64| u32::try_from(i).unwrap_or(u32::MAX);
        self.indices = match property {
            Property::ListChar(v) => v.into_iter().map(|i| index(i.into())).collect(),
            Property::ListUChar(v) => v.into_iter().map(u32::from).collect(),
            Property::ListShort(v) => v.into_iter().map(|i| index(i.into())).collect(),
            Property::ListUShort(v) => v.into_iter().map(u32::from).collect(),
            Property::ListInt(v) => v.into_iter().map(|i| index(i.into())).collect(),
            Property::ListUInt(v) => v,
            _ => return PropertyAccessResult::Ignored,
        };
        PropertyAccessResult::Set
    }
}

/// An element read past.
struct Skipped;

impl PropertyAccess for Skipped {
    fn new() -> Self {
        Skipped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &[u8]) -> Result<MeshData, String> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.ply");
        std::fs::write(&path, text).unwrap();
        read_ply(&path)
    }

    const HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n\
                          property float y\nproperty float z\nelement face 2\n\
                          property list uchar int vertex_indices\nend_header\n";

    #[test]
    fn a_quad_becomes_a_fan_and_degenerate_triangles_are_counted() {
        let text = format!("{HEADER}0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n4 0 1 2 3\n3 0 1 4\n");
        let data = read(text.as_bytes()).unwrap();
        let v = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert_eq!(data.triangles, [[v[0], v[1], v[2]], [v[0], v[2], v[3]]]);
        assert_eq!(data.indices, [[0, 1, 2], [0, 2, 3]]);
        assert_eq!(data.skipped_degenerate, 1);
        assert!(data.normals.is_empty() && data.uvs.is_empty());
    }

    #[test]
    fn normals_and_uv_are_read_with_the_vertices() {
        let text = "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 3\n\
                    property double x\nproperty double y\nproperty double z\n\
                    property float nx\nproperty float ny\nproperty float nz\n\
                    property float s\nproperty float t\nproperty uchar red\n\
                    element face 1\nproperty list uchar uint vertex_index\n\
                    element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n\
                    0 0 0 0 0 1 0 0 255\n1 0 0 0 0.6 0.8 1 0 0\n0 1 0 0 0 1 0 1 7\n3 0 1 2\n0 1\n";
        let data = read(text.as_bytes()).unwrap();
        let n = [[0.0, 0.0, 1.0], [0.0, 0.6, 0.8], [0.0, 0.0, 1.0]];
        assert_eq!(data.normals, [Some(n)]);
        assert_eq!(data.uvs, [Some([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])]);
    }

    #[test]
    fn malformed_files_say_what_is_wrong() {
        let error = |text: &str| read(text.as_bytes()).unwrap_err();
        let out_of_range = format!("{HEADER}0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 9\n");
        assert!(
            error(&out_of_range).contains("vertex index 9 in a face, but only 5 vertices"),
            "{}",
            error(&out_of_range)
        );
        let negative = format!("{HEADER}0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 -1\n");
        assert!(
            error(&negative).contains("vertex index"),
            "{}",
            error(&negative)
        );
        let two = format!("{HEADER}0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n3 0 1 2\n2 0 1\n");
        assert!(error(&two).contains("face 1: expected at least 3 vertices, found 2"));
        let word = format!("{HEADER}0 0 zero\n");
        assert!(
            error(&word).starts_with("not a valid PLY file: "),
            "{}",
            error(&word)
        );
        assert!(error("solid cube\n").starts_with("not a valid PLY file"));
        let no_faces = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n\
                        property float y\nproperty float z\nend_header\n0 0 0\n";
        assert!(error(no_faces).contains("expected a `face` element"));
        let infinite = format!("{HEADER}0 0 inf\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 3\n");
        assert!(read(infinite.as_bytes()).is_err());
    }

    #[test]
    fn binary_big_endian_reads_as_little_endian() {
        let header = |format: &str| {
            format!(
                "ply\nformat {format} 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                 property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
            )
        };
        let vertices = [0.5f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.25];
        let (mut little, mut big) = (
            header("binary_little_endian").into_bytes(),
            header("binary_big_endian").into_bytes(),
        );
        for x in vertices {
            little.extend(x.to_le_bytes());
            big.extend(x.to_be_bytes());
        }
        little.push(3);
        big.push(3);
        for i in [0i32, 1, 2] {
            little.extend(i.to_le_bytes());
            big.extend(i.to_be_bytes());
        }
        let data = read(&little).unwrap();
        assert_eq!(
            data.triangles,
            [[[0.5, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.25]]]
        );
        assert_eq!(read(&big).unwrap(), data);
        let truncated = read(&little[..little.len() - 2]).unwrap_err();
        assert!(
            truncated.contains("ends before the data its header declares"),
            "{truncated}"
        );
    }
}
