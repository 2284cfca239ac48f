//! The lights of path mode, one list: the point lights and every emitting
//! surface (each triangle of an emissive mesh, quad or box, each emissive
//! sphere), one of them picked per light sample in proportion to its power,
//! so a mesh of thousands of emissive triangles costs one sample, not
//! thousands.

use super::alias::AliasTable;
use super::area::AreaShape;
use super::environment::Environment;
use super::textured::LightTexture;
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::f32::consts::PI;
use std::sync::Arc;

/// An emitting surface: its shape and radiance, and what varies over it
/// (an emission texture, which `radiance` multiplies, or an alpha mask).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AreaLight {
    pub shape: AreaShape,
    pub radiance: Vec3,
    /// None for most lights, of one radiance all over.
    pub texture: Option<Box<LightTexture>>,
}

impl AreaLight {
    /// A light of one radiance all over.
    pub fn new(shape: AreaShape, radiance: Vec3) -> AreaLight {
        AreaLight {
            shape,
            radiance,
            texture: None,
        }
    }

    /// The radiance it gives off on average: what its power is reckoned by.
    fn mean_radiance(&self) -> Vec3 {
        self.texture
            .as_ref()
            .map_or(self.radiance, |t| t.surface.mean)
    }
}

/// A light of no size in path mode (a delta light: no path can meet it,
/// only light sampling finds it): a point light, whose intensity falls off
/// with the square of the distance, a spot light, or a directional one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointSource {
    /// Where it is (not read for a directional light).
    pub position: Vec3,
    /// Its intensity; a directional light's irradiance.
    pub intensity: Vec3,
    pub emits: Emits,
}

/// Which way a light of no size sends its light.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Emits {
    /// Every way alike: a point light.
    Everywhere,
    /// Into a cone about unit `axis`, as glTF's spot light
    /// (`super::cone_falloff`).
    Cone {
        axis: Vec3,
        cos_inner: f32,
        cos_outer: f32,
    },
    /// All along unit `direction`, from infinitely far away; `radius` is
    /// the scene's (its power is the irradiance over the scene's disk).
    Parallel { direction: Vec3, radius: f32 },
}

impl PointSource {
    /// A point light at `position` of `intensity`.
    pub fn point(position: Vec3, intensity: Vec3) -> PointSource {
        PointSource {
            position,
            intensity,
            emits: Emits::Everywhere,
        }
    }

    /// The power it gives off, by luminance, for the pick among lights:
    /// 4 pi I for a point, pbrt-v4's 2 pi I (1 - (cos inner + cos outer)
    /// / 2) for a spot, E pi r^2 over the scene's disk for a directional
    /// light.
    fn power(&self) -> f64 {
        let i = f64::from(luminance(self.intensity));
        let pi = std::f64::consts::PI;
        match self.emits {
            Emits::Everywhere => 4.0 * pi * i,
            Emits::Cone {
                cos_inner,
                cos_outer,
                ..
            } => 2.0 * pi * i * (1.0 - 0.5 * f64::from(cos_inner + cos_outer)),
            Emits::Parallel { radius, .. } => pi * f64::from(radius).powi(2) * i,
        }
    }
}

/// The point lights, the area lights and the environment, and the table
/// that picks one.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Lights {
    points: Vec<PointSource>,
    areas: Vec<AreaLight>,
    environment: Option<Arc<Environment>>,
    /// Over `points`, `areas`, then the environment; None without light.
    table: Option<AliasTable>,
    /// pi / the total power (of luminance): a triangle's density by area
    /// is its radiance's luminance times this.
    per_area: f32,
    /// (object, index into `areas`) of each emissive sphere or ellipsoid, by object,
    /// to find its density when a path meets it.
    spheres: Vec<(u32, u32)>,
}

/// Rec. 709 luminance: the weight of a colour's power.
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

