//! Checks every value of a parsed scene, so the renderer can trust it.

use crate::diagnostic::Diagnostic;
use crate::key_path::KeyPath;
use crate::model::*;
use crate::suggest::hint;

/// Largest image side accepted, and largest pixel count (2^28).
pub const MAX_IMAGE_SIDE: u32 = 16384;
pub const MAX_IMAGE_PIXELS: u64 = 1 << 28;
/// Largest `render.camera_rays`: each is a nearest hit per path.
pub const MAX_CAMERA_RAYS: u32 = 64;

/// Largest `render.path_reuse`: a group's connections grow as its square.
pub const MAX_PATH_REUSE: u32 = 32;

/// Largest `render.max_depth`: deeper mirror recursion only costs time.
pub const MAX_DEPTH_CAP: u32 = 64;

// Bounds of what single-precision (f32) tracing can handle. Finite but
// absurd values (1e19, 3e38) overflow inside the intersection tests and
// render nothing, without a word; these bounds keep every product finite.
//
// Coordinates: the tests square differences of points (sphere: |o - c|^2,
// b^2; triangle: cross products of edges, then dot products), so with
// |x| <= 1e6 the largest intermediate is about (2e6)^3 = 8e18, far below
// f32::MAX (3.4e38); at 1e19 the squares alone reach it. f32 resolves 1e6
// to 1/16 of a unit: beyond that positions stop meaning anything. The lab's
// epsilon (1e-4, the gap a ray leaves before it may hit a surface) is
// absolute, so it outweighs rounding (an ulp of |x|) only for |x| below
// about 1e3; scenes between 1e3 and 1e6 are traced, possibly with speckled
// shadows, which is a matter of quality, not of nothing at all.
/// Largest absolute coordinate of a point (eye, look_at, lights, shapes, translate).
pub const MAX_COORDINATE: f32 = 1e6;
/// Sphere radii: at least the lab's epsilon (a sphere smaller than the gap
/// a ray leaves before it may hit anything is skipped by the rays cast from
/// beside it; seen from distance d its r^2 survives |o - c|^2 - r^2 in f32
/// only when r > ~2.5e-4 d anyway), at most `MAX_COORDINATE`.
pub const MIN_RADIUS: f32 = 1e-4;
/// Largest `camera.focus_distance`: the farthest two points within
/// `MAX_COORDINATE` can be apart, rounded up.
pub const MAX_DISTANCE: f32 = 4e6;
/// Smallest `camera.fov` in degrees. Pixel directions are `u * x + v * y +
/// o` normalised, with |o| the focal length `width / (2 tan(fov / 2))`:
/// neighbouring pixels differ by 1 / focal. At 1 degree and the widest image
/// (16384) that is 1.1e-6, nine f32 ulps of 1; at 0.1 degree it is one ulp
/// and neighbouring pixels see the same ray.
pub const MIN_FOV: f32 = 1.0;
/// Mesh scale factors: |s| from 1e-6 to 1e6, so that an OBJ in ordinary
/// units (0.001 to 1000) lands within `MAX_COORDINATE` and its edges keep
/// cross products that f32 does not flush to zero. What the placement makes
/// of the mesh itself is checked once it is read (no triangle left is an error).
pub const SCALE_RANGE: (f32, f32) = (1e-6, 1e6);
/// Largest `render.samples` and `render.light_samples`: 4096 rays per
/// pixel is beyond what a reference image needs.
pub const MAX_SAMPLES: u32 = 4096;
/// Largest `render.samples` in path mode: a reference image of the path
/// tracer takes tens of thousands of paths per pixel.
pub const MAX_PATH_SAMPLES: u32 = 65536;

/// All problems found in `scene`, in file order.
pub fn validate(scene: &SceneFile) -> Vec<Diagnostic> {
    validate_with(scene, Validator::default())
}

/// [`validate`] of a file a scene includes, read on its own: a material
/// it names may be defined by another file of the scene.
pub(crate) fn validate_part(scene: &SceneFile) -> Vec<Diagnostic> {
    let v = Validator {
        names_elsewhere: true,
        ..Validator::default()
    };
    validate_with(scene, v)
}

fn validate_with(scene: &SceneFile, mut v: Validator) -> Vec<Diagnostic> {
    let root = KeyPath::root();
    v.camera(&root.key("camera"), &scene.camera);
    v.render(&root.key("render"), &scene.render);
    for (i, light) in scene.lights.iter().enumerate() {
        let path = root.key("lights").index(i);
        v.light_kind(&path, light);
        v.color(path.key("color"), light.color);
        v.light_radius(&path, light);
    }
    for (name, material) in &scene.materials {
        v.material(&root.key("materials").key(name), material);
    }
    if let Some(environment) = &scene.environment {
        v.environment(&root.key("environment"), environment);
    }
    for (i, object) in scene.objects.iter().enumerate() {
        v.object(&root.key("objects").index(i), object, scene);
    }
    v.diagnostics
}

/// The problems of one material on its own (an OBJ's, from its MTL), with
/// key paths from the material (`diffuse`).
pub(crate) fn material(m: &Material) -> Vec<Diagnostic> {
    let mut v = Validator::default();
    v.material(&KeyPath::root(), m);
    v.diagnostics
}

/// How many unknown names get a "did you mean" (each compares the name
/// with every known one): as many as diagnostics are shown.
const MAX_HINTS: usize = crate::excerpt::MAX_SHOWN;

