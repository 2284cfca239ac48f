//! The lanes' shading, a step of every lane at once, kept by field (a
//! structure of arrays): the frame, the light sample and what it adds, the
//! BSDF sample, the throughput and the roulette. Each is the one-path
//! tracer's own formula on sixteen lanes (`simd::F16`): `bsdf::frame`'s
//! tangents, `Lights::sample_of` (`light::sample`), `bsdf::lambert`,
//! `sampling::warp`, `sampling::mis` and `integrate::path::roulette`,
//! combined as `LabBsdf` and `PathTracer` combine them for a Lambertian
//! lobe alone, so every value is the one-path tracer's bit for bit.

use super::{axes, by_axis, Numbers, Paths, F, LANES, V};
use crate::bsdf::frame::{tangents, to_world};
use crate::bsdf::lambert::{lambert_f, lambert_pdf};
use crate::integrate::path::roulette::{roulette, ROULETTE_DEPTH};
use crate::light::area::AreaShape;
use crate::light::lights::Lights;
use crate::light::toward::SHADOW_SHORTEN;
use crate::sampling::mis::power_heuristic;
use crate::sampling::warp::cosine_hemisphere;
use crate::simd::{Mask, Real, F16, M16, V3};
use multiversion::multiversion;

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

/// `Frame::new` of each lane's normal.
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
pub(super) fn frames(n: &V) -> Frames {
    let (s, t) = tangents(by_axis(n));
    Frames {
        s: axes(s),
        t: axes(t),
        n: *n,
    }
}

/// Whether the scene's lights suit the lanes: points (no spot or
/// directional light) and flat emitters (triangles, parallelograms), whose
/// shadow rays `casters.rs` knows how to spare, and no environment (the
/// lanes' escaping paths see the background).
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

/// Each lane's light sample waiting for its shadow ray: what it adds if
/// the ray is clear, whether a ray is needed, its direction and reach, and
/// the light it goes to.
pub(super) struct Pending {
    pub added: V,
    pub shadow: M,
    pub wi: V,
    pub reach: F,
    light: [u32; LANES],
}

impl Pending {
    /// The light every shadow ray goes to, if they go to one (or there is
    /// none).
    pub(super) fn one_light(&self) -> Option<usize> {
        let mut picked = (0..LANES)
            .filter(|&k| self.shadow[k])
            .map(|k| self.light[k]);
        let first = picked.next().unwrap_or(0);
        picked.all(|i| i == first).then_some(first as usize)
    }
}

/// Each lane's light sample at `hits`, where the lobe reflects (a black
/// material takes none): `Lights::sample_of` with the pick `pick` and the
/// point numbers `u`, then `PathTracer::light_sample` for a Lambertian
/// lobe: f cos and the BSDF's density toward it, the MIS weight and what
/// it adds.
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
pub(super) fn light_terms(
    lights: &Lights,
    (hits, frames): (&Hits, &Frames),
    (pick, u): (&F, &(F, F)),
    throughput: &V,
) -> Pending {
    let wanted = M16::from_fn(|k| hits.shaded[k] && hits.p_lambert[k] > 0.0);
    let from = by_axis(&hits.from);
    let s = lights.sample_of(from, F16(*pick), (F16(u.0), F16(u.1)), wanted);
    // `LabBsdf::eval` of a Lambertian lobe alone, toward `wi`.
    let cos = s.wi.dot(by_axis(&frames.n));
    let above = !cos.le(F16::zero());
    let f = V3::select(
        above,
        lambert_f(by_axis(&hits.albedo), cos) * cos,
        V3::zero(),
    );
    let p_lambert = F16(hits.p_lambert);
    let bsdf_pdf = F16::select(above, p_lambert * lambert_pdf(cos), F16::zero());
    let unlit = f.is_zero() | s.pdf.is_nan() | s.pdf.le(F16::zero());
    let weight = F16::select(s.point, F16::one(), power_heuristic(s.pdf, bsdf_pdf));
    let added = by_axis(throughput) * (f * s.radiance * (weight / s.pdf));
    let shadow = s.ok & !unlit;
    Pending {
        added: axes(added),
        shadow: std::array::from_fn(|k| shadow.lane(k)),
        wi: axes(s.wi),
        reach: (s.distance * (1.0 - SHADOW_SHORTEN)).0,
        light: s.light,
    }
}

/// Each shaded lane's BSDF sample, throughput and roulette (`LabBsdf`'s
/// Lambertian sample, then `PathTracer::radiance`'s loop): its next ray,
/// or its end.
pub(super) fn bounce(paths: &mut Paths, hits: &Hits, frames: &Frames, numbers: &Numbers) {
    let next = next_segments(paths, hits, frames, numbers);
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

/// Each lane's next segment: `LabBsdf::sample` of a Lambertian lobe alone
/// (a cosine-weighted direction, its weight and density), then the
/// roulette.
#[multiversion(targets("x86_64+avx512f+avx512bw+avx512dq+avx512vl", "x86_64+avx2"))]
fn next_segments(paths: &Paths, hits: &Hits, frames: &Frames, numbers: &Numbers) -> Next {
    let wi = cosine_hemisphere((F16(numbers.direction.0), F16(numbers.direction.1)));
    let p_lambert = F16(hits.p_lambert);
    let lobe = p_lambert.gt(F16::zero());
    let pdf = F16::select(lobe, p_lambert * lambert_pdf(wi.z), F16::zero());
    let picked = F16(numbers.lobe).lt(p_lambert);
    let sampled = picked & !(pdf.le(F16::zero()) | wi.z.le(F16::zero()));
    let weight = lambert_f(by_axis(&hits.albedo), wi.z) * (wi.z / pdf);
    let throughput = by_axis(&paths.throughput) * weight;
    let deep = M16::from_fn(|k| paths.depth[k] >= ROULETTE_DEPTH);
    let r = roulette(throughput, F16::one(), deep, F16(numbers.survive));
    let axes_in = (by_axis(&frames.s), by_axis(&frames.t), by_axis(&frames.n));
    let shaded = M16::from_fn(|k| hits.shaded[k]);
    let goes_on = shaded & sampled & !(r.played & !r.survived) & !r.throughput.is_zero();
    Next {
        goes_on: std::array::from_fn(|k| goes_on.lane(k)),
        throughput: axes(r.throughput),
        dir: axes(to_world(axes_in, wi)),
        pdf: pdf.0,
    }
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
        let u = ([0.5; LANES], [0.5; LANES]);
        let frames = frames(&hits.normal);
        let numbers = (&[0.5; LANES], &u);
        let pending = light_terms(&lights, (&hits, &frames), numbers, &[[1.0; LANES]; 3]);
        let material = Material::Phong(Phong {
            diffuse: Vec3::splat(0.5),
            specular: Vec3::ZERO,
            reflectance: 0.0,
            ..Phong::default_grey()
        });
        let hit = SurfaceHit::facing(n, Vec2::ZERO);
        let sample = lights.sample(Vec3::ZERO, 0.5, Vec2::splat(0.5)).unwrap();
        let (f, _) = Bsdf::new(&material, &hit, Vec3::Y).eval(sample.wi);
        let lit = !(f == Vec3::ZERO || sample.pdf.is_nan() || sample.pdf <= 0.0);
        assert!(lit, "the one-path tracer sends a shadow ray here");
        assert!(pending.shadow[0], "so do the lanes");
        assert!(pending.added[0][0].is_nan(), "{:?}", pending.added);
    }
}
