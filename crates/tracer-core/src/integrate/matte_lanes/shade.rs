//! The lanes' shading, a step of every lane at once, kept by field (a
//! structure of arrays) so that each step is a loop over the lanes the
//! compiler turns into SIMD instructions: the frame, the light sample and
//! what it adds, the BSDF sample, the throughput and the roulette. Each
//! lane does the one-path tracer's arithmetic in its order (`Frame::new`,
//! `Lights::sample`, `LabBsdf`'s Lambertian branch, `power_heuristic`, the
//! roulette of `PathTracer::radiance`), branches made selects, so every
//! value is its value bit for bit; what cannot be written so (the light
//! table's pick, the disk's sine and cosine) is done a lane at a time
//! with the one-path tracer's own functions.

use super::{set, Numbers, Paths, F, LANES, V};
use crate::integrate::path::{ROULETTE_DEPTH, SHADOW_SHORTEN};
use crate::light::area::AreaShape;
use crate::light::lights::Lights;
use crate::sampling::concentric_disk;
use multiversion::multiversion;
use std::f32::consts::FRAC_1_PI;

/// A flag per lane.
pub(super) type M = [bool; LANES];

/// Where each lane's path is shaded this step: the lanes `shaded`, their
/// points, their normals turned toward the ray's side, and their
/// materials (`Matte`'s albedo and lobe probability).
pub(super) struct Hits {
    pub shaded: M,
    pub point: V,
    /// Where light samples and the bounce's density start (the point, its
    /// zeros made positive on the front, as the one-path tracer's).
    pub from: V,
    pub normal: V,
    pub albedo: V,
    pub p_lambert: F,
}

impl Hits {
    pub(super) const NONE: Hits = Hits {
        shaded: [false; LANES],
        point: [[0.0; LANES]; 3],
        from: [[0.0; LANES]; 3],
        normal: [[0.0; LANES]; 3],
        albedo: [[0.0; LANES]; 3],
        p_lambert: [0.0; LANES],
    };
}

/// Each lane's shading frame (`Frame`): tangents `s`, `t` and normal `n`.
pub(super) struct Frames {
    s: V,
    t: V,
    n: V,
}

/// `Frame::new` of each lane's normal (Duff et al.'s basis).
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
pub(super) fn frames(n: &V) -> Frames {
    let [nx, ny, nz] = n;
    let mut f = Frames {
        s: [[0.0; LANES]; 3],
        t: [[0.0; LANES]; 3],
        n: *n,
    };
    for k in 0..LANES {
        let sign = 1.0f32.copysign(nz[k]);
        let a = -1.0 / (sign + nz[k]);
        let b = nx[k] * ny[k] * a;
        f.s[0][k] = 1.0 + sign * nx[k] * nx[k] * a;
        f.s[1][k] = sign * b;
        f.s[2][k] = -sign * nx[k];
        f.t[0][k] = b;
        f.t[1][k] = sign + ny[k] * ny[k] * a;
        f.t[2][k] = -ny[k];
    }
    f
}

/// The kind of light each lane picked.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// No light sample: none wanted, or no light.
    None,
    Point,
    Triangle,
    Parallelogram,
}

/// The light each lane's sample picked (`Lights::sample`'s pick, a lane at
/// a time): its kind, the pick's probability, its shape (a point light's
/// position in `v0`) and its radiance (a point light's intensity).
pub(super) struct Picked {
    kind: [Kind; LANES],
    /// Its index in the light table.
    light: [u32; LANES],
    pmf: F,
    v0: V,
    e1: V,
    e2: V,
    normal: V,
    area: F,
    radiance: V,
}

impl Picked {
    /// The light every lane of `lanes` picked, if they picked one (or
    /// none of them is in `lanes`).
    pub(super) fn one_light(&self, lanes: &M) -> Option<usize> {
        let mut picked = (0..LANES).filter(|&k| lanes[k]).map(|k| self.light[k]);
        let first = picked.next().unwrap_or(0);
        picked.all(|i| i == first).then_some(first as usize)
    }
}

/// Whether the scene's lights can be sampled in lanes: points (no spot
/// or directional light) and flat emitters (triangles, parallelograms), no
/// environment.
pub(super) fn lanes_can_sample(lights: &Lights) -> bool {
    !lights.has_environment()
        && lights
            .points()
            .iter()
            .all(|p| p.emits == crate::light::lights::Emits::Everywhere)
        && lights.areas().iter().all(|a| {
            matches!(
                a.shape,
                AreaShape::Triangle { .. } | AreaShape::Parallelogram { .. }
            )
        })
}

