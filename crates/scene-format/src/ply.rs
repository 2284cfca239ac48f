//! PLY meshes (the Stanford format scanners write, ASCII or binary), read
//! with `ply-rs-bw` one record at a time: vertices with optional normals
//! (`nx ny nz`) and texture coordinates (`u v`, `s t` or `texture_u
//! texture_v`), faces made triangles, degenerate ones left out and counted.
//! Every count in the header is checked against the bytes that follow it
//! before anything is read, and faces are counted against the scene's
//! triangle budget before any triangle is built.

use crate::budget::{Budget, MAX_VERTICES};
use crate::model::{MeshData, Uv, Vec3};
use crate::obj::{is_degenerate, push_triangle};
use crate::source::Source;
use ply_rs_bw::parser::{ParseError, Parser, Reader};
use ply_rs_bw::ply::{
    ElementDef, Encoding, Header, Property, PropertyAccess, PropertyAccessResult, PropertyType,
    ScalarType,
};
use std::io::{BufRead, Cursor};
use std::path::Path;

/// The triangles of the PLY file at `path`, or what is wrong with it.
pub fn read_ply(path: &Path) -> Result<MeshData, String> {
    read_ply_from(&crate::source::Folder::new(), path)
}

/// [`read_ply`] from `source`.
pub fn read_ply_from(source: &dyn Source, path: &Path) -> Result<MeshData, String> {
    read_ply_within(source, path, &mut Budget::default())
}

/// [`read_ply_from`], its faces' triangles taken from `budget`.
pub fn read_ply_within(
    source: &dyn Source,
    path: &Path,
    budget: &mut Budget,
) -> Result<MeshData, String> {
    let bytes = source
        .read(path, crate::read::MAX_OBJ_BYTES)
        .map_err(|e| e.to_string())?;
    read_ply_bytes(&bytes, budget)
}

/// The mesh of a PLY file's bytes.
pub fn read_ply_bytes(bytes: &[u8], budget: &mut Budget) -> Result<MeshData, String> {
    let mut reader = Reader::new(Cursor::new(bytes));
    let header = Parser::<Skipped>::new()
        .read_header(&mut reader)
        .map_err(|e| invalid(&e))?;
    let payload = bytes.len() as u64 - reader.get_ref().position();
    check_counts(&header, payload)?;
    let (vertices, faces) = read_elements(&mut reader, &header, budget)?;
    let vertices = vertices.ok_or("expected a `vertex` element with x, y, z")?;
    let faces = faces.ok_or("expected a `face` element with `vertex_indices`")?;
    triangles(&vertices, &faces)
}

/// The parser's error as a message: its first line says what and where;
/// the rest repeats the I/O error beneath it.
fn invalid(e: &ParseError) -> String {
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
}

/// Checks that the records the header declares fit in the `payload` bytes
/// after it, each at least its smallest size, so no count can make the
/// reader loop or allocate beyond the file.
fn check_counts(header: &Header, payload: u64) -> Result<(), String> {
    let mut needed = 0u64;
    for element in header.elements.values() {
        let least = least_record_bytes(element, header.encoding);
        let count = element.count as u64;
        let bytes = count.checked_mul(least).and_then(|b| b.checked_add(needed));
        match bytes {
            Some(b) if b <= payload => needed = b,
            _ => {
                let plural = |n: u64| if n == 1 { "" } else { "s" };
                let before = if needed > 0 {
                    format!(", after {needed} bytes of the elements before it")
                } else {
                    String::new()
                };
                return Err(format!(
                    "not a valid PLY file: it ends before the data its header declares: at least {} bytes \
                     (element `{}`: {count} record{} of at least {least} byte{}{before}), more than the \
                     {payload} bytes after the header",
                    count.saturating_mul(least).saturating_add(needed),
                    element.name.escape_debug(),
                    plural(count),
                    plural(least),
                ));
            }
        }
    }
    let vertices = header.elements.get("vertex").map_or(0, |e| e.count);
    if vertices > MAX_VERTICES {
        return Err(format!(
            "declares {vertices} vertices; expected at most {MAX_VERTICES} (three for each triangle the tracer builds)"
        ));
    }
    Ok(())
}

