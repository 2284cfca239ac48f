//! The shapes of area lights, and how a point of each is drawn as seen
//! from a shaded point: a triangle or a parallelogram (a quad, a box's
//! face) by its area, a sphere by the cone of directions it fills (its
//! visible cap, with no samples wasted on the far side), an ellipsoid by
//! the area of the round sphere it stretches.

use super::toward::{flat_pdf, flat_shape_point, toward};
use crate::bsdf::frame::{tangents, to_world};
use crate::sampling::warp::square_to_triangle;
use crate::simd::{Mask, Real, V3};
use glam::{Mat3, Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::f32::consts::PI;

/// An emitting shape, in world space.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum AreaShape {
    /// Emits toward `normal` (the geometric one, `e1 x e2` normalised).
    Triangle {
        v0: Vec3,
        e1: Vec3,
        e2: Vec3,
        normal: Vec3,
        area: f32,
    },
    /// `corner + s e1 + t e2` for s, t in [0, 1]: sampled whole, so the
    /// strata of the point drawn cover it evenly (as two triangles, each
    /// picked by a number of its own, they would not). Emits toward
    /// `normal`, `e1 x e2` normalised.
    Parallelogram {
        corner: Vec3,
        e1: Vec3,
        e2: Vec3,
        normal: Vec3,
        area: f32,
    },
    /// Emits outward.
    Sphere { center: Vec3, radius: f32 },
    /// Emits outward. Boxed: its maps would make every light larger.
    Ellipsoid(Box<EllipsoidLight>),
}

/// The sphere of `radius` about the origin carried by `linear` to
/// `center`. Its points are drawn uniformly on that round sphere and
/// carried: their density by area is the round one over the stretch of
/// area there, |det A| |A^-T q| at the round sphere's unit normal q.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EllipsoidLight {
    center: Vec3,
    radius: f32,
    linear: Mat3,
    inverse: Mat3,
    det: f32,
    area: f32,
}

impl EllipsoidLight {
    /// None when `linear` has no inverse.
    pub fn new(center: Vec3, radius: f32, linear: Mat3) -> Option<EllipsoidLight> {
        let det = linear.determinant().abs();
        if !(det.is_finite() && det > 0.0) {
            return None;
        }
        let mut light = EllipsoidLight {
            center,
            radius,
            linear,
            inverse: linear.inverse(),
            det,
            area: 0.0,
        };
        light.area = light.measure_area();
        Some(light)
    }

    /// How much area grows where the round sphere's unit normal is `q`.
    fn stretch(&self, q: Vec3) -> f32 {
        self.det * (self.inverse.transpose() * q).length()
    }

    /// The area: the round sphere's times the mean stretch, over 4096
    /// points spread evenly on it (a spiral of equal areas). Used only to
    /// weigh the light among the others: a tenth of a percent is plenty.
    fn measure_area(&self) -> f32 {
        const N: usize = 4096;
        let golden = PI * (3.0 - 5.0f32.sqrt());
        let sum: f64 = (0..N)
            .map(|k| {
                let z = 1.0 - (2 * k + 1) as f32 / N as f32;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = golden * k as f32;
                f64::from(self.stretch(Vec3::new(r * phi.cos(), r * phi.sin(), z)))
            })
            .sum();
        (4.0 * PI * self.radius * self.radius) * (sum / N as f64) as f32
    }

    /// The density by area at surface point `point`.
    fn area_pdf(&self, point: Vec3) -> f32 {
        let q = (self.inverse * (point - self.center)).normalize_or_zero();
        1.0 / (4.0 * PI * self.radius * self.radius * self.stretch(q))
    }

    fn sample(&self, from: Vec3, u: Vec2) -> Option<AreaPoint> {
        let z = 1.0 - 2.0 * u.x;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let q = Vec3::new(r * phi.cos(), r * phi.sin(), z);
        let point = self.center + self.radius * (self.linear * q);
        let normal = (self.inverse.transpose() * q).normalize();
        let area = 4.0 * PI * self.radius * self.radius * self.stretch(q);
        seen_from(point.into(), normal.into(), area, from.into()).one()
    }
}

