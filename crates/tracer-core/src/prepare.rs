//! From a validated scene file to the scene a render reads: the one place
//! where the core reads the file format's types.

use crate::alpha_mask::AlphaMask;
use crate::bsdf;
use crate::bsdf::principled::Principled;
use crate::camera::Camera;
use crate::geometry::{
    Instance, Object, Placement, Plane, Shape, SharedMesh, Sphere, Triangle, UvMap,
};
use crate::image::{Encoding, Saturation};
use crate::integrate::path::defaults as path_defaults;
use crate::light::environment::Environment;
use crate::light::Light;
use crate::material::{EmissionTexture, Glass, Material, NormalMap, Phong, PrincipledMaterial};
use crate::names::Names;
use crate::scene::{Integrator, Scene, SceneParts, TraceSettings};
use crate::texture::{Builtin, ColorTexture, ImageTexels, Place, Texture, Wrap};
use glam::{Vec2, Vec3};
use scene_format as fmt;
use std::collections::HashMap;
use std::sync::Arc;

mod gltf;
pub use gltf::{mesh_sharing, model_extent, MeshSharing};

/// Why a scene file could not be prepared. `scene_format`'s validation
/// reports these first, with their place in the file; here they are the
/// guard for a `SceneFile` built by hand.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PrepareError {
    #[error("`{path}`: unknown material `{name}`")]
    UnknownMaterial { path: String, name: String },
    #[error("`{path}`: unknown texture `{name}`")]
    UnknownTexture { path: String, name: String },
    #[error("`{path}`: expected exactly one shape")]
    NotOneShape { path: String },
    #[error("`{path}`: the mesh's OBJ file was not read (load the scene with `load_path`)")]
    MeshNotLoaded { path: String },
    #[error("`{path}`: the texture's image was not read (load the scene with `load_path`)")]
    ImageNotLoaded { path: String },
}

/// Builds the renderable scene from a validated scene file; the BVH is
/// built on the current rayon pool.
pub fn prepare(file: &fmt::SceneFile) -> Result<Scene, PrepareError> {
    Ok(Scene::new(parts(file)?))
}

/// `prepare`, with what the file calls each object and material (for
/// `explain`).
pub fn prepare_named(file: &fmt::SceneFile) -> Result<(Scene, Names), PrepareError> {
    let (parts, names) = parts_named(file)?;
    Ok((Scene::new(parts), names))
}

/// What `prepare` makes a scene of, before its BVH is built: a caller that
/// owns the file can drop its meshes' triangles first (53 MB of a
/// 1.1M-triangle mesh, beside the objects made of them).
pub fn parts(file: &fmt::SceneFile) -> Result<SceneParts, PrepareError> {
    Ok(parts_named(file)?.0)
}

fn parts_named(file: &fmt::SceneFile) -> Result<(SceneParts, Names), PrepareError> {
    let mut materials = MaterialTable::new(file);
    let mut names = Names::default();
    let mut objects = Vec::new();
    let shared = shared_meshes(file);
    let mut meshes: Vec<Option<Arc<SharedMesh>>> = Vec::new();
    let mut models = gltf::Models::default();
    let mut lights: Vec<Light> = file.lights.iter().map(light).collect();
    for (i, o) in file.objects.iter().enumerate() {
        let path = format!("objects[{i}]");
        if let Some(g) = &o.gltf {
            let made = models.objects(&path, o, g, &mut materials, &mut lights)?;
            names.add_objects(i, made.len());
            objects.extend(made);
            continue;
        }
        let material = materials.resolve(&path, o)?;
        let mtl = materials.mtl_materials(&path, o)?;
        let made = match shared[i] {
            Some(group) => {
                meshes.resize(meshes.len().max(group + 1), None);
                instance(o, (material, &mtl), &materials, &mut meshes[group])
            }
            None => shapes(&path, o, material, &mtl)?,
        };
        names.add_objects(i, made.len());
        // Taken whole when first: a large mesh's objects are not copied
        // (twice their memory for a moment).
        if objects.is_empty() {
            objects = made;
        } else {
            objects.extend(made);
        }
    }
    for name in std::mem::take(&mut materials.names) {
        names.add_material(name);
    }
    let trace = trace_settings(file, &materials.materials);
    let parts = SceneParts {
        camera: camera(&file.camera),
        objects,
        materials: materials.materials,
        lights,
        trace,
        encoding: encoding(&file.render),
        samples: file.render.samples,
        environment: environment(file)?,
    };
    Ok((parts, names))
}

/// For each object of `file`, the group of objects it shares its mesh's
/// triangles with, if any: a mesh file named by two or more objects with
/// the same `smooth` is prepared once, in its own coordinates, and each of
/// them becomes an instance of it, with its own transform and materials
/// (the triangles hold material slots, so materials need not match).
/// Everything else about a mesh object's triangles but the transform is
/// the file's and `smooth`'s, so nothing else needs to match, but for
/// their holes: objects whose material has an `alpha_cutoff` share the
/// mesh only with objects of the same masks (`mask_key`). A mesh named
/// once stays flattened into world-space triangles (the tracer's fastest
/// case, and the images made before instancing stay bit for bit), and so
/// does an object whose transform cannot be undone in f32. Groups are
/// numbered in file order.
pub fn shared_meshes(file: &fmt::SceneFile) -> Vec<Option<usize>> {
    type Key = (usize, Option<bool>, Option<String>);
    let keys: Vec<Option<Key>> = file
        .objects
        .iter()
        .enumerate()
        .map(|(i, o)| {
            let shapes = o.shapes();
            let [fmt::ShapeRef::Mesh(m)] = shapes.as_slice() else {
                return None;
            };
            let data = m.data.as_ref()?;
            placement(o.transform.as_ref()).inverse()?;
            Some((Arc::as_ptr(data) as usize, m.smooth, mask_key(file, i, o)))
        })
        .collect();
    let mut counts: HashMap<&Key, usize> = HashMap::new();
    for key in keys.iter().flatten() {
        *counts.entry(key).or_default() += 1;
    }
    let mut groups: HashMap<&Key, usize> = HashMap::new();
    keys.iter()
        .map(|key| {
            let key = key.as_ref()?;
            (counts[key] >= 2).then(|| {
                let next = groups.len();
                *groups.entry(key).or_insert(next)
            })
        })
        .collect()
}