#[derive(Default)]
struct Validator {
    diagnostics: Vec<Diagnostic>,
    /// Unknown names given a hint so far.
    hints: usize,
    /// The names of `[materials]`, collected once.
    material_names: Option<Vec<String>>,
    /// Whether a material name may be defined in a file not read.
    names_elsewhere: bool,
}

impl Validator {
    fn error(&mut self, path: impl Into<KeyPath>, message: impl Into<String>) {
        self.diagnostics.push(Diagnostic::new(path, message));
    }

    fn finite(&mut self, path: impl Into<KeyPath>, x: f32) -> bool {
        if !x.is_finite() {
            let found = format!("{x}{}", beyond_f32(x.is_infinite()));
            self.error(path, format!("expected a finite number, found {found}"));
        }
        x.is_finite()
    }

    fn finite_vec(&mut self, path: impl Into<KeyPath>, v: Vec3) -> bool {
        if v.iter().all(|x| x.is_finite()) {
            return true;
        }
        let infinite = v.iter().any(|x| x.is_infinite());
        let found = format!("{}{}", show(v), beyond_f32(infinite));
        self.error(path, format!("expected finite numbers, found {found}"));
        false
    }

    /// A finite point within `MAX_COORDINATE` on every axis.
    fn point(&mut self, path: impl Into<KeyPath>, p: Vec3) -> bool {
        let path = path.into();
        if !self.finite_vec(&path, p) {
            return false;
        }
        if p.iter().any(|x| x.abs() > MAX_COORDINATE) {
            self.error(
                path,
                format!(
                    "expected coordinates from -{MAX_COORDINATE:e} to {MAX_COORDINATE:e}, found {}; single-precision tracing cannot handle larger ones",
                    show(p)
                ),
            );
            return false;
        }
        true
    }

    fn color(&mut self, path: impl Into<KeyPath>, c: Color) {
        let path = path.into();
        if self.finite_vec(&path, c) && c.iter().any(|&x| x < 0.0) {
            self.error(
                path,
                format!("expected a colour with channels >= 0, found {}", show(c)),
            );
        }
    }

    fn camera(&mut self, path: &KeyPath, c: &Camera) {
        let ok = self.point(path.key("eye"), c.eye)
            & self.point(path.key("look_at"), c.look_at)
            & self.finite_vec(path.key("up"), c.up);
        if self.finite(path.key("fov"), c.fov) && !(c.fov > 0.0 && c.fov < 180.0) {
            self.error(
                path.key("fov"),
                format!(
                    "expected degrees between 0 and 180 (exclusive), found {}",
                    c.fov
                ),
            );
        } else if c.fov < MIN_FOV {
            self.error(
                path.key("fov"),
                format!(
                    "expected at least {MIN_FOV} degree, found {}; below it neighbouring pixels get the same single-precision ray",
                    num(c.fov)
                ),
            );
        }
        self.image_size(path, c.width, c.height);
        self.length(path.key("aperture"), c.aperture, "a lens radius");
        self.projection(path, c);
        if let Some(f) = c.focus_distance {
            let key = path.key("focus_distance");
            if self.finite(&key, f) && f <= 0.0 {
                self.error(key, format!("expected a distance > 0, found {}", num(f)));
            } else if f > MAX_DISTANCE {
                self.error(
                    key,
                    format!("expected at most {MAX_DISTANCE:e}, found {}", num(f)),
                );
            }
        }
        if !ok {
            return;
        }
        let view = sub(c.look_at, c.eye);
        if length(view) == 0.0 {
            self.error(
                path.key("look_at"),
                format!(
                    "expected a point other than `camera.eye`, found {}, the same point; the camera would look nowhere",
                    show(c.look_at)
                ),
            );
        } else if c.up == [0.0; 3] {
            self.error(
                path.key("up"),
                format!("expected a non-zero vector, found {}", show(c.up)),
            );
        } else if parallel(c.up, view) {
            self.error(
                path.key("up"),
                format!(
                    "expected a vector not parallel to the view direction (look_at - eye = {}), found {}",
                    show(view),
                    show(c.up)
                ),
            );
        }
    }

    /// An orthographic camera's `view_width` (needed, and only there), and
    /// no lens on it.
    fn projection(&mut self, path: &KeyPath, c: &Camera) {
        let key = path.key("view_width");
        match (c.projection, c.view_width) {
            (Projection::Orthographic, None) => self.error(
                path.key("projection"),
                "an orthographic camera needs `view_width`: how many scene units the image spans across",
            ),
            (Projection::Perspective, Some(_)) => self.error(
                key,
                "expected `view_width` only with `projection = \"orthographic\"`; a perspective camera's view is `fov` wide",
            ),
            (Projection::Orthographic, Some(w)) => {
                if self.finite(&key, w) && !(w > 0.0 && w <= MAX_DISTANCE) {
                    self.error(
                        key,
                        format!("expected a width > 0 and at most {MAX_DISTANCE:e}, found {}", num(w)),
                    );
                }
                if c.aperture != 0.0 {
                    self.error(
                        path.key("aperture"),
                        "expected no `aperture` on an orthographic camera: its parallel rays have no lens to blur with",
                    );
                }
            }
            (Projection::Perspective, None) => {}
        }
    }

    /// A length (a radius, an aperture): finite, 0 or more, at most
    /// `MAX_COORDINATE`.
    fn length(&mut self, path: KeyPath, x: f32, what: &str) {
        if !self.finite(&path, x) {
            return;
        }
        if x < 0.0 {
            self.error(path, format!("expected {what} >= 0, found {}", num(x)));
        } else if x > MAX_COORDINATE {
            self.error(
                path,
                format!(
                    "expected {what} of at most {MAX_COORDINATE:e}, found {}",
                    num(x)
                ),
            );
        }
    }

