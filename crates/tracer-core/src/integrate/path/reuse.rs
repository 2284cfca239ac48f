//! Path reuse (Bekaert, Sbert and Halton, "Accelerating path tracing by
//! re-using paths", EGWR 2002): neighbouring pixels of a row share the
//! light their paths found beyond the first bounce. Where a path's first
//! surface is Lambertian, its light from farther away (the bounces after
//! the camera's surface and the light its second vertex sends back) is
//! the integral over the surfaces it sees of the light they reflect. Each
//! of a group's paths drew one point of that integral; every pixel of the
//! group connects its own first vertex to each of those points (a shadow
//! ray) and weights what it finds by the balance heuristic over the
//! group's densities: one sample of each pixel's technique, a multi-sample
//! estimator that stays unbiased (Veach 1997, 9.2). A pixel then has as
//! many samples of its indirect light as the group has pixels, for one
//! shadow ray each. Noise is what reuse takes off: the direct light at the
//! first vertex and the light emitted by the second one stay each path's
//! own.
//!
//! A Lambertian second vertex reflects the same light toward every point
//! on its side, so a neighbour's connection reads the path's own estimate.
//! A rough metal or plastic one (`Glossy`) keeps the light its path found
//! arriving there, its light sample and its BSDF sample, and a neighbour
//! weighs them by the BSDF as seen from its own first vertex: the same two
//! samples, their weights summing to 1 whoever looks, so each pixel's
//! estimate stays unbiased. Those vertices are what lights a room's
//! caustics (a lamp seen in a gold ball, on the floor), rare paths that
//! sharing spreads over the group. Which pixels take part is decided by
//! their first vertices alone (a Lambertian surface), so the densities
//! summed are those of the techniques that really drew.

use crate::bsdf::Bsdf;
use crate::geometry::SurfaceHit;
use crate::integrate::record::{PathEvent, PathEventKind, Recorder};
use crate::light::toward::SHADOW_SHORTEN;
use crate::material::Material;
use glam::Vec3;

/// The most pixels a group may have: their connections grow as its square.
pub const MAX_GROUP: u32 = scene_format::validate::MAX_PATH_REUSE;

/// The first vertex of a path whose surface is Lambertian: what its
/// neighbours' connections start from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstVertex {
    /// The point the camera ray met, and where its shadow rays leave from.
    pub point: Vec3,
    pub from: Vec3,
    /// The surface's normal on the side the camera sees: its cosine-
    /// weighted directions are drawn around it.
    pub normal: Vec3,
    pub albedo: Vec3,
}

/// The second vertex of such a path, if its surface is Lambertian too, or
/// reflects smoothly only (`Glossy`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SecondVertex {
    pub point: Vec3,
    /// The geometric normal, on the side the path arrived from: the light
    /// it reflects leaves on that side only.
    pub normal: Vec3,
    /// The light the path found beyond it (its own emission left out),
    /// per unit of the path's throughput there: an estimate of the
    /// radiance it reflects, toward any point on its normal's side (on a
    /// glossy vertex that depends on the point: the group asks `Glossy`).
    pub reflected: Vec3,
}

/// A second vertex on a surface that reflects smoothly only (a rough metal
/// or plastic): its hit, and the light its path found arriving there, by
/// the light sample and by the BSDF sample, each over its density and
/// times its MIS weight as the path weighed it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Glossy {
    pub hit: SurfaceHit,
    /// The light sample's direction and what it brings (zero if blocked).
    pub light: (Vec3, Vec3),
    /// The BSDF sample's direction and what the rest of the path found
    /// along it (zero where the sample failed).
    pub beyond: (Vec3, Vec3),
    /// The BSDF sample's density, until the path ends.
    pdf: f32,
}

