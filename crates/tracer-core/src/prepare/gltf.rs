//! A `gltf` object: the model's meshes placed by its nodes and then by the
//! object's transform, its materials (or the object's `material` for all),
//! its lights. A mesh one node places is flattened into world triangles; a
//! mesh several nodes place is prepared once and instanced, as a mesh file
//! named by several objects is.

use super::{light, mesh_objects, placement, FaceMaterials, MaterialTable, PrepareError};
use crate::geometry::{Instance, Object, Placement, Shape, SharedMesh};
use crate::light::Light;
use glam::{Mat3, Mat4, Vec3};
use scene_format as fmt;
use std::collections::HashMap;
use std::sync::Arc;

/// What the glTF objects of one scene share: each file's materials made
/// once (by the address of its data), each mesh several nodes place
/// prepared once (by the address of its triangles, and the alpha masks
/// its material slots take: an object whose `material` stands for the
/// file's may cut other holes, or none).
#[derive(Default)]
pub(super) struct Models {
    /// Per file: its default material and the scene index of each of its
    /// materials.
    materials: HashMap<usize, (usize, Vec<usize>)>,
    shared: HashMap<(usize, Vec<usize>), Arc<SharedMesh>>,
}

impl Models {
    /// The objects of glTF object `o` (at `path`), its lights added to
    /// `lights`.
    pub(super) fn objects(
        &mut self,
        path: &str,
        o: &fmt::Object,
        g: &fmt::Gltf,
        materials: &mut MaterialTable,
        lights: &mut Vec<Light>,
    ) -> Result<Vec<Object>, PrepareError> {
        let data = g.data.as_ref().ok_or_else(|| PrepareError::MeshNotLoaded {
            path: format!("{path}.gltf.file"),
        })?;
        let (default, table) = match &o.material {
            Some(_) => {
                let one = materials.resolve(path, o)?;
                (one, vec![one; data.materials.len()])
            }
            None => self.file_materials(path, data, materials)?,
        };
        let object = placement(o.transform.as_ref());
        let mut uses: HashMap<usize, usize> = HashMap::new();
        for p in &data.placed {
            *uses.entry(p.mesh).or_default() += 1;
        }
        let slots: Vec<usize> = std::iter::once(default)
            .chain(table.iter().copied())
            .collect();
        let masks = materials.masks(&slots);
        // Each slot's mask, by address: meshes are shared by equal masks.
        let masks_key: Vec<usize> = masks
            .iter()
            .map(|m| m.as_ref().map_or(0, |m| Arc::as_ptr(m) as usize))
            .collect();
        let mut objects = Vec::new();
        for p in &data.placed {
            let Some(mesh) = data.mesh(p.mesh) else {
                continue;
            };
            let placed = object.compose(&node_placement(&p.matrix));
            if uses[&p.mesh] >= 2 {
                let key = (Arc::as_ptr(mesh) as usize, masks_key.clone());
                let shared = self.shared.entry(key).or_insert_with(|| {
                    let made = shared_mesh(mesh, data.materials.len());
                    Arc::new(made.with_masks(masks.clone()))
                });
                let slots = slots.clone();
                if let Some(instance) = Instance::new(Arc::clone(shared), placed, slots) {
                    objects.push(Object::new(Shape::Instance(Arc::new(instance)), default));
                    continue;
                }
            }
            let faces = FaceMaterials {
                material: default,
                mtl: &table,
            };
            objects.extend(mesh_objects(mesh, &placed, None, faces));
        }
        for l in &data.lights {
            lights.push(light(&placed_light(l, &object)));
        }
        Ok(objects)
    }

    /// The scene indices of a file's materials (made on first use), and of
    /// glTF's default material for primitives that name none.
    fn file_materials(
        &mut self,
        path: &str,
        data: &Arc<fmt::gltf::GltfData>,
        materials: &mut MaterialTable,
    ) -> Result<(usize, Vec<usize>), PrepareError> {
        let key = Arc::as_ptr(data) as usize;
        if let Some(made) = self.materials.get(&key) {
            return Ok(made.clone());
        }
        let texture_path = format!("{path}.gltf");
        let default = fmt::gltf::default_material();
        let made = materials.material(&texture_path, &default, None)?;
        let default = materials.push(made, format!("glTF's default material of {path}"));
        let mut table = Vec::with_capacity(data.materials.len());
        for (k, m) in data.materials.iter().enumerate() {
            let made = materials.material(&texture_path, m, None)?;
            table.push(materials.push(made, format!("materials[{k}] of {path}.gltf")));
        }
        self.materials.insert(key, (default, table.clone()));
        Ok((default, table))
    }
}

