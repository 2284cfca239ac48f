//! The node hierarchy: which nodes a scene (or a picked node) holds, and
//! each one's world matrix, its own (`matrix`, or translation, rotation
//! and scale) times its parents'.

use super::doc::{Document, Node};
use super::{Failure, PlacedMesh};
use crate::key_path::KeyPath;
use crate::model::GltfPick;
use glam::{Mat4, Quat, Vec3};

/// The nodes of the chosen scene that place something.
#[derive(Debug, Default)]
pub(crate) struct Walk {
    pub meshes: Vec<PlacedMesh>,
    /// (node, camera index, world matrix).
    pub cameras: Vec<(usize, usize, Mat4)>,
    /// (node, light index, world matrix).
    pub lights: Vec<(usize, usize, Mat4)>,
}

/// How deep a hierarchy may nest: far beyond any model, and each level is
/// a frame of recursion.
const MAX_DEPTH: usize = 256;

/// A point placed by a column-major matrix.
pub(crate) fn apply(m: &[f32; 16], p: [f32; 3]) -> [f32; 3] {
    Mat4::from_cols_array(m)
        .transform_point3(Vec3::from(p))
        .to_array()
}

/// The placed nodes of the scene and node `pick` names.
pub(crate) fn walk(doc: &Document, pick: &super::Pick) -> Result<Walk, Failure> {
    let parents = parents(doc)?;
    let roots: Vec<(usize, Mat4)> = match &pick.node {
        Some(node) => {
            let n = find_node(doc, node)?;
            vec![(n, parent_matrix(doc, &parents, n)?)]
        }
        None => scene_roots(doc, pick.scene.as_ref())?
            .into_iter()
            .map(|n| (n, Mat4::IDENTITY))
            .collect(),
    };
    let mut walk = Walk::default();
    for (node, parent) in roots {
        visit(doc, node, parent, 0, &mut walk)?;
    }
    Ok(walk)
}

/// Each node's parent, checked: every child an index of `nodes`, and no
/// node the child of two (the nodes form trees, as the spec requires).
fn parents(doc: &Document) -> Result<Vec<Option<usize>>, Failure> {
    let mut parents = vec![None; doc.nodes.len()];
    for (p, node) in doc.nodes.iter().enumerate() {
        for (k, &child) in node.children.iter().enumerate() {
            let at = KeyPath::root()
                .key("nodes")
                .index(p)
                .key("children")
                .index(k);
            let slot = parents.get_mut(child).ok_or_else(|| {
                Failure::at(at.clone(), not_an_index("nodes", child, doc.nodes.len()))
            })?;
            if let Some(first) = *slot {
                return Err(Failure::at(
                    at,
                    format!(
                        "node {child} is already a child of node {first}; expected each node to have one parent (the nodes form trees)"
                    ),
                ));
            }
            *slot = Some(p);
        }
    }
    Ok(parents)
}

/// "expected an index of `list` (0 to n - 1), found i".
pub(crate) fn not_an_index(list: &str, i: usize, n: usize) -> String {
    if n == 0 {
        format!("expected an index of `{list}`, but the file has none; found {i}")
    } else {
        format!("expected an index of `{list}` (0 to {}), found {i}", n - 1)
    }
}

/// The root nodes of the scene `pick` names (by index or name), else the
/// file's `scene`, else its first; a file without scenes shows every node
/// that has no parent.
fn scene_roots(doc: &Document, pick: Option<&GltfPick>) -> Result<Vec<usize>, Failure> {
    let index = match pick {
        Some(GltfPick::Index(i)) if *i < doc.scenes.len() => *i,
        Some(GltfPick::Index(i)) => {
            return Err(Failure::file(format!(
                "there is no scene {i}: {}",
                scene_list(doc)
            )))
        }
        Some(GltfPick::Name(name)) => doc
            .scenes
            .iter()
            .position(|s| s.name.as_deref() == Some(name))
            .ok_or_else(|| {
                Failure::file(format!(
                    "there is no scene named `{name}`: {}",
                    scene_list(doc)
                ))
            })?,
        None => match doc.scene {
            Some(s) if s < doc.scenes.len() => s,
            Some(s) => {
                return Err(Failure::at(
                    KeyPath::root().key("scene"),
                    not_an_index("scenes", s, doc.scenes.len()),
                ))
            }
            None if doc.scenes.is_empty() => {
                let mut children = vec![false; doc.nodes.len()];
                for node in &doc.nodes {
                    for &c in &node.children {
                        children[c] = true;
                    }
                }
                return Ok((0..doc.nodes.len()).filter(|&n| !children[n]).collect());
            }
            None => 0,
        },
    };
    let scene = &doc.scenes[index];
    for (k, &n) in scene.nodes.iter().enumerate() {
        if n >= doc.nodes.len() {
            let at = KeyPath::root()
                .key("scenes")
                .index(index)
                .key("nodes")
                .index(k);
            return Err(Failure::at(at, not_an_index("nodes", n, doc.nodes.len())));
        }
    }
    Ok(scene.nodes.clone())
}

fn scene_list(doc: &Document) -> String {
    if doc.scenes.is_empty() {
        return "the file has no `scenes`".to_string();
    }
    let names: Vec<String> = doc
        .scenes
        .iter()
        .enumerate()
        .map(|(i, s)| match &s.name {
            Some(n) => format!("{i} (`{n}`)"),
            None => i.to_string(),
        })
        .collect();
    format!("expected one of {}", names.join(", "))
}