/// What makes the holes of object `o`'s (index `i`) mesh its own: None
/// when its material has no `alpha_cutoff` (an OBJ's MTL materials have
/// none); the material's name when it is named and the object adds no
/// texture (each such object cuts the same holes); else the object (its
/// material is made for it alone).
fn mask_key(file: &fmt::SceneFile, i: usize, o: &fmt::Object) -> Option<String> {
    let material = match &o.material {
        Some(fmt::MaterialRef::Named(name)) => file.materials.get(name),
        Some(fmt::MaterialRef::Inline(m)) => Some(m),
        None => None,
    };
    material?.alpha_cutoff?;
    Some(match (&o.material, &o.texture) {
        (Some(fmt::MaterialRef::Named(name)), None) => format!("materials.{name}"),
        _ => format!("objects[{i}]"),
    })
}

/// How many of mesh or glTF object `o`'s triangles give off light (its
/// material's emission, or each face's MTL or glTF material's when it
/// names none): in path mode each becomes a light of its own, for every
/// object or node that places the mesh, an instance's too (`scene.rs`'s
/// `path_lights`). The limits count them, as they count what else is built.
pub fn emitting_triangles(file: &fmt::SceneFile, o: &fmt::Object) -> usize {
    if let Some(model) = o.gltf.as_ref().and_then(|g| g.data.as_ref()) {
        return gltf::emitting_triangles(file, o, model);
    }
    let Some(data) = o.mesh.as_ref().and_then(|m| m.data.as_ref()) else {
        return 0;
    };
    let emits = |m: &fmt::Material| m.emission != [0.0; 3];
    match &o.material {
        Some(fmt::MaterialRef::Inline(m)) if emits(m) => data.triangles.len(),
        Some(fmt::MaterialRef::Named(name)) if file.materials.get(name).is_some_and(emits) => {
            data.triangles.len()
        }
        Some(_) => 0,
        // Each face its MTL material, else the default grey.
        None => (0..data.triangles.len())
            .filter(|&k| {
                data.triangle_material(k)
                    .and_then(|m| data.materials.get(m as usize))
                    .is_some_and(emits)
            })
            .count(),
    }
}

/// Mesh object `o` as an instance of its group's shared mesh (prepared
/// here when `mesh` holds none yet, cut where the masks of `materials`
/// cut it), with material `material` and its faces' MTL materials `mtl`;
/// nothing when its mesh has no triangle.
fn instance(
    o: &fmt::Object,
    (material, mtl): (usize, &[usize]),
    materials: &MaterialTable,
    mesh: &mut Option<Arc<SharedMesh>>,
) -> Vec<Object> {
    let Some(m) = o.mesh.as_ref() else {
        return Vec::new();
    };
    let Some(data) = m.data.as_ref() else {
        return Vec::new();
    };
    // Slot 0 is the object's material, slot 1 + k the MTL's material k:
    // what `FaceMaterials::of` picks for a flattened mesh.
    let slots = (0..data.materials.len()).map(|k| mtl.get(k).copied().unwrap_or(material));
    let table: Vec<usize> = std::iter::once(material).chain(slots).collect();
    // The group's objects have the same masks (`shared_meshes`).
    let mesh = mesh.get_or_insert_with(|| {
        Arc::new(shared_mesh(data, m.smooth).with_masks(materials.masks(&table)))
    });
    let placement = placement(o.transform.as_ref());
    let instance = Instance::new(Arc::clone(mesh), placement, table);
    instance
        .map(|i| Object::new(Shape::Instance(Arc::new(i)), material))
        .into_iter()
        .collect()
}

/// The triangles of `data` in its own coordinates, their materials slots
/// of an instance's table (see `instance`), and their tree.
fn shared_mesh(data: &fmt::MeshData, smooth: Option<bool>) -> SharedMesh {
    let slots: Vec<usize> = (1..=data.materials.len()).collect();
    let materials = FaceMaterials {
        material: 0,
        mtl: &slots,
    };
    SharedMesh::new(mesh_objects(data, &Placement::IDENTITY, smooth, materials))
}

/// The camera of the file's `[camera]` table.
fn camera(c: &fmt::Camera) -> Camera {
    let (eye, look_at) = (Vec3::from(c.eye), Vec3::from(c.look_at));
    let lab = Camera::new(eye, look_at, c.up.into(), c.fov, c.width, c.height);
    let camera = match c.handedness {
        fmt::Handedness::Lab => lab,
        fmt::Handedness::Right => lab.right_handed(),
    };
    if let (fmt::Projection::Orthographic, Some(width)) = (c.projection, c.view_width) {
        return camera.orthographic(width);
    }
    let focus = c.focus_distance.unwrap_or_else(|| (look_at - eye).length());
    camera.with_lens(c.aperture, focus)
}

/// The file's `[environment]`: its image (read at load time) or colour.
fn environment(file: &fmt::SceneFile) -> Result<Option<Arc<Environment>>, PrepareError> {
    let Some(e) = &file.environment else {
        return Ok(None);
    };
    let environment = match (&e.data, e.color) {
        (Some(data), _) => Environment::image(
            data.width,
            data.height,
            &data.texels.to_floats(),
            e.strength,
            e.rotate,
        ),
        (None, Some(color)) => Environment::uniform(Vec3::from(color) * e.strength),
        (None, None) => {
            return Err(PrepareError::ImageNotLoaded {
                path: "environment.image".to_string(),
            })
        }
    };
    Ok(Some(Arc::new(environment)))
}

/// A light of the file: a point or sphere, a spot, or a directional light
/// (validation makes sure one of `position` and `direction` is there).
fn light(l: &fmt::Light) -> Light {
    let color = Vec3::from(l.color);
    match (l.position, l.direction) {
        (Some(p), None) => Light::new(p.into(), color, l.radius),
        (Some(p), Some(d)) => {
            let [inner, outer] = l.cone.unwrap_or([0.0, 45.0]);
            Light::spot(p.into(), Vec3::from(d), color, (inner, outer))
        }
        (None, Some(d)) => Light::directional(Vec3::from(d), color),
        (None, None) => Light::new(Vec3::ZERO, color, l.radius),
    }
}

/// The file's `[render]` in the core's terms; path mode's estimator where
/// the file leaves it (`integrate::path::defaults`), from its environment, whether
/// some material of `materials` (the scene's) emits, whether some lets
/// light through, whether some is more than a Lambertian lobe, and whether
/// the image is denoised.
fn trace_settings(file: &fmt::SceneFile, materials: &[Material]) -> TraceSettings {
    let r = &file.render;
    let environment = file.environment.is_some();
    let emitters = materials.iter().any(|m| m.emission() != Vec3::ZERO);
    let glass = materials.iter().any(Material::is_transparent);
    let glossy = materials.iter().any(|m| bsdf::lambert_only(m).is_none());
    TraceSettings {
        max_depth: r.max_depth(),
        min_energy: r.min_energy,
        background: r.background.into(),
        light_samples: r.light_samples,
        integrator: match r.integrator {
            fmt::Integrator::Whitted => Integrator::Whitted,
            fmt::Integrator::Path => Integrator::Path,
        },
        path_reuse: (r.path_reuse)
            .unwrap_or_else(|| path_defaults::path_reuse(environment, glass, r.denoise)),
        camera_rays: (r.camera_rays)
            .unwrap_or_else(|| path_defaults::camera_rays(environment, emitters, r.denoise)),
        adaptive: (r.adaptive)
            .unwrap_or_else(|| path_defaults::adaptive(environment, emitters, glossy, r.denoise)),
    }
}