/// How glTF object `o` may share the meshes its file places several
/// times with other objects placing the same file, as the limits count
/// them (`Models` shares by the masks themselves, which can only share
/// more): objects without a `material` share the file's; objects whose
/// `material` cuts no holes share theirs; one whose `material` has an
/// `alpha_cutoff` keeps its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MeshSharing {
    File,
    Override,
    Own,
}

/// `MeshSharing` of glTF object `o`.
pub fn mesh_sharing(file: &fmt::SceneFile, o: &fmt::Object) -> MeshSharing {
    let material = match &o.material {
        Some(fmt::MaterialRef::Named(name)) => file.materials.get(name),
        Some(fmt::MaterialRef::Inline(m)) => Some(m),
        None => return MeshSharing::File,
    };
    match material.is_some_and(|m| m.alpha_cutoff.is_some()) {
        true => MeshSharing::Own,
        false => MeshSharing::Override,
    }
}

/// A node's world matrix (column-major) as a placement.
fn node_placement(m: &[f32; 16]) -> Placement {
    let m = Mat4::from_cols_array(m);
    Placement::affine(Mat3::from_mat4(m), m.w_axis.truncate())
}

/// A mesh in its own coordinates, its triangles' materials the slots of an
/// instance's table: 0 glTF's default, 1 + k the file's material k.
fn shared_mesh(data: &fmt::MeshData, count: usize) -> SharedMesh {
    let slots: Vec<usize> = (1..=count).collect();
    let faces = FaceMaterials {
        material: 0,
        mtl: &slots,
    };
    SharedMesh::new(mesh_objects(data, &Placement::IDENTITY, None, faces))
}

/// A light of the model placed by the object's transform.
fn placed_light(l: &fmt::Light, object: &Placement) -> fmt::Light {
    let mut placed = l.clone();
    placed.position = l.position.map(|p| object.apply(Vec3::from(p)).to_array());
    placed.direction = l.direction.map(|d| {
        object
            .apply_vector(Vec3::from(d))
            .normalize_or_zero()
            .to_array()
    });
    placed
}

/// The triangles of glTF object `o` (its model `data`) whose material
/// emits, every node's placement of them counted (`emitting_triangles` of
/// a mesh object): the object's `material` for all, else each triangle's
/// of the file (glTF's default material emits nothing).
pub(super) fn emitting_triangles(
    file: &fmt::SceneFile,
    o: &fmt::Object,
    data: &fmt::gltf::GltfData,
) -> usize {
    let emits = |m: &fmt::Material| m.emission != [0.0; 3];
    let all = match &o.material {
        Some(fmt::MaterialRef::Inline(m)) => Some(emits(m)),
        Some(fmt::MaterialRef::Named(name)) => Some(file.materials.get(name).is_some_and(emits)),
        None => None,
    };
    let of_mesh = |mesh: &fmt::MeshData| match all {
        Some(true) => mesh.triangles.len(),
        Some(false) => 0,
        None => (0..mesh.triangles.len())
            .filter(|&k| {
                mesh.triangle_material(k)
                    .and_then(|m| data.materials.get(m as usize))
                    .is_some_and(emits)
            })
            .count(),
    };
    data.placed
        .iter()
        .filter_map(|p| data.mesh(p.mesh))
        .map(|mesh| of_mesh(mesh))
        .sum()
}

/// What a glTF object makes, found without building it: the primitives
/// (a mesh one node places, its triangles; a mesh several place, its
/// triangles once, by the address of its data in `shared`, and one
/// instance per node) and the farthest coordinate its meshes' boxes reach
/// once placed by the nodes and `transform`.
pub fn model_extent(
    data: &fmt::gltf::GltfData,
    transform: Option<&fmt::Transform>,
    shared: &mut std::collections::HashSet<usize>,
) -> (usize, f32) {
    let object = placement(transform);
    let mut uses: HashMap<usize, usize> = HashMap::new();
    for p in &data.placed {
        *uses.entry(p.mesh).or_default() += 1;
    }
    let (mut primitives, mut max_abs) = (0usize, 0f32);
    for p in &data.placed {
        let Some(mesh) = data.mesh(p.mesh) else {
            continue;
        };
        let b = super::mesh_box(mesh);
        if b.triangles == 0 {
            continue;
        }
        let placed = object.compose(&node_placement(&p.matrix));
        let (lo, hi) = placed.apply_box(b.min, b.max);
        max_abs = max_abs.max(lo.abs().max(hi.abs()).max_element());
        primitives += if uses[&p.mesh] < 2 {
            b.triangles
        } else if shared.insert(Arc::as_ptr(mesh) as usize) {
            b.triangles + 1
        } else {
            1
        };
    }
    (primitives, max_abs)
}
