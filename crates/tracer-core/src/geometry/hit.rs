//! The record of a ray meeting a surface: what shading, textures and the
//! next features (glass, smooth normals) read of a hit.

use super::{Plane, Sphere, TriangleHit};
use crate::ray::Ray;
use glam::{Vec2, Vec3, Vec4};

/// A ray's hit on an object's surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceHit {
    /// Distance along the ray (in units of its direction's length).
    pub t: f32,
    /// Index of the object in `Scene::objects()`.
    pub object: usize,
    /// Index of the object's material (`Scene::material(index)`).
    pub material: usize,
    /// The unit normal of the surface as the lab defines it: a triangle's
    /// from its vertex order, a sphere's outward; never flipped toward the ray.
    pub geometric_normal: Vec3,
    /// The unit normal shading uses: the geometric one, or on a smooth
    /// triangle its vertex normals interpolated (always on the geometric
    /// normal's side: the vertex normals are oriented so when prepared).
    pub shading_normal: Vec3,
    /// Surface coordinates: barycentric (u, v) on a triangle (v0 -> (0, 0),
    /// v1 -> (1, 0), v2 -> (0, 1)) unless its object maps them (a quad's or
    /// box face's half: (s, t) over the whole face); the lab's spherical
    /// mapping on a sphere; coordinates along the plane's axes on a plane.
    pub uv: Vec2,
    /// Whether the ray met the side the geometric normal points to.
    pub front_face: bool,
    /// Where shadow rays start, from the hit point: zero, except on a
    /// smooth triangle, where the flat face lies below the curved surface
    /// its vertex normals describe, so rays leaving it toward a light just
    /// above the shading horizon would meet the neighbouring faces (blocky
    /// black shadows along the terminator). Shadow rays start on that
    /// curved surface instead (Hanika, "Hacking the shadow terminator",
    /// Ray Tracing Gems II, 2021).
    pub shadow_offset: Vec3,
    /// The tangent along the texture's u at the hit (x, y, z) and the
    /// handedness (w, +-1: bitangent = w normal x tangent), interpolated
    /// from a mesh's vertex tangents; zero where the mesh has none. A
    /// normal texture bends the shading normal in this frame
    /// (`Scene::closest_hit`).
    pub tangent: Vec4,
}

impl SurfaceHit {
    /// A hit at distance 1 on the front of object 0 (material 0) whose
    /// normals are `normal`, at `uv`: where a material is read apart from
    /// any shape (a lobe's parameters, tests).
    pub fn facing(normal: Vec3, uv: Vec2) -> SurfaceHit {
        SurfaceHit {
            t: 1.0,
            object: 0,
            material: 0,
            geometric_normal: normal,
            shading_normal: normal,
            uv,
            front_face: true,
            shadow_offset: Vec3::ZERO,
            tangent: Vec4::ZERO,
        }
    }

    /// The hit on a sphere at distance `t` along `ray`; without `with_uv`
    /// (its material reads none) its uv is left at 0, two arc sines saved.
    pub fn on_sphere(
        sphere: &Sphere,
        ray: &Ray,
        t: f32,
        (object, material): (usize, usize),
        with_uv: bool,
    ) -> SurfaceHit {
        let point = ray.at(t);
        let normal = sphere.normal(point);
        SurfaceHit {
            t,
            object,
            material,
            geometric_normal: normal,
            shading_normal: normal,
            uv: if with_uv {
                sphere.uv(point, normal)
            } else {
                Vec2::ZERO
            },
            front_face: ray.dir().dot(normal) < 0.0,
            shadow_offset: Vec3::ZERO,
            tangent: Vec4::ZERO,
        }
    }

    /// The hit on a triangle with edges `e1 = v1 - v0`, `e2 = v2 - v0`, as
    /// Moller-Trumbore found it.
    pub fn on_triangle(
        e1: Vec3,
        e2: Vec3,
        ray: &Ray,
        hit: TriangleHit,
        object: usize,
        material: usize,
    ) -> SurfaceHit {
        // The same edges and operations as `Triangle::normal`.
        let normal = e1.cross(e2).normalize();
        SurfaceHit {
            t: hit.t,
            object,
            material,
            geometric_normal: normal,
            shading_normal: normal,
            uv: hit.uv,
            front_face: ray.dir().dot(normal) < 0.0,
            shadow_offset: Vec3::ZERO,
            tangent: Vec4::ZERO,
        }
    }