impl Glossy {
    /// The radiance the vertex reflects toward unit `wo`, its surface of
    /// `material`: the two samples weighed by the BSDF seen from `wo`.
    /// Toward the path's own first vertex, the path's own estimate.
    pub fn reflected(&self, material: &Material, wo: Vec3) -> Vec3 {
        let bsdf = Bsdf::new(material, &self.hit, wo);
        let mut sum = Vec3::ZERO;
        for (dir, light) in [self.light, self.beyond] {
            if light != Vec3::ZERO {
                sum += bsdf.eval(dir).0 * light;
            }
        }
        sum
    }
}

/// One path of a group, as the group combines it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shared {
    /// The path's own value: all of it where it takes no part, and without
    /// the light beyond its second vertex where that vertex is shared.
    pub own: Vec3,
    pub first: Option<FirstVertex>,
    pub second: Option<SecondVertex>,
}

impl Shared {
    /// A path that takes no part: its value stays its own.
    pub fn alone(value: Vec3) -> Shared {
        Shared {
            own: value,
            first: None,
            second: None,
        }
    }
}

/// A connection's shadow ray: from `from` along unit `dir` up to `reach`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Connection {
    pub from: Vec3,
    pub dir: Vec3,
    pub reach: f32,
}

/// Shares the light of groups' paths, its buffers kept from group to group.
#[derive(Debug, Clone, Default)]
pub struct Combiner {
    /// `density[k * n + j]`: pixel k's density of drawing path j's second
    /// vertex (area measure), 0 where it cannot or the vertex is hidden.
    density: Vec<f32>,
    /// The connections to test, where each one's density goes, and
    /// whether each is blocked.
    connections: Vec<Connection>,
    pending: Vec<(usize, f32)>,
    blocked: Vec<bool>,
}

impl Combiner {
    /// The values of a group's paths with their indirect light shared, in
    /// the group's order, the density sums in a fixed order (the same
    /// image whatever threads and tiles rendered it). `occluded` answers
    /// for a list of shadow rays at once, into a list it is given (lanes
    /// test them sixteen at a time); `glossy(j, to)` is the light path j's
    /// second vertex reflects along `to` (not unit) if that is glossy
    /// (`Glossy::reflected`), None where it is Lambertian.
    pub fn combine(
        &mut self,
        paths: &[Shared],
        occluded: &mut dyn FnMut(&[Connection], &mut Vec<bool>),
        glossy: &mut dyn FnMut(usize, Vec3) -> Option<Vec3>,
        values: &mut Vec<Vec3>,
    ) {
        let n = paths.len();
        values.clear();
        values.extend(paths.iter().map(|p| p.own));
        self.density.clear();
        self.density.resize(n * n, 0.0);
        self.connect(paths);
        if !self.connections.is_empty() {
            self.blocked.clear();
            occluded(&self.connections, &mut self.blocked);
            for (&(at, d), &blocked) in self.pending.iter().zip(&self.blocked) {
                if !blocked {
                    self.density[at] = d;
                }
            }
        }
        for (j, b) in paths.iter().enumerate() {
            let Some(y) = b.second else { continue };
            let column = self.density.iter().skip(j).step_by(n);
            let total: f32 = column.clone().sum();
            if total <= 0.0 {
                continue;
            }
            for ((value, a), &d) in values.iter_mut().zip(paths).zip(column) {
                if let (Some(x), true) = (a.first, d > 0.0) {
                    let reflected = glossy(j, x.from - y.point).unwrap_or(y.reflected);
                    // f cos / (summed density) = albedo/pi cos / sum; the
                    // density is cos/pi times the same geometry.
                    *value += x.albedo * reflected * (d / total);
                }
            }
        }
    }