/// The node `pick` names, by index or name.
fn find_node(doc: &Document, pick: &GltfPick) -> Result<usize, Failure> {
    match pick {
        GltfPick::Index(i) if *i < doc.nodes.len() => Ok(*i),
        GltfPick::Index(i) => Err(Failure::file(format!(
            "there is no node {i}: {}",
            not_an_index("nodes", *i, doc.nodes.len())
        ))),
        GltfPick::Name(name) => doc
            .nodes
            .iter()
            .position(|n| n.name.as_deref() == Some(name))
            .ok_or_else(|| {
                let named: Vec<&str> = doc.nodes.iter().filter_map(|n| n.name.as_deref()).collect();
                let hint = match named.as_slice() {
                    [] => "the file's nodes have no names".to_string(),
                    names => crate::suggestion(name, names)
                        .map(|s| format!("did you mean `{s}`?"))
                        .unwrap_or_else(|| {
                            let shown: Vec<&str> = names.iter().take(10).copied().collect();
                            format!("its named nodes include {}", shown.join(", "))
                        }),
                };
                Failure::file(format!("there is no node named `{name}`; {hint}"))
            }),
    }
}

/// The world matrix of node `n`'s parent (the identity for a root).
fn parent_matrix(doc: &Document, parents: &[Option<usize>], n: usize) -> Result<Mat4, Failure> {
    let mut chain = Vec::new();
    let mut at = parents[n];
    while let Some(p) = at {
        if chain.len() > MAX_DEPTH || p == n {
            return Err(nesting(n));
        }
        chain.push(p);
        at = parents[p];
    }
    let mut m = Mat4::IDENTITY;
    for &p in chain.iter().rev() {
        m *= local(&doc.nodes[p], p)?;
    }
    Ok(m)
}

fn nesting(n: usize) -> Failure {
    Failure::at(
        KeyPath::root().key("nodes").index(n),
        format!(
            "the node hierarchy above or below node {n} is a cycle or nests more than {MAX_DEPTH} deep; expected trees"
        ),
    )
}

/// Visits node `n` under the world matrix `parent`, then its children.
fn visit(
    doc: &Document,
    n: usize,
    parent: Mat4,
    depth: usize,
    walk: &mut Walk,
) -> Result<(), Failure> {
    if depth > MAX_DEPTH {
        return Err(nesting(n));
    }
    let node = &doc.nodes[n];
    let at = KeyPath::root().key("nodes").index(n);
    let world = parent * local(node, n)?;
    if let Some(mesh) = node.mesh {
        if mesh >= doc.meshes.len() {
            return Err(Failure::at(
                at.key("mesh"),
                not_an_index("meshes", mesh, doc.meshes.len()),
            ));
        }
        walk.meshes.push(PlacedMesh {
            mesh,
            node: n,
            matrix: world.to_cols_array(),
        });
    }
    if let Some(camera) = node.camera {
        if camera >= doc.cameras.len() {
            return Err(Failure::at(
                at.key("camera"),
                not_an_index("cameras", camera, doc.cameras.len()),
            ));
        }
        walk.cameras.push((n, camera, world));
    }
    if let Some(light) = &node.extensions.light {
        let count = doc
            .extensions
            .lights_punctual
            .as_ref()
            .map_or(0, |l| l.lights.len());
        if light.light >= count {
            let key = at.key("extensions").key("KHR_lights_punctual").key("light");
            return Err(Failure::at(
                key,
                not_an_index("extensions.KHR_lights_punctual.lights", light.light, count),
            ));
        }
        walk.lights.push((n, light.light, world));
    }
    for &child in &node.children {
        visit(doc, child, world, depth + 1, walk)?;
    }
    Ok(())
}

/// A node's own matrix: `matrix`, or translation * rotation * scale (the
/// rotation normalised), every number finite.
fn local(node: &Node, n: usize) -> Result<Mat4, Failure> {
    let at = KeyPath::root().key("nodes").index(n);
    let finite = |key: &str, values: &[f32]| {
        if values.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(Failure::at(
                at.key(key),
                format!("expected finite numbers, found {values:?}"),
            ))
        }
    };
    if let Some(m) = &node.matrix {
        finite("matrix", m)?;
        if node.translation.is_some() || node.rotation.is_some() || node.scale.is_some() {
            return Err(Failure::at(
                at.key("matrix"),
                "expected either `matrix` or translation, rotation and scale, found both",
            ));
        }
        return Ok(Mat4::from_cols_array(m));
    }
    let t = node.translation.unwrap_or([0.0; 3]);
    let r = node.rotation.unwrap_or([0.0, 0.0, 0.0, 1.0]);
    let s = node.scale.unwrap_or([1.0; 3]);
    finite("translation", &t)?;
    finite("rotation", &r)?;
    finite("scale", &s)?;
    let q = Quat::from_array(r);
    let length = q.length();
    if !(length > 1e-6 && length.is_finite()) {
        return Err(Failure::at(
            at.key("rotation"),
            format!("expected a unit quaternion [x, y, z, w], found {r:?}, which has no direction"),
        ));
    }
    Ok(Mat4::from_scale_rotation_translation(
        Vec3::from(s),
        q / length,
        Vec3::from(t),
    ))
}