fn encoding(r: &fmt::RenderSettings) -> Encoding {
    Encoding {
        gamma: r.gamma,
        saturation: saturation(r.saturation()),
    }
}

/// The file's saturation rule in the core's terms.
fn saturation(s: fmt::Saturation) -> Saturation {
    match s {
        fmt::Saturation::White => Saturation::White,
        fmt::Saturation::Clamp => Saturation::Clamp,
    }
}

/// The objects of scene object `o` with material `material` (a mesh's
/// faces with their MTL materials `mtl`, when it takes them): one shape,
/// or a mesh's, quad's or box's triangles, each with the map of its
/// barycentrics to the object's uv and a smooth triangle's vertex normals;
/// placed by the object's transform.
fn shapes(
    path: &str,
    o: &fmt::Object,
    material: usize,
    mtl: &[usize],
) -> Result<Vec<Object>, PrepareError> {
    let placement = placement(o.transform.as_ref());
    let one = |shape| vec![Object::new(shape, material)];
    let triangle = |vertices: [Vec3; 3], uv| {
        let (shape, uv) = place_triangle(vertices, uv, &placement)?;
        Some(Object::new(shape, material).with_uv(uv))
    };
    Ok(match o.shapes().as_slice() {
        [fmt::ShapeRef::Sphere(s)] => {
            let sphere = Sphere::new(s.center.into(), s.radius);
            one(Shape::Sphere(place_sphere(&sphere, &placement)))
        }
        [fmt::ShapeRef::Triangle([a, b, c])] => {
            let vertices = [(*a).into(), (*b).into(), (*c).into()];
            let uv = o.uv.map_or(UvMap::IDENTITY, |uv| corner_uv_map(&uv));
            triangle(vertices, uv).into_iter().collect()
        }
        [fmt::ShapeRef::Plane(p)] => {
            let plane = Plane::new(p.point.into(), p.normal.into());
            one(Shape::Plane(Box::new(plane.placed(&placement))))
        }
        [fmt::ShapeRef::Quad(q)] => {
            let halves = quad_triangles(q.corner.into(), q.edge_u.into(), q.edge_v.into());
            halves
                .into_iter()
                .filter_map(|(t, uv)| triangle(t, uv))
                .map(sharing_its_diagonal)
                .collect()
        }
        [fmt::ShapeRef::Box(b)] => box_triangles(b.min.into(), b.max.into())
            .into_iter()
            .filter_map(|(t, uv)| triangle(t, uv))
            .map(sharing_its_diagonal)
            .collect(),
        [fmt::ShapeRef::Mesh(m)] => {
            let data = m.data.as_ref().ok_or_else(|| PrepareError::MeshNotLoaded {
                path: format!("{path}.mesh.{}", m.key()),
            })?;
            let materials = FaceMaterials { material, mtl };
            mesh_objects(data, &placement, m.smooth, materials)
        }
        _ => {
            return Err(PrepareError::NotOneShape {
                path: path.to_string(),
            })
        }
    })
}

/// The triangle `vertices` carried by `placement`, with its uv map; None
/// when the placement leaves it no area in f32. A mirroring placement
/// would turn the vertex order, so the normal, inward: the last two
/// vertices swap to keep the front outward, and their barycentrics with them.
fn place_triangle(vertices: [Vec3; 3], uv: UvMap, placement: &Placement) -> Option<(Shape, UvMap)> {
    let [a, b, c] = vertices.map(|v| placement.apply(v));
    let (triangle, uv) = if placement.mirrors() {
        let swapped = UvMap {
            du: uv.dv,
            dv: uv.du,
            ..uv
        };
        (Triangle::new(a, c, b), swapped)
    } else {
        (Triangle::new(a, b, c), uv)
    };
    let area = (triangle.v1 - triangle.v0).cross(triangle.v2 - triangle.v0);
    (area != Vec3::ZERO).then_some((Shape::Triangle(triangle), uv))
}

/// A sphere carried by `placement`: its centre moves; under rotations,
/// translations and even scales its radius scales and its texture turns
/// with it; under any other linear map it becomes an ellipsoid.
fn place_sphere(sphere: &Sphere, placement: &Placement) -> Sphere {
    let linear = placement.linear();
    let center = placement.apply(sphere.center);
    if linear == glam::Mat3::IDENTITY {
        return Sphere::new(center, sphere.radius);
    }
    let scale = linear.x_axis.length();
    if !is_even_scale(linear, scale) {
        return Sphere::ellipsoid(center, sphere.radius, linear);
    }
    let turn = linear * (1.0 / scale);
    Sphere {
        center,
        radius: sphere.radius * scale,
        // Orthonormal: its inverse, world to texture, is its transpose.
        texture_frame: Some(Box::new(turn.transpose())),
        stretch: None,
    }
}

/// Whether `linear` is a rotation (or mirror) times `scale` on every axis:
/// its columns orthogonal and all of length `scale`, to float rounding.
fn is_even_scale(linear: glam::Mat3, scale: f32) -> bool {
    let gram = linear.transpose() * linear;
    let off = gram - glam::Mat3::from_diagonal(glam::Vec3::splat(scale * scale));
    let tolerance = 1e-5 * scale * scale;
    off.to_cols_array().iter().all(|x| x.abs() <= tolerance)
}

/// The uv map of a triangle whose corners have texture coordinates `uv`:
/// barycentric (u, v) is the point `uv0 + u (uv1 - uv0) + v (uv2 - uv0)`.
fn corner_uv_map(uv: &[fmt::Uv; 3]) -> UvMap {
    let [a, b, c] = uv.map(Vec2::from);
    UvMap {
        origin: a,
        du: b - a,
        dv: c - a,
    }
}