    fn image_size(&mut self, path: &KeyPath, width: u32, height: u32) {
        for (key, side) in [("width", width), ("height", height)] {
            if side == 0 || side > MAX_IMAGE_SIDE {
                self.error(
                    path.key(key),
                    format!("expected 1 to {MAX_IMAGE_SIDE} pixels, found {side}"),
                );
            }
        }
        if u64::from(width) * u64::from(height) > MAX_IMAGE_PIXELS {
            self.error(
                path,
                format!(
                    "expected at most {MAX_IMAGE_PIXELS} pixels (2^28), found {width}x{height}"
                ),
            );
        }
    }

    fn render(&mut self, path: &KeyPath, r: &RenderSettings) {
        if r.max_depth() > MAX_DEPTH_CAP {
            self.error(
                path.key("max_depth"),
                format!("expected at most {MAX_DEPTH_CAP}, found {}", r.max_depth()),
            );
        }
        if self.finite(path.key("min_energy"), r.min_energy) && r.min_energy < 0.0 {
            self.error(
                path.key("min_energy"),
                format!("expected a number >= 0, found {}", r.min_energy),
            );
        }
        self.color(path.key("background"), r.background);
        if self.finite(path.key("gamma"), r.gamma) && r.gamma <= 0.0 {
            self.error(
                path.key("gamma"),
                format!("expected a number > 0, found {}", r.gamma),
            );
        }
        let samples = path.key("samples");
        match r.integrator {
            Integrator::Whitted if r.samples > MAX_SAMPLES => self.error(
                samples,
                format!(
                    "expected 1 to {MAX_SAMPLES} samples, found {}; more are allowed with integrator = \"path\"",
                    r.samples
                ),
            ),
            _ if r.samples == 0 || r.samples > MAX_PATH_SAMPLES => {
                let max = match r.integrator {
                    Integrator::Whitted => MAX_SAMPLES,
                    Integrator::Path => MAX_PATH_SAMPLES,
                };
                self.error(
                    samples,
                    format!("expected 1 to {max} samples, found {}", r.samples),
                )
            }
            _ => {}
        }
        if let Some(limit) = r.time_limit {
            let key = path.key("time_limit");
            if self.finite(&key, limit) && limit <= 0.0 {
                self.error(key, format!("expected seconds > 0, found {}", num(limit)));
            }
        }
        if let Some(n) = r.path_reuse.filter(|&n| n == 0 || n > MAX_PATH_REUSE) {
            self.error(
                path.key("path_reuse"),
                format!("expected 1 to {MAX_PATH_REUSE} pixels, found {n}"),
            );
        }
        if let Some(n) = r.camera_rays.filter(|&n| n == 0 || n > MAX_CAMERA_RAYS) {
            self.error(
                path.key("camera_rays"),
                format!("expected 1 to {MAX_CAMERA_RAYS} rays, found {n}"),
            );
        }
        let n = r.light_samples;
        if n == 0 || n > MAX_SAMPLES {
            self.error(
                path.key("light_samples"),
                format!("expected 1 to {MAX_SAMPLES} samples, found {n}"),
            );
        }
    }

    fn material(&mut self, path: &KeyPath, m: &Material) {
        self.color(path.key("ambient"), m.ambient);
        self.color(path.key("diffuse"), m.diffuse);
        self.color(path.key("specular"), m.specular);
        self.color(path.key("emission"), m.emission);
        let shin = path.key("shininess");
        if self.finite(&shin, m.shininess) && m.shininess < 0.0 {
            self.error(
                &shin,
                format!("expected a number >= 0, found {}", m.shininess),
            );
        }
        let refl = path.key("reflectance");
        if self.finite(&refl, m.reflectance) && !(0.0..=1.0).contains(&m.reflectance) {
            self.error(
                &refl,
                format!("expected a number from 0 to 1, found {}", m.reflectance),
            );
        }
        if let Some(t) = &m.texture {
            self.texture(&path.key("texture"), t);
        }
        for (key, t) in [
            ("metallic_roughness_texture", &m.metallic_roughness_texture),
            ("emission_texture", &m.emission_texture),
            ("normal_texture", &m.normal_texture),
        ] {
            let Some(t) = t else { continue };
            match t {
                TextureRef::Image(_) => self.texture(&path.key(key), t),
                _ => self.error(
                    path.key(key),
                    format!("expected an image table on `{key}`: {{ image = \"file.png\" }}"),
                ),
            }
        }
        if let Some(s) = m.normal_strength {
            let key = path.key("normal_strength");
            if self.finite(&key, s) && m.normal_texture.is_none() {
                self.error(key, "expected `normal_strength` only with `normal_texture`");
            }
        }
        if m.normal_texture.is_some() && !m.is_physical() {
            self.error(
                path.key("normal_texture"),
                "expected `normal_texture` on a physically based material (one with `base_color`, `metallic`, `roughness` or `transmission`): the lab's Blinn-Phong material does not bend its normal; try base_color = [...] in place of `diffuse`",
            );
        }
        self.alpha_cutoff(path, m);
        self.transmission(path, m);
        self.physical(path, m);
    }

