//! What the tracer can build, checked on a loaded scene before anything is
//! allocated for it: how many primitives (and, in path mode, lights made
//! of emitting triangles), and what each mesh's placement leaves of it.

use crate::Error;
use scene_format::validate::MAX_COORDINATE;
use scene_format::{Diagnostic, Integrator, Origins, SceneFile, ShapeRef};
use std::collections::{HashMap, HashSet};
use tracer_core::prepare::{self, MeshBox};

/// Most primitives a scene may have. Preparing costs about
/// [`BYTES_PER_PRIMITIVE`] at its peak (the triangles, the object list and
/// the BVH build), so 20 million take about 3.4 GB: room to spare on the
/// lab's machines (this one has 24 GiB shared by 2 cores), and renders of
/// that size already take minutes there. The mesh readers count their
/// triangles against the same number before building any.
pub const MAX_PRIMITIVES: usize = scene_format::MAX_TRIANGLES;

/// Peak memory per primitive while preparing, measured: 20 copies of the
/// bunny (1.39M triangles) peak at 219 MB more than one (70k). (They were
/// flattened copies then; now the 20 share one mesh. An instance counts as
/// one primitive: it takes a few hundred bytes, so a scene of millions of
/// instances would outgrow this figure, but not a machine's memory.)
pub const BYTES_PER_PRIMITIVE: u64 = 170;

/// The limits a loaded scene breaks, at the object that breaks them: the
/// one that takes the count of primitives past [`MAX_PRIMITIVES`] (counted
/// from the OBJ files' triangles, before any is placed; a mesh shared by
/// several objects counts its triangles once, and one per object; in path
/// mode every object's emitting triangles once more, each a light), a mesh
/// whose placement leaves no triangle, or one it moves beyond
/// `MAX_COORDINATE`.
pub(crate) fn check(file: &SceneFile) -> Vec<Diagnostic> {
    let shared = tracer_core::prepare::shared_meshes(file);
    let path_mode = file.render.integrator == Integrator::Path;
    if let Some(d) = primitive_count(file, &shared, MAX_PRIMITIVES, path_mode) {
        return vec![d];
    }
    placements(file, &shared)
}

/// [`check`]'s count of primitives again, when options made a scene of
/// Whitted mode (`was_path` false) path traced (`--integrator path`): its
/// emitting triangles become lights only now.
pub(crate) fn check_path_mode(
    origins: &Origins,
    was_path: bool,
    file: &SceneFile,
) -> Result<(), Error> {
    if was_path || file.render.integrator != Integrator::Path {
        return Ok(());
    }
    let shared = tracer_core::prepare::shared_meshes(file);
    match primitive_count(file, &shared, MAX_PRIMITIVES, true) {
        Some(d) => Err(Error::Scene(origins.invalid(vec![d]))),
        None => Ok(()),
    }
}

/// The diagnostic of the object that takes the count of what is built past
/// `max` ([`MAX_PRIMITIVES`]), if one does: unique primitives, and in
/// `path_mode` each object's emitting triangles, which path mode makes
/// lights of one by one, an instance's as a flattened mesh's (a light
/// takes about what a primitive does: 150 instances of an emitting mesh of
/// 100,000 triangles peaked at 2.85 GB, 188 bytes a light). This is the
/// place a light table shared by instances would count them once instead.
fn primitive_count(
    file: &SceneFile,
    shared: &[Option<usize>],
    max: usize,
    path_mode: bool,
) -> Option<Diagnostic> {
    let mut total = 0usize;
    let mut counted = HashSet::new();
    let mut models: HashMap<prepare::MeshSharing, HashSet<usize>> = HashMap::new();
    for (i, o) in file.objects.iter().enumerate() {
        let triangles = match o.shapes().as_slice() {
            [ShapeRef::Mesh(m)] => m.data.as_ref().map_or(0, |d| d.triangles.len()),
            [ShapeRef::Gltf(g)] => g.data.as_ref().map_or(0, |d| {
                // Objects share a file's meshes only with equal holes.
                let sharing = prepare::mesh_sharing(file, o);
                let mut own = HashSet::new();
                let shared = match sharing {
                    prepare::MeshSharing::Own => &mut own,
                    _ => models.entry(sharing).or_default(),
                };
                prepare::model_extent(d, o.transform.as_ref(), shared).0
            }),
            _ => 1,
        };
        let n = match shared[i] {
            Some(group) if counted.insert(group) => triangles + 1,
            Some(_) => 1,
            None => triangles,
        };
        let lights = if path_mode {
            tracer_core::prepare::emitting_triangles(file, o)
        } else {
            0
        };
        total += n + lights;
        if total > max {
            let path = if o.mesh.is_some() {
                format!("objects[{i}].mesh")
            } else if o.gltf.is_some() {
                format!("objects[{i}].gltf")
            } else {
                format!("objects[{i}]")
            };
            let gb = |n: usize| n as f64 * BYTES_PER_PRIMITIVE as f64 / 1e9;
            let this = match lights {
                0 => format!("this one: {n}"),
                _ => format!(
                    "this one: {n}, and {lights} emitting triangles, each a light of its own in path mode, for every object that places the mesh"
                ),
            };
            return Some(Diagnostic::new(
                path,
                format!(
                    "with this object the scene has {total} primitives ({this}), more than the {max} the tracer builds \
                     (they would take about {:.1} GB to prepare); a mesh file named by several objects (with the same `smooth`) is shared and counts its triangles once, \
                     plus one per object, while a mesh named once is a copy of its triangles of its own",
                    gb(total)
                ),
            ));
        }
    }
    None
}