/// A quad `corner + s edge_u + t edge_v` as two triangles facing
/// `edge_u x edge_v`, their uv the quad's (s, t).
///
/// Triangles rather than a shape of their own: the BVH's four-wide
/// triangle test, shadows, glass and the brute-force reference then serve
/// quads and boxes as they are, and a box of 12 triangles is the same
/// surface (its normals outward by the vertex order). Only the uv needs
/// more than a triangle carries: the second half's barycentrics run from
/// the far corner, so its map turns them back into (s, t).
fn quad_triangles(corner: Vec3, edge_u: Vec3, edge_v: Vec3) -> [([Vec3; 3], UvMap); 2] {
    let (near_u, near_v) = (corner + edge_u, corner + edge_v);
    let far = near_u + edge_v;
    // (corner, +u, +v): barycentric (a, b) is (s, t); its normal u x v.
    let first = [corner, near_u, near_v];
    // (far, +v, +u): edges -u and -v, so the normal is (-u) x (-v) = u x v
    // and the point far - a u - b v has s = 1 - a, t = 1 - b.
    let second = [far, near_v, near_u];
    let flipped = UvMap {
        origin: Vec2::ONE,
        du: -Vec2::X,
        dv: -Vec2::Y,
    };
    [(first, UvMap::IDENTITY), (second, flipped)]
}

/// Half `o` of a quad (`quad_triangles`), its `v1` to `v2` edge the
/// diagonal both halves share, which the triangle test then closes.
fn sharing_its_diagonal(mut o: Object) -> Object {
    if let Shape::Triangle(t) = &mut o.shape {
        t.shared_diagonal = true;
    }
    o
}

/// The six faces of the box from `min` to `max` as quads facing outward
/// (`edge_u x edge_v` along the face's outward axis), each with uv 0..1.
fn box_triangles(min: Vec3, max: Vec3) -> Vec<([Vec3; 3], UvMap)> {
    let d = max - min;
    let (x, y, z) = (Vec3::X * d.x, Vec3::Y * d.y, Vec3::Z * d.z);
    let faces = [
        (min, z, y),                            // -x: z x y = -x
        (Vec3::new(max.x, min.y, min.z), y, z), // +x: y x z = +x
        (min, x, z),                            // -y: x x z = -y
        (Vec3::new(min.x, max.y, min.z), z, x), // +y: z x x = +y
        (min, y, x),                            // -z: y x x = -z
        (Vec3::new(min.x, min.y, max.z), x, y), // +z: x x y = +z
    ];
    faces
        .into_iter()
        .flat_map(|(corner, u, v)| quad_triangles(corner, u, v))
        .collect()
}

/// The placement of an object's `transform`: the table form exactly as
/// meshes always had it (scale, rotate, translate in one step), the list
/// form as the product of its steps, the last acting first.
fn placement(t: Option<&fmt::Transform>) -> Placement {
    match t {
        None => Placement::IDENTITY,
        Some(fmt::Transform::Table(t)) => Placement::new(
            t.scale.per_axis().into(),
            t.rotate.into(),
            t.translate.into(),
        ),
        Some(fmt::Transform::Steps(steps)) => steps.iter().fold(Placement::IDENTITY, |m, step| {
            m.compose(&step_placement(step))
        }),
    }
}

fn step_placement(step: &fmt::TransformStep) -> Placement {
    match *step {
        fmt::TransformStep::Translate(v) => Placement::translation(v.into()),
        fmt::TransformStep::Rotate(r) => Placement::new(Vec3::ONE, r.into(), Vec3::ZERO),
        fmt::TransformStep::Scale(s) => Placement::new(s.per_axis().into(), Vec3::ZERO, Vec3::ZERO),
    }
}

/// A mesh object's material, and its faces' MTL materials (indices into the
/// prepared scene's) when it takes them.
#[derive(Clone, Copy)]
struct FaceMaterials<'a> {
    material: usize,
    mtl: &'a [usize],
}

impl FaceMaterials<'_> {
    /// The material of triangle `k` of `data`.
    fn of(&self, data: &fmt::MeshData, k: usize) -> usize {
        data.triangle_material(k)
            .and_then(|m| self.mtl.get(m as usize).copied())
            .unwrap_or(self.material)
    }
}

/// The triangles of a mesh placed by `placement`, with their uv and, when
/// smooth, their vertex normals. A mirroring placement swaps the last two
/// vertices (`place_triangle`): their normals and uv swap with them.
fn mesh_objects(
    data: &fmt::MeshData,
    placement: &Placement,
    smooth: Option<bool>,
    materials: FaceMaterials,
) -> Vec<Object> {
    let made = (smooth == Some(true)).then(|| face_weighted_normals(data));
    let to_world = placement.normal_matrix();
    let mirrors = placement.mirrors();
    // Reserved whole: grown by doubling, a million objects were copied
    // and their pages first touched twice.
    let mut objects = Vec::with_capacity(data.triangles.len());
    objects.extend(placed(data, placement).map(|(k, triangle)| {
        let file_normals = match smooth {
            Some(false) => None,
            _ => data.normals.get(k).copied().flatten(),
        };
        let normals = file_normals.map(|n| n.map(Vec3::from)).or_else(|| {
            let made = made.as_ref()?;
            let ids = data.indices.get(k)?;
            Some(ids.map(|i| made[i as usize]))
        });
        let vertex_normals = normals
            .map(|n| in_placed_order(n, mirrors))
            .and_then(|n| oriented(&triangle, n.map(|n| to_world * n)))
            .map(Box::new);
        let uv = data.uvs.get(k).copied().flatten();
        let uv = uv.map_or(UvMap::IDENTITY, |uv| {
            corner_uv_map(&in_placed_order(uv, mirrors))
        });
        let tangents = data.tangents.get(k).copied().flatten().map(|t| {
            // Directions along the surface, placed as the triangle is; a
            // mirroring placement turns their handedness.
            let sign = if mirrors { -1.0 } else { 1.0 };
            let placed = t.map(|[x, y, z, w]| {
                let d = placement.apply_vector(Vec3::new(x, y, z));
                d.normalize_or_zero().extend(w * sign)
            });
            Box::new(in_placed_order(placed, mirrors))
        });
        Object {
            vertex_normals,
            tangents,
            ..Object::new(Shape::Triangle(triangle), materials.of(data, k))
        }
        .with_uv(uv)
    }));
    objects
}

/// A triangle's corner values in the order `place_triangle` puts its
/// vertices: the last two swapped under a mirroring placement.
fn in_placed_order<T>([a, b, c]: [T; 3], mirrors: bool) -> [T; 3] {
    if mirrors {
        [a, c, b]
    } else {
        [a, b, c]
    }
}

/// The normal at each vertex of the file: the sum of the faces' normals
/// around it weighted by their areas (the cross product of two edges is
/// twice the area along the normal), in the file's space. Placed, these are
/// the area-weighted normals of the placed mesh: the normal matrix takes a
/// face's cross product to the placed face's, divided by the determinant.
/// Empty when the file's vertex indices are not known.
fn face_weighted_normals(data: &fmt::MeshData) -> Vec<Vec3> {
    if data.indices.len() != data.triangles.len() {
        return Vec::new();
    }
    let count = data
        .indices
        .iter()
        .flatten()
        .max()
        .map_or(0, |&i| i as usize + 1);
    let mut normals = vec![Vec3::ZERO; count];
    for (t, ids) in data.triangles.iter().zip(&data.indices) {
        let [a, b, c] = t.map(Vec3::from);
        let n = (b - a).cross(c - a);
        for &i in ids {
            normals[i as usize] += n;
        }
    }
    normals
}

