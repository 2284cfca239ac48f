//! A glTF mesh's primitives as one `MeshData`: triangles (strips and fans
//! cut into them, points and lines left out), their corners' normals,
//! texture coordinates and tangents (from the file, or made by MikkTSpace
//! where a normal texture needs them), each triangle's material.

use super::accessor::{Reader, TEXCOORD, VEC3_FLOAT, VEC4_FLOAT};
use super::Failure;
use crate::budget::Budget;
use crate::key_path::KeyPath;
use crate::model::{MeshData, Uv, Vec3};

const POINTS: u32 = 0;
const TRIANGLES: u32 = 4;
const TRIANGLE_STRIP: u32 = 5;
const TRIANGLE_FAN: u32 = 6;

/// Mesh `index` of the document read by `reader`; `normal_mapped[m]` says
/// whether material `m` has a normal texture (its triangles need tangents).
pub(crate) fn read(
    reader: &Reader,
    index: usize,
    normal_mapped: &[bool],
    budget: &mut Budget,
    warnings: &mut Vec<(KeyPath, String)>,
) -> Result<MeshData, Failure> {
    let mesh = &reader.doc.meshes[index];
    let at = KeyPath::root().key("meshes").index(index);
    let mut data = MeshData::default();
    let mut vertices = 0u32;
    for (p, primitive) in mesh.primitives.iter().enumerate() {
        let at = at.key("primitives").index(p);
        if primitive.mode < TRIANGLES {
            let what = if primitive.mode == POINTS {
                "points"
            } else {
                "lines"
            };
            warnings.push((
                at.key("mode"),
                format!("{what} are not rendered (a ray meets surfaces only); left out"),
            ));
            continue;
        }
        if primitive.mode > TRIANGLE_FAN {
            return Err(Failure::at(
                at.key("mode"),
                format!(
                    "expected a primitive mode from 0 to 6, found {}",
                    primitive.mode
                ),
            ));
        }
        if let Some(m) = primitive.material {
            if m >= reader.doc.materials.len() {
                return Err(Failure::at(
                    at.key("material"),
                    super::nodes::not_an_index("materials", m, reader.doc.materials.len()),
                ));
            }
        }
        let corners = Corners::read(reader, primitive, &at)?;
        let indices = match primitive.indices {
            Some(i) => reader.indices(i, &at.key("indices"))?,
            None => (0..corners.count() as u32).collect(),
        };
        if let Some(k) = indices.iter().position(|&i| i as usize >= corners.count()) {
            return Err(Failure::at(
                at.key("indices"),
                format!(
                    "index {k} is {}, past the {} vertices of the primitive's POSITION; expected indices below {}",
                    indices[k],
                    corners.count(),
                    corners.count()
                ),
            ));
        }
        let triangles = cut(primitive.mode, &indices);
        budget
            .take(triangles.len())
            .map_err(|m| Failure::at(at.clone(), m))?;
        let wants_tangents = primitive
            .material
            .is_some_and(|m| normal_mapped.get(m).copied().unwrap_or(false));
        let tangents = match (&corners.tangents, wants_tangents) {
            (Some(t), _) => Some(t.clone()),
            (None, true) => corners.mikktspace(&triangles, &at, warnings),
            (None, false) => None,
        };
        corners.add(
            &triangles,
            tangents.as_deref(),
            primitive.material,
            vertices,
            &mut data,
        );
        vertices = vertices.saturating_add(corners.count() as u32);
    }
    Ok(data)
}

/// A primitive's indices cut into triangles, as the spec numbers them.
fn cut(mode: u32, indices: &[u32]) -> Vec<[u32; 3]> {
    let n = indices.len();
    match mode {
        TRIANGLE_STRIP => (0..n.saturating_sub(2))
            .map(|i| {
                let (a, b) = if i % 2 == 0 { (1, 2) } else { (2, 1) };
                [indices[i], indices[i + a], indices[i + b]]
            })
            .collect(),
        TRIANGLE_FAN => (1..n.saturating_sub(1))
            .map(|i| [indices[i], indices[i + 1], indices[0]])
            .collect(),
        _ => indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
    }
}

/// A primitive's vertex attributes, all of one count.
struct Corners {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Uv>>,
    tangents: Option<Vec<[f32; 4]>>,
}

impl Corners {
    fn read(
        reader: &Reader,
        primitive: &super::doc::Primitive,
        at: &KeyPath,
    ) -> Result<Corners, Failure> {
        let attributes = at.key("attributes");
        let attribute = |name: &str| {
            primitive
                .attributes
                .get(name)
                .map(|&a| (a, attributes.key(name)))
        };
        let Some((position, position_at)) = attribute("POSITION") else {
            return Err(Failure::at(
                attributes,
                "expected a POSITION attribute: a primitive without positions has nothing to show",
            ));
        };
        let positions: Vec<Vec3> = reader.floats(position, &position_at, &VEC3_FLOAT)?;
        if let Some(k) = positions
            .iter()
            .position(|p| !p.iter().all(|x| x.is_finite()))
        {
            return Err(Failure::at(
                position_at,
                format!(
                    "vertex {k} is {:?}; expected finite coordinates",
                    positions[k]
                ),
            ));
        }
        let count = positions.len();
        let same_count = |len: usize, at: &KeyPath| {
            if len == count {
                Ok(())
            } else {
                Err(Failure::at(
                    at.clone(),
                    format!("{len} elements; expected as many as POSITION has, {count}"),
                ))
            }
        };
        let normals = match attribute("NORMAL") {
            Some((a, at)) => {
                let n: Vec<Vec3> = reader.floats(a, &at, &VEC3_FLOAT)?;
                same_count(n.len(), &at)?;
                Some(n)
            }
            None => None,
        };
        let uvs = match attribute("TEXCOORD_0") {
            Some((a, at)) => {
                let uv: Vec<Uv> = reader.floats(a, &at, &TEXCOORD)?;
                same_count(uv.len(), &at)?;
                // glTF's v runs down the image, the tracer's up it.
                Some(uv.into_iter().map(|[u, v]| [u, 1.0 - v]).collect())
            }
            None => None,
        };
        let tangents = match attribute("TANGENT") {
            Some((a, at)) => {
                let t: Vec<[f32; 4]> = reader.floats(a, &at, &VEC4_FLOAT)?;
                same_count(t.len(), &at)?;
                Some(t)
            }
            None => None,
        };
        Ok(Corners {
            positions,
            normals,
            uvs,
            tangents,
        })
    }