/// The diagnostics of mesh objects whose placement leaves no triangle or
/// moves one beyond `MAX_COORDINATE`. An instance of a shared mesh is
/// judged by its mesh's box: its corners placed reach at least as far as
/// any vertex, and placing a thousand instances' every vertex would take
/// longer than rendering them.
fn placements(file: &SceneFile, shared: &[Option<usize>]) -> Vec<Diagnostic> {
    let mut boxes: HashMap<usize, MeshBox> = HashMap::new();
    let mut diagnostics = Vec::new();
    for (i, o) in file.objects.iter().enumerate() {
        if let Some(d) = o.gltf.as_ref().and_then(|g| Some((g, g.data.as_ref()?))) {
            let (g, data) = d;
            let (_, max_abs) =
                prepare::model_extent(data, o.transform.as_ref(), &mut HashSet::new());
            if max_abs > MAX_COORDINATE {
                diagnostics.push(Diagnostic::new(
                    format!("objects[{i}].gltf"),
                    format!(
                        "once placed, `{}` reaches a coordinate of {max_abs:e}; expected coordinates from -{MAX_COORDINATE:e} to {MAX_COORDINATE:e}, which single-precision tracing can handle",
                        g.file
                    ),
                ));
            }
            continue;
        }
        let Some(mesh) = &o.mesh else { continue };
        let Some(data) = &mesh.data else { continue };
        let transform = o.transform.as_ref();
        let extent = match shared[i] {
            Some(group) => {
                let b = boxes
                    .entry(group)
                    .or_insert_with(|| prepare::mesh_box(data));
                prepare::instance_extent(b, transform)
            }
            None => prepare::mesh_extent(data, transform),
        };
        if extent.triangles == 0 {
            diagnostics.push(Diagnostic::new(
                format!("objects[{i}].mesh"),
                format!(
                    "no triangle of `{}` is left once placed: its {} triangles all have zero area in single precision (check `transform.scale`)",
                    mesh.path(),
                    data.triangles.len()
                ),
            ));
        } else if extent.max_abs > MAX_COORDINATE {
            diagnostics.push(Diagnostic::new(
                format!("objects[{i}].mesh"),
                format!(
                    "once placed, `{}` reaches a coordinate of {:e}; expected coordinates from -{MAX_COORDINATE:e} to {MAX_COORDINATE:e}, which single-precision tracing can handle",
                    mesh.path(), extent.max_abs
                ),
            ));
        }
    }
    diagnostics
}

#[cfg(test)]
mod tests {
    use super::*;
    use scene_format::MeshData;
    use std::sync::Arc;

    /// A mesh of `n` triangles.
    fn mesh(n: usize) -> Arc<MeshData> {
        let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        Arc::new(MeshData {
            triangles: vec![t; n],
            ..MeshData::default()
        })
    }