/// Unit vertex normals `n` of `triangle` on its own normal's side (files
/// wind their faces either way; the lab's normal comes from the vertex
/// order, and shading keeps to its side), or None when one has no
/// direction: then the triangle is shaded flat.
fn oriented(triangle: &Triangle, n: [Vec3; 3]) -> Option<[Vec3; 3]> {
    let [a, b, c] = [
        n[0].try_normalize()?,
        n[1].try_normalize()?,
        n[2].try_normalize()?,
    ];
    let geometric = (triangle.v1 - triangle.v0).cross(triangle.v2 - triangle.v0);
    if (a + b + c).dot(geometric) < 0.0 {
        Some([-a, -b, -c])
    } else {
        Some([a, b, c])
    }
}

/// The mesh's triangles placed, each with its index in `data`; those of
/// zero area in f32 left out.
fn placed<'a>(
    data: &'a fmt::MeshData,
    placement: &'a Placement,
) -> impl Iterator<Item = (usize, Triangle)> + 'a {
    data.triangles.iter().enumerate().filter_map(|(k, t)| {
        let vertices = t.map(Vec3::from);
        match place_triangle(vertices, UvMap::IDENTITY, placement)? {
            (Shape::Triangle(t), _) => Some((k, t)),
            _ => None,
        }
    })
}

/// What `prepare` will make of a mesh object, found without building it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshExtent {
    /// Triangles left once placed (the others have zero area in f32).
    pub triangles: usize,
    /// The largest absolute coordinate of a placed vertex.
    pub max_abs: f32,
}

/// The extent of a mesh placed by `transform`: the same arithmetic as
/// `prepare`, so it says exactly how many triangles it keeps, with no
/// allocation.
pub fn mesh_extent(data: &fmt::MeshData, transform: Option<&fmt::Transform>) -> MeshExtent {
    let placement = placement(transform);
    let mut extent = MeshExtent {
        triangles: 0,
        max_abs: 0.0,
    };
    for (_, t) in placed(data, &placement) {
        extent.triangles += 1;
        let m = t.v0.abs().max(t.v1.abs()).max(t.v2.abs()).max_element();
        extent.max_abs = extent.max_abs.max(m);
    }
    extent
}

/// A mesh's box and triangle count in its own coordinates: what an
/// instance of it is made of (`shared_meshes`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshBox {
    pub(crate) min: Vec3,
    pub(crate) max: Vec3,
    /// Triangles of non-zero area in the file's coordinates.
    pub triangles: usize,
}

/// The box and triangle count of `data` as a shared mesh keeps it.
pub fn mesh_box(data: &fmt::MeshData) -> MeshBox {
    let mut b = MeshBox {
        min: Vec3::INFINITY,
        max: Vec3::NEG_INFINITY,
        triangles: 0,
    };
    for (_, t) in placed(data, &Placement::IDENTITY) {
        b.triangles += 1;
        b.min = b.min.min(t.v0.min(t.v1).min(t.v2));
        b.max = b.max.max(t.v0.max(t.v1).max(t.v2));
    }
    b
}

/// The extent of an instance of the mesh of box `b` placed by `transform`,
/// from its box's placed corners, without placing the triangles (for a
/// thousand instances of a large mesh that would take a while): the largest
/// coordinate of a corner (at least that of any placed vertex), and the
/// mesh's triangles, or none when the corners coincide on two axes or more
/// in f32 (a scale that leaves nothing of the mesh but a point or a line,
/// as a flattened mesh's triangles would each have no area).
pub fn instance_extent(b: &MeshBox, transform: Option<&fmt::Transform>) -> MeshExtent {
    if b.triangles == 0 {
        return MeshExtent {
            triangles: 0,
            max_abs: 0.0,
        };
    }
    let placement = placement(transform);
    let (lo, hi) = placement.apply_box(b.min, b.max);
    let spread = (hi - lo).cmpgt(Vec3::ZERO).bitmask().count_ones();
    MeshExtent {
        triangles: if spread >= 2 { b.triangles } else { 0 },
        max_abs: lo.abs().max(hi.abs()).max_element(),
    }
}

/// Materials of the prepared scene: the named ones once each, inline ones
/// per object, and textures shared: built-in ones by name, images by the
/// file's data.
struct MaterialTable<'a> {
    file: &'a fmt::SceneFile,
    materials: Vec<Material>,
    /// What the file calls each of `materials`.
    names: Vec<String>,
    /// Named material and object texture name -> index, so objects share
    /// materials (an object's texture table makes a material of its own).
    by_key: HashMap<(String, Option<String>), usize>,
    textures: HashMap<Builtin, Arc<Texture>>,
    /// Decoded images by the address of the file's data and whether they
    /// are sRGB colours: each file is decoded to linear once each way.
    images: HashMap<(usize, bool), Arc<ImageTexels>>,
    /// The mean colours of emission textures' images, by their address.
    means: HashMap<usize, Vec3>,
}

/// What a texture does to a material.
enum Texturing {
    /// The lab's: multiplies the whole local colour.
    Lab(Arc<Texture>),
    /// Multiplies ambient and diffuse.
    Color(ColorTexture),
}

impl<'a> MaterialTable<'a> {
    fn new(file: &'a fmt::SceneFile) -> Self {
        MaterialTable {
            file,
            materials: Vec::new(),
            names: Vec::new(),
            by_key: HashMap::new(),
            textures: HashMap::new(),
            images: HashMap::new(),
            means: HashMap::new(),
        }
    }

    fn texture(&mut self, path: &str, t: &fmt::TextureRef) -> Result<Texturing, PrepareError> {
        match t {
            fmt::TextureRef::Named(name) => self.builtin(path, name).map(Texturing::Lab),
            fmt::TextureRef::Image(image) => self.image(path, image, true).map(Texturing::Color),
            fmt::TextureRef::Checker(c) => Ok(Texturing::Color(ColorTexture::Checker {
                colors: c.checker.map(Vec3::from),
                scale: c.scale.per_axis().into(),
            })),
        }
    }

