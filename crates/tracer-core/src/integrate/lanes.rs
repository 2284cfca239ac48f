//! The lab's Whitted shading four rays at a time, one per SIMD lane, for
//! the scenes where it is simplest: a few spheres, flat triangles and
//! planes, plain Blinn-Phong materials (no texture, no glass) and point lights, as
//! in most of the lab's tables. Each lane does the one-ray path's
//! operations (`Whitted`, `Sphere::intersect`, Moller-Trumbore, glam's
//! `dot` and `normalize`) in the same order, so every colour is the same
//! bit for bit and the same rays are counted; each instruction serves four
//! rays. Other scenes take the one-ray path.

use super::whitted::COS_THRESHOLD;
use super::RayStats;
use crate::geometry::{
    moller_trumbore, plane_distance, sphere_roots, Edges, Object, OriginTerms, Shape, Triangle,
};
use crate::light::Light;
use crate::material::{Material, Phong};
use crate::ray::Ray;
use crate::scene::{Integrator, Scene, TraceSettings};
use crate::simd::Real;
use crate::EPSILON;
use glam::{BVec4A, Vec3, Vec4};

/// Three-vectors of four lanes.
type V3 = crate::simd::V3<Vec4>;

/// Scenes of up to this many objects are shaded in lanes: every ray tests
/// every object, as the small scenes' flat search does (`accel::flat`).
const MAX_OBJECTS: usize = 8;

/// A scene ready to be shaded in lanes: its objects in the scene's order
/// (the first listed wins a tie, as in the one-ray search), their
/// materials and the point lights.
#[derive(Debug, Clone)]
pub struct LaneScene {
    prims: Vec<Prim>,
    surfaces: Vec<Surface>,
    lights: Vec<(Vec3, Vec3)>,
}

/// One object as its test needs it, with what the one-ray test computes
/// anew on each call worked out once (the same values).
#[derive(Debug, Clone)]
enum Prim {
    Sphere {
        center: Vec3,
        radius2: f32,
    },
    Triangle {
        v0: Vec3,
        e1: Vec3,
        e2: Vec3,
        edge_scale: f32,
    },
    Plane {
        point: Vec3,
        normal: Vec3,
    },
}

/// What shading reads of an object: its normal (a triangle's, constant) or
/// centre (a sphere's), and its material.
#[derive(Debug, Clone)]
struct Surface {
    sphere: bool,
    center: Vec3,
    normal: Vec3,
    material: Phong,
}

impl LaneScene {
    /// `scene` as Whitted mode shades it in lanes, if it is one of the
    /// small plain scenes they shade (`new`) and holds its objects: made
    /// for each render, by the integrator that reads it. Not in path mode,
    /// nor under an environment (the lanes see the background colour
    /// only) or alpha masks (their search reads none).
    pub fn of(scene: &Scene) -> Option<LaneScene> {
        let path_mode = scene.trace_settings().integrator == Integrator::Path;
        if path_mode || scene.environment().is_some() || scene.has_alpha_masks() {
            return None;
        }
        LaneScene::new(scene.every_object()?, scene.materials(), scene.lights())
    }

