//! The bench scenes: the benchmark scene of the peers (the Stanford bunny),
//! the same bunny at 16 samples per pixel and at 1.1M triangles, and the
//! lab's final scene.

use anyhow::{Context, Result};
use scene_format::{MeshData, SceneFile};
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The bunny's mesh, relative to the workspace root (Embree reads it too).
pub const BUNNY_OBJ: &str = "scenes/bench/bunny.obj";

/// The lab's final scene, relative to the workspace root.
const REFLECTANCE2: &str = "scenes/reflectance2.toml";

pub struct BenchScene {
    pub name: &'static str,
    /// The scene, its meshes loaded.
    pub file: SceneFile,
    /// Samples per pixel, for us and for POV-Ray (1: one ray through each
    /// pixel centre, as the peers' benchmark).
    pub samples: u32,
    /// For a scene Embree can run (the bunny): its `--subdiv`.
    pub embree_subdiv: Option<u32>,
    /// The OBJ file of its mesh, whose reading is timed.
    pub obj: Option<PathBuf>,
    /// The scene file, for a scene whose whole `tracer render` process is
    /// timed too (a small one: start-up and output weigh beside its render).
    pub process: Option<PathBuf>,
}

pub fn scenes(root: &Path) -> Result<Vec<BenchScene>> {
    let bunny = load(&root.join("scenes/bench/bunny.toml"))?;
    let mut big = bunny.clone();
    for object in &mut big.objects {
        if let Some(mesh) = object.mesh.as_mut() {
            let data = mesh.data.as_ref().context("bunny mesh not loaded")?;
            mesh.data = Some(Arc::new(subdivide(&subdivide(data))));
        }
    }
    let big_obj = crate::target_dir().join("bench/bunny-1.1m.obj");
    if !big_obj.exists() {
        let data = big
            .objects
            .iter()
            .find_map(|o| o.mesh.as_ref()?.data.as_ref());
        write_obj(data.context("bunny mesh not loaded")?, &big_obj)?;
    }
    Ok(vec![
        BenchScene {
            name: "bunny",
            file: bunny.clone(),
            samples: 1,
            embree_subdiv: Some(0),
            obj: Some(root.join(BUNNY_OBJ)),
            process: None,
        },
        // Anti-aliased: POV-Ray's supersampling against ours. Embree's
        // harness casts one ray per pixel only.
        BenchScene {
            name: "bunny-16spp",
            file: bunny,
            samples: 16,
            embree_subdiv: None,
            obj: None,
            process: None,
        },
        BenchScene {
            name: "bunny-1.1m",
            file: big,
            samples: 1,
            embree_subdiv: Some(2),
            obj: Some(big_obj),
            process: None,
        },
        BenchScene {
            name: "reflectance2",
            file: load(&root.join(REFLECTANCE2))?,
            samples: 1,
            embree_subdiv: None,
            obj: None,
            process: Some(root.join(REFLECTANCE2)),
        },
    ])
}

fn load(path: &Path) -> Result<SceneFile> {
    scene_format::load_path(path).map_err(|e| anyhow::anyhow!("{e}"))
}

/// Writes `data` as an OBJ file, each distinct vertex once (as the peers'
/// `--subdiv` meshes share them), through a temporary file.
fn write_obj(data: &MeshData, path: &Path) -> Result<()> {
    let mut index: HashMap<[u32; 3], usize> = HashMap::new();
    let mut vertices = Vec::new();
    let mut faces = Vec::with_capacity(data.triangles.len());
    for triangle in &data.triangles {
        faces.push(triangle.map(|v| {
            *index.entry(v.map(f32::to_bits)).or_insert_with(|| {
                vertices.push(v);
                vertices.len()
            })
        }));
    }
    let mut text = Vec::new();
    for [x, y, z] in vertices {
        writeln!(text, "v {x} {y} {z}")?;
    }
    for [a, b, c] in faces {
        writeln!(text, "f {a} {b} {c}")?;
    }
    std::fs::create_dir_all(path.parent().context("no folder")?)?;
    let temporary = path.with_extension("obj.part");
    std::fs::write(&temporary, text)?;
    std::fs::rename(&temporary, path).with_context(|| format!("writing {}", path.display()))
}

/// Splits every triangle 1 -> 4 at its edge midpoints: the same surface,
/// four times the triangles (the peers' `--subdiv`).
pub fn subdivide(data: &MeshData) -> MeshData {
    let mid = |a: [f32; 3], b: [f32; 3]| {
        [
            (a[0] + b[0]) * 0.5,
            (a[1] + b[1]) * 0.5,
            (a[2] + b[2]) * 0.5,
        ]
    };
    let mut triangles = Vec::with_capacity(data.triangles.len() * 4);
    for &[a, b, c] in &data.triangles {
        let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    MeshData {
        triangles,
        skipped_degenerate: data.skipped_degenerate,
        first_degenerate_line: data.first_degenerate_line,
        // The bench meshes have no materials.
        ..MeshData::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subdivision_quarters_each_triangle_on_the_same_surface() {
        let data = MeshData {
            triangles: vec![[[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]],
            ..MeshData::default()
        };
        let twice = subdivide(&subdivide(&data));
        assert_eq!(twice.triangles.len(), 16);
        let area = |[a, b, c]: &[[f32; 3]; 3]| {
            ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2.0
        };
        // Same orientation and total area (2) as the original.
        assert!(twice.triangles.iter().all(|t| area(t) == 0.125));
    }
}
