use glam::{Vec3, Vec4};

/// A half line `origin + t * dir`, t >= 0.
///
/// Each vector is kept in a 16-byte SIMD value, written and read whole: a
/// ray is mostly made just before it is searched, and written as three
/// floats in pieces (as the compiler grouped them), it was read back in
/// other pieces the processor could not forward from those writes; the
/// wait was a fifth of a shadow ray's search in a small scene.
#[derive(Clone, Copy, PartialEq)]
pub struct Ray {
    origin: Vec4,
    dir: Vec4,
}

/// A placeholder in arrays of rays.
pub const NO_RAY: Ray = Ray {
    origin: Vec4::ZERO,
    dir: Vec4::ZERO,
};

impl std::fmt::Debug for Ray {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Ray")
            .field("origin", &self.origin())
            .field("dir", &self.dir())
            .finish()
    }
}

impl Ray {
    #[inline(always)]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray {
            origin: origin.extend(0.0),
            dir: dir.extend(0.0),
        }
    }

    #[inline(always)]
    pub fn origin(&self) -> Vec3 {
        self.origin.truncate()
    }

    #[inline(always)]
    pub fn dir(&self) -> Vec3 {
        self.dir.truncate()
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin() + t * self.dir()
    }

    /// The mirror reflection at `point` with unit `normal` (lab 5.2):
    /// `dir = normalize(v - 2 (v.n) n)`; the normal's sign does not matter.
    pub fn reflected(&self, point: Vec3, normal: Vec3) -> Ray {
        let v = self.dir();
        Ray::new(point, (v - 2.0 * v.dot(normal) * normal).normalize())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflected_ray_matches_the_lab_check() {
        let ray = Ray::new(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(0.5, 0.5, 0.0));
        let r = ray.reflected(Vec3::ZERO, Vec3::Y);
        assert_eq!(r.origin(), Vec3::ZERO);
        let expected = Vec3::new(0.71, -0.71, 0.0);
        assert!(
            (r.dir() - expected).abs().max_element() < 0.01,
            "{:?}",
            r.dir
        );
    }
}
