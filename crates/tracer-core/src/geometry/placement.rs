//! Where an object's transform takes its points.

use glam::{Mat3, Vec3};

/// An affine placement: scale, then rotate about x, y, z (in that order),
/// then translate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    linear: Mat3,
    translate: Vec3,
}

impl Placement {
    pub const IDENTITY: Placement = Placement {
        linear: Mat3::IDENTITY,
        translate: Vec3::ZERO,
    };

    /// Scale per axis, rotation angles in degrees about x, then y, then z,
    /// then the translation.
    pub fn new(scale: Vec3, rotate_degrees: Vec3, translate: Vec3) -> Placement {
        let [rx, ry, rz] = rotate_degrees.to_array().map(f32::to_radians);
        let rotation =
            Mat3::from_rotation_z(rz) * Mat3::from_rotation_y(ry) * Mat3::from_rotation_x(rx);
        Placement {
            linear: rotation * Mat3::from_diagonal(scale),
            translate,
        }
    }

    /// The placement `p -> linear p + translate` (a glTF node's matrix).
    pub fn affine(linear: Mat3, translate: Vec3) -> Placement {
        Placement { linear, translate }
    }

    /// A move by `v`.
    pub fn translation(v: Vec3) -> Placement {
        Placement {
            linear: Mat3::IDENTITY,
            translate: v,
        }
    }

    /// `self * inner`, as the lab multiplies matrices: `inner` acts first.
    pub fn compose(&self, inner: &Placement) -> Placement {
        Placement {
            linear: self.linear * inner.linear,
            translate: self.linear * inner.translate + self.translate,
        }
    }

    pub fn apply(&self, p: Vec3) -> Vec3 {
        self.linear * p + self.translate
    }

