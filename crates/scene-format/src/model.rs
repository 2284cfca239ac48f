//! The serde types of a 3D scene file. These names and this nesting are the
//! contract with users (the scene files they have written, `schema.json`,
//! the book's reference of keys): extend, never rename.

use schemars::JsonSchema;
use serde::{Deserialize, Deserializer, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;

pub type Vec3 = [f32; 3];
pub type Color = [f32; 3];
/// Texture coordinates (u, v).
pub type Uv = [f32; 2];

/// Examples the schema gives keys that no scene of `scenes/` uses (the
/// book's reference shows them). Constants, as schemars' attribute takes a
/// path but not an array.
const EXAMPLE_INCLUDE: [&str; 1] = ["lib/materials.toml"];
const EXAMPLE_SKY: Color = [0.5, 0.6, 0.8];
const EXAMPLE_UV: [Uv; 3] = [[0.0, 0.0], [1.0, 0.0], [0.5, 1.0]];

/// A 3D scene: a camera, lights, materials and objects.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Where the scene is seen from, and the image's size.
    pub camera: Camera,
    /// How rays are traced and the image encoded; every key has a default
    /// (the lab's values).
    #[serde(default)]
    pub render: RenderSettings,
    /// The lights; ambient is added once per light. Default: none (a
    /// black image, with a warning).
    #[serde(default)]
    pub lights: Vec<Light>,
    /// Materials by name, for objects to name in their `material`.
    /// Default: none.
    #[serde(default)]
    pub materials: BTreeMap<String, Material>,
    /// The objects, each with exactly one shape key. Default: none.
    #[serde(default)]
    pub objects: Vec<Object>,
    /// Light arriving from every direction around the scene, from far away:
    /// a latitude-longitude HDR image or one colour. In path mode it is a
    /// light; in Whitted mode it is what a ray that leaves the scene sees.
    /// Default: none (`[render] background` instead).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub environment: Option<Box<Environment>>,
    /// Files whose materials, lights and objects join the scene's (before
    /// its own, in list order), each a path relative to this file, TOML or
    /// JSON by its extension. An included file holds only `materials`,
    /// `lights`, `objects` and `include`; material names are shared, so a
    /// name may be defined once. Default: none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[schemars(example = EXAMPLE_INCLUDE)]
    pub include: Vec<String>,
    /// The JSON Schema an editor checks a JSON scene against (TOML scenes
    /// use a `#:schema` comment instead). The tracer ignores it.
    #[serde(rename = "$schema", default, skip_serializing_if = "Option::is_none")]
    #[schemars(example = "./schema.json")]
    pub schema: Option<String>,
}

/// The light around the scene: exactly one of `image` and `color`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Environment {
    /// A latitude-longitude (equirectangular) image of linear radiance, a
    /// Radiance `.hdr` or an OpenEXR `.exr` file, relative to the scene
    /// file's folder: its top row is straight up (+y), its middle row the
    /// horizon, and its centre column looks along -z (turned by `rotate`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image: Option<String>,
    /// One radiance (linear, channels >= 0) from every direction: a uniform
    /// sky.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(inner(range(min = 0)))]
    #[schemars(example = EXAMPLE_SKY)]
    pub color: Option<Color>,
    /// What the radiance is multiplied by (>= 0). Default 1.
    #[serde(default = "one")]
    #[schemars(range(min = 0))]
    pub strength: f32,
    /// Degrees the image is turned about the up axis (+y), counter-clockwise
    /// seen from above. Default 0.
    #[serde(default)]
    pub rotate: f32,
    /// The image's texels, read at load time (not part of the file format).
    #[serde(skip)]
    #[schemars(skip)]
    pub data: Option<Arc<ImageData>>,
}

fn one() -> f32 {
    1.0
}

/// A pinhole camera (or a thin lens with `aperture`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    /// Where the camera is; coordinates from -1e6 to 1e6.
    pub eye: Vec3,
    /// The point the camera looks at; not `eye`.
    pub look_at: Vec3,
    /// Which way is up in the image; not zero, not parallel to
    /// `look_at - eye`. Default [0, 1, 0].
    #[serde(default = "default_up")]
    pub up: Vec3,
    /// Horizontal field of view in degrees, at least 1 and below 180.
    /// Default 50.
    #[serde(default = "default_fov")]
    #[schemars(extend("minimum" = 1, "exclusiveMaximum" = 180))]
    pub fov: f32,
    /// Image width in pixels, 1 to 16384. Default 500.
    #[serde(default = "default_width")]
    #[schemars(range(min = 1, max = 16384))]
    pub width: u32,
    /// Image height in pixels, 1 to 16384. Default 400.
    #[serde(default = "default_height")]
    #[schemars(range(min = 1, max = 16384))]
    pub height: u32,
    /// Which way world +x runs in the image: "lab" (to the left, as the
    /// lab) or "right" (to the right, as other renderers and modellers).
    /// Default "lab".
    #[serde(default)]
    pub handedness: Handedness,
    /// Lens radius for depth of field; 0 is the lab's pinhole (all sharp).
    /// Default 0.
    #[serde(default)]
    #[schemars(range(min = 0))]
    pub aperture: f32,
    /// Distance from the eye to the plane in focus, along the view
    /// direction; left out, the distance from `eye` to `look_at`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0))]
    pub focus_distance: Option<f32>,
    /// "perspective" (rays from the eye, `fov` wide) or "orthographic"
    /// (parallel rays along the view direction, from a plane through the
    /// eye `view_width` wide; `fov` and `aperture` are not used). Default
    /// "perspective".
    #[serde(default, skip_serializing_if = "Projection::is_perspective")]
    pub projection: Projection,
    /// An orthographic camera's view: how many scene units the image
    /// spans across (the height follows the image's shape). Only with
    /// `projection = "orthographic"`, which needs it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0))]
    pub view_width: Option<f32>,
}

/// How a camera's rays leave it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Projection {
    /// Rays from the eye through the image (a pinhole, or a thin lens).
    #[default]
    Perspective,
    /// Parallel rays along the view direction.
    Orthographic,
}