    /// `alpha_cutoff`: a fraction, and an image to read alpha from when
    /// the material names a texture (an object may give it one instead).
    fn alpha_cutoff(&mut self, path: &KeyPath, m: &Material) {
        let Some(cutoff) = m.alpha_cutoff else {
            return;
        };
        let key = path.key("alpha_cutoff");
        if self.finite(&key, cutoff) && !(0.0..=1.0).contains(&cutoff) {
            self.error(
                &key,
                format!("expected a number from 0 to 1, found {}", num(cutoff)),
            );
        }
        let other = match &m.texture {
            Some(TextureRef::Named(name)) => format!("the built-in `{name}`"),
            Some(TextureRef::Checker(_)) => "a checker".to_string(),
            _ => return,
        };
        self.error(
            key,
            format!("expected an image `texture` to read alpha from, found {other}, which has none; try texture = {{ image = \"leaf.png\" }}"),
        );
    }

    /// The physically based keys: fractions within 0..1, a colour, and no
    /// key of the lab's kind beside them.
    fn physical(&mut self, path: &KeyPath, m: &Material) {
        if let Some(c) = m.base_color {
            self.color(path.key("base_color"), c);
        }
        for (key, value) in [
            ("metallic", m.metallic),
            ("roughness", m.roughness),
            ("transmission", m.transmission),
        ] {
            let Some(x) = value else { continue };
            let key = path.key(key);
            if self.finite(&key, x) && !(0.0..=1.0).contains(&x) {
                self.error(
                    key,
                    format!("expected a number from 0 to 1, found {}", num(x)),
                );
            }
        }
        if let (true, Some(TextureRef::Named(name))) = (m.is_physical(), &m.texture) {
            self.error(
                path.key("texture"),
                format!("expected an image or checker texture table on a physically based material, found the lab's `{name}`, which multiplies the lab's local colour; try {{ image = \"...\" }}"),
            );
        }
        let (physical, lab) = (m.physical_keys(), m.lab_keys());
        if let (Some(first), Some(other)) = (physical.first(), lab.first()) {
            self.error(
                path.key(first),
                format!(
                    "expected one kind of material: physically based (`base_color`, `metallic`, `roughness`, `transmission`) or the lab's Blinn-Phong (`ambient`, `diffuse`, `specular`, `shininess`, `reflectance`, `transmittance`, `fresnel`, `absorption`); found `{first}` with the lab's `{other}`"
                ),
            );
        }
    }

    /// `[environment]`: an image or a colour (exactly one), its strength
    /// and turn.
    fn environment(&mut self, path: &KeyPath, e: &Environment) {
        match (&e.image, e.color) {
            (Some(_), Some(_)) => self.error(
                path.key("color"),
                "expected either `image` or `color`, found both; an environment is an image or one colour",
            ),
            (None, None) => self.error(
                path.clone(),
                "expected `image` (a latitude-longitude .hdr or .exr file) or `color`; found neither",
            ),
            (None, Some(c)) => self.color(path.key("color"), c),
            (Some(_), None) => {}
        }
        let strength = path.key("strength");
        if self.finite(&strength, e.strength) && e.strength < 0.0 {
            self.error(
                strength,
                format!("expected a number >= 0, found {}", num(e.strength)),
            );
        } else if let (Some(c), None) = (e.color, &e.image) {
            let brightest = c.into_iter().fold(0.0f32, f32::max);
            if let Some(message) =
                environment_overflow(brightest, e.strength, "its colour's largest channel")
            {
                self.error(strength, message);
            }
        }
        self.finite(path.key("rotate"), e.rotate);
    }

    /// The glass keys: `transmittance` within 0..1 and, unless `fresnel`
    /// splits the energy, adding up with `reflectance` to at most 1 (the
    /// lab's energy rule); `ior` above 0; `absorption` a colour.
    fn transmission(&mut self, path: &KeyPath, m: &Material) {
        let trans = path.key("transmittance");
        let fraction = (0.0..=1.0).contains(&m.transmittance);
        if self.finite(&trans, m.transmittance) && !fraction {
            self.error(
                &trans,
                format!("expected a number from 0 to 1, found {}", m.transmittance),
            );
        } else if fraction
            && !m.fresnel
            && (0.0..=1.0).contains(&m.reflectance)
            && m.reflectance + m.transmittance > 1.0
        {
            self.error(
                &trans,
                format!(
                    "expected `reflectance` + `transmittance` at most 1 (without `fresnel = true` they are the energies of the reflected and transmitted rays), found {} + {} = {}",
                    m.reflectance,
                    m.transmittance,
                    m.reflectance + m.transmittance
                ),
            );
        }
        let ior = path.key("ior");
        if self.finite(&ior, m.ior) && m.ior <= 0.0 {
            self.error(
                &ior,
                format!(
                    "expected an index of refraction > 0 (1 air, 1.33 water, 1.5 glass), found {}",
                    m.ior
                ),
            );
        }
        self.color(path.key("absorption"), m.absorption);
    }

    fn texture(&mut self, path: &KeyPath, t: &TextureRef) {
        match t {
            TextureRef::Named(name) => self.texture_name(path.clone(), name),
            TextureRef::Image(image) => {
                if image.image.trim().is_empty() {
                    self.error(path.key("image"), "expected the path of a PNG or JPEG file");
                }
                self.texture_scale(path.key("scale"), image.scale);
            }
            TextureRef::Checker(checker) => {
                for (i, c) in checker.checker.iter().enumerate() {
                    self.color(path.key("checker").index(i), *c);
                }
                self.texture_scale(path.key("scale"), checker.scale);
            }
        }
    }