    /// The smallest box holding the box `lo`..`hi` placed: its eight
    /// corners placed (so at least as far as any point of the box reaches).
    pub fn apply_box(&self, lo: Vec3, hi: Vec3) -> (Vec3, Vec3) {
        (0..8u32)
            .map(|k| {
                let pick = |axis: usize| {
                    if k >> axis & 1 == 0 {
                        lo[axis]
                    } else {
                        hi[axis]
                    }
                };
                self.apply(Vec3::new(pick(0), pick(1), pick(2)))
            })
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), p| {
                (a.min(p), b.max(p))
            })
    }

    /// A direction (a difference of points): moved by the linear part only.
    pub fn apply_vector(&self, v: Vec3) -> Vec3 {
        self.linear * v
    }

    /// A surface normal, unit length: the inverse transpose keeps it
    /// perpendicular to the surface when the scale differs per axis.
    pub fn apply_normal(&self, n: Vec3) -> Vec3 {
        (self.normal_matrix() * n).normalize()
    }

    /// Whether the placement mirrors (a negative determinant): a vertex
    /// order then turns the other way round.
    pub fn mirrors(&self) -> bool {
        self.linear.determinant() < 0.0
    }

    /// The placement that undoes this one, when it has one in f32 (every
    /// entry finite): `inverse().apply(apply(p))` is `p` up to rounding.
    pub fn inverse(&self) -> Option<Placement> {
        let det = self.linear.determinant();
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let linear = self.linear.inverse();
        let translate = -(linear * self.translate);
        let finite = linear.is_finite() && translate.is_finite();
        finite.then_some(Placement { linear, translate })
    }

    /// The linear part.
    pub fn linear(&self) -> Mat3 {
        self.linear
    }

    /// The matrix that takes normals where the placement takes the surface:
    /// the inverse transpose of its linear part (a normal stays
    /// perpendicular to the tangents, which the linear part takes). Its
    /// results are not unit: normalise them.
    pub fn normal_matrix(&self) -> Mat3 {
        self.linear.inverse().transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_then_rotate_then_translate() {
        let placement = Placement::new(
            Vec3::new(2.0, 1.0, 1.0),
            Vec3::new(0.0, 0.0, 90.0),
            Vec3::new(1.0, 2.0, 3.0),
        );
        let p = placement.apply(Vec3::X);
        // (1,0,0) -> scale (2,0,0) -> 90 deg about z (0,2,0) -> (1,4,3).
        assert!((p - Vec3::new(1.0, 4.0, 3.0)).length() < 1e-5, "{p}");
        let rx = Placement::new(Vec3::ONE, Vec3::new(90.0, 0.0, 90.0), Vec3::ZERO);
        // x first: y -> z; then z about z stays z.
        let q = rx.apply(Vec3::Y);
        assert!((q - Vec3::Z).length() < 1e-5, "{q}");
    }

    #[test]
    fn composition_applies_the_inner_placement_first() {
        let move_x = Placement::translation(Vec3::X);
        let double = Placement::new(Vec3::splat(2.0), Vec3::ZERO, Vec3::ZERO);
        // Scale, then move: (1,0,0) -> (2,0,0) -> (3,0,0); the other way (4,0,0).
        assert_eq!(
            move_x.compose(&double).apply(Vec3::X),
            Vec3::new(3.0, 0.0, 0.0)
        );
        assert_eq!(
            double.compose(&move_x).apply(Vec3::X),
            Vec3::new(4.0, 0.0, 0.0)
        );
    }

    #[test]
    fn normals_stay_perpendicular_under_an_uneven_scale() {
        // The plane x + y = 0 (normal (1,1,0)/sqrt 2) stretched 3x along x
        // holds (3,-1,0): its normal must be perpendicular to that.
        let stretch = Placement::new(Vec3::new(3.0, 1.0, 1.0), Vec3::ZERO, Vec3::ZERO);
        let n = stretch.apply_normal(Vec3::new(1.0, 1.0, 0.0));
        let along = stretch.apply_vector(Vec3::new(1.0, -1.0, 0.0));
        assert!(n.dot(along).abs() < 1e-6, "{n} . {along}");
        assert!((n.length() - 1.0).abs() < 1e-6);
        assert!(!stretch.mirrors());
        assert!(Placement::new(Vec3::new(-1.0, 1.0, 1.0), Vec3::ZERO, Vec3::ZERO).mirrors());
    }

    #[test]
    fn normals_stay_perpendicular_to_a_stretched_surface() {
        // The plane x + y = 0 (normal (1, 1, 0)) stretched 3 times along x
        // is the plane x / 3 + y = 0, whose normal is (1/3, 1, 0).
        let placement = Placement::new(Vec3::new(3.0, 1.0, 1.0), Vec3::ZERO, Vec3::ONE);
        let n = (placement.normal_matrix() * Vec3::new(1.0, 1.0, 0.0)).normalize();
        let expected = Vec3::new(1.0 / 3.0, 1.0, 0.0).normalize();
        assert!((n - expected).length() < 1e-6, "{n}");
        // Under a rotation a normal turns with the surface.
        let turn = Placement::new(Vec3::splat(2.0), Vec3::new(0.0, 0.0, 90.0), Vec3::ZERO);
        let n = (turn.normal_matrix() * Vec3::X).normalize();
        assert!((n - Vec3::Y).length() < 1e-6, "{n}");
    }

    #[test]
    fn the_inverse_takes_points_back() {
        let placement = Placement::new(
            Vec3::new(2.0, -0.5, 3.0),
            Vec3::new(30.0, -70.0, 10.0),
            Vec3::new(1.0, -2.0, 5.0),
        );
        let inverse = placement.inverse().expect("invertible");
        for p in [Vec3::ZERO, Vec3::new(0.3, -4.0, 2.5), Vec3::X] {
            let back = inverse.apply(placement.apply(p));
            assert!((back - p).length() < 1e-5, "{p} -> {back}");
        }
        let flat = Placement::new(Vec3::new(1.0, 0.0, 1.0), Vec3::ZERO, Vec3::ZERO);
        assert_eq!(flat.inverse(), None);
    }

    #[test]
    fn the_identity_keeps_points_exactly() {
        let p = Vec3::new(0.1, 0.2, 0.3);
        assert_eq!(Placement::IDENTITY.apply(p), p);
    }
}
