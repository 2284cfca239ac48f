use glam::Vec3;

/// A half line `origin + t * dir`, t >= 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
}

/// A placeholder in arrays of rays.
pub const NO_RAY: Ray = Ray {
    origin: Vec3::ZERO,
    dir: Vec3::ZERO,
};

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray { origin, dir }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }

    /// The mirror reflection at `point` with unit `normal` (lab 5.2):
    /// `dir = normalize(v - 2 (v.n) n)`; the normal's sign does not matter.
    pub fn reflected(&self, point: Vec3, normal: Vec3) -> Ray {
        let v = self.dir;
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
        assert_eq!(r.origin, Vec3::ZERO);
        let expected = Vec3::new(0.71, -0.71, 0.0);
        assert!((r.dir - expected).abs().max_element() < 0.01, "{:?}", r.dir);
    }
}