    /// Each pixel's density of each shared second vertex, visibility
    /// aside: a path's own vertex is seen, and the others' connections
    /// are left to test.
    fn connect(&mut self, paths: &[Shared]) {
        let n = paths.len();
        self.connections.clear();
        self.pending.clear();
        for (k, a) in paths.iter().enumerate() {
            let Some(x) = a.first else { continue };
            for (j, b) in paths.iter().enumerate() {
                let Some(y) = b.second else { continue };
                let Some(d) = area_density(&x, &y) else {
                    continue;
                };
                if k == j {
                    self.density[k * n + j] = d;
                    continue;
                }
                let to = y.point - x.from;
                let distance = to.length();
                self.connections.push(Connection {
                    from: x.from,
                    dir: to / distance,
                    reach: distance * (1.0 - SHADOW_SHORTEN),
                });
                self.pending.push((k * n + j, d));
            }
        }
    }
}

/// The density, per unit area of `y`'s surface, of a cosine-weighted
/// direction from `x` meeting `y` (visibility aside): cos_x / pi *
/// cos_y / d^2. None where `y` lies below `x`'s surface or `x` behind
/// `y`'s lit side.
fn area_density(x: &FirstVertex, y: &SecondVertex) -> Option<f32> {
    let to = y.point - x.point;
    let d2 = to.length_squared();
    let cos_x = x.normal.dot(to);
    let cos_y = -y.normal.dot(to);
    if cos_x <= 0.0 || cos_y <= 0.0 || d2 <= 0.0 {
        return None;
    }
    // cos_x cos_y / d^2 with both cosines of the unnormalised `to`.
    let d = cos_x * cos_y / (d2 * d2) * std::f32::consts::FRAC_1_PI;
    d.is_finite().then_some(d)
}

/// Follows one path (a `Recorder` of the one-path tracer) for what a group
/// shares: its first two vertices and the light found beyond the second.
#[derive(Debug, Clone, Default)]
pub struct FirstBounces {
    /// The depth of the vertex the path is at, and its point.
    depth: u32,
    point: Vec3,
    first: Option<FirstVertex>,
    /// The second vertex's point and normal, once it is shared.
    second: Option<(Vec3, Vec3)>,
    /// The path's throughput at its second vertex.
    throughput: Vec3,
    /// The path's radiance so far, added as the tracer adds it, and what
    /// it was when the second vertex was reached.
    total: Vec3,
    own: Vec3,
    /// A glossy second vertex, its samples as they come.
    glossy: Option<Glossy>,
    /// The path's radiance when that vertex's BSDF sample was drawn, and
    /// the throughput after it: what the path adds later came along it.
    beyond_from: Option<(Vec3, Vec3)>,
}

impl FirstBounces {
    /// Ready for the next path.
    pub fn clear(&mut self) {
        *self = FirstBounces::default();
    }

    /// The path just traced, whose value was `value`, and its second
    /// vertex's samples if that is glossy.
    pub fn shared(&self, value: Vec3) -> (Shared, Option<Glossy>) {
        let glossy = self.glossy.map(|g| self.finished(g, value));
        // A glossy vertex whose light beyond cannot be read is not shared.
        let second = match glossy {
            Some(None) => None,
            _ => self.second,
        };
        let second = second.map(|(point, normal)| (point, normal, self.own));
        let shared = shared(value, self.first, second, self.throughput);
        let glossy = glossy.flatten().filter(|_| shared.second.is_some());
        (shared, glossy)
    }

    /// `g` with the light its BSDF sample found, the path's value being
    /// `value`; None where a channel of the throughput after that sample
    /// is 0 (what came along it is then unknown in that channel).
    fn finished(&self, g: Glossy, value: Vec3) -> Option<Glossy> {
        let Some((before, throughput)) = self.beyond_from else {
            // The BSDF sample failed: nothing came beyond.
            return Some(g);
        };
        let arriving = (value - before) / throughput;
        let beyond = arriving / g.pdf;
        let usable = throughput.cmpgt(Vec3::ZERO).all() && beyond.is_finite();
        usable.then_some(Glossy {
            beyond: (g.beyond.0, beyond),
            ..g
        })
    }

    /// Leaves the second vertex out of sharing: the path keeps its value.
    fn unshared(&mut self) {
        (self.second, self.glossy) = (None, None);
    }

