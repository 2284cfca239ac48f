//! Small scenes searched without the tree: when there are only a few
//! primitives, testing them all costs less than the traversal around them
//! (the ray's inverse direction, the thread's stack, the root's boxes, the
//! pushes and pops).
//!
//! The hits are the tree's and the brute-force loop's: the same tests on
//! the same records, offered to the same `Best`, whose rule (nearer, or as
//! near and listed first) does not depend on the order of the offers.

use super::traverse::Best;
use super::tri4::Ray4;
use super::Bvh;
use crate::ray::Ray;

/// Scenes of up to this many primitives (spheres and triangles, each
/// counted) are searched flat. Every scene the lab's four-lane form takes
/// (`integrate/lanes.rs`: at most 8 objects, each tested) is, so the two
/// meet the same hits even where rounding decides (a ray grazing a sphere
/// of radius 0).
pub(super) const FLAT_MAX: usize = 8;

/// Larger scenes of spheres in up to this many blocks of four
/// (`sphere4.rs`) and at most one block of triangles are searched flat too:
/// four blocks' tests cost less than the walk (`scenes/materials.toml`, 10
/// spheres and a quad: 9 to 12 % less time, path traced, 1 thread; 16
/// spheres and a quad: 8 %). Triangles come four to a test too, but the
/// root's boxes cull them often: with more than a few the tree was faster
/// (the courtyard's 2 spheres and 14 triangles: 6 % less time through the
/// tree, `textures.toml`'s 1 and 14: 40 %, 16 triangles: 35 %).
const FLAT_SPHERE_BLOCKS: usize = 4;

/// Whether a scene of `spheres` and `triangles` (its planes and instances
/// left out) is searched flat.
pub(super) fn few(spheres: usize, triangles: usize) -> bool {
    spheres + triangles <= FLAT_MAX || (spheres.div_ceil(4) <= FLAT_SPHERE_BLOCKS && triangles <= 4)
}

impl Bvh {
    /// Whether the scene is small enough to be searched flat (`few`, as
    /// `build` found it).
    #[inline(always)]
    pub(super) fn is_flat(&self) -> bool {
        self.few
    }

    /// Offers `best` every hit of the spheres and triangles.
    #[inline(always)]
    pub(super) fn nearest_flat(&self, ray: &Ray, t_min: f32, t_max: f32, best: &mut Best) {
        self.offer_spheres(0..self.spheres.len(), ray, t_min, t_max, best);
        if !self.tris.is_empty() {
            let ray4 = Ray4::new(ray);
            self.offer_blocks(0..self.tris.len(), &ray4, t_min, t_max, best);
        }
    }

