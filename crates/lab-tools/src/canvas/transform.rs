//! The lab's homogeneous 3x3 transforms (section 1): translation, rotation
//! about (0, 0), scale, and their composition as the lab writes it.

use glam::{Mat3, Vec2};
use scene_format::canvas::Transform;

/// A 3x3 matrix written row by row, as the lab prints them.
fn from_rows(rows: [[f32; 3]; 3]) -> Mat3 {
    Mat3::from_cols_array_2d(&rows).transpose()
}

/// Translation by (tx, ty): `[[1,0,tx],[0,1,ty],[0,0,1]]`.
pub fn translation(tx: f32, ty: f32) -> Mat3 {
    from_rows([[1.0, 0.0, tx], [0.0, 1.0, ty], [0.0, 0.0, 1.0]])
}

/// Rotation by `degrees` about (0, 0): `[[cos,-sin,0],[sin,cos,0],[0,0,1]]`.
pub fn rotation(degrees: f32) -> Mat3 {
    let (sin, cos) = degrees.to_radians().sin_cos();
    from_rows([[cos, -sin, 0.0], [sin, cos, 0.0], [0.0, 0.0, 1.0]])
}

/// Scale by (sx, sy): `[[sx,0,0],[0,sy,0],[0,0,1]]`.
pub fn scale(sx: f32, sy: f32) -> Mat3 {
    from_rows([[sx, 0.0, 0.0], [0.0, sy, 0.0], [0.0, 0.0, 1.0]])
}

pub fn matrix(t: &Transform) -> Mat3 {
    match *t {
        Transform::Translate([tx, ty]) => translation(tx, ty),
        Transform::Rotate(degrees) => rotation(degrees),
        Transform::Scale(s) => {
            let [sx, sy] = s.per_axis();
            scale(sx, sy)
        }
    }
}

/// The product of the list in the order written, `[A, B, C]` -> `A * B * C`,
/// as the lab writes `M = T * R * S`: the last entry acts on a point first.
pub fn compose(transforms: &[Transform]) -> Mat3 {
    transforms.iter().fold(Mat3::IDENTITY, |m, t| m * matrix(t))
}

/// `M * [x, y, 1]`, back to 2D.
pub fn apply(m: &Mat3, p: Vec2) -> Vec2 {
    let q = *m * p.extend(1.0);
    Vec2::new(q.x, q.y) / q.z
}