    /// A texture's scale: finite factors, non-zero (a negative one flips
    /// the texture), their size within `SCALE_RANGE`.
    fn texture_scale(&mut self, path: KeyPath, scale: TextureScale) {
        let s = scale.per_axis();
        let (lo, hi) = SCALE_RANGE;
        if !s.iter().all(|x| x.is_finite()) {
            self.error(path, format!("expected finite numbers, found {s:?}"));
        } else if s.iter().any(|x| !(lo..=hi).contains(&x.abs())) {
            self.error(
                path,
                format!(
                    "expected factors from {lo:e} to {hi:e} (or their negatives), found [{}, {}]",
                    num(s[0]),
                    num(s[1])
                ),
            );
        }
    }

    fn texture_name(&mut self, path: impl Into<KeyPath>, name: &str) {
        if BuiltinTexture::from_name(name).is_none() {
            let known = BuiltinTexture::ALL.map(BuiltinTexture::name);
            self.error(
                path,
                format!("unknown texture `{}`; {}", shown(name), hint(name, &known)),
            );
        }
    }

    fn object(&mut self, path: &KeyPath, o: &Object, scene: &SceneFile) {
        match o.shapes().as_slice() {
            [] => self.error(
                path,
                "expected a shape: one of `sphere`, `triangle`, `mesh`, `plane`, `box`, `quad`, `gltf`; found none",
            ),
            [shape] => self.shape(path, shape),
            _ => self.error(
                path,
                "expected exactly one shape per object; found several of `sphere`, `triangle`, `mesh`, `plane`, `box`, `quad`, `gltf`",
            ),
        }
        if o.gltf.is_some() && o.texture.is_some() {
            self.error(
                path.key("texture"),
                "expected no `texture` on a `gltf` object: its materials have their own (`material` replaces them all)",
            );
        }
        if let Some(t) = &o.transform {
            self.transform(&path.key("transform"), t);
        }
        if let Some(uv) = &o.uv {
            self.triangle_uv(&path.key("uv"), uv, o.triangle.is_some());
        }
        match &o.material {
            Some(MaterialRef::Named(name))
                if !scene.materials.contains_key(name) && !self.names_elsewhere =>
            {
                let expected = if scene.materials.is_empty() {
                    "expected a name from [materials], but none are defined".to_string()
                } else if self.hints < MAX_HINTS && name.len() <= MAX_NAME_SHOWN {
                    self.hints += 1;
                    let known = self
                        .material_names
                        .get_or_insert_with(|| scene.materials.keys().cloned().collect());
                    let known: Vec<&str> = known.iter().map(String::as_str).collect();
                    hint(name, &known)
                } else {
                    // Past the diagnostics shown, a search through every
                    // name per mistake would only cost time.
                    "expected a name from [materials]".to_string()
                };
                self.error(
                    path.key("material"),
                    format!("unknown material `{}`; {expected}", shown(name)),
                );
            }
            Some(MaterialRef::Inline(m)) => self.material(&path.key("material"), m),
            _ => {}
        }
        if let Some(t) = &o.texture {
            self.texture(&path.key("texture"), t);
        }
        let material = match &o.material {
            Some(MaterialRef::Inline(m)) => Some(m),
            Some(MaterialRef::Named(name)) => scene.materials.get(name),
            None => None,
        };
        if let Some(m) = material {
            self.emissive_plane(path, o, m);
            self.cut_out_sphere_or_plane(path, o, m);
        }
    }

    /// An emissive material on a plane: a light of infinite area, which no
    /// light sampling can pick a point of.
    fn emissive_plane(&mut self, path: &KeyPath, o: &Object, m: &Material) {
        if o.plane.is_some() && m.is_emissive() {
            self.error(
                path.key("material"),
                "expected a material without `emission` on a plane: an infinite plane cannot be sampled as a light; use a `quad` (or a `box`) of the size you need",
            );
        }
    }

    /// `alpha_cutoff` on a sphere or a plane: the searches cut triangles
    /// only, and it would be silently ignored.
    fn cut_out_sphere_or_plane(&mut self, path: &KeyPath, o: &Object, m: &Material) {
        let shape = match (&o.sphere, &o.plane) {
            (Some(_), _) => "a sphere",
            (_, Some(_)) => "a plane",
            _ => return,
        };
        if m.alpha_cutoff.is_some() {
            self.error(
                path.key("material"),
                format!("expected a material without `alpha_cutoff` on {shape}: alpha masks cut triangles only; cut out a `quad`, `box`, `triangle`, `mesh` or `gltf` model"),
            );
        }
    }

    fn transform(&mut self, path: &KeyPath, t: &Transform) {
        match t {
            Transform::Table(t) => {
                self.point(path.key("translate"), t.translate);
                self.finite_vec(path.key("rotate"), t.rotate);
                self.scale(&path.key("scale"), t.scale);
            }
            Transform::Steps(steps) => {
                for (k, step) in steps.iter().enumerate() {
                    let path = path.index(k);
                    match *step {
                        TransformStep::Translate(v) => _ = self.point(path.key("translate"), v),
                        TransformStep::Rotate(v) => _ = self.finite_vec(path.key("rotate"), v),
                        TransformStep::Scale(s) => self.scale(&path.key("scale"), s),
                    }
                }
            }
        }
    }