/// The fewest bytes a record of `element` takes: in binary its scalars and
/// list lengths, in ASCII a character for each value and a space or line
/// end between them (a record without properties is an empty line).
fn least_record_bytes(element: &ElementDef, encoding: Encoding) -> u64 {
    let properties = element.properties.len() as u64;
    match encoding {
        Encoding::Ascii => (2 * properties).saturating_sub(1).max(1),
        Encoding::BinaryBigEndian | Encoding::BinaryLittleEndian => element
            .properties
            .values()
            .map(|p| match &p.data_type {
                PropertyType::Scalar(t) | PropertyType::List(t, _) => scalar_bytes(t),
            })
            .sum(),
    }
}

fn scalar_bytes(t: &ScalarType) -> u64 {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// The faces of a file: each face's corners, one after another.
#[derive(Debug, Default)]
struct Faces {
    corners: Vec<u32>,
    /// Where each face's corners end in `corners`.
    ends: Vec<u32>,
}

type Elements = (Option<Vec<PlyVertex>>, Option<Faces>);

/// The `vertex` and `face` elements of the file; other elements (edges,
/// materials) are read past.
fn read_elements(
    reader: &mut Reader<Cursor<&[u8]>>,
    header: &Header,
    budget: &mut Budget,
) -> Result<Elements, String> {
    let (mut vertices, mut faces) = (None, None);
    for (name, element) in &header.elements {
        match name.as_str() {
            "vertex" => {
                let mut read = Vec::with_capacity(element.count.min(1 << 16));
                each_record(reader, header, element, |_, v: PlyVertex| {
                    read.push(v);
                    Ok(())
                })?;
                let has = |p: &str| element.properties.contains_key(p);
                if ["x", "y", "z"].iter().all(|p| has(p)) {
                    vertices = Some(read);
                }
            }
            "face" => faces = Some(read_faces(reader, header, element, budget)?),
            _ => skip(reader, header, element)?,
        }
    }
    Ok((vertices, faces))
}

/// The faces of `element`, each counted against `budget` as it is read.
fn read_faces(
    reader: &mut Reader<Cursor<&[u8]>>,
    header: &Header,
    element: &ElementDef,
    budget: &mut Budget,
) -> Result<Faces, String> {
    let lists = ["vertex_indices", "vertex_index"];
    if !lists.iter().any(|p| element.properties.contains_key(*p)) {
        return Err("expected a `face` element with `vertex_indices`".to_string());
    }
    let mut faces = Faces::default();
    each_record(reader, header, element, |f, face: PlyFace| {
        let corners = face.corners(f)?;
        if corners.len() < 3 {
            return Err(format!(
                "face {f}: expected at least 3 vertices, found {}",
                corners.len()
            ));
        }
        budget.take(corners.len() - 2)?;
        faces.corners.extend(corners);
        // Within the budget's triangles, the corners fit in u32.
        faces.ends.push(faces.corners.len() as u32);
        Ok(())
    })?;
    Ok(faces)
}

/// Reads past `element`: a binary one of fixed-size records at once, others
/// record by record (the counts were checked against the file's size).
fn skip(
    reader: &mut Reader<Cursor<&[u8]>>,
    header: &Header,
    element: &ElementDef,
) -> Result<(), String> {
    let scalars = element
        .properties
        .values()
        .all(|p| matches!(p.data_type, PropertyType::Scalar(_)));
    if scalars && header.encoding != Encoding::Ascii {
        let size = least_record_bytes(element, header.encoding) * element.count as u64;
        let cursor = reader.get_mut();
        cursor.set_position(cursor.position() + size);
        return Ok(());
    }
    each_record(reader, header, element, |_, _: Skipped| Ok(()))
}

/// Reads the records of `element` one at a time, handing each to `each`
/// with its index.
fn each_record<E: PropertyAccess>(
    reader: &mut Reader<Cursor<&[u8]>>,
    header: &Header,
    element: &ElementDef,
    mut each: impl FnMut(usize, E) -> Result<(), String>,
) -> Result<(), String> {
    let parser = Parser::<E>::new();
    let mut line = String::new();
    for i in 0..element.count {
        let cursor = reader.get_mut();
        let record = match header.encoding {
            Encoding::Ascii => {
                line.clear();
                let read = cursor.read_line(&mut line).map_err(|e| e.to_string())?;
                if read == 0 {
                    return Err(ends_early(element, i));
                }
                parser.read_ascii_element(&line, element)
            }
            Encoding::BinaryBigEndian => parser.read_big_endian_element(cursor, element),
            Encoding::BinaryLittleEndian => parser.read_little_endian_element(cursor, element),
        };
        let record = record.map_err(|e| match e.kind() {
            std::io::ErrorKind::UnexpectedEof => ends_early(element, i),
            _ => format!(
                "{} (`{}` record {i})",
                invalid(&e),
                element.name.escape_debug()
            ),
        })?;
        each(i, record)?;
    }
    Ok(())
}

fn ends_early(element: &ElementDef, i: usize) -> String {
    format!(
        "not a valid PLY file: it ends before the data its header declares (`{}` record {i} of {})",
        element.name.escape_debug(),
        element.count
    )
}

/// The mesh of the file's vertices and faces, each face cut into triangles
/// as `polygon` says (a convex one as a fan from its first vertex).
fn triangles(vertices: &[PlyVertex], faces: &Faces) -> Result<MeshData, String> {
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
    let mut start = 0;
    let mut clip_work = crate::polygon::CLIP_WORK;
    for (f, &end) in faces.ends.iter().enumerate() {
        let face = &faces.corners[start..end as usize];
        start = end as usize;
        let cut = if face.len() == 3 {
            vec![[0, 1, 2]]
        } else {
            let points = (face.iter())
                .map(|&i| position(i).map(|v| v.position))
                .collect::<Result<Vec<_>, _>>()?;
            let (cut, trouble) = crate::polygon::triangulate(&points, &mut clip_work);
            if let Some(trouble) = trouble {
                data.polygon_troubles += 1;
                (data.first_polygon_trouble).get_or_insert((format!(" face {f}"), trouble.says()));
            }
            cut
        };
        for [a, b, c] in cut {
            let ids = [face[a], face[b], face[c]];
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

/// One face: its vertex indices as the file writes them, or what kind of
/// list it holds instead of integers.
#[derive(Debug, Default)]
struct PlyFace {
    indices: Vec<i64>,
    not_integers: Option<&'static str>,
}

impl PlyFace {
    /// The face's corners as vertex indices, or why they are none.
    fn corners(self, f: usize) -> Result<Vec<u32>, String> {
        if let Some(kind) = self.not_integers {
            return Err(format!(
                "face {f}: its `vertex_indices` are {kind}; expected integers"
            ));
        }
        self.indices
            .into_iter()
            .map(|i| {
                u32::try_from(i)
                    .map_err(|_| format!("face {f}: vertex index {i}; expected indices from 0 up"))
            })
            .collect()
    }
}

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        PlyFace::default()
    }

    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        if name != "vertex_indices" && name != "vertex_index" {
            return PropertyAccessResult::Ignored;
        }
        let wide = |v: Vec<i64>| (v, None);
        (self.indices, self.not_integers) = match property {
            Property::ListChar(v) => wide(v.into_iter().map(i64::from).collect()),
            Property::ListUChar(v) => wide(v.into_iter().map(i64::from).collect()),
            Property::ListShort(v) => wide(v.into_iter().map(i64::from).collect()),
            Property::ListUShort(v) => wide(v.into_iter().map(i64::from).collect()),
            Property::ListInt(v) => wide(v.into_iter().map(i64::from).collect()),
            Property::ListUInt(v) => wide(v.into_iter().map(i64::from).collect()),
            Property::ListFloat(_) | Property::ListDouble(_) => (Vec::new(), Some("floats")),
            _ => (Vec::new(), Some("a single number, not a list")),
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
    fn a_concave_face_keeps_its_shape_and_a_crossed_one_is_said() {
        let header = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\n\
                      property float y\nproperty float z\nelement face 2\n\
                      property list uchar int vertex_indices\nend_header\n";
        // An L of area 3 from a corner whose fan covered its notch, then a
        // bow tie (face 1).
        let l = "0 2 0\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n";
        let data = read(format!("{header}{l}6 0 1 2 3 4 5\n4 0 2 1 3\n").as_bytes()).unwrap();
        assert_eq!(crate::polygon::flat_area(&data.triangles[..4]), 3.0);
        assert_eq!(data.polygon_troubles, 1);
        assert_eq!(
            data.first_polygon_trouble,
            Some((" face 1".to_string(), "self-intersecting"))
        );
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

    /// A header of `elements` (already with their properties), binary
    /// little-endian, followed by `payload`.
    fn binary(elements: &str, payload: &[u8]) -> Vec<u8> {
        let mut bytes =
            format!("ply\nformat binary_little_endian 1.0\n{elements}end_header\n").into_bytes();
        bytes.extend_from_slice(payload);
        bytes
    }

    #[test]
    fn counts_beyond_the_file_are_refused_before_reading() {
        let start = std::time::Instant::now();
        // An element without properties: 4e9 records of no bytes each.
        let empty = binary(
            "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
             element nothing 4000000000\nelement face 1\nproperty list uchar int vertex_indices\n",
            &[[0; 36].as_slice(), &[3], &[0; 12]].concat(),
        );
        // Its records take no bytes: read past at once, not one by one.
        let error = read(&empty).unwrap_err();
        assert!(error.contains("non-zero area"), "{error}");
        // The same count of vertices is refused by the vertex cap.
        let vertices = binary("element vertex 4000000000\n", &[]);
        let error = read(&vertices).unwrap_err();
        assert!(error.contains("4000000000 vertices"), "{error}");
        // A count near 2^64 of records of a byte each.
        let skipped = binary(
            "element junk 18446744073709551615\nproperty uchar a\n",
            &[0; 8],
        );
        let error = read(&skipped).unwrap_err();
        assert!(error.contains("18446744073709551615 records"), "{error}");
        // One face too many for what the vertices leave: the need in all.
        let short = binary(
            "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
             element face 1\nproperty list uchar int vertex_indices\n",
            &[0; 48],
        );
        let error = read(&short).unwrap_err();
        assert!(
            error.contains("at least 49 bytes (element `face`: 1 record of at least 1 byte, after 48 bytes of the elements before it), more than the 48 bytes"),
            "{error}"
        );
        let ascii = "ply\nformat ascii 1.0\nelement junk 18446744073709551615\n\
                     property list uchar int a\nend_header\n0\n";
        let error = read(ascii.as_bytes()).unwrap_err();
        assert!(error.contains("more than the 2 bytes"), "{error}");
        assert!(error.contains("ends before the data its header declares"));
        // Empty ASCII records are lines: more of them than lines is refused.
        let lines = "ply\nformat ascii 1.0\nelement junk 4000000000\nend_header\n\n\n";
        assert!(read(lines.as_bytes())
            .unwrap_err()
            .contains("4000000000 records"));
        assert!(start.elapsed().as_secs() < 5, "{:?}", start.elapsed());
    }

    #[test]
    fn faces_are_counted_against_the_budget_before_they_are_built() {
        // One face of 250 corners: 248 triangles.
        let mut payload = Vec::new();
        for x in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
            payload.extend(x.to_le_bytes());
        }
        payload.push(250);
        payload.extend((0..250u8).map(|i| i % 3));
        let header = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                      element face 1\nproperty list uchar uchar vertex_indices\n";
        let bytes = binary(header, &payload);
        let error = read_ply_bytes(&bytes, &mut Budget::of(247)).unwrap_err();
        assert_eq!(error, crate::budget::TOO_MANY);
        let mut budget = Budget::of(248);
        assert!(read_ply_bytes(&bytes, &mut budget).is_ok());
        // The budget is the scene's: a second file finds it spent.
        assert!(read_ply_bytes(&bytes, &mut budget).is_err());
    }

    #[test]
    fn indices_are_reported_as_the_file_writes_them() {
        let negative = format!("{HEADER}0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 -1\n");
        let error = read(negative.as_bytes()).unwrap_err();
        assert_eq!(error, "face 1: vertex index -1; expected indices from 0 up");
        let floats = HEADER.replace("list uchar int", "list uchar float");
        let floats = format!("{floats}0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 3\n");
        let error = read(floats.as_bytes()).unwrap_err();
        assert_eq!(
            error,
            "face 0: its `vertex_indices` are floats; expected integers"
        );
        let scalar = HEADER.replace(
            "property list uchar int vertex_indices",
            "property int vertex_indices",
        );
        let scalar = format!("{scalar}0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n1\n2\n");
        let error = read(scalar.as_bytes()).unwrap_err();
        assert!(error.contains("not a list"), "{error}");
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