/// The light each lane of `hits` picks with its number `pick`: only where
/// the lobe reflects (a black material takes no light sample).
pub(super) fn pick_lights(lights: &Lights, hits: &Hits, pick: &F) -> Picked {
    let zero = [[0.0; LANES]; 3];
    let mut p = Picked {
        kind: [Kind::None; LANES],
        light: [0; LANES],
        pmf: [0.0; LANES],
        v0: zero,
        e1: zero,
        e2: zero,
        normal: zero,
        area: [0.0; LANES],
        radiance: zero,
    };
    let Some(table) = lights.table() else {
        return p;
    };
    let (points, areas) = (lights.points(), lights.areas());
    for k in 0..LANES {
        if !hits.shaded[k] || hits.p_lambert[k] <= 0.0 {
            continue;
        }
        let (i, pmf) = table.sample(pick[k]);
        (p.light[k], p.pmf[k]) = (i as u32, pmf);
        if let Some(point) = points.get(i) {
            p.kind[k] = Kind::Point;
            set(&mut p.v0, k, point.position);
            set(&mut p.radiance, k, point.intensity);
            continue;
        }
        let Some(light) = areas.get(i - points.len()) else {
            continue;
        };
        let (kind, v0, e1, e2, normal, area) = match light.shape {
            AreaShape::Triangle {
                v0,
                e1,
                e2,
                normal,
                area,
            } => (Kind::Triangle, v0, e1, e2, normal, area),
            AreaShape::Parallelogram {
                corner,
                e1,
                e2,
                normal,
                area,
            } => (Kind::Parallelogram, corner, e1, e2, normal, area),
            // `lanes_can_sample` keeps the scenes of other lights out.
            _ => continue,
        };
        p.kind[k] = kind;
        set(&mut p.v0, k, v0);
        set(&mut p.e1, k, e1);
        set(&mut p.e2, k, e2);
        set(&mut p.normal, k, normal);
        p.area[k] = area;
        set(&mut p.radiance, k, light.radiance);
    }
    p
}

/// Each lane's light sample waiting for its shadow ray: what it adds if
/// the ray is clear, whether a ray is needed, its direction and reach.
pub(super) struct Pending {
    pub added: V,
    pub shadow: M,
    pub wi: V,
    pub reach: F,
}