/// A point drawn on an area light, seen from a shaded point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AreaPoint {
    pub point: Vec3,
    /// Unit, from the shaded point toward `point`.
    pub wi: Vec3,
    pub distance: f32,
    /// The density of `wi` (solid angle) given this shape was picked.
    pub pdf: f32,
    /// Where on the shape: a triangle's barycentric (b1, b2) (the weights
    /// of `e1` and `e2`), a parallelogram's (s, t); zero on a sphere or
    /// ellipsoid (`point` says). What an emission texture is read by.
    pub at: Vec2,
}

impl AreaShape {
    /// The triangle `v0`, `v0 + e1`, `v0 + e2`; None without area.
    pub fn triangle(v0: Vec3, e1: Vec3, e2: Vec3) -> Option<AreaShape> {
        let cross = e1.cross(e2);
        let normal = cross.try_normalize()?;
        Some(AreaShape::Triangle {
            v0,
            e1,
            e2,
            normal,
            area: 0.5 * cross.length(),
        })
    }

    /// The parallelogram `corner + s e1 + t e2`; None without area.
    pub fn parallelogram(corner: Vec3, e1: Vec3, e2: Vec3) -> Option<AreaShape> {
        let cross = e1.cross(e2);
        let normal = cross.try_normalize()?;
        Some(AreaShape::Parallelogram {
            corner,
            e1,
            e2,
            normal,
            area: cross.length(),
        })
    }

    /// The area of the surface.
    pub fn area(&self) -> f32 {
        match self {
            AreaShape::Triangle { area, .. } | AreaShape::Parallelogram { area, .. } => *area,
            AreaShape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
            AreaShape::Ellipsoid(e) => e.area,
        }
    }

    /// A point of the shape facing `from`, drawn by `u`; None when the
    /// point drawn faces away (a triangle seen from behind) or `from` is
    /// inside a sphere (which emits outward only). The lanes' formulas on
    /// one lane (`Flat::sample`, `sphere_sample`).
    #[inline(always)]
    pub fn sample(&self, from: Vec3, u: Vec2) -> Option<AreaPoint> {
        let (from, u) = (V3::from(from), (u.x, u.y));
        match self {
            AreaShape::Triangle { .. } | AreaShape::Parallelogram { .. } => {
                let flat = Flat::lanes(|_| Some(self));
                flat.sample(from, u).one()
            }
            AreaShape::Sphere { center, radius } => {
                sphere_sample(V3::from(*center), *radius, from, u).one()
            }
            AreaShape::Ellipsoid(e) => e.sample(from.into(), Vec2::new(u.0, u.1)),
        }
    }

    /// The density `sample` gives a direction from `from` that meets the
    /// shape at `point`, whose cosine with the normal there is `cos`
    /// (positive on the emitting side).
    #[inline(always)]
    pub fn pdf(&self, from: Vec3, point: Vec3, cos: f32) -> f32 {
        match self {
            AreaShape::Triangle { area, .. } | AreaShape::Parallelogram { area, .. } => {
                if cos <= 0.0 {
                    return 0.0;
                }
                (point - from).length_squared() / (cos * area)
            }
            AreaShape::Sphere { center, radius } => {
                sphere_pdf(V3::from(*center), *radius, V3::from(from))
            }
            AreaShape::Ellipsoid(e) => {
                if cos <= 0.0 {
                    return 0.0;
                }
                e.area_pdf(point) * (point - from).length_squared() / cos
            }
        }
    }
}

/// `point` of a light of unit `normal` there, drawn with density 1 / `area`
/// by area (uniformly on a flat light), seen from `from`, by lane: its
/// density by solid angle is d^2 / (cos A). Not `ok` where it faces away.
#[inline(always)]
fn seen_from<N: Real>(point: V3<N>, normal: V3<N>, area: N, from: V3<N>) -> AreaPoints<N> {
    let way = toward(from, point);
    let (pdf, facing) = flat_pdf(&way, normal, area);
    AreaPoints {
        point,
        wi: way.wi,
        distance: way.distance,
        pdf,
        at: (N::zero(), N::zero()),
        ok: facing & way.apart,
    }
}