    /// The scene of `objects`, `materials` and `lights` in lanes, if it
    /// is one they shade: up to `MAX_OBJECTS` spheres, flat triangles and
    /// planes, every light a point, every material Blinn-Phong without a
    /// texture.
    pub fn new(objects: &[Object], materials: &[Material], lights: &[Light]) -> Option<LaneScene> {
        if objects.is_empty() || objects.len() > MAX_OBJECTS {
            return None;
        }
        let mut lane_scene = LaneScene {
            prims: Vec::with_capacity(objects.len()),
            surfaces: Vec::with_capacity(objects.len()),
            lights: Vec::with_capacity(lights.len()),
        };
        for light in lights {
            let Light::Point(point) = light else {
                return None;
            };
            lane_scene.lights.push((point.position, point.color));
        }
        for object in objects {
            // The shape first: an instance's own `material` is not an index
            // the scene checks.
            let (prim, surface) = match &object.shape {
                Shape::Sphere(s) if s.stretch.is_none() => (
                    Prim::Sphere {
                        center: s.center,
                        radius2: s.radius * s.radius,
                    },
                    Surface::sphere(s.center),
                ),
                Shape::Triangle(t) if object.vertex_normals.is_none() => {
                    (Prim::triangle(t), Surface::flat(t))
                }
                Shape::Plane(plane) => (
                    Prim::Plane {
                        point: plane.point,
                        normal: plane.normal,
                    },
                    Surface::facing(plane.normal),
                ),
                _ => return None,
            };
            let surface = surface.with(plain_phong(&materials[object.material])?);
            lane_scene.prims.push(prim);
            lane_scene.surfaces.push(surface);
        }
        Some(lane_scene)
    }

    /// The colours of `rays` (up to 16 primary rays, energy 1, depth 0)
    /// under the recursion settings `trace` into `colours`, counting the
    /// rays traced into `stats`.
    pub fn trace(
        &self,
        trace: &TraceSettings,
        rays: &[Ray],
        colours: &mut [Vec3],
        stats: &mut RayStats,
    ) {
        for (rays, colours) in rays.chunks(4).zip(colours.chunks_mut(4)) {
            let active = BVec4A::from_array(std::array::from_fn(|k| k < rays.len()));
            let found = self.primary(trace, &Rays4::new(rays), active, stats);
            colours.copy_from_slice(&found[..colours.len()]);
        }
    }

    /// The colours of the `active` lanes of four primary rays from
    /// `origin` along `dirs` (x, y and z by lane), under the recursion
    /// settings `trace`, counting the rays traced into `stats`.
    pub fn trace_dirs(
        &self,
        trace: &TraceSettings,
        (origin, [x, y, z]): (Vec3, [Vec4; 3]),
        active: BVec4A,
        stats: &mut RayStats,
    ) -> [Vec3; 4] {
        let rays = Rays4::from_lanes(V3::splat(origin), V3 { x, y, z });
        self.primary(trace, &rays, active, stats)
    }

    /// The colours of the `active` lanes of primary rays `rays` (energy 1,
    /// depth 0), by lane.
    fn primary(
        &self,
        trace: &TraceSettings,
        rays: &Rays4,
        active: BVec4A,
        stats: &mut RayStats,
    ) -> [Vec3; 4] {
        let colour = self.trace4(trace, rays, (active, Vec4::ONE, 0), stats);
        std::array::from_fn(|k| colour.lane(k))
    }

    /// `Whitted::trace` of the `active` lanes of `rays`, each already
    /// scaled by its `energy`; `depth` is the lab's ray-tree counter.
    fn trace4(
        &self,
        trace: &TraceSettings,
        rays: &Rays4,
        (active, energy, depth): (BVec4A, Vec4, u32),
        stats: &mut RayStats,
    ) -> V3 {
        stats.nearest += count(active);
        let missed = V3::splat(trace.background) * energy;
        let (t, which) = self.nearest(rays, active);
        let hit = which.cmpge(Vec4::ZERO);
        if !hit.any() {
            return missed;
        }
        let p = rays.at(t);
        let at = self.shading_point(&which, hit, p);
        let mut colour = self.local(rays, p, &at, hit, stats) * energy;
        if depth < trace.max_depth {
            let reflect = hit & at.reflective & energy.cmpgt(Vec4::splat(trace.min_energy));
            if reflect.any() {
                let reflected = rays.reflected(p, at.n);
                let energy = energy * at.reflectance;
                let more = self.trace4(trace, &reflected, (reflect, energy, depth + 1), stats);
                colour = V3::select(reflect, colour + more, colour);
            }
        }
        V3::select(hit, colour, missed)
    }