impl Projection {
    fn is_perspective(&self) -> bool {
        *self == Projection::Perspective
    }
}

/// Which way world +x runs in the image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Handedness {
    /// The lab's camera: +x to the image's left (a mirror image of what
    /// other renderers show).
    #[default]
    Lab,
    /// +x to the image's right, +y up: models look as in other renderers.
    Right,
}

fn default_up() -> Vec3 {
    [0.0, 1.0, 0.0]
}
fn default_fov() -> f32 {
    50.0
}
fn default_width() -> u32 {
    500
}
fn default_height() -> u32 {
    400
}

/// What to do with a pixel whose linear colour has a channel above 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Saturation {
    /// The lab's rule: the whole pixel becomes white.
    #[default]
    White,
    /// Each channel is clamped to 1 on its own.
    Clamp,
}

/// How rays are traced and the image encoded; every key left out takes
/// the lab's value (or, for `max_depth` and `saturation`, the path
/// tracer's own default in path mode).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct RenderSettings {
    /// How light is computed: "whitted" (the lab's `rayTrace`: local
    /// Blinn-Phong, shadows, mirrors, glass) or "path" (path tracing:
    /// the global model of light, where objects light each other and
    /// emissive materials are area lights). Default "whitted".
    pub integrator: Integrator,
    /// With "whitted", the lab's MAX_RAY_TREE: how many mirror bounces (and
    /// glass crossings) a ray may take. With "path", the longest path, as
    /// pbrt-v4's `maxdepth`: 0 shows only emitters seen directly, 1 adds
    /// direct light, each more one bounce of indirect light (Mitsuba 3's
    /// `max_depth` is this + 1, Blender Cycles' `max_bounces` this - 1).
    /// At most 64. Default 1 with "whitted", 7 with "path".
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(max = 64))]
    pub max_depth: Option<u32>,
    /// The lab's MIN_RAY_ENERGY: no bounce once the energy falls to this.
    /// Whitted only. Default 0.01.
    #[schemars(range(min = 0), extend("x-integrator" = "whitted"))]
    pub min_energy: f32,
    /// The colour of rays that leave the scene (linear, channels >= 0).
    /// With "path" it is a uniform sky that also lights the scene (found by
    /// the paths' bounces, not sampled as a light). Default [0, 0, 0].
    #[schemars(inner(range(min = 0)))]
    pub background: Color,
    /// A pixel with a channel above 1: "white" (the lab's rule: the whole
    /// pixel white) or "clamp" (each channel to 1 on its own). Default
    /// "white" with "whitted", "clamp" with "path" (light sources and their
    /// highlights are far above 1 there).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub saturation: Option<Saturation>,
    /// Display gamma; 1.0 writes linear values. Default 2.2.
    #[schemars(extend("exclusiveMinimum" = 0))]
    pub gamma: f32,
    /// Samples per pixel: 1 is one ray through the pixel's centre (the
    /// lab); more are stratified and jittered over the pixel (anti-aliasing).
    /// With "path", the paths per pixel (their mean over the image where
    /// sampling is `adaptive`). From 1 to 4096 with "whitted", to 65536
    /// with "path". Default 1.
    #[schemars(range(min = 1, max = 65536))]
    pub samples: u32,
    /// Shadow rays per light of `radius` > 0 at each shaded point. Whitted
    /// only: the path tracer samples a sphere light as an emitter, one
    /// point per bounce. Default 16.
    #[schemars(range(min = 1, max = 4096), extend("x-integrator" = "whitted"))]
    pub light_samples: u32,
    /// Path mode: render in passes of doubling samples per pixel (1, 2, 4,
    /// ...) and stop after the last pass that fits in this many seconds
    /// (`tracer render --time-limit` overrides it). Left out: every sample.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0, "x-integrator" = "path"), example = 10)]
    pub time_limit: Option<f32>,
    /// Path mode: how many neighbouring pixels of a row share the light
    /// their paths find beyond the first bounce (path reuse). Where a
    /// pixel's first surface is Lambertian, it connects to the second
    /// vertex of each path of its group by a shadow ray: as many samples
    /// of its indirect light as the group has pixels, unbiased, for one
    /// ray each. 1 shares nothing. Left out, path mode decides: 8, where it
    /// takes noise off for its time (a room lit by its lamps, the caustics
    /// of rough metal), but 1 in a scene of glass under an environment,
    /// where it costs time for little, or where the image is denoised.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(
        range(min = 1, max = crate::validate::MAX_PATH_REUSE),
        extend("x-integrator" = "path", "x-default" = "8 unless denoised or glass under an environment, else 1"),
        example = 8
    )]
    pub path_reuse: Option<u32>,
    /// Path mode: camera rays per path for the light a pixel sees
    /// directly (an emitter, the sky), in the pixels where that light
    /// changes across the pixel (the edge of a lamp): their corners and
    /// centre are looked at first. Each path's own camera ray is replaced
    /// by this many, stratified together over the pixel's samples, for
    /// what it sees directly; unbiased. Other pixels cost nothing more
    /// than that first look. 1 is the path's own ray. Left out, path mode
    /// decides: 16 where the image is denoised (the denoiser is not given
    /// what they see); else 8 in a scene without an environment that has
    /// emitting surfaces, and 1 otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(
        range(min = 1, max = crate::validate::MAX_CAMERA_RAYS),
        extend("x-integrator" = "path", "x-default" = "8 with emitters, no environment and no denoising, else 1"),
        example = 8
    )]
    pub camera_rays: Option<u32>,
    /// Path mode: adaptive sampling. After a pilot of 8 paths in every
    /// pixel, each block of 8 x 4 pixels takes paths in proportion to the
    /// noise of the blocks around it (over the cost of their paths), so
    /// `samples` becomes the image's mean paths per pixel: noisy glass and
    /// shadows get more, a flat sky fewer. Unbiased: a block's share never
    /// reads its own paths. Left out, path mode decides: on in a scene lit
    /// by an environment, or by emitting surfaces that some material other
    /// than a plain diffuse one (metal, plastic, glass, a highlight or a
    /// mirror) throws about, unless it is denoised; else off.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(
        extend("x-integrator" = "path", "x-default" = "true under an environment, or with emitters and a material that is not plain diffuse, unless denoised; else false"),
        example = true
    )]
    pub adaptive: Option<bool>,
    /// Path mode: clean the final image with Intel Open Image Denoise
    /// (`tracer render --denoise`), guided by the albedo and normal of
    /// what each pixel sees; the library is installed by `cargo xtask
    /// oidn`. Default false.
    #[schemars(extend("x-integrator" = "path"), example = true)]
    pub denoise: bool,
    /// The denoiser's quality, as Open Image Denoise names them: "fast",
    /// "balanced" or "high" (`--denoise-quality` overrides it). Default
    /// "high".
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("x-integrator" = "path", "default" = "high"), example = &"fast")]
    pub denoise_quality: Option<DenoiseQuality>,
    /// What the denoiser does with its guides, as Blender names it:
    /// "accurate" cleans the albedo and normal first, "fast" tells the
    /// filter they are noisy and cleans them with the image, "none" takes
    /// them as clean (`--denoise-prefilter` overrides it). Default
    /// "accurate".
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(extend("x-integrator" = "path", "default" = "accurate"), example = &"fast")]
    pub denoise_prefilter: Option<DenoisePrefilter>,
}