impl Lights {
    /// The lights of `points`, `areas` and the `environment` around a scene
    /// of `radius` (its power is pi radius^2 times its radiance over the
    /// sphere, as pbrt-v4 weighs it), where `sphere_objects[k]` is the scene
    /// object of the k-th sphere in `areas` (in order).
    pub fn new(
        points: Vec<PointSource>,
        areas: Vec<AreaLight>,
        sphere_objects: &[u32],
        environment: Option<(Arc<Environment>, f32)>,
    ) -> Lights {
        let point_power = PointSource::power;
        // One-sided: a surface of radiance L and area A gives off pi L A
        // (L its mean over a texture).
        let area_power = |a: &AreaLight| {
            PI as f64 * f64::from(luminance(a.mean_radiance())) * f64::from(a.shape.area())
        };
        let environment_power = environment.as_ref().map(|(e, radius)| {
            PI as f64 * f64::from(*radius).powi(2) * f64::from(e.luminance_integral())
        });
        let weights: Vec<f64> = points
            .iter()
            .map(point_power)
            .chain(areas.iter().map(area_power))
            .chain(environment_power)
            .collect();
        let total: f64 = weights.iter().sum();
        let spheres = areas
            .iter()
            .enumerate()
            .filter(|(_, a)| matches!(a.shape, AreaShape::Sphere { .. } | AreaShape::Ellipsoid(_)))
            .zip(sphere_objects)
            .map(|((k, _), &object)| (object, k as u32))
            .collect::<Vec<_>>();
        let mut spheres = spheres;
        spheres.sort_unstable();
        Lights {
            table: AliasTable::new(&weights),
            per_area: (PI as f64 / total) as f32,
            points,
            areas,
            environment: environment.map(|(e, _)| e),
            spheres,
        }
    }

    /// Whether there is any light to sample.
    pub fn is_empty(&self) -> bool {
        self.table.is_none()
    }

    /// The table that picks a light (`sample`'s first step); None without
    /// light.
    pub(crate) fn table(&self) -> Option<&AliasTable> {
        self.table.as_ref()
    }

    pub fn has_environment(&self) -> bool {
        self.environment.is_some()
    }

    pub(crate) fn environment(&self) -> Option<&Environment> {
        self.environment.as_deref()
    }

    pub fn areas(&self) -> &[AreaLight] {
        &self.areas
    }

    pub fn points(&self) -> &[PointSource] {
        &self.points
    }

    /// The density `sample` gives a direction toward the environment that
    /// the environment alone draws with density `pdf` (its `pdf`, or
    /// `radiance_and_pdf`'s): that times the environment's pick.
    #[inline(always)]
    pub fn pdf_environment(&self, pdf: f32) -> f32 {
        match (&self.table, &self.environment) {
            (Some(table), Some(_)) => table.pmf(table.len() - 1) * pdf,
            _ => 0.0,
        }
    }

    /// The density `sample` gives the direction from `from` that meets an
    /// emitting surface of mean radiance `radiance` (over its texture, if
    /// it has one: `Material::emission_mean`) at `point`, on scene object
    /// `object`, with cosine `cos` to its normal (positive on the emitting
    /// side). A triangle is picked with probability in proportion to its
    /// power, pi L A, and its points by area: whichever triangle it is,
    /// its density by area is pi luminance(L) / total power.
    #[inline(always)]
    pub fn pdf_hit(&self, from: Vec3, point: Vec3, cos: f32, radiance: Vec3, object: usize) -> f32 {
        let Some(table) = &self.table else {
            return 0.0;
        };
        if let Ok(k) = self.spheres.binary_search_by_key(&(object as u32), |s| s.0) {
            let area = self.spheres[k].1 as usize;
            let pmf = table.pmf(self.points.len() + area);
            return pmf * self.areas[area].shape.pdf(from, point, cos);
        }
        if cos <= 0.0 {
            return 0.0;
        }
        let per_area = self.per_area * luminance(radiance);
        per_area * (point - from).length_squared() / cos
    }
}

impl Lights {
    /// Why lights read back from a file (`--cache`) cannot be sampled, if
    /// so: a table of another length than the lights, an index past them.
    pub(crate) fn check(&self) -> Result<(), String> {
        let n = self.points.len() + self.areas.len() + usize::from(self.environment.is_some());
        if let Some(table) = &self.table {
            if !table.is_whole() || table.len() != n {
                return Err(format!("a light table of {} for {n} lights", table.len()));
            }
        }
        if let Some(&(_, k)) = self
            .spheres
            .iter()
            .find(|s| s.1 as usize >= self.areas.len())
        {
            return Err(format!("sphere light {k} of {}", self.areas.len()));
        }
        let textures = self.areas.iter().filter_map(|a| a.texture.as_ref());
        if textures.into_iter().any(|t| !t.is_whole()) {
            return Err("a light's texture of the wrong size".into());
        }
        match &self.environment {
            Some(e) if !e.is_whole() => Err("an environment of the wrong size".into()),
            _ => Ok(()),
        }
    }
}