    /// The nearest hit of each active lane in (EPSILON, inf): its distance,
    /// and the index of its object as a float (-1: none).
    fn nearest(&self, rays: &Rays4, active: BVec4A) -> (Vec4, Vec4) {
        let mut best = Vec4::INFINITY;
        let mut which = Vec4::NEG_ONE;
        for (k, prim) in self.prims.iter().enumerate() {
            let (t, found) = prim.hit(rays, best);
            let found = found & active;
            best = Vec4::select(found, t, best);
            which = Vec4::select(found, Vec4::splat(k as f32), which);
        }
        (best, which)
    }

    /// Which `active` lanes of `rays` meet an object in (EPSILON, length).
    fn blocked(&self, rays: &Rays4, length: Vec4, active: BVec4A) -> BVec4A {
        let mut blocked = BVec4A::FALSE;
        for prim in &self.prims {
            blocked |= prim.hit(rays, length).1;
            if (blocked | !active).all() {
                break;
            }
        }
        blocked & active
    }

    /// The normals and materials of the objects `which` (by lane) at `p`.
    fn shading_point(&self, which: &Vec4, hit: BVec4A, p: V3) -> ShadingPoint {
        let surfaces: [&Surface; 4] = std::array::from_fn(|k| {
            let index = if hit.test(k) { which[k] as usize } else { 0 };
            &self.surfaces[index]
        });
        let lanes = |f: &dyn Fn(&Surface) -> f32| Vec4::from_array(surfaces.map(f));
        let v3 = |f: &dyn Fn(&Surface) -> Vec3| {
            let v = surfaces.map(f);
            V3::from_fn(|k| v[k])
        };
        let sphere = BVec4A::from_array(surfaces.map(|s| s.sphere));
        let mut n = v3(&|s| s.normal);
        if (sphere & hit).any() {
            let outward = (p - v3(&|s| s.center)).normalize();
            n = V3::select(sphere, outward, n);
        }
        let specular = v3(&|s| s.material.specular);
        ShadingPoint {
            n,
            ambient: v3(&|s| s.material.ambient),
            diffuse: v3(&|s| s.material.diffuse),
            specular,
            shininess: lanes(&|s| s.material.shininess),
            has_specular: BVec4A::from_array(surfaces.map(|s| s.material.specular != Vec3::ZERO)),
            reflectance: lanes(&|s| s.material.reflectance),
            reflective: BVec4A::from_array(surfaces.map(|s| s.material.reflectance > 0.0)),
        }
    }

    /// `Whitted::local_colour`: ambient, diffuse and specular of every
    /// light, in the lab's order, diffuse and specular only where the
    /// light is not shadowed.
    fn local(
        &self,
        rays: &Rays4,
        p: V3,
        at: &ShadingPoint,
        hit: BVec4A,
        stats: &mut RayStats,
    ) -> V3 {
        let view = -rays.dir;
        let mut colour = V3::splat(Vec3::ZERO);
        for &(position, color) in &self.lights {
            let color = V3::splat(color);
            colour = colour + color * at.ambient;
            let to_light = V3::splat(position) - p;
            let distance = to_light.length();
            let l = to_light / distance;
            let cos_a = at.n.dot(l);
            let lit = hit & !cos_a.cmple(Vec4::splat(COS_THRESHOLD));
            if !lit.any() {
                continue;
            }
            stats.shadow += count(lit);
            let open = lit & !self.blocked(&Rays4::from_lanes(p, l), distance, lit);
            if !open.any() {
                continue;
            }
            colour = V3::select(open, colour + color * at.diffuse * cos_a, colour);
            let cos_b = at.n.dot((l + view).normalize());
            let shiny = open & at.has_specular & cos_b.cmpgt(Vec4::splat(COS_THRESHOLD));
            if shiny.any() {
                let power = Vec4::from_array(std::array::from_fn(|k| {
                    let (c, s) = (cos_b[k], at.shininess[k]);
                    if shiny.test(k) {
                        c.powf(s)
                    } else {
                        0.0
                    }
                }));
                colour = V3::select(shiny, colour + color * at.specular * power, colour);
            }
        }
        colour
    }
}