/// Open Image Denoise's filter quality.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum DenoiseQuality {
    /// For previews.
    Fast,
    /// Between the two.
    Balanced,
    /// For final images.
    #[default]
    High,
}

impl DenoiseQuality {
    pub const ALL: [DenoiseQuality; 3] = [
        DenoiseQuality::Fast,
        DenoiseQuality::Balanced,
        DenoiseQuality::High,
    ];

    pub fn name(self) -> &'static str {
        match self {
            DenoiseQuality::Fast => "fast",
            DenoiseQuality::Balanced => "balanced",
            DenoiseQuality::High => "high",
        }
    }
}

/// What the denoiser does with its guides (the albedo and the normal),
/// as Blender's "Prefilter" names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum DenoisePrefilter {
    /// Taken as clean: one network, the fastest.
    None,
    /// Cleaned with the image, by its own network: blurrier.
    Fast,
    /// Cleaned first, each by a network of its own: the sharpest.
    #[default]
    Accurate,
}

impl DenoisePrefilter {
    pub const ALL: [DenoisePrefilter; 3] = [
        DenoisePrefilter::None,
        DenoisePrefilter::Fast,
        DenoisePrefilter::Accurate,
    ];

    pub fn name(self) -> &'static str {
        match self {
            DenoisePrefilter::None => "none",
            DenoisePrefilter::Fast => "fast",
            DenoisePrefilter::Accurate => "accurate",
        }
    }
}

/// Which way light is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Integrator {
    /// The lab's `rayTrace` (Whitted-style): local light, shadows, mirrors
    /// and glass.
    #[default]
    Whitted,
    /// Unidirectional path tracing with next-event estimation and multiple
    /// importance sampling: objects light each other.
    Path,
}

impl Integrator {
    pub fn name(self) -> &'static str {
        match self {
            Integrator::Whitted => "whitted",
            Integrator::Path => "path",
        }
    }
}

/// `render.max_depth` left out: the lab's MAX_RAY_TREE.
pub const WHITTED_MAX_DEPTH: u32 = 1;
/// `render.max_depth` left out in path mode: Mitsuba 3's default
/// (`max_depth = 8`, which counts one more).
pub const PATH_MAX_DEPTH: u32 = 7;

impl RenderSettings {
    /// `max_depth`, or the integrator's default when left out.
    pub fn max_depth(&self) -> u32 {
        self.max_depth.unwrap_or(match self.integrator {
            Integrator::Whitted => WHITTED_MAX_DEPTH,
            Integrator::Path => PATH_MAX_DEPTH,
        })
    }

    /// `saturation`, or the integrator's default when left out.
    pub fn saturation(&self) -> Saturation {
        self.saturation.unwrap_or(match self.integrator {
            Integrator::Whitted => Saturation::White,
            Integrator::Path => Saturation::Clamp,
        })
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            integrator: Integrator::Whitted,
            max_depth: None,
            min_energy: 0.01,
            background: [0.0, 0.0, 0.0],
            saturation: None,
            gamma: 2.2,
            samples: 1,
            light_samples: 16,
            time_limit: None,
            path_reuse: None,
            camera_rays: None,
            adaptive: None,
            denoise: false,
            denoise_quality: None,
            denoise_prefilter: None,
        }
    }
}

/// A light: a point (`position`), a sphere with `radius`, a spot
/// (`position` and `direction`, with `cone`) or a directional light
/// (`direction` alone). In path mode a point or spot light's `color` is
/// its intensity (its light falls off with the square of the distance: 1
/// gives an irradiance of 1 at distance 1, facing it; glTF's candela),
/// and a sphere light is a sphere that emits, of the same total light.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Light {
    /// Where the light is (a sphere light's centre); coordinates from -1e6
    /// to 1e6. Left out, the light is directional (a sun: `direction`
    /// alone).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<Vec3>,
    /// Where the light shines: with `position`, a spot light's axis (its
    /// cone is `cone`); without, a directional light's direction of
    /// travel, from infinitely far away, its `color` the irradiance it
    /// gives a surface facing it (glTF's lux). Any non-zero length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<Vec3>,
    /// A spot light's cone: [inner, outer] angles in degrees from its
    /// axis, 0 <= inner <= outer <= 90; full strength inside `inner`,
    /// fading to none at `outer` as glTF's `KHR_lights_punctual` fades it.
    /// Only with `position` and `direction`. Default [0, 45].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cone: Option<[f32; 2]>,
    /// The light's colour and strength (linear, channels >= 0); it scales
    /// diffuse, specular and ambient alike. Default [1, 1, 1], white.
    #[serde(default = "white")]
    #[schemars(inner(range(min = 0)))]
    pub color: Color,
    /// 0 is the lab's point light; above 0 a sphere light of this radius
    /// (from 1e-4 to 1e6), which casts soft shadows. Default 0.
    #[serde(default)]
    #[schemars(range(min = 0))]
    pub radius: f32,
}