    /// An image texture, its texels decoded from sRGB (`srgb`, colours)
    /// or read as they are (data: metallic-roughness, normals); each file
    /// decoded once each way.
    fn image(
        &mut self,
        path: &str,
        image: &fmt::ImageTexture,
        srgb: bool,
    ) -> Result<ColorTexture, PrepareError> {
        let data = image
            .data
            .as_ref()
            .ok_or_else(|| PrepareError::ImageNotLoaded {
                path: format!("{path}.image"),
            })?;
        let texels = self
            .images
            .entry((Arc::as_ptr(data) as usize, srgb))
            .or_insert_with(|| {
                let (w, h) = (data.width, data.height);
                let texels = match (&data.texels, srgb) {
                    (fmt::Texels::Bytes(t), true) => ImageTexels::from_srgb8(w, h, t.clone()),
                    (fmt::Texels::Floats(t), true) => ImageTexels::from_srgb(w, h, t),
                    (fmt::Texels::Bytes(t), false) => ImageTexels::from_raw8(w, h, t.clone()),
                    (fmt::Texels::Floats(t), false) => ImageTexels::from_raw(w, h, t),
                };
                Arc::new(match &data.alpha {
                    Some(alpha) => texels.with_alpha(Arc::clone(alpha)),
                    None => texels,
                })
            })
            .clone();
        let placed = image.rotate != 0.0 || image.offset != [0.0; 2] || image.wrap_v.is_some();
        let place = placed.then(|| {
            let (sin, cos) = image.rotate.to_radians().sin_cos();
            Box::new(Place {
                turn: Vec2::new(cos, sin),
                offset: Vec2::from(image.offset),
                wrap_v: wrap(image.wrap_v.unwrap_or(image.wrap)),
            })
        });
        Ok(ColorTexture::Image {
            texels,
            scale: image.scale.per_axis().into(),
            wrap: wrap(image.wrap),
            place,
        })
    }

    /// A data texture (`metallic_roughness_texture`, `normal_texture`) of
    /// material key `key` at `path`: an image read as it is.
    fn data_texture(
        &mut self,
        path: &str,
        t: Option<&fmt::TextureRef>,
        srgb: bool,
    ) -> Result<Option<ColorTexture>, PrepareError> {
        match t {
            Some(fmt::TextureRef::Image(image)) => self.image(path, image, srgb).map(Some),
            _ => Ok(None),
        }
    }

    fn builtin(&mut self, path: &str, name: &str) -> Result<Arc<Texture>, PrepareError> {
        let builtin = match fmt::BuiltinTexture::from_name(name) {
            Some(fmt::BuiltinTexture::LabStripes) => Builtin::LabStripes,
            None => {
                return Err(PrepareError::UnknownTexture {
                    path: path.to_string(),
                    name: name.to_string(),
                })
            }
        };
        let texture = self.textures.entry(builtin);
        Ok(texture
            .or_insert_with(|| Arc::new(builtin.texture()))
            .clone())
    }

    /// `surface` with texture `t` (if any) applied.
    fn textured(
        &mut self,
        path: &str,
        mut surface: Phong,
        t: Option<&fmt::TextureRef>,
    ) -> Result<Phong, PrepareError> {
        match t.map(|t| self.texture(path, t)).transpose()? {
            Some(Texturing::Lab(t)) => surface.texture = Some(t),
            Some(Texturing::Color(t)) => surface.color_texture = Some(t),
            None => {}
        }
        Ok(surface)
    }

    /// The mean colour of `texture`, each image's worked out once.
    fn mean(&mut self, texture: &ColorTexture) -> Vec3 {
        match texture {
            ColorTexture::Image { texels, .. } => *self
                .means
                .entry(Arc::as_ptr(texels) as usize)
                .or_insert_with(|| texels.mean()),
            checker => checker.mean(),
        }
    }

    /// The alpha masks of materials `indices`, in order.
    fn masks(&self, indices: &[usize]) -> Vec<Option<Arc<AlphaMask>>> {
        let mask = |&m: &usize| self.materials[m].alpha_mask().cloned();
        indices.iter().map(mask).collect()
    }

    fn push(&mut self, material: Material, name: String) -> usize {
        self.materials.push(material);
        self.names.push(name);
        self.materials.len() - 1
    }

    /// Material `m`, with the object's texture if it has one, else the
    /// material's own: the lab's Blinn-Phong, or glass when it lets light
    /// through or reflects by Fresnel.
    fn material(
        &mut self,
        path: &str,
        m: &fmt::Material,
        texture: Option<&fmt::TextureRef>,
    ) -> Result<Material, PrepareError> {
        if m.is_physical() {
            return self.principled(path, m, texture);
        }
        let surface = Phong {
            ambient: m.ambient.into(),
            diffuse: m.diffuse.into(),
            specular: m.specular.into(),
            shininess: m.shininess,
            reflectance: m.reflectance,
            texture: None,
            color_texture: None,
            emission: m.emission.into(),
            emission_texture: None,
            alpha_mask: None,
        };
        let mut surface = self.textured(path, surface, texture.or(m.texture.as_ref()))?;
        surface.alpha_mask = alpha_mask(m, surface.color_texture.as_ref());
        let emission = m.emission_texture.as_ref();
        if let Some(texture) = self.data_texture(path, emission, true)? {
            let mean = self.mean(&texture);
            surface.emission_texture = Some(EmissionTexture { texture, mean });
        }
        if m.transmittance == 0.0 && !m.fresnel {
            return Ok(Material::Phong(surface));
        }
        Ok(Material::Glass(Glass {
            surface,
            transmittance: m.transmittance,
            ior: m.ior,
            fresnel: m.fresnel,
            absorption: m.absorption.into(),
        }))
    }

    /// A physically based material, with the object's texture if it has
    /// one, else the material's own, on its base colour (validation keeps
    /// the lab's built-in textures off it).
    fn principled(
        &mut self,
        path: &str,
        m: &fmt::Material,
        texture: Option<&fmt::TextureRef>,
    ) -> Result<Material, PrepareError> {
        let params = Principled {
            base_color: m.base_color.unwrap_or(fmt::DEFAULT_BASE_COLOR).into(),
            metallic: m.metallic.unwrap_or(0.0),
            roughness: m.roughness.unwrap_or(fmt::DEFAULT_ROUGHNESS),
            ior: m.ior,
            transmission: m.transmission.unwrap_or(0.0),
        };
        let mut material = PrincipledMaterial::new(params, m.emission.into());
        let texture = texture.or(m.texture.as_ref());
        if let Some(Texturing::Color(t)) = texture.map(|t| self.texture(path, t)).transpose()? {
            material = material.with_color_texture(t);
        }
        let mr = m.metallic_roughness_texture.as_ref();
        material.metallic_roughness = self.data_texture(path, mr, false)?;
        let emission = m.emission_texture.as_ref();
        if let Some(texture) = self.data_texture(path, emission, true)? {
            let mean = self.mean(&texture);
            material = material.with_emission_texture(texture, mean);
        }
        material.alpha_mask = alpha_mask(m, material.color_texture.as_ref());
        let normals = self.data_texture(path, m.normal_texture.as_ref(), false)?;
        material.normal_map = normals.map(|texture| NormalMap {
            texture,
            strength: m.normal_strength.unwrap_or(1.0),
        });
        Ok(Material::Principled(Box::new(material)))
    }