    /// A transform's scale: finite, non-zero, within `SCALE_RANGE` (on a
    /// sphere, uneven factors make an ellipsoid).
    fn scale(&mut self, path: &KeyPath, scale: Scale) {
        let s = scale.per_axis();
        let (lo, hi) = SCALE_RANGE;
        if !self.finite_vec(path, s) {
            return;
        }
        if s.contains(&0.0) {
            self.error(path, format!("expected non-zero factors, found {s:?}"));
        } else if s.iter().any(|x| !(lo..=hi).contains(&x.abs())) {
            self.error(
                path,
                format!(
                    "expected factors from {lo:e} to {hi:e} (or their negatives), found {}; single-precision tracing would flatten or overflow the shape",
                    show(s)
                ),
            );
        }
    }

    /// Exactly one file, `obj` or `ply`, with a path.
    fn mesh(&mut self, path: &KeyPath, m: &Mesh) {
        match (&m.obj, &m.ply) {
            (None, None) => self.error(
                path,
                "expected a mesh file: `obj = \"file.obj\"` or `ply = \"file.ply\"`; found neither",
            ),
            (Some(_), Some(_)) => self.error(
                path.key("ply"),
                "expected one mesh file, `obj` or `ply`; found both",
            ),
            (Some(file), None) if file.trim().is_empty() => {
                self.error(path.key("obj"), "expected the path of an OBJ file")
            }
            (None, Some(file)) if file.trim().is_empty() => {
                self.error(path.key("ply"), "expected the path of a PLY file")
            }
            _ => {}
        }
    }

    /// A triangle's `uv`: finite, and only on a triangle.
    fn triangle_uv(&mut self, path: &KeyPath, uv: &[Uv; 3], on_triangle: bool) {
        if !on_triangle {
            self.error(
                path,
                "expected `uv` only on a `triangle` object (a mesh's come from its file; other shapes have their own)",
            );
        } else if let Some(k) = uv.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
            let [u, v] = uv[k];
            self.error(
                path.index(k),
                format!("expected finite numbers, found [{u}, {v}]"),
            );
        }
    }

    /// A light's kind by its keys: `position` (a point, or with
    /// `direction` a spot and its `cone`) or `direction` alone (a
    /// directional light).
    fn light_kind(&mut self, path: &KeyPath, light: &crate::Light) {
        if let Some(p) = light.position {
            self.point(path.key("position"), p);
        }
        if let Some(d) = light.direction {
            let key = path.key("direction");
            if self.point(&key, d) && length(d) == 0.0 {
                self.error(
                    key,
                    format!("expected a non-zero vector, found {}", show(d)),
                );
            }
        }
        match (light.position, light.direction) {
            (None, None) => self.error(
                path.key("position"),
                format!(
                    "missing key `position` in `{path}`: a point or spot light needs it (a directional light has `direction` and no `position`)"
                ),
            ),
            (None, Some(_)) if light.radius != 0.0 => self.error(
                path.key("radius"),
                "expected no `radius` on a directional light (`direction` without `position`): it has no place to be a sphere at",
            ),
            (Some(_), Some(_)) if light.radius != 0.0 => self.error(
                path.key("radius"),
                "expected no `radius` on a spot light (`position` and `direction`); a sphere light shines every way",
            ),
            _ => {}
        }
        let Some(cone) = light.cone else { return };
        let key = path.key("cone");
        if light.position.is_none() || light.direction.is_none() {
            self.error(
                &key,
                "expected `cone` only on a spot light, which has both `position` and `direction`",
            );
        } else if !(cone.iter().all(|x| x.is_finite())
            && 0.0 <= cone[0]
            && cone[0] <= cone[1]
            && cone[1] <= 90.0)
        {
            self.error(
                key,
                format!(
                    "expected [inner, outer] degrees with 0 <= inner <= outer <= 90, found [{}, {}]",
                    num(cone[0]),
                    num(cone[1])
                ),
            );
        }
    }

    /// A light's radius: 0 (a point) or a sphere's, whose radiance in path
    /// mode, its color over pi r^2, a float must hold (else it would light
    /// nothing, silently).
    fn light_radius(&mut self, path: &KeyPath, light: &crate::Light) {
        let r = light.radius;
        self.length(path.key("radius"), r, "a radius");
        if !(r > 0.0 && r.is_finite()) {
            return;
        }
        if r < MIN_RADIUS {
            self.error(
                path.key("radius"),
                format!(
                    "expected 0 (a point light) or a radius from {MIN_RADIUS:e}, found {}; single-precision tracing cannot handle a smaller sphere",
                    num(r)
                ),
            );
            return;
        }
        let brightest = light.color.into_iter().fold(0.0f32, f32::max);
        let radiance = brightest / (std::f32::consts::PI * r * r);
        if !radiance.is_finite() {
            self.error(
                path.key("color"),
                format!(
                    "expected a color that a sphere of radius {} can give off: as a sphere light its radiance, color / (pi radius^2), is {brightest:e} / {:e}, more than single precision holds",
                    num(r),
                    std::f32::consts::PI * r * r
                ),
            );
        }
    }

    fn shape(&mut self, path: &KeyPath, shape: &ShapeRef) {
        match shape {
            ShapeRef::Mesh(m) => self.mesh(&path.key("mesh"), m),
            ShapeRef::Gltf(g) => {
                if g.file.trim().is_empty() {
                    self.error(
                        path.key("gltf").key("file"),
                        "expected the path of a .gltf or .glb file",
                    );
                }
            }
            ShapeRef::Sphere(s) => {
                self.point(path.key("sphere").key("center"), s.center);
                let r = path.key("sphere").key("radius");
                if !self.finite(&r, s.radius) {
                    return;
                }
                if s.radius <= 0.0 {
                    self.error(
                        &r,
                        format!(
                            "expected a radius from {MIN_RADIUS:e} to {MAX_COORDINATE:e}, found {}",
                            num(s.radius)
                        ),
                    );
                } else if !(MIN_RADIUS..=MAX_COORDINATE).contains(&s.radius) {
                    self.error(
                        &r,
                        format!(
                            "expected a radius from {MIN_RADIUS:e} to {MAX_COORDINATE:e}, found {}; single-precision tracing cannot handle it",
                            num(s.radius)
                        ),
                    );
                }
            }
            ShapeRef::Plane(plane) => {
                let p = path.key("plane");
                self.point(p.key("point"), plane.point);
                // Bounded like a point, so its length neither overflows
                // nor (when non-zero here) normalises to NaN.
                if self.point(p.key("normal"), plane.normal) && length(plane.normal) == 0.0 {
                    self.error(
                        p.key("normal"),
                        format!(
                            "expected a non-zero vector, found {}; a plane needs the side it faces",
                            show(plane.normal)
                        ),
                    );
                }
            }
            ShapeRef::Box(b) => {
                let p = path.key("box");
                let ok = self.point(p.key("min"), b.min) & self.point(p.key("max"), b.max);
                if ok && (0..3).any(|a| b.min[a] >= b.max[a]) {
                    self.error(
                        p.key("max"),
                        format!(
                            "expected `max` above `min` on every axis, found min {} and max {}; the box would be flat or inside out",
                            show(b.min),
                            show(b.max)
                        ),
                    );
                }
            }
            ShapeRef::Quad(q) => self.quad(&path.key("quad"), q),
            ShapeRef::Triangle(t) => {
                let p = path.key("triangle");
                if t.iter().all(|v| self.point(&p, *v)) {
                    let n = cross(sub(t[1], t[0]), sub(t[2], t[0]));
                    if length(n) == 0.0 {
                        self.error(
                            &p,
                            format!(
                                "expected three vertices not on one line, found {}, {}, {}; the triangle is degenerate (zero area)",
                                show(t[0]),
                                show(t[1]),
                                show(t[2])
                            ),
                        );
                    }
                }
            }
        }
    }
}