fn white() -> Color {
    [1.0, 1.0, 1.0]
}

/// A material of one of two kinds. The lab's Blinn-Phong material:
/// `ambient`, `diffuse`, `specular`, `shininess`, `reflectance`,
/// `transmittance`, `fresnel`, `absorption`; every key left out is 0
/// (black, no reflection, opaque). Or a physically based one (the names of
/// glTF 2.0 and Blender's Principled BSDF): `base_color`, `metallic`,
/// `roughness`, `transmission`, and the textures
/// `metallic_roughness_texture` and `normal_texture` (Whitted mode reads
/// `metallic` and `roughness` without their texture). Both kinds take
/// `ior` (1.5 when left out), `emission`, `emission_texture` and
/// `texture`; keys of both kinds in one material are an error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Material {
    /// Colour added once per light whatever the light's direction, never
    /// shadowed (linear, channels from 0 to 1); path mode ignores it (it
    /// computes the light that bounces). Default [0, 0, 0].
    #[schemars(inner(range(min = 0)), extend("x-integrator" = "whitted"))]
    pub ambient: Color,
    /// Lambert colour: times the cosine between the normal and the light
    /// (linear, channels from 0 to 1). Default [0, 0, 0].
    #[schemars(inner(range(min = 0)))]
    pub diffuse: Color,
    /// Blinn-Phong highlight colour (linear, channels from 0 to 1).
    /// Default [0, 0, 0].
    #[schemars(inner(range(min = 0)))]
    pub specular: Color,
    /// The Blinn-Phong exponent: higher is a smaller, sharper highlight.
    /// Default 0.
    #[schemars(range(min = 0))]
    pub shininess: f32,
    /// 0 = no mirror reflection, 1 = perfect mirror. Default 0.
    #[schemars(range(min = 0, max = 1))]
    pub reflectance: f32,
    /// Light the surface gives off (linear radiance, channels >= 0, on the
    /// side its normal faces): every object with this material is an area
    /// light in path mode, and shows this colour in Whitted mode (seen and
    /// mirrored, lighting nothing). Not on a `plane`: an infinite emitter
    /// cannot be sampled (use a `quad`). Default [0, 0, 0].
    #[schemars(inner(range(min = 0)))]
    pub emission: Color,
    /// A built-in texture's name ("lab-stripes": multiplies the whole
    /// local colour, as the lab), or a table: an image
    /// (`{ image = "wood.png" }`) or a checkerboard
    /// (`{ checker = [[1, 1, 1], [0, 0, 0]] }`), whose colour multiplies
    /// `ambient` and `diffuse` only. Default: none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub texture: Option<TextureRef>,
    /// Cuts the surface out where the alpha of its image `texture` (the
    /// material's, or the object's own) is below this, as glTF's
    /// `alphaMode` MASK does: there every ray (from the camera, mirrored,
    /// bounced, toward a light) passes as if nothing were there, so a leaf
    /// drawn on a quad casts a leaf's shadow. From 0 to 1; 0.5 keeps the
    /// texels at least half opaque. Cuts triangles only (quads, boxes,
    /// meshes, glTF models): on a sphere or a plane it is an error.
    /// Default: none, the surface is whole.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0, max = 1))]
    pub alpha_cutoff: Option<f32>,
    /// 0 = opaque, 1 = all the light passes (refracted by `ior`). Default 0.
    #[schemars(range(min = 0, max = 1))]
    pub transmittance: f32,
    /// Index of refraction of the inside: 1.5 glass, 1.33 water, 1 air.
    /// Default 1.5.
    #[schemars(extend("exclusiveMinimum" = 0))]
    pub ior: f32,
    /// Split reflection and transmission by the Fresnel equations instead
    /// of `reflectance` and `transmittance` as given. Default false.
    pub fresnel: bool,
    /// Light absorbed per unit length travelled inside (Beer-Lambert),
    /// per channel: [0, 0.5, 1] tints toward red. Default [0, 0, 0].
    #[schemars(inner(range(min = 0)))]
    pub absorption: Color,
    /// Physically based: the colour (linear, channels from 0 to 1) of a
    /// dielectric's diffuse base, or a metal's reflection at normal
    /// incidence (Schlick's approximation); a texture table multiplies it.
    /// Default [0.8, 0.8, 0.8].
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(inner(range(min = 0, max = 1)))]
    pub base_color: Option<Color>,
    /// Physically based: 0 a dielectric (plastic, paint, glass), 1 a metal;
    /// between, a mix of the two. Default 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0, max = 1))]
    pub metallic: Option<f32>,
    /// Physically based: 0 a smooth mirror-like surface, 1 a very rough
    /// one (GGX microfacets of alpha = roughness^2). Default 0.5.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0, max = 1))]
    pub roughness: Option<f32>,
    /// Physically based: 0 opaque, 1 a dielectric that lets light through
    /// (glass, smooth or frosted by `roughness`), tinted by `base_color`.
    /// Default 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0, max = 1))]
    pub transmission: Option<f32>,
    /// Physically based: an image whose blue channel multiplies
    /// `metallic` and green channel `roughness` at each point (glTF's
    /// packing; its values are linear, not sRGB): `{ image = "mr.png" }`.
    /// Default: none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub metallic_roughness_texture: Option<TextureRef>,
    /// An image (sRGB colours) that multiplies `emission` at each point,
    /// on either kind of material: what Whitted mode shows, and in path
    /// mode the light given off there (a light sample's point reads it as
    /// a path that meets the surface does). No `emission`, no light: it
    /// multiplies nothing. `{ image = "glow.png" }`. Default: none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub emission_texture: Option<TextureRef>,
    /// A tangent-space normal map (linear values; red along the texture's
    /// u, green along v, blue out of the surface, as glTF's and
    /// Blender's): it bends the shading normal at each point, on a
    /// physically based material only (the lab's keeps its normal: an
    /// error). A mesh's tangents come from its file, or are made by
    /// MikkTSpace. Default: none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normal_texture: Option<TextureRef>,
    /// How far `normal_texture` bends the normal: its x and y are scaled
    /// by this (glTF's `normalTexture.scale`). Default 1.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normal_strength: Option<f32>,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            ambient: [0.0; 3],
            diffuse: [0.0; 3],
            specular: [0.0; 3],
            shininess: 0.0,
            reflectance: 0.0,
            texture: None,
            alpha_cutoff: None,
            transmittance: 0.0,
            ior: DEFAULT_IOR,
            fresnel: false,
            absorption: [0.0; 3],
            emission: [0.0; 3],
            base_color: None,
            metallic: None,
            roughness: None,
            transmission: None,
            metallic_roughness_texture: None,
            emission_texture: None,
            normal_texture: None,
            normal_strength: None,
        }
    }
}