    /// The index of object `o`'s material, with the object's texture applied.
    fn resolve(&mut self, path: &str, o: &fmt::Object) -> Result<usize, PrepareError> {
        let texture_path = format!("{path}.texture");
        match &o.material {
            None => {
                let grey =
                    self.textured(&texture_path, Phong::default_grey(), o.texture.as_ref())?;
                let name = format!("the default grey of {path}");
                Ok(self.push(Material::Phong(grey), name))
            }
            Some(fmt::MaterialRef::Inline(m)) => {
                let material = self.material(&texture_path, m, o.texture.as_ref())?;
                Ok(self.push(material, format!("{path}.material")))
            }
            Some(fmt::MaterialRef::Named(name)) => {
                let texture_name = match &o.texture {
                    None => None,
                    Some(fmt::TextureRef::Named(t)) => Some(t.clone()),
                    // A table of the object's own: a material of its own.
                    Some(_) => {
                        let m = self.named(path, name)?;
                        let material = self.material(&texture_path, m, o.texture.as_ref())?;
                        let name = format!("`{name}` with {path}.texture");
                        return Ok(self.push(material, name));
                    }
                };
                let key = (name.clone(), texture_name);
                if let Some(&index) = self.by_key.get(&key) {
                    return Ok(index);
                }
                let m = self.named(path, name)?;
                let material = self.material(&texture_path, m, o.texture.as_ref())?;
                let shown = match &key.1 {
                    Some(texture) => format!("`{name}` with texture `{texture}`"),
                    None => format!("`{name}`"),
                };
                let index = self.push(material, shown);
                self.by_key.insert(key, index);
                Ok(index)
            }
        }
    }

    /// The material called `name` in `[materials]`.
    fn named(&self, path: &str, name: &str) -> Result<&'a fmt::Material, PrepareError> {
        let file = self.file;
        file.materials
            .get(name)
            .ok_or_else(|| PrepareError::UnknownMaterial {
                path: format!("{path}.material"),
                name: name.to_string(),
            })
    }

    /// The indices of a mesh object's MTL materials, in the OBJ's order,
    /// each with the object's texture if it has one; none when the object
    /// names its own material (which overrides the MTL) or is no mesh.
    fn mtl_materials(&mut self, path: &str, o: &fmt::Object) -> Result<Vec<usize>, PrepareError> {
        let Some(data) = o.mesh.as_ref().and_then(|m| m.data.as_ref()) else {
            return Ok(Vec::new());
        };
        if o.material.is_some() {
            return Ok(Vec::new());
        }
        let texture_path = format!("{path}.texture");
        let mut indices = Vec::with_capacity(data.materials.len());
        for (k, m) in data.materials.iter().enumerate() {
            let material = self.material(&texture_path, m, o.texture.as_ref())?;
            let name = format!("MTL material {} of {path}", k + 1);
            indices.push(self.push(material, name));
        }
        Ok(indices)
    }
}

/// Where material `m` with colour texture `texture` is cut out: by its
/// `alpha_cutoff`, on the texture's alpha.
fn alpha_mask(m: &fmt::Material, texture: Option<&ColorTexture>) -> Option<Arc<AlphaMask>> {
    let cutoff = m.alpha_cutoff?;
    AlphaMask::new(texture.cloned(), cutoff).map(Arc::new)
}