    /// What the second vertex's light sample and BSDF sample tell of a
    /// glossy one.
    #[inline(always)]
    fn glossy_sample(&mut self, event: &PathEvent) {
        let Some(g) = &mut self.glossy else { return };
        match event.kind {
            PathEventKind::LightSample {
                wi,
                radiance,
                light_pdf,
                f_cos,
                weight,
                blocked,
                absorbed,
                ..
            } => {
                // Not lit for this path's own view: its shadow ray was not
                // traced, and another view might see the light.
                if f_cos == Vec3::ZERO && light_pdf > 0.0 {
                    return self.unshared();
                }
                if !blocked && light_pdf > 0.0 {
                    g.light = (wi, radiance * (weight / light_pdf) * absorbed);
                }
            }
            PathEventKind::BsdfSample {
                wi,
                weight,
                pdf,
                specular,
            } => {
                if specular || pdf <= 0.0 {
                    return self.unshared();
                }
                (g.beyond.0, g.pdf) = (wi, pdf);
                self.beyond_from = Some((self.total, event.throughput * weight));
            }
            _ => {}
        }
    }
}

/// A path of value `value` as a group shares it, its first vertex
/// `first`, and its second's point, normal and the path's value when it
/// got there, with the throughput there: what lies beyond is the rest of
/// the value (as the tracer added it), per unit throughput.
pub(super) fn shared(
    value: Vec3,
    first: Option<FirstVertex>,
    second: Option<(Vec3, Vec3, Vec3)>,
    throughput: Vec3,
) -> Shared {
    let Some(first) = first else {
        return Shared::alone(value);
    };
    let second = second.and_then(|(point, normal, own)| {
        let reflected = (value - own) / throughput;
        let usable = throughput.cmpgt(Vec3::ZERO).all() && reflected.is_finite();
        usable.then_some((
            own,
            SecondVertex {
                point,
                normal,
                reflected,
            },
        ))
    });
    Shared {
        own: second.map_or(value, |(own, _)| own),
        first: Some(first),
        second: second.map(|(_, y)| y),
    }
}

impl Recorder for FirstBounces {
    #[inline(always)]
    fn path(&mut self, event: PathEvent) {
        if let PathEventKind::Vertex { depth, point, .. } = event.kind {
            (self.depth, self.point) = (depth, point);
            if depth == 1 {
                self.throughput = event.throughput;
            }
        } else if self.depth == 1 {
            self.glossy_sample(&event);
        }
        self.total += event.added;
    }