/// The physically based material's defaults.
pub const DEFAULT_BASE_COLOR: Color = [0.8, 0.8, 0.8];
pub const DEFAULT_ROUGHNESS: f32 = 0.5;

impl Material {
    /// Whether the material gives off light.
    pub fn is_emissive(&self) -> bool {
        self.emission.iter().any(|&c| c > 0.0)
    }

    /// The physically based keys it has, by name.
    pub fn physical_keys(&self) -> Vec<&'static str> {
        [
            ("base_color", self.base_color.is_some()),
            ("metallic", self.metallic.is_some()),
            ("roughness", self.roughness.is_some()),
            ("transmission", self.transmission.is_some()),
            (
                "metallic_roughness_texture",
                self.metallic_roughness_texture.is_some(),
            ),
        ]
        .into_iter()
        .filter_map(|(key, set)| set.then_some(key))
        .collect()
    }

    /// Whether it is the physically based kind.
    pub fn is_physical(&self) -> bool {
        !self.physical_keys().is_empty()
    }

    /// The lab's keys it sets to other than their defaults, by name.
    pub fn lab_keys(&self) -> Vec<&'static str> {
        [
            ("ambient", self.ambient != [0.0; 3]),
            ("diffuse", self.diffuse != [0.0; 3]),
            ("specular", self.specular != [0.0; 3]),
            ("shininess", self.shininess != 0.0),
            ("reflectance", self.reflectance != 0.0),
            ("transmittance", self.transmittance != 0.0),
            ("fresnel", self.fresnel),
            ("absorption", self.absorption != [0.0; 3]),
        ]
        .into_iter()
        .filter_map(|(key, set)| set.then_some(key))
        .collect()
    }
}

/// Crown glass's index of refraction.
pub const DEFAULT_IOR: f32 = 1.5;

/// A material given by name (a key of `[materials]`) or inline.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
// Parsed once per object, never in a render's loop: the inline material's
// size costs nothing worth a box (and every match on it).
#[allow(clippy::large_enum_variant)]
pub enum MaterialRef {
    Named(String),
    Inline(Material),
}

/// By hand rather than `untagged`: serde's untagged enums hide the inner
/// error ("did not match any variant"); this keeps a misspelt key inside
/// an inline material reported as such, with its path.
impl<'de> Deserialize<'de> for MaterialRef {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = MaterialRef;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a material name (a string) or an inline material table")
            }
            fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<MaterialRef, E> {
                Ok(MaterialRef::Named(name.to_string()))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<MaterialRef, A::Error> {
                let de = serde::de::value::MapAccessDeserializer::new(map);
                Material::deserialize(de).map(MaterialRef::Inline)
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// One object: exactly one shape key (`sphere`, `triangle`, `mesh`,
/// `plane`, `box`, `quad`, `gltf`) and its material.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Object {
    /// A sphere: `{ center = [x, y, z], radius = r }`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sphere: Option<Sphere>,
    /// Three vertices, clockwise as seen from the front (the lab's order).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub triangle: Option<[Vec3; 3]>,
    /// Texture coordinates [u, v] of a `triangle`'s three vertices, in its
    /// vertex order; only with `triangle`. Left out, a triangle's uv are its
    /// barycentrics: [[0, 0], [1, 0], [0, 1]].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(example = EXAMPLE_UV)]
    pub uv: Option<[Uv; 3]>,
    /// A triangle mesh read from a Wavefront OBJ or a PLY file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mesh: Option<Mesh>,
    /// An infinite plane.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<Plane>,
    /// An axis-aligned box, closed (glass works on it).
    #[serde(default, skip_serializing_if = "Option::is_none", rename = "box")]
    pub box_: Option<BoxShape>,
    /// A parallelogram: `corner + s * edge_u + t * edge_v`, s and t in 0..1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quad: Option<Quad>,
    /// A glTF 2.0 model: `{ file = "model.glb" }` (or a .gltf file with
    /// its .bin files and images beside it), its meshes, materials and
    /// lights placed by its nodes, then by this object's `transform`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gltf: Option<Gltf>,
    /// Where the shape goes: a list of steps `[{ translate = [..] },
    /// { rotate = [..] }, { scale = .. }]` (the lab's matrix product: the
    /// last step acts first), or the table `{ translate, rotate, scale }`
    /// (scale, then rotate, then translate). A sphere scaled unevenly is an
    /// ellipsoid. Left out: the shape as written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform: Option<Transform>,
    /// A material's name (a key of `materials`) or an inline material
    /// table. Left out: matte grey (or a mesh's own MTL materials).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<MaterialRef>,
    /// A texture on this object (a name or a table, as a material's);
    /// overrides the material's. Default: the material's texture, if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<TextureRef>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Sphere {
    /// The centre; coordinates from -1e6 to 1e6.
    pub center: Vec3,
    /// From 1e-4 (the lab's epsilon) to 1e6: what single-precision tracing handles.
    #[schemars(extend("minimum" = 1e-4, "maximum" = 1e6))]
    pub radius: f32,
}

/// An infinite plane; its uv are coordinates in the plane (unit scale)
/// from `point`, along world x projected into it (y when the plane faces
/// nearly along x) and along `normal` x that.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Plane {
    /// A point of the plane; coordinates from -1e6 to 1e6.
    pub point: Vec3,
    /// The side the plane faces (the one it is lit from); any non-zero length.
    pub normal: Vec3,
}

