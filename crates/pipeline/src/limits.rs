//! What the tracer can build, checked on a loaded scene before anything is
//! allocated for it: how many primitives, and what each mesh's placement
//! leaves of it.

use scene_format::validate::MAX_COORDINATE;
use scene_format::{Diagnostic, SceneFile, ShapeRef};

/// Most primitives a scene may have. Preparing costs about
/// [`BYTES_PER_PRIMITIVE`] at its peak (the triangles, the object list and
/// the BVH build), so 20 million take about 3.4 GB: room to spare on the
/// lab's machines (this one has 24 GiB shared by 2 cores), and renders of
/// that size already take minutes there.
pub const MAX_PRIMITIVES: usize = 20_000_000;

/// Peak memory per primitive while preparing, measured: 20 copies of the
/// bunny (1.39M triangles) peak at 219 MB more than one (70k).
pub const BYTES_PER_PRIMITIVE: u64 = 170;

/// The limits a loaded scene breaks, at the object that breaks them: the
/// one that takes the count of primitives past [`MAX_PRIMITIVES`] (counted
/// from the OBJ files' triangles, before any is placed), a mesh whose
/// placement leaves no triangle, or one it moves beyond `MAX_COORDINATE`.
pub(crate) fn check(file: &SceneFile) -> Vec<Diagnostic> {
    let mut total = 0usize;
    for (i, o) in file.objects.iter().enumerate() {
        let n = match o.shapes().as_slice() {
            [ShapeRef::Mesh(m)] => m.data.as_ref().map_or(0, |d| d.triangles.len()),
            _ => 1,
        };
        total += n;
        if total > MAX_PRIMITIVES {
            let path = if o.mesh.is_some() {
                format!("objects[{i}].mesh")
            } else {
                format!("objects[{i}]")
            };
            let gb = |n: usize| n as f64 * BYTES_PER_PRIMITIVE as f64 / 1e9;
            return vec![Diagnostic::new(
                path,
                format!(
                    "with this object the scene has {total} primitives (this one: {n}), more than the {MAX_PRIMITIVES} the tracer builds \
                     (they would take about {:.1} GB to prepare); each mesh object is a full copy of its triangles, as instancing is not supported yet",
                    gb(total)
                ),
            )];
        }
    }
    let mut diagnostics = Vec::new();
    for (i, o) in file.objects.iter().enumerate() {
        let Some(mesh) = &o.mesh else { continue };
        let Some(data) = &mesh.data else { continue };
        let extent = tracer_core::prepare::mesh_extent(data, o.transform.as_ref());
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