/// Flat lights by lane: triangles and parallelograms, each drawn by area.
pub struct Flat<N: Real> {
    v0: V3<N>,
    e1: V3<N>,
    e2: V3<N>,
    normal: V3<N>,
    area: N,
    /// A triangle's lane (else a parallelogram's).
    triangle: N::Mask,
}

impl<N: Real> Flat<N> {
    /// Each lane's flat shape `shape(k)`; a lane of None (or of another
    /// shape) is left zero.
    #[inline(always)]
    pub fn lanes<'a>(shape: impl Fn(usize) -> Option<&'a AreaShape>) -> Flat<N> {
        let zero = V3::zero();
        let mut f = Flat {
            v0: zero,
            e1: zero,
            e2: zero,
            normal: zero,
            area: N::zero(),
            triangle: N::Mask::splat(false),
        };
        for k in 0..N::LANES {
            let (v0, e1, e2, normal, area) = match shape(k) {
                Some(AreaShape::Triangle {
                    v0,
                    e1,
                    e2,
                    normal,
                    area,
                }) => {
                    f.triangle.set_lane(k, true);
                    (v0, e1, e2, normal, area)
                }
                Some(AreaShape::Parallelogram {
                    corner,
                    e1,
                    e2,
                    normal,
                    area,
                }) => (corner, e1, e2, normal, area),
                _ => continue,
            };
            f.v0.set_lane(k, *v0);
            f.e1.set_lane(k, *e1);
            f.e2.set_lane(k, *e2);
            f.normal.set_lane(k, *normal);
            f.area.set_lane(k, *area);
        }
        f
    }

    /// A point of each lane's shape drawn by `u`, uniformly by area (a
    /// triangle's by `square_to_triangle`, a parallelogram's (s, t) = u),
    /// seen from `from`.
    #[inline(always)]
    pub fn sample(&self, from: V3<N>, u: (N, N)) -> AreaPoints<N> {
        let (b1, b2) = square_to_triangle(u);
        let b = (
            N::select(self.triangle, b1, u.0),
            N::select(self.triangle, b2, u.1),
        );
        let point = flat_shape_point(self.v0, (self.e1, self.e2), b);
        AreaPoints {
            at: b,
            ..seen_from(point, self.normal, self.area, from)
        }
    }
}

/// The cone of directions a sphere fills, seen from a point outside it,
/// by lane (`simd::Real`).
struct Cone<N: Real> {
    /// Unit, from the point toward the centre.
    axis: V3<N>,
    sin2_max: N,
    cos_max: N,
    one_minus_cos_max: N,
    /// Where the point is outside the sphere (and not NaN).
    outside: N::Mask,
}

/// Below this sin^2 of the cone's half-angle (about 1.5 degrees), 1 - cos
/// is computed from its series: in f32 it would cancel to nothing.
const SMALL_CONE_SIN2: f32 = 0.000_685_2;

impl<N: Real> Cone<N> {
    #[inline(always)]
    fn of(center: V3<N>, radius: N, from: V3<N>) -> Cone<N> {
        let to = center - from;
        let distance = to.length();
        let ratio = radius / distance;
        let sin2_max = ratio * ratio;
        let cos_max = (N::one() - sin2_max).max(N::zero()).sqrt();
        let small = sin2_max.lt(N::splat(SMALL_CONE_SIN2));
        Cone {
            axis: to / distance,
            sin2_max,
            cos_max,
            one_minus_cos_max: N::select(small, sin2_max / 2.0, N::one() - cos_max),
            outside: !(distance.is_nan() | distance.le(radius)),
        }
    }

    /// The density of each of its directions: uniform in solid angle.
    #[inline(always)]
    fn pdf(&self) -> N {
        N::one() / (self.one_minus_cos_max * (2.0 * PI))
    }
}

/// The density `sphere_sample` gives a direction from `from` toward the
/// sphere, by lane: nothing from inside it.
#[inline(always)]
pub fn sphere_pdf<N: Real>(center: V3<N>, radius: N, from: V3<N>) -> N {
    let cone = Cone::of(center, radius, from);
    N::select(cone.outside, cone.pdf(), N::zero())
}