/// An axis-aligned box from `min` to `max`, normals outward; each face has
/// uv from 0 to 1.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct BoxShape {
    /// The corner of the smallest coordinates; coordinates from -1e6 to 1e6.
    pub min: Vec3,
    /// The opposite corner: above `min` on every axis.
    pub max: Vec3,
}

/// A parallelogram `corner + s * edge_u + t * edge_v` (s, t from 0 to 1),
/// with uv = (s, t); it faces `edge_u x edge_v`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Quad {
    /// The corner where s = t = 0; coordinates from -1e6 to 1e6.
    pub corner: Vec3,
    /// Where s runs: non-zero, not parallel to `edge_v`.
    pub edge_u: Vec3,
    /// Where t runs: non-zero, not parallel to `edge_u`.
    pub edge_v: Vec3,
}

/// A mesh from a file: exactly one of `obj` and `ply`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Mesh {
    /// A Wavefront OBJ file, relative to the scene file's folder.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub obj: Option<String>,
    /// A PLY file (ASCII or binary, as scanners write them), relative to the
    /// scene file's folder; faces of more than 3 vertices become fans.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(example = "scans/bunny.ply")]
    pub ply: Option<String>,
    /// Shading normals. Left out: the file's vertex normals (OBJ `vn`, PLY
    /// `nx ny nz`) where it has them, flat elsewhere. true: vertex normals,
    /// made from the faces (area-weighted) where the file has none. false:
    /// flat, every triangle shaded with its own normal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub smooth: Option<bool>,
    /// The triangles of the file, filled in by `load_path`; not part of the file.
    #[serde(skip)]
    #[schemars(skip)]
    pub data: Option<Arc<MeshData>>,
}

/// The kinds of mesh file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    Obj,
    Ply,
}

impl MeshFormat {
    /// The key that names a file of this kind in `mesh`.
    pub fn key(self) -> &'static str {
        match self {
            MeshFormat::Obj => "obj",
            MeshFormat::Ply => "ply",
        }
    }
}

impl Mesh {
    /// The file and its kind, when exactly one of `obj` and `ply` is given.
    pub fn file(&self) -> Option<(MeshFormat, &str)> {
        match (&self.obj, &self.ply) {
            (Some(path), None) => Some((MeshFormat::Obj, path)),
            (None, Some(path)) => Some((MeshFormat::Ply, path)),
            _ => None,
        }
    }

    /// The file's path as written (the first given), or "" for none.
    pub fn path(&self) -> &str {
        self.obj.as_deref().or(self.ply.as_deref()).unwrap_or("")
    }

    /// The key of the file (`obj` or `ply`; `obj` when neither is given).
    pub fn key(&self) -> &'static str {
        self.file().map_or("obj", |(format, _)| format.key())
    }
}

/// The triangles read from a mesh file, in the file's vertex order, with
/// what the file says of their corners.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshData {
    pub triangles: Vec<[Vec3; 3]>,
    /// The file's vertex index of each corner (counted from 0 over the whole
    /// file), so corners that share a vertex are known: parallel to `triangles`.
    pub indices: Vec<[u32; 3]>,
    /// The file's normals at each corner (not normalised), where the face has
    /// them; empty when no face has any, else parallel to `triangles`.
    pub normals: Vec<Option<[Vec3; 3]>>,
    /// The file's texture coordinates at each corner, where the face has
    /// them; empty when no face has any, else parallel to `triangles`.
    pub uvs: Vec<Option<[Uv; 3]>>,
    /// Tangents at each corner (x, y, z along the texture's u, w = +-1 the
    /// handedness: bitangent = w (normal x tangent)), where the face has
    /// them (a glTF file's, or made for its normal texture); empty when no
    /// face has any, else parallel to `triangles`.
    pub tangents: Vec<Option<[[f32; 4]; 3]>>,
    /// Faces of zero area, left out.
    pub skipped_degenerate: usize,
    /// Faces that repeat an earlier face, left out (`repeated_faces`).
    pub skipped_repeated: usize,
    /// The file's line (OBJ) of the first face left out, when a scan found it.
    pub first_degenerate_line: Option<usize>,
    /// Faces of more than 3 corners fanned though they may not be convex
    /// (degenerate, self-intersecting: see `polygon`).
    pub polygon_troubles: usize,
    /// Where the first is (`line 7` of an OBJ, `face 3` of a PLY) and what
    /// it is.
    pub first_polygon_trouble: Option<(String, &'static str)>,
    /// The materials of the OBJ's MTL files (`mtllib`), as scene materials
    /// (Kd diffuse, Ka ambient, Ks specular, Ns shininess, map_Kd an image
    /// texture, 1 - d or Tr transmittance, Ni ior).
    pub materials: Vec<Material>,
    /// Each triangle's index in `materials` (its face's `usemtl`), in the
    /// order of `triangles`; `None` for a face without a material known.
    /// Empty when the OBJ has no materials.
    pub triangle_materials: Vec<Option<u32>>,
    /// What went wrong with the MTL files (missing, unreadable, bad values,
    /// a missing map_Kd): warnings for the objects that use them.
    pub material_warnings: Vec<String>,
}

impl MeshData {
    /// The material index of triangle `i` (`None`: the default grey).
    pub fn triangle_material(&self, i: usize) -> Option<u32> {
        self.triangle_materials.get(i).copied().flatten()
    }
}

/// An object's transform: a list of steps, or the table shorthand.
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
pub enum Transform {
    /// `[A, B, C]` is the lab's `M = A * B * C`: C acts on a point first.
    Steps(Vec<TransformStep>),
    /// Scale, then rotate, then translate: `[translate, rotate, scale]`.
    Table(TransformTable),
}

impl Transform {
    /// The steps in the list's order (the table's as `[translate, rotate,
    /// scale]`), the last acting first.
    pub fn steps(&self) -> Vec<TransformStep> {
        match self {
            Transform::Steps(steps) => steps.clone(),
            Transform::Table(t) => vec![
                TransformStep::Translate(t.translate),
                TransformStep::Rotate(t.rotate),
                TransformStep::Scale(t.scale),
            ],
        }
    }
}

impl From<TransformTable> for Transform {
    fn from(t: TransformTable) -> Transform {
        Transform::Table(t)
    }
}