/// A material the lanes shade: Blinn-Phong without a texture.
fn plain_phong(material: &Material) -> Option<Phong> {
    match material {
        Material::Phong(m)
            if m.texture.is_none() && m.color_texture.is_none() && m.emission == Vec3::ZERO =>
        {
            Some(m.clone())
        }
        _ => None,
    }
}

impl Prim {
    fn triangle(t: &Triangle) -> Prim {
        let (e1, e2, edge_scale) = t.edges();
        Prim::Triangle {
            v0: t.v0,
            e1,
            e2,
            edge_scale,
        }
    }

    /// The nearest distance in (EPSILON, limit) by lane, and which lanes
    /// have one.
    #[inline(always)]
    fn hit(&self, rays: &Rays4, limit: Vec4) -> (Vec4, BVec4A) {
        match self {
            Prim::Sphere { center, radius2 } => sphere_hit(rays, *center, *radius2, limit),
            Prim::Triangle {
                v0,
                e1,
                e2,
                edge_scale,
            } => triangle_hit(rays, [*v0, *e1, *e2], *edge_scale, limit),
            Prim::Plane { point, normal } => plane_hit(rays, *point, *normal, limit),
        }
    }
}

impl Surface {
    fn sphere(center: Vec3) -> Surface {
        Surface {
            sphere: true,
            center,
            normal: Vec3::ZERO,
            material: Phong::default_grey(),
        }
    }

    /// A flat triangle: its normal as `SurfaceHit::on_triangle` finds it.
    fn flat(t: &Triangle) -> Surface {
        let (e1, e2, _) = t.edges();
        Surface::facing(e1.cross(e2).normalize())
    }

    /// A surface of one normal everywhere.
    fn facing(normal: Vec3) -> Surface {
        Surface {
            sphere: false,
            center: Vec3::ZERO,
            normal,
            material: Phong::default_grey(),
        }
    }

    fn with(self, material: Phong) -> Surface {
        Surface { material, ..self }
    }
}

/// `Sphere::intersect` by lane.
#[inline(always)]
fn sphere_hit(rays: &Rays4, center: Vec3, radius2: f32, limit: Vec4) -> (Vec4, BVec4A) {
    let v = rays.origin - V3::splat(center);
    let range = (Vec4::splat(EPSILON), limit);
    let (hit, t) = sphere_roots(v, rays.dir, rays.dir_dot, Vec4::splat(radius2), range);
    (t, hit)
}

/// `Triangle::intersect` (Moller-Trumbore) by lane.
#[inline(always)]
fn triangle_hit(
    rays: &Rays4,
    [v0, e1, e2]: [Vec3; 3],
    edge_scale: f32,
    limit: Vec4,
) -> (Vec4, BVec4A) {
    let (e1, e2) = (V3::splat(e1), V3::splat(e2));
    let terms = OriginTerms::new(rays.origin, V3::splat(v0), e1, e2);
    let edges = Edges {
        e1,
        e2,
        scale: Vec4::splat(edge_scale),
    };
    let range = (Vec4::splat(EPSILON), limit);
    let (hit, t, _) = moller_trumbore(&terms, rays.dir, rays.dir_len, &edges, range);
    (t, hit)
}

/// `Plane::intersect` by lane.
#[inline(always)]
fn plane_hit(rays: &Rays4, point: Vec3, normal: Vec3, limit: Vec4) -> (Vec4, BVec4A) {
    let at = (V3::splat(point), V3::splat(normal));
    let range = (Vec4::splat(EPSILON), limit);
    let (hit, t) = plane_distance(at, rays.origin, rays.dir, rays.dir_len, range);
    (t, hit)
}