/// Each lane's light sample at `hits` (`Lights::sample` from the picked
/// light with the point numbers `u`, then `PathTracer::light_sample` for
/// a Lambertian lobe): the point, the direction and its density, f cos
/// and the BSDF's density toward it, the MIS weight and what it adds.
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
pub(super) fn light_terms(
    hits: &Hits,
    frames: &Frames,
    picked: &Picked,
    u: &(F, F),
    throughput: &V,
) -> Pending {
    let mut out = Pending {
        added: [[0.0; LANES]; 3],
        shadow: [false; LANES],
        wi: [[0.0; LANES]; 3],
        reach: [0.0; LANES],
    };
    let (p, from) = (picked, &hits.from);
    for k in 0..LANES {
        let kind = p.kind[k];
        let (ux, uy) = (u.0[k], u.1[k]);
        // `square_to_triangle`, or a parallelogram's (u.x, u.y).
        let upper = uy > ux;
        let tb1 = if upper { ux / 2.0 } else { ux - uy / 2.0 };
        let tb2 = if upper { uy - ux / 2.0 } else { uy / 2.0 };
        let flat_triangle = kind == Kind::Triangle;
        let (b1, b2) = if flat_triangle { (tb1, tb2) } else { (ux, uy) };
        let is_point = kind == Kind::Point;
        let mut to = [0.0f32; 3];
        for a in 0..3 {
            let on_shape = p.v0[a][k] + b1 * p.e1[a][k] + b2 * p.e2[a][k];
            let point = if is_point { p.v0[a][k] } else { on_shape };
            to[a] = point - from[a][k];
        }
        let distance2 = to[0] * to[0] + to[1] * to[1] + to[2] * to[2];
        let distance = distance2.sqrt();
        let wi = to.map(|x| x / distance);
        let n = [p.normal[0][k], p.normal[1][k], p.normal[2][k]];
        let cos = -(wi[0] * n[0] + wi[1] * n[1] + wi[2] * n[2]);
        let far = !(distance.is_nan() | (distance <= 0.0));
        // Not `cos <= 0`: a NaN passes here, and its density fails below.
        let sampled = if is_point {
            far
        } else {
            far & ((cos > 0.0) | cos.is_nan())
        };
        let sampled = sampled & (kind != Kind::None);
        let shape_pdf = distance2 / (cos * p.area[k]);
        let light_pdf = if is_point {
            p.pmf[k]
        } else {
            p.pmf[k] * shape_pdf
        };
        let radiance = |a: usize| {
            let r = p.radiance[a][k];
            if is_point {
                r / distance2
            } else {
                r
            }
        };
        // `eval`: f cos and the density of the Lambertian lobe toward wi.
        let local_z = wi[0] * frames.n[0][k] + wi[1] * frames.n[1][k] + wi[2] * frames.n[2][k];
        // Not `> 0`: as `LabBsdf::eval`, a NaN cosine is evaluated (and
        // its NaN sample dropped by the film, as the one-path tracer's).
        let above = (local_z > 0.0) | local_z.is_nan();
        let f = |a: usize| {
            let f = (0.0 + hits.albedo[a][k] * FRAC_1_PI) * local_z;
            if above {
                f
            } else {
                0.0
            }
        };
        let f = [f(0), f(1), f(2)];
        let lobe_pdf = 0.0 + hits.p_lambert[k] * (local_z.max(0.0) * FRAC_1_PI);
        let bsdf_pdf = if above { lobe_pdf } else { 0.0 };
        let black = (f[0] == 0.0) & (f[1] == 0.0) & (f[2] == 0.0);
        let unlit = black | light_pdf.is_nan() | (light_pdf <= 0.0);
        let weight = if is_point {
            1.0
        } else {
            power_heuristic(light_pdf, bsdf_pdf)
        };
        let scale = weight / light_pdf;
        for a in 0..3 {
            out.added[a][k] = throughput[a][k] * (f[a] * radiance(a) * scale) * 1.0;
            out.wi[a][k] = wi[a];
        }
        out.shadow[k] = sampled & !unlit;
        out.reach[k] = distance * (1.0 - SHADOW_SHORTEN);
    }
    out
}

/// `power_heuristic`, branches made selects.
#[inline(always)]
fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    let sum = a2 + b2;
    let w = a2 / sum;
    let w = if sum == 0.0 { 0.0 } else { w };
    if a2.is_infinite() {
        1.0
    } else {
        w
    }
}

/// Each shaded lane's BSDF sample, throughput and roulette (`LabBsdf`'s
/// Lambertian sample, then `PathTracer::radiance`'s loop): its next ray,
/// or its end.
pub(super) fn bounce(paths: &mut Paths, hits: &Hits, frames: &Frames, numbers: &Numbers) {
    // The disk's points a lane at a time: their sines and cosines are libm's.
    let (mut dx, mut dy) = ([0.0; LANES], [0.0; LANES]);
    for k in 0..LANES {
        if hits.shaded[k] {
            let d = concentric_disk(glam::Vec2::new(
                numbers.direction.0[k],
                numbers.direction.1[k],
            ));
            (dx[k], dy[k]) = (d.x, d.y);
        }
    }
    let next = bounce_from_disk(paths, hits, frames, numbers, (&dx, &dy));
    for k in 0..LANES {
        let goes_on = next.goes_on[k];
        for a in 0..3 {
            let keep = |new: f32, old: f32| if goes_on { new } else { old };
            paths.throughput[a][k] = keep(next.throughput[a][k], paths.throughput[a][k]);
            paths.from[a][k] = keep(hits.from[a][k], paths.from[a][k]);
            paths.rays.origin[a][k] = keep(hits.point[a][k], paths.rays.origin[a][k]);
            paths.rays.dir[a][k] = keep(next.dir[a][k], paths.rays.dir[a][k]);
        }
        paths.pdf[k] = if goes_on { next.pdf[k] } else { paths.pdf[k] };
        paths.specular[k] &= !goes_on;
        paths.alive[k] = if hits.shaded[k] {
            goes_on
        } else {
            paths.alive[k]
        };
    }
}

/// Where each lane's path goes on, if it does: its throughput, its next
/// direction and that direction's density.
struct Next {
    goes_on: M,
    throughput: V,
    dir: V,
    pdf: F,
}

