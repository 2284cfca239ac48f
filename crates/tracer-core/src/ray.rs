use glam::{Vec3, Vec4};

/// A half line `origin + t * dir`, t >= 0.
///
/// The origin and the direction are each kept in a 16-byte SIMD value,
/// written and read whole. Most rays are searched just after they are
/// made; kept as plain `Vec3`s, they were written in pieces (as the
/// compiler grouped the floats) and read back in other pieces, which the
/// processor cannot forward from the writes: the wait was a fifth to a
/// quarter of a shadow ray's search in a small scene.
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
    fn a_ray_gives_back_its_vectors_bit_for_bit() {
        let odd = [-0.0, f32::MIN_POSITIVE / 8.0, f32::INFINITY, 1.0e-30, -3.25];
        for (i, &x) in odd.iter().enumerate() {
            let (y, z) = (odd[(i + 1) % odd.len()], odd[(i + 2) % odd.len()]);
            let (origin, dir) = (Vec3::new(x, y, z), Vec3::new(z, x, y));
            let ray = Ray::new(origin, dir);
            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
            assert_eq!(bits(ray.origin()), bits(origin));
            assert_eq!(bits(ray.dir()), bits(dir));
            assert_eq!(ray, Ray::new(origin, dir));
        }
        assert_ne!(Ray::new(Vec3::ZERO, Vec3::X), Ray::new(Vec3::ZERO, Vec3::Y));
    }

    #[test]
    fn reflected_ray_matches_the_lab_check() {
        let ray = Ray::new(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(0.5, 0.5, 0.0));
        let r = ray.reflected(Vec3::ZERO, Vec3::Y);
        assert_eq!(r.origin(), Vec3::ZERO);
        let expected = Vec3::new(0.71, -0.71, 0.0);
        assert!(
            (r.dir() - expected).abs().max_element() < 0.01,
            "{:?}",
            r.dir()
        );
    }
}