    /// This hit of `ray` on the triangle `v0`, `v0 + e1`, `v0 + e2` with
    /// unit vertex `normals`, at barycentric `b` (before any uv map): the
    /// shading normal interpolated from them (where they cancel out, the
    /// geometric one stays), and shadow rays moved onto the curved surface.
    pub fn with_vertex_normals(
        mut self,
        ray: &Ray,
        [v0, e1, e2]: [Vec3; 3],
        normals: &[Vec3; 3],
        b: Vec2,
    ) -> SurfaceHit {
        let weights = [1.0 - b.x - b.y, b.x, b.y];
        let n = weights[0] * normals[0] + weights[1] * normals[1] + weights[2] * normals[2];
        if let Some(n) = n.try_normalize() {
            self.shading_normal = n;
        }
        // Hanika's offset: the point projected onto each vertex's tangent
        // plane where it lies below it, blended by the barycentrics.
        let p = ray.at(self.t);
        let corners = [v0, v0 + e1, v0 + e2];
        let mut offset = Vec3::ZERO;
        for k in 0..3 {
            let below = (p - corners[k]).dot(normals[k]).min(0.0);
            offset -= weights[k] * below * normals[k];
        }
        self.shadow_offset = offset;
        self
    }

    /// This hit with the vertex `tangents` interpolated at barycentric `b`
    /// (their handedness is the first corner's: a triangle has one).
    pub fn with_tangents(mut self, tangents: &[Vec4; 3], b: Vec2) -> SurfaceHit {
        let weights = [1.0 - b.x - b.y, b.x, b.y];
        let t = weights[0] * tangents[0].truncate()
            + weights[1] * tangents[1].truncate()
            + weights[2] * tangents[2].truncate();
        let sign = if tangents[0].w < 0.0 { -1.0 } else { 1.0 };
        self.tangent = t.normalize_or_zero().extend(sign);
        self
    }

    /// The hit on a plane at distance `t` along `ray`.
    pub fn on_plane(
        plane: &Plane,
        ray: &Ray,
        t: f32,
        object: usize,
        material: usize,
    ) -> SurfaceHit {
        SurfaceHit {
            t,
            object,
            material,
            geometric_normal: plane.normal,
            shading_normal: plane.normal,
            uv: plane.uv(ray.at(t)),
            front_face: ray.dir().dot(plane.normal) < 0.0,
            shadow_offset: Vec3::ZERO,
            tangent: Vec4::ZERO,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Triangle;

    fn hit_at_centroid(normals: &[Vec3; 3]) -> SurfaceHit {
        let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        let ray = Ray::new(Vec3::new(1.0 / 3.0, 1.0 / 3.0, 2.0), -Vec3::Z);
        let hit = t.intersect(&ray, 0.0, f32::INFINITY).expect("a hit");
        let (e1, e2, _) = t.edges();
        let flat = SurfaceHit::on_triangle(e1, e2, &ray, hit, 0, 0);
        flat.with_vertex_normals(&ray, [t.v0, e1, e2], normals, hit.uv)
    }

    #[test]
    fn flat_vertex_normals_change_nothing() {
        let hit = hit_at_centroid(&[Vec3::Z; 3]);
        assert_eq!(hit.shading_normal, Vec3::Z);
        assert_eq!(hit.shadow_offset, Vec3::ZERO);
    }

    #[test]
    fn a_dome_lifts_the_shadow_rays_above_the_face() {
        // Normals of a sphere of radius r around c = centroid - h z through
        // the three corners: at the centroid the interpolated normal is
        // about +z, and the shadow origin rises above the flat face to at
        // least the sphere's height there (its sagitta r - h), and less
        // than twice it (the tangent planes, as in Phong tessellation,
        // bulge beyond the sphere).
        let centroid = Vec3::new(1.0 / 3.0, 1.0 / 3.0, 0.0);
        let d = (Vec3::X - centroid).length();
        let r = 2.0f32;
        let h = (r * r - d * d).sqrt();
        let c = centroid - Vec3::Z * h;
        let normals = [Vec3::ZERO, Vec3::X, Vec3::Y].map(|v| (v - c).normalize());
        let hit = hit_at_centroid(&normals);
        assert!(
            (hit.shading_normal - Vec3::Z).length() < 0.02,
            "{}",
            hit.shading_normal
        );
        let (lift, sagitta) = (hit.shadow_offset.z, r - h);
        assert!(
            lift > sagitta && lift < 2.0 * sagitta,
            "{lift} vs {sagitta}"
        );
        // Mostly up: the right triangle is not symmetric about its centroid.
        let sideways = hit.shadow_offset.truncate().length();
        assert!(sideways < 0.1 * lift, "{sideways}");
    }
}