/// The file's wrap mode in the core's terms.
fn wrap(w: fmt::Wrap) -> Wrap {
    match w {
        fmt::Wrap::Repeat => Wrap::Repeat,
        fmt::Wrap::Clamp => Wrap::Clamp,
        fmt::Wrap::Mirror => Wrap::Mirror,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One material for every face.
    const GREY: FaceMaterials = FaceMaterials {
        material: 0,
        mtl: &[],
    };

    #[test]
    fn without_a_transform_mesh_vertices_are_kept_exactly() {
        let data = fmt::MeshData {
            triangles: vec![[[0.1, 0.2, 0.3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]],
            ..fmt::MeshData::default()
        };
        let tris = mesh_objects(&data, &placement(None), None, GREY);
        assert_eq!(tris.len(), 1);
        let Shape::Triangle(t) = &tris[0].shape else {
            panic!("a triangle")
        };
        assert_eq!(t.v0, Vec3::new(0.1, 0.2, 0.3));
    }

    /// One triangle facing +z by its vertex order, with file normals `n`.
    fn one_smooth_triangle(n: [fmt::Vec3; 3]) -> fmt::MeshData {
        fmt::MeshData {
            triangles: vec![[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]],
            indices: vec![[0, 1, 2]],
            normals: vec![Some(n)],
            ..fmt::MeshData::default()
        }
    }

    fn vertex_normals(objects: &[Object]) -> Option<[Vec3; 3]> {
        objects[0].vertex_normals.as_deref().copied()
    }

    #[test]
    fn file_normals_turn_with_the_placement_and_keep_to_the_face_side() {
        let slanted = [1.0, 1.0, 1.0];
        let data = one_smooth_triangle([slanted, [0.0, 0.0, 2.0], [0.0, 0.0, 1.0]]);
        let none = placement(None);
        let n = vertex_normals(&mesh_objects(&data, &none, None, GREY)).expect("smooth");
        assert!((n[0] - Vec3::ONE.normalize()).length() < 1e-6);
        assert_eq!(n[1], Vec3::Z, "normalised");
        // Stretched 3 times along x: the slanted normal leans by 1/3 there.
        let t = fmt::Transform::Table(fmt::TransformTable {
            scale: fmt::Scale::PerAxis([3.0, 1.0, 1.0]),
            ..fmt::TransformTable::default()
        });
        let n = vertex_normals(&mesh_objects(&data, &placement(Some(&t)), None, GREY)).unwrap();
        let expected = Vec3::new(1.0 / 3.0, 1.0, 1.0).normalize();
        assert!((n[0] - expected).length() < 1e-6, "{}", n[0]);
        // A file wound the other way round (normals against the face's):
        // they are turned to the face's side, all three.
        let inward = one_smooth_triangle([[0.0, 0.0, -1.0], [0.1, 0.0, -1.0], [0.0, 0.0, -1.0]]);
        let n = vertex_normals(&mesh_objects(&inward, &none, None, GREY)).unwrap();
        assert!(n.iter().all(|n| n.z > 0.0), "{n:?}");
        // `smooth = false` ignores them; a normal of no length makes it flat.
        assert_eq!(
            vertex_normals(&mesh_objects(&data, &none, Some(false), GREY)),
            None
        );
        let zero = one_smooth_triangle([[0.0; 3], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]);
        assert_eq!(
            vertex_normals(&mesh_objects(&zero, &none, None, GREY)),
            None
        );
    }

    #[test]
    fn a_mirror_keeps_each_vertex_its_own_normal_and_uv() {
        // Normals leaning toward +x at vertex 1 (at x = 1) and +y at vertex
        // 2; mirrored in x, vertex 1 is at x = -1 and its normal must lean
        // toward -x, whichever order the placed triangle lists it in.
        let mut data = one_smooth_triangle([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]);
        data.uvs = vec![Some([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])];
        let t = fmt::Transform::Table(fmt::TransformTable {
            scale: fmt::Scale::PerAxis([-1.0, 1.0, 1.0]),
            ..fmt::TransformTable::default()
        });
        let objects = mesh_objects(&data, &placement(Some(&t)), None, GREY);
        let Shape::Triangle(tri) = &objects[0].shape else {
            panic!("a triangle")
        };
        let normals = vertex_normals(&objects).expect("smooth");
        let corners = [tri.v0, tri.v1, tri.v2];
        for (corner, n) in corners.iter().zip(normals) {
            let expected = if corner.x < -0.5 {
                Vec3::new(-1.0, 0.0, 1.0)
            } else if corner.y > 0.5 {
                Vec3::new(0.0, 1.0, 1.0)
            } else {
                Vec3::Z
            };
            // On the face's side: +z or -z, as its vertex order says.
            let side = tri.normal().z.signum();
            let expected = Vec3::new(expected.x, expected.y, expected.z * side).normalize();
            assert!(
                (n - expected).length() < 1e-6,
                "{corner}: {n} vs {expected}"
            );
        }
        // The uv of each corner is the one the file gave its vertex.
        let uv = objects[0].uv_map();
        let at = |b: Vec2| uv.apply(b);
        for (corner, bary) in corners.iter().zip([Vec2::ZERO, Vec2::X, Vec2::Y]) {
            let expected = Vec2::new(
                (corner.x < -0.5) as u8 as f32,
                (corner.y > 0.5) as u8 as f32,
            );
            assert_eq!(at(bary), expected, "{corner}");
        }
    }

    #[test]
    fn smooth_normals_weigh_the_faces_by_area() {
        // Two faces around vertex 0: one in z = 0 of area 2, one in x = 0
        // of area 0.5; the vertex normal is (2 z + 0.5 x) normalised.
        let data = fmt::MeshData {
            triangles: vec![
                [[0.0; 3], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]],
                [[0.0; 3], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            ],
            indices: vec![[0, 1, 2], [0, 3, 4]],
            ..fmt::MeshData::default()
        };
        let objects = mesh_objects(&data, &placement(None), Some(true), GREY);
        let n = vertex_normals(&objects).expect("made from the faces");
        assert!((n[0] - Vec3::new(0.5, 0.0, 2.0).normalize()).length() < 1e-6);
        assert_eq!(n[1], Vec3::Z, "a vertex of one face has its normal");
        // Without `smooth = true` a file without normals stays flat.
        assert_eq!(
            vertex_normals(&mesh_objects(&data, &placement(None), None, GREY)),
            None
        );
    }

    #[test]
    fn a_mesh_extent_counts_the_triangles_prepare_keeps() {
        let data = fmt::MeshData {
            triangles: vec![
                [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                [[0.0; 3], [1e-3, 0.0, 0.0], [0.0, 1e-3, 0.0]],
            ],
            ..fmt::MeshData::default()
        };
        // Tiny triangles far from the origin: whatever f32 keeps of them,
        // the count is prepare's.
        let t = fmt::Transform::Table(fmt::TransformTable {
            scale: fmt::Scale::Uniform(1e-18),
            translate: [0.0, 0.0, 5.0],
            ..fmt::TransformTable::default()
        });
        let kept = mesh_objects(&data, &placement(Some(&t)), None, GREY).len();
        let extent = mesh_extent(&data, Some(&t));
        assert_eq!(extent.triangles, kept);
        assert_eq!(extent.max_abs, 5.0);
    }

    #[test]
    fn a_transform_is_scale_then_rotate_then_translate() {
        let t = fmt::Transform::Table(fmt::TransformTable {
            translate: [1.0, 2.0, 3.0],
            rotate: [0.0, 0.0, 90.0],
            scale: fmt::Scale::PerAxis([2.0, 1.0, 1.0]),
        });
        // (1,0,0) -> scale (2,0,0) -> 90 deg about z (0,2,0) -> (1,4,3).
        let p = placement(Some(&t)).apply(Vec3::X);
        assert!((p - Vec3::new(1.0, 4.0, 3.0)).length() < 1e-5, "{p}");
    }

    #[test]
    fn every_built_in_texture_name_prepares() {
        let text = "[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\n";
        let file = fmt::load_str(text, fmt::Format::Toml, std::path::Path::new("t.toml"))
            .expect("a minimal scene");
        let mut table = MaterialTable::new(&file);
        for builtin in fmt::BuiltinTexture::ALL {
            assert!(table.builtin("t", builtin.name()).is_ok(), "{builtin:?}");
        }
        assert!(table.builtin("t", "wood").is_err());
    }
}

#[cfg(test)]
mod texture_tests {
    use super::*;

    #[test]
    fn an_8_bit_image_is_shared_with_the_model_not_copied() {
        let text = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n\
                    [materials.m]\ntexture = { image = \"t.png\" }\n\
                    [[objects]]\nsphere = { center = [0, 0, 0], radius = 1 }\nmaterial = \"m\"\n";
        let mut file = fmt::load_str(text, fmt::Format::Toml, "s.toml".as_ref()).unwrap();
        let bytes = Arc::new(vec![[10u8, 20, 30]; 4]);
        let fmt::TextureRef::Image(image) = file
            .materials
            .get_mut("m")
            .unwrap()
            .texture
            .as_mut()
            .unwrap()
        else {
            panic!("an image texture")
        };
        image.data = Some(Arc::new(fmt::ImageData {
            width: 2,
            height: 2,
            texels: fmt::Texels::Bytes(bytes.clone()),
            alpha: None,
        }));
        let scene = prepare(&file).unwrap();
        // The test's, the model's, and the tracer's.
        assert_eq!(Arc::strong_count(&bytes), 3);
        drop(scene);
        assert_eq!(Arc::strong_count(&bytes), 2);
    }
}