    fn count(&self) -> usize {
        self.positions.len()
    }

    /// The triangles added to `data`, their vertex indices offset by
    /// `first` (each primitive's vertices are its own), those of no area
    /// counted and left out.
    fn add(
        &self,
        triangles: &[[u32; 3]],
        tangents: Option<&[[f32; 4]]>,
        material: Option<usize>,
        first: u32,
        data: &mut MeshData,
    ) {
        for t in triangles {
            let corner = |f: &dyn Fn(usize) -> Vec3| t.map(|i| f(i as usize));
            let p = corner(&|i| self.positions[i]);
            if area2(&p) == 0.0 {
                data.skipped_degenerate += 1;
                continue;
            }
            data.triangles.push(p);
            data.indices.push(t.map(|i| first.saturating_add(i)));
            if let Some(n) = &self.normals {
                data.normals.push(Some(corner(&|i| n[i])));
            }
            if let Some(uv) = &self.uvs {
                data.uvs.push(Some(t.map(|i| uv[i as usize])));
            }
            if let Some(tangents) = tangents {
                data.tangents.push(Some(t.map(|i| tangents[i as usize])));
            }
            data.triangle_materials.push(material.map(|m| m as u32));
        }
    }

    /// Per-vertex tangents made as MikkTSpace makes them (what the glTF
    /// spec asks for when a normal texture has none in the file), or None
    /// with a warning when the primitive lacks the normals or texture
    /// coordinates they are made from.
    fn mikktspace(
        &self,
        triangles: &[[u32; 3]],
        at: &KeyPath,
        warnings: &mut Vec<(KeyPath, String)>,
    ) -> Option<Vec<[f32; 4]>> {
        let (Some(normals), Some(uvs)) = (&self.normals, &self.uvs) else {
            warnings.push((
                at.key("attributes"),
                "its material has a normal texture, but the primitive has no NORMAL or no TEXCOORD_0 to make tangents from; the normal texture is left out here".to_string(),
            ));
            return None;
        };
        let mut geometry = Mikk {
            positions: &self.positions,
            normals,
            uvs,
            triangles,
            tangents: vec![[0.0, 0.0, 0.0, 0.0]; self.count()],
        };
        // The crate's error type has no values: it always succeeds.
        let _ = bevy_mikktspace::generate_tangents(&mut geometry);
        Some(geometry.tangents)
    }
}

/// Twice a triangle's area, squared's root: zero for a degenerate one.
fn area2(p: &[Vec3; 3]) -> f32 {
    let e1 = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
    let e2 = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
    let c = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    c[0] * c[0] + c[1] * c[1] + c[2] * c[2]
}

/// A primitive as the `bevy_mikktspace` crate sees it. MikkTSpace writes one
/// tangent per face corner; vertices shared by faces get the same one
/// where the algorithm welds them, so keeping the last written per vertex
/// is what a welded index buffer gives.
struct Mikk<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    uvs: &'a [Uv],
    triangles: &'a [[u32; 3]],
    tangents: Vec<[f32; 4]>,
}

impl Mikk<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.triangles[face][vert] as usize
    }
}

impl bevy_mikktspace::Geometry for Mikk<'_> {
    fn num_faces(&self) -> usize {
        self.triangles.len()
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.vertex(face, vert)]
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[self.vertex(face, vert)]
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        // In the texture space whose v runs up the image (the tracer's and
        // Blender's, which flips glTF's on import), so that the bitangent,
        // w (normal x tangent), points up the image: a normal texture's
        // green, as glTF's writers (Blender's exporter) sign their tangents.
        self.uvs[self.vertex(face, vert)]
    }
    fn set_tangent(
        &mut self,
        tangent: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        // None for a face of no area with no neighbour to borrow from: the
        // crate's default frame.
        let tangent = tangent.unwrap_or_default().tangent_encoded();
        let i = self.vertex(face, vert);
        self.tangents[i] = tangent;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_are_cut_as_the_spec_numbers_them() {
        let idx = [0, 1, 2, 3, 4];
        assert_eq!(cut(TRIANGLES, &idx), [[0, 1, 2]]);
        assert_eq!(cut(TRIANGLE_STRIP, &idx), [[0, 1, 2], [1, 3, 2], [2, 3, 4]]);
        assert_eq!(cut(TRIANGLE_FAN, &idx), [[1, 2, 0], [2, 3, 0], [3, 4, 0]]);
        assert!(cut(TRIANGLE_STRIP, &[0, 1]).is_empty());
    }
}