impl Validator {
    /// A quad: its corner and edges within `MAX_COORDINATE`, each edge
    /// non-zero, the two not parallel, and every corner it reaches within
    /// `MAX_COORDINATE` too (they become triangle vertices).
    fn quad(&mut self, p: &KeyPath, q: &Quad) {
        let ok = self.point(p.key("corner"), q.corner)
            & self.point(p.key("edge_u"), q.edge_u)
            & self.point(p.key("edge_v"), q.edge_v);
        if !ok {
            return;
        }
        for (key, edge) in [("edge_u", q.edge_u), ("edge_v", q.edge_v)] {
            if length(edge) == 0.0 {
                self.error(
                    p.key(key),
                    format!("expected a non-zero edge, found {}", show(edge)),
                );
                return;
            }
        }
        if length(cross(q.edge_u, q.edge_v)) == 0.0 {
            // Parallel, or so short that the area underflows single precision.
            let message = if parallel(q.edge_u, q.edge_v) {
                format!(
                    "expected an edge not parallel to `edge_u` ({}), found {}; the quad is degenerate (zero area)",
                    show(q.edge_u),
                    show(q.edge_v)
                )
            } else {
                format!(
                    "expected longer edges: with `edge_u` {} and this one, {}, the quad's area is too small for single precision (it rounds to 0)",
                    show(q.edge_u),
                    show(q.edge_v)
                )
            };
            self.error(p.key("edge_v"), message);
            return;
        }
        let far = add(add(q.corner, q.edge_u), q.edge_v);
        for corner in [add(q.corner, q.edge_u), add(q.corner, q.edge_v), far] {
            if corner.iter().any(|x| x.abs() > MAX_COORDINATE) {
                self.error(
                    p.clone(),
                    format!(
                        "expected corners with coordinates from -{MAX_COORDINATE:e} to {MAX_COORDINATE:e}, found {}; single-precision tracing cannot handle larger ones",
                        show(corner)
                    ),
                );
                return;
            }
        }
    }
}

fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// A vector as it is written in a scene file: `[0, 1.5, -2]`.
fn show(v: Vec3) -> String {
    format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]))
}

/// A number as a person writes it: `1e19` rather than twenty digits.
fn num(x: f32) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e7).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The longest name a message quotes whole, in bytes: a file of one 30 MB
/// name wrote 30 MB of message.
const MAX_NAME_SHOWN: usize = 64;

/// `name` as a message quotes it: whole, or its start and its length.
fn shown(name: &str) -> String {
    if name.len() <= MAX_NAME_SHOWN {
        return name.to_string();
    }
    let start: String = name.chars().take(40).collect();
    format!("{start}... ({} bytes)", name.len())
}

/// Why an environment whose brightest radiance is `brightest` times
/// `strength` cannot be rendered: past the largest float every path that
/// sees it would be infinite, and left out (a black image). None if it can.
pub(crate) fn environment_overflow(brightest: f32, strength: f32, what: &str) -> Option<String> {
    (brightest * strength).is_infinite().then(|| {
        format!(
            "expected a strength that leaves the light finite: {what}, {brightest:e}, times {}, is more than single precision holds",
            num(strength)
        )
    })
}

/// Whether `a` and `b` are parallel to within 1e-6 radians, in f64: any
/// finite single-precision vectors (an `up` of 1e20 or of 1e-25) are
/// compared without overflow or underflow.
fn parallel(a: Vec3, b: Vec3) -> bool {
    let [a, b] = [a, b].map(|v| v.map(f64::from));
    let cross = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    let length = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    length(cross) <= 1e-6 * length(a) * length(b)
}

