//! Triangle meshes: the triangles of an OBJ file, placed by the object's
//! transform. Each becomes a triangle of the scene, shaded like the lab's.

use super::Triangle;
use glam::{Mat3, Vec3};
use scene_format::{MeshData, Transform};

/// Where a transform takes a point: scale, then rotate about x, y, z (in
/// that order, degrees), then translate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    linear: Mat3,
    translate: Vec3,
}

impl Placement {
    pub fn from_scene(t: Option<&Transform>) -> Placement {
        let Some(t) = t else {
            return Placement {
                linear: Mat3::IDENTITY,
                translate: Vec3::ZERO,
            };
        };
        let [rx, ry, rz] = t.rotate.map(f32::to_radians);
        let rotation =
            Mat3::from_rotation_z(rz) * Mat3::from_rotation_y(ry) * Mat3::from_rotation_x(rx);
        Placement {
            linear: rotation * Mat3::from_diagonal(t.scale.per_axis().into()),
            translate: t.translate.into(),
        }
    }

    pub fn apply(&self, p: Vec3) -> Vec3 {
        self.linear * p + self.translate
    }
}

/// The mesh's triangles in world space; triangles that the transform makes
/// degenerate (zero area in f32) are left out.
pub fn triangles(data: &MeshData, placement: &Placement) -> Vec<Triangle> {
    data.triangles
        .iter()
        .map(|[a, b, c]| {
            let [a, b, c] = [*a, *b, *c].map(|v| placement.apply(v.into()));
            Triangle::new(a, b, c)
        })
        .filter(|t| (t.v1 - t.v0).cross(t.v2 - t.v0) != Vec3::ZERO)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use scene_format::Scale;

    #[test]
    fn scale_then_rotate_then_translate() {
        let t = Transform {
            translate: [1.0, 2.0, 3.0],
            rotate: [0.0, 0.0, 90.0],
            scale: Scale::PerAxis([2.0, 1.0, 1.0]),
        };
        let p = Placement::from_scene(Some(&t)).apply(Vec3::X);
        // (1,0,0) -> scale (2,0,0) -> 90 deg about z (0,2,0) -> (1,4,3).
        assert!((p - Vec3::new(1.0, 4.0, 3.0)).length() < 1e-5, "{p}");
        let rx = Transform {
            rotate: [90.0, 0.0, 90.0],
            ..Transform::default()
        };
        // x first: y -> z; then z about z stays z.
        let q = Placement::from_scene(Some(&rx)).apply(Vec3::Y);
        assert!((q - Vec3::Z).length() < 1e-5, "{q}");
    }

    #[test]
    fn without_a_transform_vertices_are_kept_exactly() {
        let data = MeshData {
            triangles: vec![[[0.1, 0.2, 0.3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]],
            skipped_degenerate: 0,
        };
        let tris = triangles(&data, &Placement::from_scene(None));
        assert_eq!(tris.len(), 1);
        assert_eq!(tris[0].v0, Vec3::new(0.1, 0.2, 0.3));
    }
}
