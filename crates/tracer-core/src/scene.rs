//! The prepared scene: shapes with resolved materials, lights, settings.

use crate::bvh::Bvh;
use crate::camera::Camera;
use crate::image::Encoding;
use crate::light::PointLight;
use crate::material::Material;
use crate::ray::Ray;
use crate::shapes::mesh::{self, Placement};
use crate::shapes::{Shape, Sphere, Triangle};
use crate::texture::Texture;
use glam::Vec3;
use scene_format as fmt;
use std::collections::HashMap;
use std::sync::Arc;

/// One shape and the index of its material in `Scene::materials`.
#[derive(Debug, Clone, PartialEq)]
pub struct Object {
    pub shape: Shape,
    pub material: usize,
}

/// The recursion settings of the lab's `rayTrace` (lab 5.3).
#[derive(Debug, Clone, PartialEq)]
pub struct TraceSettings {
    pub max_depth: u32,
    pub min_energy: f32,
    pub background: Vec3,
}

#[derive(Debug, Clone)]
pub struct Scene {
    pub camera: Camera,
    pub objects: Vec<Object>,
    pub materials: Vec<Material>,
    pub lights: Vec<PointLight>,
    pub trace: TraceSettings,
    pub encoding: Encoding,
    /// The hierarchy over `objects`; None: every ray tests every object.
    pub bvh: Option<Bvh>,
}

/// A hit: the distance along the ray, the object's index, and what shading
/// needs of it. The BVH fills in the normal and material from the record it
/// has just tested, in cache, rather than from `Scene::objects`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub object: usize,
    /// The unit normal, as the lab defines it (`Shape::normal`).
    pub normal: Vec3,
    /// The index of the object's material in `Scene::materials`.
    pub material: usize,
}

impl Hit {
    /// The hit on `objects[index]` at distance `t` along `ray`.
    pub fn on(objects: &[Object], index: usize, ray: &Ray, t: f32) -> Hit {
        let object = &objects[index];
        Hit {
            t,
            object: index,
            normal: object.shape.normal(ray.at(t)),
            material: object.material,
        }
    }
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PrepareError {
    #[error("`{path}`: unknown material `{name}`")]
    UnknownMaterial { path: String, name: String },
    #[error("`{path}`: unknown texture `{name}`")]
    UnknownTexture { path: String, name: String },
    #[error("`{path}`: expected exactly one shape")]
    NotOneShape { path: String },
    #[error("`{path}`: the mesh's OBJ file was not read (load the scene with `load_path`)")]
    MeshNotLoaded { path: String },
}

impl Scene {
    /// Builds the renderable scene from a validated scene file.
    pub fn prepare(file: &fmt::SceneFile) -> Result<Scene, PrepareError> {
        let mut materials = MaterialTable::new(file);
        let mut objects = Vec::new();
        for (i, o) in file.objects.iter().enumerate() {
            prepare_object(&format!("objects[{i}]"), o, &mut materials, &mut objects)?;
        }
        let bvh = Some(Bvh::build(&objects));
        let lights = file
            .lights
            .iter()
            .map(|l| PointLight {
                position: l.position.into(),
                color: l.color.into(),
            })
            .collect();
        let r = &file.render;
        Ok(Scene {
            camera: Camera::from_scene(&file.camera),
            objects,
            materials: materials.materials,
            lights,
            trace: TraceSettings {
                max_depth: r.max_depth,
                min_energy: r.min_energy,
                background: r.background.into(),
            },
            encoding: Encoding {
                gamma: r.gamma,
                saturation: r.saturation,
            },
            bvh,
        })
    }

    /// The same scene without its BVH: every ray tests every object. The
    /// reference the BVH is tested against.
    pub fn brute_force(self) -> Scene {
        Scene { bvh: None, ..self }
    }

    /// The nearest hit in (t_min, t_max); of hits at the same distance, the
    /// object listed first.
    pub fn closest_hit(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        match &self.bvh {
            Some(bvh) => bvh.closest_hit(ray, t_min, t_max),
            None => self.closest_hit_brute_force(ray, t_min, t_max),
        }
    }

    /// Whether anything lies on the ray within (t_min, t_max): shadow rays.
    pub fn occluded(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        match &self.bvh {
            Some(bvh) => bvh.occluded(ray, t_min, t_max),
            None => self.occluded_brute_force(ray, t_min, t_max),
        }
    }