/// The shading inputs of four hits.
struct ShadingPoint {
    n: V3,
    ambient: V3,
    diffuse: V3,
    specular: V3,
    shininess: Vec4,
    has_specular: BVec4A,
    reflectance: Vec4,
    reflective: BVec4A,
}

/// Four rays, and what their tests share: `dir . dir` and `|dir|`.
struct Rays4 {
    origin: V3,
    dir: V3,
    dir_dot: Vec4,
    dir_len: Vec4,
}

impl Rays4 {
    /// The lanes of `rays` (one to four); lanes past the last repeat it.
    fn new(rays: &[Ray]) -> Rays4 {
        let ray = |k: usize| rays[k.min(rays.len() - 1)];
        let origin = V3::from_fn(|k| ray(k).origin());
        let dir = V3::from_fn(|k| ray(k).dir());
        Rays4::from_lanes(origin, dir)
    }

    fn from_lanes(origin: V3, dir: V3) -> Rays4 {
        let dir_dot = dir.dot(dir);
        Rays4 {
            origin,
            dir,
            dir_dot,
            dir_len: dir_dot.sqrt(),
        }
    }

    /// `Ray::at`, by lane.
    fn at(&self, t: Vec4) -> V3 {
        self.origin + self.dir * t
    }

    /// `Ray::reflected` at `p` about unit normals `n`, by lane.
    fn reflected(&self, p: V3, n: V3) -> Rays4 {
        let v = self.dir;
        let dir = (v - n * (Vec4::splat(2.0) * v.dot(n))).normalize();
        Rays4::from_lanes(p, dir)
    }
}