fn length(v: Vec3) -> f32 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Why a number reads as infinite: the file may say `inf`, or a number
/// too large for the tracer's 32-bit floats (`1e39`), which becomes inf.
fn beyond_f32(infinite: bool) -> &'static str {
    if infinite {
        " (`inf`, or a number beyond 3.4e38, the largest the tracer's 32-bit numbers hold)"
    } else {
        ""
    }
}

#[cfg(test)]
mod tests {
    use crate::{load_str, Format};
    use std::path::Path;

    /// The first error of a camera looking down -z with `up`, if any.
    fn up_error(up: &str) -> Option<String> {
        let text = format!("[camera]\neye = [0, 0, 4]\nlook_at = [0, 0, 0]\nup = {up}\n");
        let error = load_str(&text, Format::Toml, Path::new("up.toml")).err()?;
        Some(error.diagnostics()[0].message.clone())
    }

    #[test]
    fn an_up_of_any_finite_size_is_judged_by_its_direction_alone() {
        // Far above or below 1, where an f32 cross product overflows or
        // underflows: across the view, fine; along it, parallel.
        for size in ["1e20", "3e38", "1e-25", "1e-44"] {
            assert_eq!(up_error(&format!("[0, {size}, 0]")), None, "{size}");
            let along = up_error(&format!("[0, 0, {size}]")).expect("refused");
            assert!(
                along.contains("not parallel to the view"),
                "{size}: {along}"
            );
        }
        let zero = up_error("[0, 0, 0]").expect("refused");
        assert!(zero.contains("expected a non-zero vector"), "{zero}");
    }

    /// The first error of a scene with one light of `light` (TOML keys).
    fn light_error(light: &str) -> Option<(String, String)> {
        let text = format!(
            "[camera]\neye = [0, 0, 4]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [0, 2, 0]\n{light}\n"
        );
        let error = load_str(&text, Format::Toml, Path::new("l.toml")).err()?;
        let d = &error.diagnostics()[0];
        Some((d.path.to_string(), d.message.clone()))
    }

    #[test]
    fn a_sphere_light_too_small_or_too_bright_for_a_float_is_refused() {
        for fine in [
            "radius = 0",
            "radius = 1e-4",
            "radius = 0.5\ncolor = [1e30, 1, 1]",
        ] {
            assert_eq!(light_error(fine), None, "{fine}");
        }
        // Its radiance, 1 / (pi 1e-40), would be infinite: black, silently.
        let (key, message) = light_error("radius = 1e-20").expect("refused");
        assert_eq!(key, "lights[0].radius");
        assert!(
            message.contains("expected 0 (a point light) or a radius from 1e-4"),
            "{message}"
        );
        let (key, message) = light_error("radius = 1e-4\ncolor = [1e32, 1, 1]").expect("refused");
        assert_eq!(key, "lights[0].color");
        assert!(
            message.contains("more than single precision holds"),
            "{message}"
        );
    }

    #[test]
    fn an_environment_brighter_than_a_float_is_refused_at_its_strength() {
        let text = |color: &str, strength: &str| {
            format!(
                "[camera]\neye = [0, 0, 4]\nlook_at = [0, 0, 0]\n[environment]\ncolor = {color}\nstrength = {strength}\n"
            )
        };
        let load = |t: &str| load_str(t, Format::Toml, Path::new("e.toml"));
        assert!(load(&text("[3e38, 1, 1]", "1")).is_ok());
        // Every path that sees it would be infinite, and left out: black.
        let error = load(&text("[3e38, 1, 1]", "10")).expect_err("refused");
        let d = &error.diagnostics()[0];
        assert_eq!(d.path.to_string(), "environment.strength");
        assert!(
            d.message.contains("more than single precision holds"),
            "{}",
            d.message
        );
    }

    #[test]
    fn a_quad_of_no_area_says_whether_its_edges_are_parallel_or_too_short() {
        let quad = |u: &str, v: &str| {
            let text = format!(
                "[camera]\neye = [0, 0, 4]\nlook_at = [0, 0, 0]\n[[objects]]\nquad = {{ corner = [0, 0, 0], edge_u = {u}, edge_v = {v} }}\n"
            );
            let error = load_str(&text, Format::Toml, Path::new("q.toml")).expect_err("refused");
            error.diagnostics()[0].message.clone()
        };
        let parallel = quad("[1, 0, 0]", "[2, 0, 0]");
        assert!(parallel.contains("not parallel to `edge_u`"), "{parallel}");
        let tiny = quad("[1e-19, 0, 0]", "[0, 0, 1e-19]");
        assert!(tiny.contains("expected longer edges"), "{tiny}");
    }

    #[test]
    fn a_long_unknown_name_is_quoted_by_its_start() {
        let name = "h".repeat(100_000);
        let text = format!(
            "[camera]\neye = [0, 0, 4]\nlook_at = [0, 0, 0]\n[materials.red]\ndiffuse = [1, 0, 0]\n[[objects]]\nsphere = {{ center = [0, 0, 0], radius = 1 }}\nmaterial = \"{name}\"\n"
        );
        let error = load_str(&text, Format::Toml, Path::new("m.toml")).expect_err("refused");
        let message = &error.diagnostics()[0].message;
        assert!(message.len() < 200, "{} bytes", message.len());
        assert!(message.contains("... (100000 bytes)"), "{message}");
    }
}