/// Points drawn on area lights, by lane: `AreaPoint`'s fields, and where
/// there is one.
pub struct AreaPoints<N: Real> {
    pub point: V3<N>,
    pub wi: V3<N>,
    pub distance: N,
    pub pdf: N,
    pub at: (N, N),
    pub ok: N::Mask,
}

impl AreaPoints<f32> {
    /// The one lane's point, if there is one.
    #[inline(always)]
    pub fn one(self) -> Option<AreaPoint> {
        self.ok.then(|| AreaPoint {
            point: self.point.into(),
            wi: self.wi.into(),
            distance: self.distance,
            pdf: self.pdf,
            at: Vec2::new(self.at.0, self.at.1),
        })
    }
}

/// A direction of the cone a sphere fills from `from`, uniform in solid
/// angle, and the point of the sphere it meets first, by lane. The point
/// is found by its angle at the centre rather than by intersecting the
/// ray: tiny or far spheres would lose it to cancellation.
#[inline(always)]
pub fn sphere_sample<N: Real>(
    center: V3<N>,
    radius: N,
    from: V3<N>,
    (u1, u2): (N, N),
) -> AreaPoints<N> {
    let cone = Cone::of(center, radius, from);
    let small = cone.sin2_max.lt(N::splat(SMALL_CONE_SIN2));
    let sin2_small = cone.sin2_max * u1;
    let cos_large = (cone.cos_max - 1.0) * u1 + 1.0;
    let sin2 = N::select(small, sin2_small, N::one() - cos_large * cos_large);
    let cos = N::select(small, (N::one() - sin2_small).sqrt(), cos_large);
    // The angle at the centre between the axis back to `from` and the
    // point: law of sines in the triangle (from, centre, point).
    let sin_max = cone.sin2_max.sqrt();
    let cos_alpha = sin2 / sin_max + cos * (N::one() - sin2 / cone.sin2_max).max(N::zero()).sqrt();
    let sin_alpha = (N::one() - cos_alpha * cos_alpha).max(N::zero()).sqrt();
    let (sin_phi, cos_phi) = (u2 * (2.0 * PI)).sin_cos();
    let back = -cone.axis;
    let (s, t) = tangents(back);
    let local = V3::new(sin_alpha * cos_phi, sin_alpha * sin_phi, cos_alpha);
    let point = center + to_world((s, t, back), local) * radius;
    let way = toward(from, point);
    AreaPoints {
        point,
        wi: way.wi,
        distance: way.distance,
        pdf: cone.pdf(),
        at: (N::zero(), N::zero()),
        ok: cone.outside & way.apart,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_points_lie_on_the_visible_cap_with_the_cone_s_density() {
        let (center, radius) = (Vec3::new(0.0, 0.0, 5.0), 1.0);
        let sphere = AreaShape::Sphere { center, radius };
        let from = Vec3::ZERO;
        let cos_max = (1.0f32 - 1.0 / 25.0).sqrt();
        for k in 0..100 {
            let u = Vec2::new((k as f32 + 0.5) / 100.0, (k * 37 % 100) as f32 / 100.0);
            let s = sphere.sample(from, u).expect("outside the sphere");
            assert!(((s.point - center).length() - radius).abs() < 1e-5);
            // Seen from `from`: facing it, and within the cone.
            assert!((s.point - center).dot(from - s.point) >= -1e-5);
            assert!(s.wi.dot(Vec3::Z) >= cos_max - 1e-6);
            let expected = 1.0 / (2.0 * PI * (1.0 - cos_max));
            assert!((s.pdf / expected - 1.0).abs() < 1e-3);
            assert_eq!(sphere.pdf(from, s.point, 1.0), s.pdf);
        }
        // From inside, nothing: the sphere emits outward.
        assert!(sphere.sample(center, Vec2::splat(0.5)).is_none());
    }

    #[test]
    fn an_ellipsoid_s_area_and_density_agree_with_its_samples() {
        // Semi-axes 3, 1, 1: area 2 pi (1 + 3 e^-1 asin e), e^2 = 8/9.
        let linear = Mat3::from_diagonal(Vec3::new(3.0, 1.0, 1.0));
        let e = EllipsoidLight::new(Vec3::new(0.0, 0.0, 10.0), 1.0, linear).unwrap();
        let ecc = (8.0f32 / 9.0).sqrt();
        let exact = 2.0 * PI * (1.0 + 3.0 / ecc * ecc.asin());
        assert!((e.area / exact - 1.0).abs() < 1e-3, "{} vs {exact}", e.area);
        // The solid angle the samples report (the mean of 1/pdf over all
        // draws, facing ones counted) equals the ellipsoid's silhouette
        // seen from far, pi * 3 * 1 / d^2, within a few percent; and each
        // sample's density is the one pdf() gives its point.
        let shape = AreaShape::Ellipsoid(Box::new(e));
        let n = 256;
        let mut solid_angle = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let Some(s) = shape.sample(Vec3::ZERO, u) else {
                    continue;
                };
                let q = s.point - Vec3::new(0.0, 0.0, 10.0);
                assert!(((q.x / 3.0).powi(2) + q.y * q.y + q.z * q.z - 1.0).abs() < 1e-4);
                let normal = Vec3::new(q.x / 9.0, q.y, q.z).normalize();
                let cos = -s.wi.dot(normal);
                assert!((shape.pdf(Vec3::ZERO, s.point, cos) / s.pdf - 1.0).abs() < 1e-3);
                solid_angle += 1.0 / f64::from(s.pdf);
            }
        }
        let solid_angle = solid_angle / f64::from(n * n);
        let expected = f64::from(3.0 * PI / 100.0);
        assert!(
            (solid_angle / expected - 1.0).abs() < 0.03,
            "{solid_angle} vs {expected}"
        );
    }

    /// Sixteen lanes give each lane's one-lane sphere point and density,
    /// bit for bit: near, far and tiny spheres, points inside them.
    #[test]
    fn sphere_points_in_lanes_are_the_one_lane_points() {
        use crate::simd::{Mask, F16};
        let mut rng = crate::sampling::Rng::new(21);
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        let (mut drawn, mut inside) = (0, 0);
        for round in 0..100 {
            let spheres: [(Vec3, f32); 16] = std::array::from_fn(|k| {
                let c = rng.square().extend(rng.square().x) * 4.0 - 2.0;
                (c, [1.0, 0.01, 0.5, 3.0][(k + round) % 4])
            });
            let from: [Vec3; 16] = std::array::from_fn(|k| {
                let far = [1.0, 100.0, 3.0][k % 3];
                (rng.square().extend(rng.square().y) - 0.5) * far
            });
            let u: [Vec2; 16] = std::array::from_fn(|_| rng.square());
            let lanes = |v: &dyn Fn(usize) -> Vec3| V3::<F16>::from_fn(v);
            let center = lanes(&|k| spheres[k].0);
            let radius = F16::from_fn(|k| spheres[k].1);
            let u16 = (F16::from_fn(|k| u[k].x), F16::from_fn(|k| u[k].y));
            let s = sphere_sample(center, radius, lanes(&|k| from[k]), u16);
            let pdf = sphere_pdf(center, radius, lanes(&|k| from[k]));
            for k in 0..16 {
                let (c, r) = spheres[k];
                let shape = AreaShape::Sphere {
                    center: c,
                    radius: r,
                };
                let one = shape.sample(from[k], u[k]);
                let lane = s.ok.lane(k).then(|| {
                    let (p, wi) = (bits(s.point.lane(k)), bits(s.wi.lane(k)));
                    (p, wi, s.distance.lane(k).to_bits(), s.pdf.lane(k).to_bits())
                });
                let one = one.map(|o| {
                    (
                        bits(o.point),
                        bits(o.wi),
                        o.distance.to_bits(),
                        o.pdf.to_bits(),
                    )
                });
                assert_eq!(lane, one, "round {round}, lane {k}");
                let one_pdf = shape.pdf(from[k], Vec3::ZERO, 1.0);
                assert_eq!(pdf.lane(k).to_bits(), one_pdf.to_bits());
                drawn += usize::from(one.is_some());
                inside += usize::from(one.is_none());
            }
        }
        assert!(drawn > 800 && inside > 50, "{drawn} drawn, {inside} inside");
    }
}