    /// Whether a sphere or triangle lies on the ray in (t_min, t_max).
    #[inline(always)]
    pub(super) fn any_flat(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        if self.any_sphere(0..self.spheres.len(), ray, t_min, t_max) {
            return true;
        }
        !self.tris.is_empty() && self.any_block(0..self.tris.len(), &Ray4::new(ray), t_min, t_max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::brute_force;
    use crate::accel::tests::Rng;
    use crate::geometry::{Object, Plane, Shape, Sphere, Triangle};
    use glam::Vec3;

    /// A few spheres and triangles (and sometimes a plane) close together,
    /// some of them copies of others: ties the object listed first wins.
    /// Past 12 objects, all but two triangles are spheres.
    fn small_scene(rng: &mut Rng, n: usize) -> Vec<Object> {
        let mut objects: Vec<Object> = (0..n)
            .map(|i| {
                let c = rng.vec(2.0);
                let radius = 0.2 + 0.8 * rng.next().abs();
                let shape = if i % 6 == 4 {
                    // An ellipsoid, stretched and turned: tested alone.
                    let axes = Vec3::new(1.0, 0.3, 0.6);
                    let turn = glam::Mat3::from_axis_angle(Vec3::X, rng.next() * 3.0);
                    let linear = turn * glam::Mat3::from_diagonal(axes);
                    Shape::Sphere(Sphere::ellipsoid(c, radius, linear))
                } else if i % 2 == 0 || (n > 12 && i >= 4) {
                    Shape::Sphere(Sphere::new(c, radius))
                } else {
                    Shape::Triangle(Triangle::new(c, c + rng.vec(2.0), c + rng.vec(2.0)))
                };
                Object::new(shape, i % 3)
            })
            .collect();
        if n.is_multiple_of(3) {
            objects.push(objects[0].clone());
        }
        if n % 4 == 1 {
            let plane = Plane::new(Vec3::new(0.0, -1.5, 0.0), Vec3::new(0.1, 1.0, 0.0));
            objects.insert(1, Object::new(Shape::Plane(Box::new(plane)), 1));
        }
        objects
    }

    #[test]
    fn small_scenes_searched_flat_find_exactly_the_brute_force_hits() {
        let mut rng = Rng(0xF1A7);
        let (mut flat_scenes, mut hits) = (0, 0);
        for n in 1..=20 {
            for _ in 0..6 {
                let objects = small_scene(&mut rng, n);
                let bvh = Bvh::build(&objects);
                flat_scenes += bvh.is_flat() as u32;
                for k in 0..2000 {
                    // From outside, and from among the objects (mirror and
                    // shadow rays start on a surface), some axis-parallel.
                    let origin = rng.vec(if k % 2 == 0 { 6.0 } else { 2.0 });
                    let mut dir = rng.vec(1.0);
                    if k % 7 == 0 {
                        dir = Vec3::new(0.0, dir.y.signum(), 0.0);
                    }
                    let ray = Ray::new(origin, dir);
                    let t_max = if k % 3 == 0 { 1.5 } else { f32::INFINITY };
                    let expected = brute_force::closest_hit(&objects, &ray, 1e-4, t_max);
                    assert_eq!(
                        bvh.closest_hit(&ray, 1e-4, t_max),
                        expected,
                        "n {n}, ray {k}"
                    );
                    let any = brute_force::occluded(&objects, &ray, 1e-4, t_max);
                    assert_eq!(bvh.occluded(&ray, 1e-4, t_max), any, "n {n}, ray {k}");
                    hits += expected.is_some() as u32;
                }
            }
        }
        // Most of these scenes are searched flat, and the rays meet things.
        assert!(flat_scenes >= 70, "only {flat_scenes} flat scenes of 120");
        assert!(hits > 25_000, "only {hits} hits");
    }

    #[test]
    fn only_a_small_scene_is_searched_flat() {
        let mut rng = Rng(3);
        let spheres = |n: usize, rng: &mut Rng| -> Vec<Object> {
            let sphere = |rng: &mut Rng| Shape::Sphere(Sphere::new(rng.vec(5.0), 0.3));
            (0..n).map(|_| Object::new(sphere(rng), 0)).collect()
        };
        assert!(Bvh::build(&spheres(FLAT_MAX, &mut rng)).is_flat());
        // Spheres are tested four at a time: up to four such blocks.
        assert!(Bvh::build(&spheres(16, &mut rng)).is_flat());
        assert!(!Bvh::build(&spheres(17, &mut rng)).is_flat());
        assert!(!Bvh::build(&spheres(200, &mut rng)).is_flat());
        assert!(!Bvh::build(&[]).is_flat());
        // The lab's final scene: three spheres and a mirror of two triangles.
        let wall = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
            let t = Triangle::new(Vec3::from(a), Vec3::from(b), Vec3::from(c));
            Object::new(Shape::Triangle(t), 3)
        };
        let mut lab = spheres(3, &mut rng);
        lab.push(wall(
            [5.0, 5.0, -5.0],
            [-5.0, 5.0, -5.0],
            [-5.0, -5.0, -5.0],
        ));
        lab.push(wall(
            [5.0, 5.0, -5.0],
            [-5.0, -5.0, -5.0],
            [5.0, -5.0, -5.0],
        ));
        assert!(Bvh::build(&lab).is_flat());
        // Each triangle counts, not each block of four: three spheres and
        // six triangles (two blocks at most) go through the tree.
        let mut more = lab.clone();
        more.extend(lab[3..].iter().cloned().cycle().take(4));
        assert_eq!(more.len(), 9);
        assert!(!Bvh::build(&more).is_flat());
        // The materials scene: ten spheres on a quad's two triangles.
        let mut balls = spheres(10, &mut rng);
        balls.extend(lab[3..].iter().cloned());
        assert!(Bvh::build(&balls).is_flat());
        // Beside more than one block of triangles, spheres go to the tree.
        balls.extend(lab[3..].iter().cloned().cycle().take(3));
        assert!(!Bvh::build(&balls).is_flat());
    }
}
