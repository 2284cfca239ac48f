//! What an integrator can tell about the light it computes, as it computes
//! it: `tracer explain` passes a recorder that keeps every ray, hit, light
//! term and weight; renders pass `Silent`, whose methods do nothing and
//! compile away. The numbers are the integrator's own, so the pixel a tree
//! explains is the pixel the render wrote.

use crate::bsdf::Bsdf;
use crate::geometry::SurfaceHit;
use crate::ray::Ray;
use glam::Vec3;
use serde::Serialize;

/// Why a ray was traced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RayKind {
    /// From the eye through the pixel.
    Primary,
    /// The mirror ray of a reflecting surface.
    Reflected,
    /// Bent into or out of glass.
    Refracted,
}

/// One light's diffuse and specular terms at a shaded point, in the lab's
/// order (lab 4.4), and its shadow ray.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LightTerm {
    /// The light's index in `[[lights]]`.
    pub light: usize,
    /// The point of the light the terms come from (a sphere light's
    /// sample, or the point light itself).
    pub from: Vec3,
    /// The light's colour.
    pub color: Vec3,
    /// Unit, from the point toward `from`.
    pub l: Vec3,
    /// N.L: at or below the lab's threshold (0.001) the light adds nothing
    /// and no shadow ray is cast.
    pub n_dot_l: f32,
    /// The shadow ray, its length, and what passes along it (None:
    /// blocked; otherwise 1, or less through glass).
    pub shadow: Option<ShadowRay>,
    /// H = normalize(L + V) and N.H, where the specular term was worked out.
    pub h: Option<Vec3>,
    pub n_dot_h: Option<f32>,
    /// (N.H)^shininess.
    pub n_dot_h_pow: Option<f32>,
    /// color * diffuse * N.L, and color * specular * (N.H)^n.
    pub diffuse: Vec3,
    pub specular: Vec3,
}

/// A shadow ray toward a light.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ShadowRay {
    pub origin: Vec3,
    pub direction: Vec3,
    pub length: f32,
    /// What reaches the point: None when something opaque is in the way.
    pub passes: Option<Vec3>,
}

/// What a path-tracing bounce did, for one sample of a pixel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PathEvent {
    /// In JSON its `event` and fields sit beside `throughput` and `added`.
    #[serde(flatten)]
    pub kind: PathEventKind,
    /// The throughput of the path before the event.
    pub throughput: Vec3,
    /// What the event added to the pixel's radiance (already times the
    /// throughput and any weight).
    pub added: Vec3,
}

/// The events of a path, in order.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum PathEventKind {
    /// The path met a surface: its point, normal and material.
    Vertex {
        depth: u32,
        point: Vec3,
        normal: Vec3,
        material: usize,
        front_face: bool,
    },
    /// Light given off by the surface met, and its MIS weight against the
    /// light sample that could have found it (1 after the camera or a
    /// specular bounce).
    Emitted { radiance: Vec3, weight: f32 },
    /// The path left the scene: the background or environment, weighted.
    Escaped { radiance: Vec3, weight: f32 },
    /// Next-event estimation: toward `wi`, a light's `radiance` of density
    /// `light_pdf`, the BSDF's f cos and its density, the MIS weight, and
    /// whether the shadow ray was blocked.
    LightSample {
        wi: Vec3,
        distance: f32,
        radiance: Vec3,
        light_pdf: f32,
        f_cos: Vec3,
        bsdf_pdf: f32,
        weight: f32,
        blocked: bool,
        /// What glass the path is inside leaves of the light on its way
        /// (1 outside glass).
        absorbed: Vec3,
    },
    /// The BSDF sample that continues the path: its direction, weight (f
    /// cos / pdf), density, and whether a specular lobe gave it.
    BsdfSample {
        wi: Vec3,
        weight: Vec3,
        pdf: f32,
        specular: bool,
    },
    /// Next-event estimation that found nothing to sample: no point of
    /// the light picked faces the surface (or the path is inside a sphere
    /// light).
    NoLightPoint,
    /// Russian roulette: the chance to go on, and whether it did.
    Roulette { survive: f32, survived: bool },
}

/// What an integrator reports; every method does nothing unless a
/// recorder says otherwise.
pub trait Recorder {
    /// Whether it keeps nothing (renders): paths may then be traced
    /// together, where recorders follow one at a time.
    const SILENT: bool = false;
    /// A ray starts, of `energy` at the lab's tree `depth`.
    #[inline(always)]
    fn ray(&mut self, _kind: RayKind, _ray: &Ray, _energy: f32, _depth: u32) {}
    /// The ray's nearest hit (None: it left the scene).
    #[inline(always)]
    fn hit(&mut self, _hit: Option<&SurfaceHit>) {}
    /// A light's ambient term at the hit (added once per light).
    #[inline(always)]
    fn ambient(&mut self, _light: usize, _term: Vec3) {}
    /// A light's diffuse and specular terms at the hit.
    #[inline(always)]
    fn light(&mut self, _term: &LightTerm) {}
    /// The local colour of the hit (ambient, diffuse and specular of every
    /// light), and what the lab's texture multiplied it by, if any.
    #[inline(always)]
    fn local(&mut self, _colour: Vec3, _texture: Option<Vec3>) {}
    /// The hit's emission, seen (in Whitted mode it lights nothing).
    #[inline(always)]
    fn emitted(&mut self, _emission: Vec3) {}
    /// The factor absorption left of a ray's colour on its way through
    /// glass (Beer-Lambert: exp(-absorption * t)).
    #[inline(always)]
    fn absorbed(&mut self, _factor: Vec3) {}
    /// A mirror or glass hit that spawns no ray: the tree's limits.
    #[inline(always)]
    fn stopped(&mut self, _why: Stop) {}
    /// The ray's colour, times its energy, children included.
    #[inline(always)]
    fn end_ray(&mut self, _colour: Vec3) {}
    /// A path tracer's event.
    #[inline(always)]
    fn path(&mut self, _event: PathEvent) {}
    /// How the surface of the path's last vertex scatters (after the light
    /// it emits, before its light sample).
    #[inline(always)]
    fn scattering(&mut self, _hit: &SurfaceHit, _bsdf: &Bsdf) {}
}

/// Why a hit that reflects or refracts spawns no ray (lab 5.3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "limit", rename_all = "snake_case")]
pub enum Stop {
    /// The ray is at `max_depth`.
    MaxDepth { max_depth: u32 },
    /// Its energy is at or below `min_energy`.
    MinEnergy { min_energy: f32 },
    /// The sample has traced its `rays` (`MAX_TREE_RAYS`).
    RayBudget { rays: u32 },
}

/// The recorder of renders: nothing is kept.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Recorder for Silent {
    const SILENT: bool = true;
}