    pub fn closest_hit_brute_force(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
        let mut best: Option<(f32, usize)> = None;
        for (index, object) in self.objects.iter().enumerate() {
            let limit = best.map_or(t_max, |(t, _)| t);
            if let Some(t) = object.shape.intersect(ray, t_min, limit) {
                best = Some((t, index));
            }
        }
        best.map(|(t, index)| Hit::on(&self.objects, index, ray, t))
    }

    pub fn occluded_brute_force(&self, ray: &Ray, t_min: f32, t_max: f32) -> bool {
        self.objects
            .iter()
            .any(|o| o.shape.intersect(ray, t_min, t_max).is_some())
    }
}

/// Materials of the prepared scene: the named ones once each, inline ones
/// per object, and textures shared by name.
struct MaterialTable<'a> {
    file: &'a fmt::SceneFile,
    materials: Vec<Material>,
    /// Named material and object texture -> index, so objects share materials.
    by_key: HashMap<(String, Option<String>), usize>,
    textures: HashMap<String, Arc<Texture>>,
}

impl<'a> MaterialTable<'a> {
    fn new(file: &'a fmt::SceneFile) -> Self {
        MaterialTable {
            file,
            materials: Vec::new(),
            by_key: HashMap::new(),
            textures: HashMap::new(),
        }
    }

    fn texture(&mut self, path: &str, name: &str) -> Result<Arc<Texture>, PrepareError> {
        if let Some(t) = self.textures.get(name) {
            return Ok(t.clone());
        }
        let texture = match name {
            "lab-stripes" => Arc::new(Texture::lab_stripes(400, 400)),
            _ => {
                return Err(PrepareError::UnknownTexture {
                    path: path.to_string(),
                    name: name.to_string(),
                })
            }
        };
        self.textures.insert(name.to_string(), texture.clone());
        Ok(texture)
    }

    fn add(
        &mut self,
        path: &str,
        m: &fmt::Material,
        texture: Option<&String>,
    ) -> Result<usize, PrepareError> {
        let texture = match texture.or(m.texture.as_ref()) {
            Some(name) => Some(self.texture(path, name)?),
            None => None,
        };
        self.materials.push(Material::from_scene(m, texture));
        Ok(self.materials.len() - 1)
    }

    /// The index of object `o`'s material, with the object's texture applied.
    fn resolve(&mut self, path: &str, o: &fmt::Object) -> Result<usize, PrepareError> {
        let texture_path = format!("{path}.texture");
        match &o.material {
            None => {
                let mut grey = Material::default_grey();
                if let Some(name) = &o.texture {
                    grey.texture = Some(self.texture(&texture_path, name)?);
                }
                self.materials.push(grey);
                Ok(self.materials.len() - 1)
            }
            Some(fmt::MaterialRef::Inline(m)) => self.add(&texture_path, m, o.texture.as_ref()),
            Some(fmt::MaterialRef::Named(name)) => {
                let key = (name.clone(), o.texture.clone());
                if let Some(&index) = self.by_key.get(&key) {
                    return Ok(index);
                }
                let file = self.file;
                let m = file
                    .materials
                    .get(name)
                    .ok_or_else(|| PrepareError::UnknownMaterial {
                        path: format!("{path}.material"),
                        name: name.clone(),
                    })?;
                let index = self.add(&texture_path, m, o.texture.as_ref())?;
                self.by_key.insert(key, index);
                Ok(index)
            }
        }
    }
}

fn prepare_object(
    path: &str,
    o: &fmt::Object,
    materials: &mut MaterialTable,
    objects: &mut Vec<Object>,
) -> Result<(), PrepareError> {
    let shapes = match o.shapes().as_slice() {
        [fmt::ShapeRef::Sphere(s)] => vec![Shape::Sphere(Sphere::new(s.center.into(), s.radius))],
        [fmt::ShapeRef::Triangle([a, b, c])] => vec![Shape::Triangle(Triangle::new(
            (*a).into(),
            (*b).into(),
            (*c).into(),
        ))],
        [fmt::ShapeRef::Mesh(m)] => {
            let data = m.data.as_ref().ok_or_else(|| PrepareError::MeshNotLoaded {
                path: format!("{path}.mesh.obj"),
            })?;
            let placement = Placement::from_scene(o.transform.as_ref());
            mesh::triangles(data, &placement)
                .into_iter()
                .map(Shape::Triangle)
                .collect()
        }
        _ => {
            return Err(PrepareError::NotOneShape {
                path: path.to_string(),
            })
        }
    };
    let material = materials.resolve(path, o)?;
    objects.extend(shapes.into_iter().map(|shape| Object { shape, material }));
    Ok(())
}