/// By hand rather than `untagged`, as `MaterialRef`: a mistake inside
/// either form is reported as such, with its path.
impl<'de> Deserialize<'de> for Transform {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = Transform;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "a list of steps like [{ translate = [x, y, z] }, { rotate = [x, y, z] }, { scale = s }], \
                     or a table { translate, rotate, scale }",
                )
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                seq: A,
            ) -> Result<Transform, A::Error> {
                let de = serde::de::value::SeqAccessDeserializer::new(seq);
                Vec::deserialize(de).map(Transform::Steps)
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<Transform, A::Error> {
                let de = serde::de::value::MapAccessDeserializer::new(map);
                TransformTable::deserialize(de).map(Transform::Table)
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// One step of a transform list.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum TransformStep {
    /// Move by [x, y, z].
    Translate(Vec3),
    /// Degrees about the x axis, then y, then z.
    Rotate(Vec3),
    /// One factor for all axes, or one per axis; each non-zero, its size
    /// from 1e-6 to 1e6.
    Scale(Scale),
}

/// The table form of a transform: scale, then rotate, then translate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct TransformTable {
    /// Move by [x, y, z], last. Default [0, 0, 0].
    pub translate: Vec3,
    /// Degrees about the x axis, then y, then z. Default [0, 0, 0].
    pub rotate: Vec3,
    /// One factor for all axes, or one per axis; each non-zero, its size
    /// from 1e-6 to 1e6. Default 1.
    pub scale: Scale,
}

impl Default for TransformTable {
    fn default() -> Self {
        TransformTable {
            translate: [0.0; 3],
            rotate: [0.0; 3],
            scale: Scale::Uniform(1.0),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(
    untagged,
    expecting = "a number (one factor for all axes) or [x, y, z] (one per axis)"
)]
pub enum Scale {
    Uniform(f32),
    PerAxis(Vec3),
}

impl Scale {
    pub fn per_axis(self) -> Vec3 {
        match self {
            Scale::Uniform(s) => [s; 3],
            Scale::PerAxis(v) => v,
        }
    }
}

/// The object's shape, once validation has made sure there is exactly one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ShapeRef<'a> {
    Sphere(&'a Sphere),
    Triangle(&'a [Vec3; 3]),
    Mesh(&'a Mesh),
    Plane(&'a Plane),
    Box(&'a BoxShape),
    Quad(&'a Quad),
    Gltf(&'a Gltf),
}

/// A glTF model as an object's shape: the file, and which part of it.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Gltf {
    /// The .gltf or .glb file, relative to the scene file's folder.
    pub file: String,
    /// Which of the file's scenes: its index (from 0) or its name.
    /// Default: the file's own `scene`, else its first.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<GltfPick>,
    /// Only this node and the nodes under it (its index or its name),
    /// placed where its parents place it. Default: every node of the scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub node: Option<GltfPick>,
    /// What the file holds, filled in by `load_path`; not part of the file.
    #[serde(skip)]
    #[schemars(skip)]
    pub data: Option<Arc<crate::gltf::GltfData>>,
}

/// A scene or node of a glTF file: its index or its name.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged, expecting = "an index (a whole number from 0) or a name")]
pub enum GltfPick {
    Index(usize),
    Name(String),
}

impl Object {
    /// All shape keys that are set, in declaration order.
    pub fn shapes(&self) -> Vec<ShapeRef<'_>> {
        let mut shapes = Vec::new();
        if let Some(s) = &self.sphere {
            shapes.push(ShapeRef::Sphere(s));
        }
        if let Some(t) = &self.triangle {
            shapes.push(ShapeRef::Triangle(t));
        }
        if let Some(m) = &self.mesh {
            shapes.push(ShapeRef::Mesh(m));
        }
        if let Some(p) = &self.plane {
            shapes.push(ShapeRef::Plane(p));
        }
        if let Some(b) = &self.box_ {
            shapes.push(ShapeRef::Box(b));
        }
        if let Some(q) = &self.quad {
            shapes.push(ShapeRef::Quad(q));
        }
        if let Some(g) = &self.gltf {
            shapes.push(ShapeRef::Gltf(g));
        }
        shapes
    }
}

/// The textures built into the tracer, as scene files name them
/// (`texture = "lab-stripes"`): the one list of them. A new one goes into
/// the enum and `ALL`; the core's `prepare` then fails to compile until it
/// maps the new variant to an image (an exhaustive match).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BuiltinTexture {
    LabStripes,
}

impl BuiltinTexture {
    pub const ALL: [BuiltinTexture; 1] = [BuiltinTexture::LabStripes];

    pub fn name(self) -> &'static str {
        match self {
            BuiltinTexture::LabStripes => "lab-stripes",
        }
    }

    /// The built-in texture called `name`, if there is one.
    pub fn from_name(name: &str) -> Option<BuiltinTexture> {
        Self::ALL.into_iter().find(|t| t.name() == name)
    }
}

/// A texture: a built-in one by name, or a table (an image or a checkerboard).
#[derive(Debug, Clone, PartialEq, Serialize, JsonSchema)]
#[serde(untagged)]
pub enum TextureRef {
    /// A built-in texture: "lab-stripes".
    Named(String),
    Image(ImageTexture),
    Checker(CheckerTexture),
}

/// An image read from a PNG or JPEG file, sRGB-encoded (decoded to linear
/// colours), sampled bilinearly; u runs left to right across the image and
/// v from its bottom row up (as OBJ texture coordinates do).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ImageTexture {
    /// The image file (PNG or JPEG), relative to the scene file's folder.
    pub image: String,
    /// Repeats across the surface's uv: the image is sampled at
    /// (u * sx, v * sy), so [4, 4] repeats it 4 times each way. One number
    /// for both. Default 1 ([1, 1]).
    #[serde(default)]
    pub scale: TextureScale,
    /// What lies beyond the image's 0..1: "repeat" (default) tiles it,
    /// "clamp" extends its edge texels, "mirror" tiles it flipping every
    /// other copy. Default "repeat".
    #[serde(default)]
    pub wrap: Wrap,
    /// A different wrap along v (the image's height) than along u
    /// (`wrap`). Default: `wrap`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wrap_v: Option<Wrap>,
    /// Degrees the texture is turned counter-clockwise in uv, after
    /// `scale`. Default 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rotate: f32,
    /// Added to uv last, after `scale` and `rotate`: [du, dv]. Default
    /// [0, 0].
    #[serde(default, skip_serializing_if = "is_origin")]
    pub offset: Uv,
    /// The image's texels, filled in by `load_path`; not part of the file.
    #[serde(skip)]
    #[schemars(skip)]
    pub data: Option<Arc<ImageData>>,
}

fn is_zero(x: &f32) -> bool {
    *x == 0.0
}

fn is_origin(uv: &Uv) -> bool {
    *uv == [0.0; 2]
}

/// A checkerboard in the surface's uv: squares 1 / scale wide, starting
/// with the first colour at uv (0, 0).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckerTexture {
    /// The two colours (linear, like material colours).
    #[schemars(inner(inner(range(min = 0))))]
    pub checker: [Color; 2],
    /// Squares per unit of uv: 4 gives squares 0.25 wide; one number for
    /// both directions or [su, sv]. Default 1.
    #[serde(default)]
    pub scale: TextureScale,
}

/// A texture's scale: one factor for u and v, or [su, sv].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(
    untagged,
    expecting = "a number (one factor for u and v) or [su, sv] (one each)"
)]
pub enum TextureScale {
    Uniform(f32),
    PerAxis([f32; 2]),
}