/// How many lanes `mask` holds.
fn count(mask: BVec4A) -> u64 {
    mask.bitmask().count_ones() as u64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::geometry::{Instance, Placement, Plane, SharedMesh, Sphere};
    use crate::image::Encoding;
    use crate::integrate::whitted::Whitted;
    use crate::material::Glass;
    use crate::scene::{Scene, SceneParts};
    use crate::texture::{ColorTexture, Texture};
    use std::sync::Arc;

    /// xorshift: reproducible numbers in [0, 1).
    struct Numbers(u64);
    impl Numbers {
        fn unit(&mut self) -> f32 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
        fn below(&mut self, n: usize) -> usize {
            (self.unit() * n as f32) as usize
        }
        fn vec(&mut self, scale: f32) -> Vec3 {
            (Vec3::new(self.unit(), self.unit(), self.unit()) * 2.0 - 1.0) * scale
        }
        fn pick(&mut self, values: &[f32]) -> f32 {
            values[self.below(values.len())]
        }
    }

    fn phong(numbers: &mut Numbers) -> Phong {
        let specular = if numbers.below(3) == 0 {
            Vec3::ZERO
        } else {
            numbers.vec(0.5).abs()
        };
        Phong {
            ambient: numbers.vec(0.2).abs(),
            diffuse: numbers.vec(0.7).abs(),
            specular,
            shininess: numbers.pick(&[0.0, 1.0, 10.0, 30.5, 200.0]),
            reflectance: numbers.pick(&[0.0, 0.0, 0.5, 1.0]),
            ..Phong::default_grey()
        }
    }

    /// One to eight spheres and flat triangles close together (sometimes
    /// one listed twice: the first wins the tie), under one to three
    /// point lights, with mirrors, highlights and a background.
    fn random_parts(numbers: &mut Numbers) -> SceneParts {
        let materials: Vec<Material> = (0..3).map(|_| Material::Phong(phong(numbers))).collect();
        let mut objects: Vec<Object> = (0..1 + numbers.below(8))
            .map(|_| {
                let c = numbers.vec(2.0);
                let shape = if numbers.below(2) == 0 {
                    Shape::Sphere(Sphere::new(c, 0.2 + numbers.unit()))
                } else {
                    Shape::Triangle(Triangle::new(c, c + numbers.vec(3.0), c + numbers.vec(3.0)))
                };
                Object::new(shape, numbers.below(3))
            })
            .collect();
        if objects.len() < MAX_OBJECTS && numbers.below(3) == 0 {
            objects.push(objects[0].clone());
        }
        if objects.len() < MAX_OBJECTS && numbers.below(3) == 0 {
            let plane = Plane::new(numbers.vec(2.0), numbers.vec(1.0));
            let at = numbers.below(objects.len() + 1);
            objects.insert(at, Object::new(Shape::Plane(Box::new(plane)), 2));
        }
        let lights = (0..1 + numbers.below(3))
            .map(|_| Light::new(numbers.vec(8.0), numbers.vec(0.6).abs(), 0.0))
            .collect();
        SceneParts {
            camera: Camera::new(Vec3::Z * 10.0, Vec3::ZERO, Vec3::Y, 50.0, 8, 8),
            objects,
            materials,
            lights,
            trace: TraceSettings {
                max_depth: numbers.below(4) as u32,
                min_energy: numbers.pick(&[0.01, 0.4]),
                background: numbers.vec(0.3).abs() * numbers.below(2) as f32,
                light_samples: 1,
                integrator: Default::default(),
                path_reuse: 1,
                camera_rays: 1,
                adaptive: false,
            },
            encoding: Encoding::default(),
            samples: 1,
            environment: None,
        }
    }

    /// A ray from outside or from among the objects, mostly toward them;
    /// some along an axis.
    fn random_ray(numbers: &mut Numbers) -> Ray {
        let far = numbers.below(2) == 0;
        let origin = numbers.vec(if far { 8.0 } else { 2.0 });
        let mut dir = numbers.vec(1.0) - origin;
        if numbers.below(8) == 0 {
            dir = Vec3::new(0.0, 0.0, dir.z.signum());
        }
        Ray::new(origin, dir.normalize())
    }

    fn bits(v: Vec3) -> [u32; 3] {
        v.to_array().map(f32::to_bits)
    }

    #[test]
    fn lanes_shade_and_count_every_ray_as_the_one_ray_path_does() {
        let mut numbers = Numbers(0x1A_7E5);
        let (mut primary, mut totals, mut lit) = (0, RayStats::default(), 0);
        for case in 0..60 {
            let scene = Scene::new(random_parts(&mut numbers));
            let lanes = LaneScene::of(&scene).expect("a scene the lanes shade");
            for packet in 0..40 {
                let n = 1 + numbers.below(16);
                let rays: Vec<Ray> = (0..n).map(|_| random_ray(&mut numbers)).collect();
                let (mut colours, mut stats) = ([Vec3::ZERO; 16], RayStats::default());
                lanes.trace(scene.trace_settings(), &rays, &mut colours[..n], &mut stats);
                let mut whitted = Whitted::new(&scene);
                for (k, ray) in rays.iter().enumerate() {
                    let expected = whitted.trace(ray, 1.0, 0);
                    let found = colours[k];
                    assert_eq!(
                        bits(found),
                        bits(expected),
                        "case {case}, packet {packet}, ray {k}: {found} vs {expected}"
                    );
                    lit += (expected != Vec3::ZERO) as u32;
                }
                assert_eq!(stats, whitted.stats, "case {case}, packet {packet}");
                primary += n as u64;
                totals = totals + stats;
            }
        }
        // The rays met things, were reflected and cast shadow rays.
        assert!(
            lit as u64 > primary / 3,
            "{lit} of {primary} rays brought light"
        );
        assert!(totals.nearest > primary + primary / 10, "{totals:?}");
        assert!(totals.shadow > primary / 4, "{totals:?}");
    }

    /// Objects on a small grid, so that rays aimed at their corners, edge
    /// midpoints and poles meet them exactly there: quads of two triangles
    /// sharing an edge, zero-area triangles, a sphere and the triangle
    /// tangent to it (listed either way), zero and tiny radii; and those
    /// points, to aim at.
    fn grid_parts(numbers: &mut Numbers) -> (SceneParts, Vec<Vec3>) {
        let mut parts = random_parts(numbers);
        let (mut objects, mut points) = (Vec::new(), vec![Vec3::ZERO]);
        let grid = |numbers: &mut Numbers| numbers.vec(2.0).round();
        while objects.len() < MAX_OBJECTS - 1 {
            let (c, m) = (grid(numbers), numbers.below(3));
            let triangle = |a, b, c| Object::new(Shape::Triangle(Triangle::new(a, b, c)), m);
            let sphere = |r| Object::new(Shape::Sphere(Sphere::new(c, r)), m);
            match numbers.below(5) {
                0 => {
                    let (a, b) = (c + Vec3::X, c + Vec3::X + Vec3::Y);
                    objects.extend([triangle(c, a, b), triangle(c, b, c + Vec3::Y)]);
                    points.extend([c, b, (c + b) * 0.5, (c + a) * 0.5]);
                }
                1 => {
                    let d = grid(numbers);
                    objects.push(triangle(c, c + d, c + d * 2.0));
                    points.extend([c, c + d]);
                }
                2 => {
                    let pole = c + Vec3::Z;
                    let flat = triangle(pole - Vec3::X, pole + Vec3::X, pole + Vec3::Y);
                    // Another material: which of the two wins shows.
                    let round = Object::new(Shape::Sphere(Sphere::new(c, 1.0)), (m + 1) % 3);
                    let pair = if numbers.below(2) == 0 {
                        [flat, round]
                    } else {
                        [round, flat]
                    };
                    objects.extend(pair);
                    // A corner, and the middles of the edges from it.
                    let half = |p: Vec3| (pole - Vec3::X + p) * 0.5;
                    points.extend([pole - Vec3::X, pole, half(pole + Vec3::Y), c + Vec3::X]);
                }
                3 => {
                    // Axis-aligned: rays along the other axes run in it.
                    let plane = Plane::new(c, Vec3::Y);
                    objects.push(Object::new(Shape::Plane(Box::new(plane)), m));
                    points.extend([c, c + Vec3::X]);
                }
                _ => {
                    objects.push(sphere(numbers.pick(&[0.0, 1e-3, 0.5, 1.0])));
                    points.extend([c, c + Vec3::Y * 0.5]);
                }
            }
        }
        parts.objects = objects;
        (parts, points)
    }

    #[test]
    fn lanes_meet_edges_vertices_poles_and_ties_as_the_one_ray_path_does() {
        let mut numbers = Numbers(0xED6E);
        for case in 0..300 {
            let (parts, points) = grid_parts(&mut numbers);
            let scene = Scene::new(parts);
            let lanes = LaneScene::of(&scene).expect("a scene the lanes shade");
            let mut rays = Vec::new();
            for &target in &points {
                // Along the axes (exactly through edges and poles) and from afar.
                let from = [Vec3::Z * 5.0, -Vec3::X * 4.0, numbers.vec(6.0)];
                rays.extend(from.map(|f| Ray::new(target + f, -f.normalize())));
            }
            for packet in rays.chunks(1 + case % 16) {
                let (mut colours, mut stats) = ([Vec3::ZERO; 16], RayStats::default());
                lanes.trace(
                    scene.trace_settings(),
                    packet,
                    &mut colours[..packet.len()],
                    &mut stats,
                );
                let mut whitted = Whitted::new(&scene);
                for (ray, found) in packet.iter().zip(colours) {
                    let expected = whitted.trace(ray, 1.0, 0);
                    assert_eq!(bits(found), bits(expected), "case {case}, {ray:?}");
                }
                assert_eq!(stats, whitted.stats, "case {case}");
            }
        }
    }

    #[test]
    fn an_instance_is_refused_before_its_material_is_read() {
        // An instance's own `material` need not index the scene's list.
        let mut parts = random_parts(&mut Numbers(11));
        let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
        let mesh = SharedMesh::new(vec![Object::new(Shape::Triangle(t), 0)]);
        let instance = Instance::new(Arc::new(mesh), Placement::IDENTITY, vec![0]);
        let instance = Shape::Instance(Arc::new(instance.expect("an instance")));
        parts.objects = vec![Object::new(instance, 99)];
        assert!(LaneScene::of(&Scene::new(parts)).is_none());
    }

    #[test]
    fn an_image_shaded_in_lanes_is_the_one_ray_image() {
        // An odd size: the driver's blocks of 4 x 4 pixels are cut short at
        // the right and bottom edges.
        let mut numbers = Numbers(0xB10C);
        for case in 0..8 {
            let mut parts = random_parts(&mut numbers);
            parts.camera = Camera::new(Vec3::Z * 6.0, Vec3::ZERO, Vec3::Y, 60.0, 37, 23);
            let scene = Scene::new(parts);
            assert!(LaneScene::of(&scene).is_some());
            let rendered = crate::render(&scene, &crate::RenderJob::full(&scene), &|_| {});
            let mut whitted = Whitted::new(&scene);
            for j in 0..23 {
                for i in 0..37 {
                    let expected = whitted.trace(&scene.camera().primary_ray(i, j), 1.0, 0);
                    let found = rendered.image.get(i, j);
                    assert_eq!(bits(found), bits(expected), "case {case}, pixel ({i}, {j})");
                }
            }
            assert_eq!(rendered.rays, whitted.stats, "case {case}");
        }
    }

    #[test]
    fn only_plain_scenes_are_shaded_in_lanes() {
        let plain = || {
            let mut numbers = Numbers(7);
            let mut parts = random_parts(&mut numbers);
            parts.objects.truncate(1);
            parts.objects[0] = Object::new(Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0)), 0);
            parts
        };
        assert!(LaneScene::of(&Scene::new(plain())).is_some());
        assert!(LaneScene::of(&Scene::lean(plain())).is_some());
        let refused = |change: &dyn Fn(&mut SceneParts)| {
            let mut parts = plain();
            change(&mut parts);
            LaneScene::of(&Scene::new(parts)).is_none()
        };
        assert!(refused(&|p| p.objects.clear()));
        assert!(refused(
            &|p| p.objects = vec![p.objects[0].clone(); MAX_OBJECTS + 1]
        ));
        assert!(refused(&|p| p.lights.push(Light::new(
            Vec3::X,
            Vec3::ONE,
            0.5
        ))));
        assert!(refused(&|p| {
            let t = Triangle::new(Vec3::ZERO, Vec3::X, Vec3::Y);
            let mut smooth = Object::new(Shape::Triangle(t), 0);
            smooth.vertex_normals = Some(Box::new([Vec3::Z; 3]));
            p.objects.push(smooth);
        }));
        let with_material = |m: Material| {
            move |p: &mut SceneParts| {
                p.materials[0] = m.clone();
            }
        };
        let glass = Glass {
            surface: Phong::default_grey(),
            transmittance: 0.9,
            ior: 1.5,
            fresnel: true,
            absorption: Vec3::ZERO,
        };
        assert!(refused(&with_material(Material::Glass(glass))));
        let textured = Phong {
            texture: Some(Arc::new(Texture::lab_stripes(4, 4))),
            ..Phong::default_grey()
        };
        assert!(refused(&with_material(Material::Phong(textured))));
        let checker = Phong {
            color_texture: Some(ColorTexture::Checker {
                colors: [Vec3::ZERO, Vec3::ONE],
                scale: glam::Vec2::ONE,
            }),
            ..Phong::default_grey()
        };
        assert!(refused(&with_material(Material::Phong(checker))));
    }
}