    /// Objects naming mesh a (10 triangles) three times, b (5) once, and a
    /// sphere: [a, b, a, sphere, a].
    fn scene() -> SceneFile {
        let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
            [[objects]]\nmesh = { obj = \"a.obj\" }\n\
            [[objects]]\nmesh = { obj = \"b.obj\" }\n\
            [[objects]]\nmesh = { obj = \"a.obj\" }\ntransform = { translate = [1, 0, 0] }\n\
            [[objects]]\nsphere = { center = [0, 0, 0], radius = 1 }\n\
            [[objects]]\nmesh = { obj = \"a.obj\" }\ntransform = { rotate = [0, 90, 0] }\n";
        let mut file = scene_format::load_str(
            text,
            scene_format::Format::Toml,
            std::path::Path::new("s.toml"),
        )
        .expect("a scene");
        let (a, b) = (mesh(10), mesh(5));
        for (k, data) in [(0, &a), (1, &b), (2, &a), (4, &a)] {
            file.objects[k].mesh.as_mut().unwrap().data = Some(Arc::clone(data));
        }
        file
    }

    #[test]
    fn a_shared_mesh_counts_its_triangles_once_and_one_per_object() {
        let file = scene();
        let shared = tracer_core::prepare::shared_meshes(&file);
        assert_eq!(shared, [Some(0), None, Some(0), None, Some(0)]);
        // a: 10 + 1, b: 5, a: 1, sphere: 1, a: 1 -> 11, 16, 17, 18, 19.
        assert!(primitive_count(&file, &shared, 19, false).is_none());
        let d = primitive_count(&file, &shared, 18, false).expect("refused");
        assert_eq!(d.path.to_string(), "objects[4].mesh");
        assert!(
            d.message.contains("19 primitives (this one: 1)"),
            "{}",
            d.message
        );
        assert!(
            d.message.contains("counts its triangles once"),
            "{}",
            d.message
        );
        let d = primitive_count(&file, &shared, 17, false).expect("refused");
        assert_eq!(d.path.to_string(), "objects[3]");
        let d = primitive_count(&file, &shared, 10, false).expect("refused");
        assert!(
            d.message.contains("11 primitives (this one: 11)"),
            "{}",
            d.message
        );
    }

    #[test]
    fn a_thousand_instances_count_once_toward_the_limit() {
        let mut file = scene();
        let template = file.objects[0].clone();
        file.objects = vec![template; 1000];
        let shared = tracer_core::prepare::shared_meshes(&file);
        assert!(shared.iter().all(|&g| g == Some(0)));
        assert!(primitive_count(&file, &shared, 10 + 1000, false).is_none());
        assert!(primitive_count(&file, &shared, 10 + 999, false).is_some());
    }

    #[test]
    fn in_path_mode_each_instance_s_emitting_triangles_count_as_lights() {
        let mut file = scene();
        // Mesh a (10 triangles) emits; it is placed three times, b once.
        file.materials.insert(
            "lamp".to_string(),
            scene_format::Material {
                emission: [1.0, 1.0, 1.0],
                ..scene_format::Material::default()
            },
        );
        for k in [0, 2, 4] {
            file.objects[k].material = Some(scene_format::MaterialRef::Named("lamp".to_string()));
        }
        let shared = tracer_core::prepare::shared_meshes(&file);
        // Whitted mode builds no lights of them: 19, as before.
        assert!(primitive_count(&file, &shared, 19, false).is_none());
        // Path mode: 10 lights for each of the three objects.
        assert!(primitive_count(&file, &shared, 49, true).is_none());
        let d = primitive_count(&file, &shared, 48, true).expect("refused");
        assert_eq!(d.path.to_string(), "objects[4].mesh");
        assert!(
            d.message.contains("49 primitives (this one: 1, and 10 emitting triangles, each a light of its own in path mode"),
            "{}",
            d.message
        );
    }
    #[test]
    fn in_path_mode_a_gltf_model_s_emitting_triangles_count_as_lights() {
        let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
            [[objects]]\ngltf = { file = \"m.gltf\" }\n";
        let mut file = scene_format::load_str(
            text,
            scene_format::Format::Toml,
            std::path::Path::new("s.toml"),
        )
        .expect("a scene");
        // A mesh of 10 triangles of the file's emitting material 0, placed
        // by two nodes, and one of 5 without a material (glTF's default).
        let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let lamp = Arc::new(MeshData {
            triangles: vec![t; 10],
            triangle_materials: vec![Some(0); 10],
            ..MeshData::default()
        });
        let emitting = scene_format::Material {
            emission: [1.0, 1.0, 1.0],
            ..scene_format::Material::default()
        };
        let at = |mesh, node| scene_format::gltf::PlacedMesh {
            mesh,
            node,
            matrix: glam::Mat4::IDENTITY.to_cols_array(),
        };
        let model = scene_format::gltf::GltfData {
            meshes: vec![Some(lamp), Some(mesh(5))],
            materials: vec![emitting.clone()],
            placed: vec![at(0, 0), at(0, 1), at(1, 2)],
            ..Default::default()
        };
        file.objects[0].gltf.as_mut().unwrap().data = Some(Arc::new(model));
        let shared = tracer_core::prepare::shared_meshes(&file);
        // Whitted mode: the lamp mesh once and an instance each (10 + 2),
        // the other mesh's 5 triangles: 17.
        assert!(primitive_count(&file, &shared, 17, false).is_none());
        assert!(primitive_count(&file, &shared, 16, false).is_some());
        // Path mode: and the lamp's 10 emitting triangles at each of its
        // two places.
        assert!(primitive_count(&file, &shared, 37, true).is_none());
        let d = primitive_count(&file, &shared, 36, true).expect("refused");
        assert_eq!(d.path.to_string(), "objects[0].gltf");
        assert!(
            d.message
                .contains("(this one: 17, and 20 emitting triangles"),
            "{}",
            d.message
        );
        // The object's emitting material for all: every placed triangle.
        file.objects[0].material = Some(scene_format::MaterialRef::Inline(emitting));
        assert!(primitive_count(&file, &shared, 17 + 25, true).is_none());
        assert!(primitive_count(&file, &shared, 17 + 24, true).is_some());
    }
}