impl Default for TextureScale {
    fn default() -> Self {
        TextureScale::Uniform(1.0)
    }
}

impl TextureScale {
    pub fn per_axis(self) -> [f32; 2] {
        match self {
            TextureScale::Uniform(s) => [s; 2],
            TextureScale::PerAxis(v) => v,
        }
    }
}

/// How an image texture is read outside its 0..1 square.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Wrap {
    /// Tiles the image.
    #[default]
    Repeat,
    /// Extends the edge texels.
    Clamp,
    /// Tiles the image, every other copy flipped, so edges meet seamlessly.
    Mirror,
}

/// An image's texels as stored in its file: sRGB-encoded values from 0 to
/// 1, row by row from the top row; and its alpha, if it has some.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageData {
    pub width: u32,
    pub height: u32,
    pub texels: Texels,
    /// Each texel's alpha (coverage, linear: 0 none, 255 whole), row by
    /// row from the top; None for an image without an alpha channel or
    /// whose alpha is 255 everywhere. A 16-bit alpha is kept to 8 bits:
    /// `alpha_cutoff` compares it with a cutoff, which needs no finer step.
    pub alpha: Option<Arc<Vec<u8>>>,
}

/// Texels as their file holds them: an 8-bit image's bytes (v / 255 each,
/// a quarter of the memory of floats; shared with the tracer, which reads
/// them as they are), or floats (16-bit and HDR images).
#[derive(Debug, Clone, PartialEq)]
pub enum Texels {
    Bytes(Arc<Vec<[u8; 3]>>),
    Floats(Vec<[f32; 3]>),
}

impl Texels {
    pub fn len(&self) -> usize {
        match self {
            Texels::Bytes(t) => t.len(),
            Texels::Floats(t) => t.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Texel `i` as values from 0 to 1 (a byte's v / 255, as the image
    /// crate reads it).
    pub fn at(&self, i: usize) -> [f32; 3] {
        match self {
            Texels::Bytes(t) => t[i].map(|v| f32::from(v) / 255.0),
            Texels::Floats(t) => t[i],
        }
    }

    /// Every texel as floats (a copy for bytes).
    pub fn to_floats(&self) -> std::borrow::Cow<'_, [[f32; 3]]> {
        match self {
            Texels::Bytes(_) => (0..self.len()).map(|i| self.at(i)).collect(),
            Texels::Floats(t) => std::borrow::Cow::Borrowed(t),
        }
    }
}

/// The keys of a texture table, read before it is known which kind it is.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TextureTable {
    image: Option<String>,
    checker: Option<[Color; 2]>,
    scale: Option<TextureScale>,
    wrap: Option<Wrap>,
    wrap_v: Option<Wrap>,
    rotate: Option<f32>,
    offset: Option<Uv>,
}

/// By hand, as `MaterialRef`: a misspelt key or a wrong type inside the
/// table is reported as such, at its key.
impl<'de> Deserialize<'de> for TextureRef {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = TextureRef;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a texture name (a string) or a texture table (`image` or `checker`)")
            }
            fn visit_str<E: serde::de::Error>(self, name: &str) -> Result<TextureRef, E> {
                Ok(TextureRef::Named(name.to_string()))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                map: A,
            ) -> Result<TextureRef, A::Error> {
                let de = serde::de::value::MapAccessDeserializer::new(map);
                let table = TextureTable::deserialize(de)?;
                table.into_texture().map_err(serde::de::Error::custom)
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

impl TextureTable {
    fn into_texture(self) -> Result<TextureRef, &'static str> {
        let scale = self.scale.unwrap_or_default();
        match (self.image, self.checker) {
            (Some(image), None) => Ok(TextureRef::Image(ImageTexture {
                image,
                scale,
                wrap: self.wrap.unwrap_or_default(),
                wrap_v: self.wrap_v,
                rotate: self.rotate.unwrap_or(0.0),
                offset: self.offset.unwrap_or([0.0; 2]),
                data: None,
            })),
            (None, Some(_))
                if self.wrap_v.is_some() || self.rotate.is_some() || self.offset.is_some() =>
            {
                Err("expected `wrap_v`, `rotate` and `offset` only with `image`")
            }
            (None, Some(checker)) if self.wrap.is_none() => {
                Ok(TextureRef::Checker(CheckerTexture { checker, scale }))
            }
            (None, Some(_)) => Err("expected `wrap` only with `image`; a checkerboard has no edge"),
            (Some(_), Some(_)) => {
                Err("expected one of `image` or `checker` in a texture table, found both")
            }
            (None, None) => Err("expected `image` or `checker` in a texture table, found neither"),
        }
    }
}