/// `bounce` from each lane's point of the disk: the lanes' next segments.
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
fn bounce_from_disk(
    paths: &Paths,
    hits: &Hits,
    frames: &Frames,
    numbers: &Numbers,
    (dx, dy): (&F, &F),
) -> Next {
    let mut next = Next {
        goes_on: [false; LANES],
        throughput: [[0.0; LANES]; 3],
        dir: [[0.0; LANES]; 3],
        pdf: [0.0; LANES],
    };
    for k in 0..LANES {
        let (x, y) = (dx[k], dy[k]);
        let z = (1.0 - (x * x + y * y)).max(0.0).sqrt();
        let p_lambert = hits.p_lambert[k];
        let lobe = p_lambert > 0.0;
        let pdf = 0.0 + p_lambert * (z.max(0.0) * FRAC_1_PI);
        let pdf = if lobe { pdf } else { 0.0 };
        let sampled = (numbers.lobe[k] < p_lambert) & !((pdf <= 0.0) | (z <= 0.0));
        let mut throughput = [0.0f32; 3];
        for a in 0..3 {
            let f = 0.0 + hits.albedo[a][k] * FRAC_1_PI;
            let weight = f * (z / pdf);
            throughput[a] = paths.throughput[a][k] * weight;
        }
        let roulette = paths.depth[k] >= ROULETTE_DEPTH;
        let max = |a: f32, b: f32| if a > b { a } else { b };
        let q = max(throughput[0], max(throughput[1], throughput[2]));
        let chance = roulette & (q < 1.0);
        let ended = chance & (numbers.survive[k] >= q);
        for a in 0..3 {
            throughput[a] = if chance {
                throughput[a] / q
            } else {
                throughput[a]
            };
            next.throughput[a][k] = throughput[a];
            next.dir[a][k] = x * frames.s[a][k] + y * frames.t[a][k] + z * frames.n[a][k];
        }
        let black = (throughput[0] == 0.0) & (throughput[1] == 0.0) & (throughput[2] == 0.0);
        next.goes_on[k] = hits.shaded[k] & sampled & !ended & !black;
        next.pdf[k] = pdf;
    }
    next
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::Bsdf;
    use crate::geometry::SurfaceHit;
    use crate::light::lights::PointSource;
    use crate::material::{Material, Phong};
    use glam::{Vec2, Vec3};

    /// A shading normal of NaN (no scene file has made one): the lanes
    /// send the shadow ray and add what the one-path tracer adds, NaN
    /// (which the film drops), not a finite value of their own.
    #[test]
    fn a_nan_cosine_is_lit_as_the_one_path_tracer_lights_it() {
        let point = PointSource::point(Vec3::Y, Vec3::ONE);
        let lights = Lights::new(vec![point], vec![], &[], None);
        let n = Vec3::new(f32::NAN, 0.0, 0.0);
        let mut hits = Hits::NONE;
        hits.shaded[0] = true;
        hits.p_lambert[0] = 1.0;
        for a in 0..3 {
            hits.normal[a][0] = n[a];
            hits.albedo[a][0] = 0.5;
        }
        let picked = pick_lights(&lights, &hits, &[0.5; LANES]);
        let u = ([0.5; LANES], [0.5; LANES]);
        let pending = light_terms(
            &hits,
            &frames(&hits.normal),
            &picked,
            &u,
            &[[1.0; LANES]; 3],
        );
        let material = Material::Phong(Phong {
            diffuse: Vec3::splat(0.5),
            specular: Vec3::ZERO,
            reflectance: 0.0,
            ..Phong::default_grey()
        });
        let hit = SurfaceHit {
            t: 1.0,
            object: 0,
            material: 0,
            geometric_normal: n,
            shading_normal: n,
            uv: Vec2::ZERO,
            front_face: true,
            shadow_offset: Vec3::ZERO,
            tangent: glam::Vec4::ZERO,
        };
        let sample = lights.sample(Vec3::ZERO, 0.5, Vec2::splat(0.5)).unwrap();
        let (f, _) = Bsdf::new(&material, &hit, Vec3::Y).eval(sample.wi);
        let lit = !(f == Vec3::ZERO || sample.pdf.is_nan() || sample.pdf <= 0.0);
        assert!(lit, "the one-path tracer sends a shadow ray here");
        assert!(pending.shadow[0], "so do the lanes");
        assert!(pending.added[0][0].is_nan(), "{:?}", pending.added);
    }
}