    #[inline(always)]
    fn scattering(&mut self, hit: &SurfaceHit, bsdf: &Bsdf) {
        let lambert = bsdf.lambert_only();
        match self.depth {
            0 => {
                let Some((albedo, 1.0)) = lambert else { return };
                let from = match hit.front_face {
                    true => self.point + hit.shadow_offset,
                    false => self.point,
                };
                self.first = Some(FirstVertex {
                    point: self.point,
                    from,
                    normal: bsdf.normal(),
                    albedo,
                });
            }
            1 if self.first.is_some() => {
                let glossy = lambert.is_none() && bsdf.reflects_smoothly_only();
                if lambert.is_none() && !glossy {
                    return;
                }
                let facing = if hit.front_face { 1.0 } else { -1.0 };
                let normal = hit.geometric_normal * facing;
                self.second = Some((self.point, normal));
                self.own = self.total;
                self.glossy = glossy.then_some(Glossy {
                    hit: *hit,
                    light: (Vec3::ZERO, Vec3::ZERO),
                    beyond: (Vec3::ZERO, Vec3::ZERO),
                    pdf: 0.0,
                });
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path whose first vertex is at `x` on the floor (facing +z, albedo
    /// 1/2) and whose second is at `y` on the ceiling (facing -z), having
    /// found `reflected` there; its own value 0.1.
    fn path(x: Vec3, y: Vec3, reflected: f32) -> Shared {
        Shared {
            own: Vec3::splat(0.1),
            first: Some(FirstVertex {
                point: x,
                from: x,
                normal: Vec3::Z,
                albedo: Vec3::splat(0.5),
            }),
            second: Some(SecondVertex {
                point: y,
                normal: -Vec3::Z,
                reflected: Vec3::splat(reflected),
            }),
        }
    }

    /// The group's values, each connection answered by `blocked`.
    fn combined(paths: &[Shared], blocked: bool) -> Vec<f32> {
        let mut values = Vec::new();
        let mut occluded = |c: &[Connection], out: &mut Vec<bool>| out.resize(c.len(), blocked);
        let mut glossy = |_: usize, _: Vec3| None;
        Combiner::default().combine(paths, &mut occluded, &mut glossy, &mut values);
        values.iter().map(|v| v.x).collect()
    }

    #[test]
    fn a_path_alone_in_its_group_keeps_its_whole_value() {
        let one = path(Vec3::ZERO, Vec3::new(0.3, 0.2, 1.0), 0.8);
        assert_eq!(combined(&[one], false), vec![0.1 + 0.5 * 0.8]);
    }

    #[test]
    fn pixels_of_one_point_share_the_mean_of_what_their_paths_found() {
        // Drawn from the same point, every vertex has the same density for
        // each pixel: each takes a quarter of each path's light.
        let ys = [
            (0.3, 0.2, 0.8),
            (-0.5, 0.1, 0.2),
            (0.0, 0.9, 0.4),
            (0.7, -0.6, 0.0),
        ];
        let paths: Vec<Shared> = ys
            .iter()
            .map(|&(a, b, l)| path(Vec3::ZERO, Vec3::new(a, b, 1.0), l))
            .collect();
        for value in combined(&paths, false) {
            assert!((value - (0.1 + 0.5 * 0.35)).abs() < 1e-6, "{value}");
        }
    }

    #[test]
    fn a_hidden_vertex_is_left_to_its_own_path() {
        let paths = [
            path(Vec3::ZERO, Vec3::new(0.3, 0.2, 1.0), 0.8),
            path(Vec3::X, Vec3::new(0.1, 0.0, 1.0), 0.2),
        ];
        assert_eq!(
            combined(&paths, true),
            vec![0.1 + 0.5 * 0.8, 0.1 + 0.5 * 0.2]
        );
    }

    #[test]
    fn the_densities_weigh_each_vertex_by_its_pixels_chances_of_drawing_it() {
        // Vertex 0 straight above pixel 0 and far from pixel 1, vertex 1
        // straight above pixel 1: each pixel takes most of the light above
        // it, and the weights of a vertex add up to 1.
        let (x0, x1) = (Vec3::ZERO, Vec3::new(3.0, 0.0, 0.0));
        let paths = [
            path(x0, Vec3::new(0.0, 0.0, 1.0), 1.0),
            path(x1, Vec3::new(3.0, 0.0, 1.0), 0.0),
        ];
        let values = combined(&paths, false);
        // Densities of vertex 0: 1/pi for pixel 0 (cosines 1, distance 1),
        // and (1/sqrt 10)^2 / 10 / pi = 1/(100 pi) for pixel 1.
        let w0 = 1.0 / (1.0 + 0.01);
        assert!((values[0] - (0.1 + 0.5 * w0)).abs() < 1e-6, "{values:?}");
        assert!(
            (values[1] - (0.1 + 0.5 * (1.0 - w0))).abs() < 1e-6,
            "{values:?}"
        );
    }

    #[test]
    fn a_pixel_without_a_lambertian_first_vertex_neither_gives_nor_takes() {
        let paths = [
            path(Vec3::ZERO, Vec3::new(0.3, 0.2, 1.0), 0.8),
            Shared::alone(Vec3::splat(7.0)),
        ];
        assert_eq!(combined(&paths, false), vec![0.1 + 0.5 * 0.8, 7.0]);
    }

    #[test]
    fn a_glossy_vertex_seen_from_its_own_path_gives_back_the_path_s_light() {
        // Paths from the floor of a lamp-lit room by a ball of rough gold:
        // what a path shares of a glossy second vertex, weighed from its
        // own first vertex, is the light the path found beyond that vertex.
        use crate::integrate::path::PathTracer;
        use crate::sampler::PixelSampler;
        let text = "[camera]\neye = [0, 1, 4]\nlook_at = [0.6, -1, 1.2]\nfov = 12\nwidth = 8\nheight = 8\n\
            [render]\nintegrator = \"path\"\nmax_depth = 5\n\
            [materials.w]\ndiffuse = [0.6, 0.6, 0.6]\n\
            [materials.lamp]\ndiffuse = [0.5, 0.5, 0.5]\nemission = [6, 6, 6]\n\
            [materials.gold]\nbase_color = [1, 0.78, 0.34]\nmetallic = 1\nroughness = 0.3\n\
            [[objects]]\nquad = { corner = [-3, -1, 3], edge_u = [6, 0, 0], edge_v = [0, 0, -6] }\nmaterial = \"w\"\n\
            [[objects]]\nquad = { corner = [-2.5, -1, -1], edge_u = [0, 2, 0], edge_v = [0, 0, 2] }\nmaterial = \"lamp\"\n\
            [[objects]]\nsphere = { center = [0.6, -0.2, 0], radius = 0.8 }\nmaterial = \"gold\"\n";
        let file = scene_format::load_str(
            text,
            scene_format::Format::Toml,
            std::path::Path::new("g.toml"),
        )
        .unwrap();
        let scene = crate::prepare(&file).unwrap();
        let mut tracer = PathTracer::with_recorder(&scene, FirstBounces::default());
        let (mut glossy, mut lit) = (0, 0);
        for s in 0..8192 {
            let (i, j) = (s % 8, (s / 8) % 8);
            let mut sampler = PixelSampler::new(i, j, 0);
            tracer.rec.clear();
            let value = tracer.sample(&mut sampler, (i, j), s);
            let (shared, g) = tracer.rec.shared(value);
            let (Some(x), Some(y), Some(g)) = (shared.first, shared.second, g) else {
                continue;
            };
            // The vertex shared is the glossy one's hit.
            assert_eq!(y.normal.abs(), g.hit.geometric_normal.abs());
            let wo = (x.from - y.point).normalize();
            let rebuilt = shared.own + x.albedo * g.reflected(scene.material(g.hit.material), wo);
            let tolerance = 1e-4 * value.max_element().max(1.0);
            assert!(
                (rebuilt - value).abs().max_element() < tolerance,
                "path {s}: {rebuilt} shared, {value} traced"
            );
            glossy += 1;
            lit += (g.light.1 != Vec3::ZERO) as u32;
        }
        // Enough glossy vertices, and some lit by their light sample.
        assert!(glossy > 200 && lit > 50, "{glossy} glossy, {lit} lit");
    }

    #[test]
    fn a_vertex_below_a_pixel_s_surface_or_lit_on_the_other_side_has_no_density() {
        let x = path(Vec3::ZERO, Vec3::Z, 0.0).first.unwrap();
        let y = |z: f32, normal: Vec3| SecondVertex {
            point: Vec3::new(0.0, 0.0, z),
            normal,
            reflected: Vec3::ONE,
        };
        let straight_above = area_density(&x, &y(1.0, -Vec3::Z)).unwrap();
        assert!((straight_above - std::f32::consts::FRAC_1_PI).abs() < 1e-7);
        assert_eq!(area_density(&x, &y(-1.0, Vec3::Z)), None);
        assert_eq!(area_density(&x, &y(1.0, Vec3::Z)), None);
    }
}
