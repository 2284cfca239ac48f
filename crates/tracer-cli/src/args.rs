//! The command line as clap parses it (`*Args`), and resolved once, before
//! any work (ripgrep's `HiArgs`): the gamma checked, the thread pool built.
//! Every command then reads the resolved form only.

use clap::{Args, Subcommand, ValueEnum};
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use tracer_pipeline::lab::DEFAULT_CHART_SIZE;
use tracer_pipeline::output::BitDepth;
use tracer_pipeline::{Aov, Gamma, Input, Options, Part, Region};

/// Render a scene file to an image: PNG, JPEG, OpenEXR or Radiance HDR.
#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (.toml or .json, or a .zip archive made by `tracer
    /// pack`). Without one, the lab's final scene (table 1.10, reflectance2)
    /// is rendered.
    pub scene: Option<PathBuf>,
    /// Output image, its format by its extension: .png, .jpg/.jpeg (8-bit,
    /// gamma-encoded), .exr, .hdr (linear floats, no gamma, no saturation
    /// rule) [default: the scene's file name with .png, in the current folder]
    #[arg(short, long, value_name = "OUT.png")]
    pub output: Option<PathBuf>,
    /// Bits per channel of a PNG output: 16 keeps the gamma-encoded values
    /// at 16-bit precision (truncated, as the 8-bit ones)
    #[arg(long, value_name = "BITS", default_value = "8")]
    pub bit_depth: BitDepthArg,
    /// Display gamma for encoding, overriding the scene's `[render] gamma`
    /// (1 writes linear values)
    #[arg(long, value_name = "G", allow_negative_numbers = true)]
    pub gamma: Option<f32>,
    /// Write one quantity per pixel instead of the shaded colour (linear,
    /// unless --gamma is given). No integrator shades it, so it cannot be
    /// given with --integrator; a scene's own integrator is not used
    #[arg(long, value_name = "NAME", conflicts_with = "integrator")]
    pub aov: Option<AovArg>,
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub denoise: DenoiseArgs,
    /// With --denoise, to an .exr output: keep what went into the denoiser
    /// in the same file, as Blender's "Denoising Data" pass does. The
    /// denoised image is the file's default layer (R, G, B: what viewers
    /// show); the layers `noisy` (the render before denoising), `albedo`
    /// and `normal` (-1 to 1; the guides, as --aov albedo and
    /// shading-normal give them) and `emission` (the light seen directly,
    /// left out of what was filtered and added back) are beside it
    #[arg(long, conflicts_with_all = ["aov", "region", "tile"])]
    pub denoising_data: bool,
    /// Render only the pixels X0..X1 by Y0..Y1 (ends exclusive); to an .exr
    /// output a tile for `tracer merge`
    #[arg(long, value_name = "X0,Y0,X1,Y1", value_parser = parse_region, conflicts_with = "tile")]
    pub region: Option<Region>,
    /// Render only tile I of N (0-based): bands of near-equal row counts,
    /// top to bottom; to an .exr output a tile for `tracer merge`
    #[arg(long, value_name = "I/N", value_parser = parse_tile)]
    pub tile: Option<(u32, u32)>,
    /// Do nothing when the output already is this tile (same scene digest,
    /// same region): for schedulers that retry tasks
    #[arg(long)]
    pub skip_existing: bool,
    /// Keep the prepared scene (meshes read, BVH built) in DIR, and read it
    /// from there in later renders of the same scene and options instead of
    /// preparing it again: for a farm's tasks, each rendering a tile of one
    /// scene. An entry is used only while every file of the scene is
    /// unchanged; nothing in DIR is deleted. Not with --aov; a scene with
    /// instances is rendered but not kept (a warning).
    #[arg(long, value_name = "DIR", conflicts_with = "aov")]
    pub cache: Option<PathBuf>,
    /// Path mode: render in passes of doubling samples per pixel and stop
    /// after the last pass that fits in SECONDS (overrides the scene's
    /// `[render] time_limit`); says how many samples it took
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds, conflicts_with_all = ["region", "tile", "aov"])]
    pub time_limit: Option<f64>,
    /// Path mode: print after each pass of doubling samples the error
    /// (RMSE of the linear values) against this image of the same size
    /// (.exr or .hdr), as pbrt's --mse-reference-image does
    #[arg(long, value_name = "REF.exr", conflicts_with_all = ["region", "tile", "aov"])]
    pub reference: Option<PathBuf>,
    /// Print no progress bar and no summary, only warnings and errors
    #[arg(short, long)]
    pub quiet: bool,
}

fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err("expected a number of seconds > 0".to_string()),
    }
}

fn parse_region(s: &str) -> Result<Region, String> {
    let n: Vec<u32> = s
        .split(',')
        .map(|v| v.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .map_err(|_| "expected X0,Y0,X1,Y1: four whole numbers of pixels".to_string())?;
    match n[..] {
        [x0, y0, x1, y1] => Ok(Region { x0, y0, x1, y1 }),
        _ => Err("expected X0,Y0,X1,Y1: four whole numbers of pixels".to_string()),
    }
}

fn parse_tile(s: &str) -> Result<(u32, u32), String> {
    let bad = || "expected I/N: tile I of N, 0 <= I < N".to_string();
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let (i, n): (u32, u32) = (i.parse().map_err(|_| bad())?, n.parse().map_err(|_| bad())?);
    if i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

/// Explain one pixel: why it has its colour, in the lab's numbers and
/// order: the primary ray (from the projection matrix, lab 1.2.3), each
/// object tested along it, the nearest hit, each light's ambient, diffuse
/// and specular terms and its shadow ray, the mirror and refracted rays,
/// then the saturation rule, gamma and the 8-bit value, which is the
/// rendered pixel's. In path mode: one sample's path, its light and BSDF
/// samples and their MIS weights
///
/// X counts columns from the left and Y rows from the top of the written
/// image: (0, 0) is its top-left pixel, as image viewers count.
#[derive(Args)]
pub struct ExplainArgs {
    /// Scene file (.toml or .json, or a .zip archive made by `tracer pack`)
    pub scene: PathBuf,
    /// The pixel's column, from 0 at the image's left
    pub x: u32,
    /// The pixel's row, from 0 at the image's top
    pub y: u32,
    /// Which of the pixel's samples to trace (0 is the first; in path mode
    /// the pixel is the mean of all of its samples)
    #[arg(long, value_name = "K", default_value_t = 0)]
    pub sample: u32,
    /// Print the tree as JSON instead: its structure is in the book
    /// (docs/src/reference/explain-json.md), its `version` raised when a
    /// field changes meaning
    #[arg(long)]
    pub json: bool,
    /// Also write the render with the pixel's ray tree drawn over it (its
    /// hits ringed, shadow rays dashed red where blocked, the lights
    /// marked) and a legend below, for a report or an exercise sheet
    #[arg(long, value_name = "OUT.png")]
    pub draw: Option<PathBuf>,
    /// Keep at most N events of the tree (rays, lights' terms, a path's
    /// events); beyond, the tree says what it left out. A tree of glass
    /// under hundreds of lights has millions
    #[arg(long, value_name = "N", default_value_t = tracer_pipeline::explain::DEFAULT_MAX_EVENTS,
          value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=100_000_000))]
    pub max_events: usize,
    /// Show only the terms of lights[K] (its index in `[[lights]]`) at each
    /// hit, in Whitted mode
    #[arg(long, value_name = "K")]
    pub light: Option<usize>,
    /// Display gamma, overriding the scene's `[render] gamma`
    #[arg(long, value_name = "G", allow_negative_numbers = true)]
    pub gamma: Option<f32>,
    #[command(flatten)]
    pub view: ViewArgs,
}

/// `tracer explain`, resolved.
pub struct Explain {
    pub input: Input,
    pub x: u32,
    pub y: u32,
    pub sample: u32,
    pub json: bool,
    /// Where to write the render with the ray tree drawn over it.
    pub draw: Option<PathBuf>,
    /// What of the tree is kept.
    pub limits: tracer_pipeline::explain::Limits,
    pub options: Options,
}

impl ExplainArgs {
    pub fn resolve(self) -> anyhow::Result<Explain> {
        Ok(Explain {
            input: Input::File(self.scene),
            x: self.x,
            y: self.y,
            sample: self.sample,
            json: self.json,
            draw: self.draw,
            limits: tracer_pipeline::explain::Limits {
                max_events: self.max_events,
                light: self.light,
                ..Default::default()
            },
            options: Options {
                gamma: checked(self.gamma)?,
                ..self.view.options()
            },
        })
    }
}

/// Merge render-farm tiles (.exr files of `tracer render --tile` or
/// `--region`) into the whole image; they must come from one scene and
/// options and cover the image exactly once.
#[derive(Args)]
pub struct MergeArgs {
    /// The tiles (.exr)
    #[arg(required = true, value_name = "TILE")]
    pub tiles: Vec<PathBuf>,
    /// The whole image, its format by its extension (.png, .jpg, .exr, .hdr)
    #[arg(short, long, value_name = "OUT.png")]
    pub output: PathBuf,
    /// Bits per channel of a PNG output
    #[arg(long, value_name = "BITS", default_value = "8")]
    pub bit_depth: BitDepthArg,
    /// Denoise the merged image with Intel Open Image Denoise, guided by
    /// the albedo, normal and emission the tiles carry (tiles rendered with
    /// --denoise, which are denoised when merged even without this)
    #[arg(long)]
    pub denoise: bool,
    /// The denoiser's quality, overriding the one the tiles were rendered
    /// for
    #[arg(long, value_name = "QUALITY")]
    pub denoise_quality: Option<QualityArg>,
    /// What the denoiser does with its guides, overriding the prefilter
    /// the tiles were rendered for
    #[arg(long, value_name = "PREFILTER")]
    pub denoise_prefilter: Option<PrefilterArg>,
}

/// What `render` and `watch` share: how many samples, how large, on how
/// many threads.
#[derive(Args)]
pub struct ViewArgs {
    /// Samples per pixel, overriding the scene's `[render] samples`: 1 is one
    /// ray through each pixel's centre (the lab); more smooth the edges
    /// (anti-aliasing) and the blur of depth of field. In path mode, the
    /// paths per pixel (their mean over the image where sampling is
    /// adaptive: `[render] adaptive`). At most 4096, or 65536 in path mode
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub samples: Option<u32>,
    /// How light is computed, overriding the scene's `[render]
    /// integrator`: "whitted" (the lab's rayTrace: local light, shadows,
    /// mirrors, glass) or "path" (path tracing: objects light each other,
    /// emissive materials are area lights)
    #[arg(long, value_name = "NAME")]
    pub integrator: Option<IntegratorArg>,
    /// Image width in pixels, overriding the camera's: the same view at
    /// another resolution (alone, the height follows to keep the shape)
    #[arg(long, value_name = "PIXELS", value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: Option<u32>,
    /// Image height in pixels, overriding the camera's (alone, the width
    /// follows)
    #[arg(long, value_name = "PIXELS", value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: Option<u32>,
    /// Threads to render with [default: one per core]
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
}

impl ViewArgs {
    /// The render options these give (no gamma, no AOV).
    fn options(&self) -> Options {
        Options {
            gamma: None,
            aov: None,
            samples: self.samples,
            integrator: self.integrator.map(Into::into),
            width: self.width,
            height: self.height,
            part: None,
            // Set from the output's format once it is known.
            raw_depth: false,
            pixel_shift: None,
            denoise: false,
            denoise_quality: None,
            denoise_prefilter: None,
        }
    }
}

/// Denoising, in `tracer render` and `tracer watch`.
#[derive(Args)]
pub struct DenoiseArgs {
    /// Path mode: clean the image with Intel Open Image Denoise, guided by
    /// the albedo and normal of what each pixel sees (as the scene's
    /// `[render] denoise = true`); install it first with `cargo xtask
    /// oidn`. A tile (--tile/--region to .exr) carries the guides instead,
    /// and `tracer merge --denoise` denoises the merged image
    #[arg(long, conflicts_with = "aov")]
    pub denoise: bool,
    /// The denoiser's quality, overriding `[render] denoise_quality`
    #[arg(long, value_name = "QUALITY", conflicts_with = "aov")]
    pub denoise_quality: Option<QualityArg>,
    /// What the denoiser does with its guides (the albedo and normal), as
    /// Blender names it, overriding `[render] denoise_prefilter`
    #[arg(long, value_name = "PREFILTER", conflicts_with = "aov")]
    pub denoise_prefilter: Option<PrefilterArg>,
}

impl DenoiseArgs {
    /// `options` with these set.
    fn apply(&self, options: Options) -> Options {
        Options {
            denoise: self.denoise,
            denoise_quality: self.denoise_quality.map(Into::into),
            denoise_prefilter: self.denoise_prefilter.map(Into::into),
            ..options
        }
    }
}

/// Denoising in `tracer watch` (which has no --aov).
#[derive(Args)]
pub struct WatchDenoiseArgs {
    /// Path mode: denoise each pass shown with Intel Open Image Denoise (as
    /// the scene's `[render] denoise = true`); install it first with `cargo
    /// xtask oidn`
    #[arg(long)]
    pub denoise: bool,
    /// The denoiser's quality, overriding `[render] denoise_quality`
    #[arg(long, value_name = "QUALITY")]
    pub denoise_quality: Option<QualityArg>,
    /// What the denoiser does with its guides, overriding `[render]
    /// denoise_prefilter`
    #[arg(long, value_name = "PREFILTER")]
    pub denoise_prefilter: Option<PrefilterArg>,
}

/// `--denoise-quality`'s values, Open Image Denoise's names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum QualityArg {
    /// For previews
    Fast,
    /// Between the two
    Balanced,
    /// For final images (the default)
    High,
}

impl From<QualityArg> for tracer_pipeline::denoise::Quality {
    fn from(q: QualityArg) -> Self {
        use tracer_pipeline::denoise::Quality;
        match q {
            QualityArg::Fast => Quality::Fast,
            QualityArg::Balanced => Quality::Balanced,
            QualityArg::High => Quality::High,
        }
    }
}

/// `--denoise-prefilter`'s values, Blender's names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PrefilterArg {
    /// The guides taken as clean: one network, the fastest (noise in them
    /// stays in the image)
    None,
    /// The guides cleaned with the image by one network: blurrier
    Fast,
    /// The guides cleaned first, each by a network of its own: the
    /// sharpest (the default)
    Accurate,
}

impl From<PrefilterArg> for tracer_pipeline::denoise::Prefilter {
    fn from(p: PrefilterArg) -> Self {
        use tracer_pipeline::denoise::Prefilter;
        match p {
            PrefilterArg::None => Prefilter::None,
            PrefilterArg::Fast => Prefilter::Fast,
            PrefilterArg::Accurate => Prefilter::Accurate,
        }
    }
}

/// `--bit-depth`'s values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum BitDepthArg {
    #[value(name = "8")]
    Eight,
    #[value(name = "16")]
    Sixteen,
}

impl From<BitDepthArg> for BitDepth {
    fn from(b: BitDepthArg) -> BitDepth {
        match b {
            BitDepthArg::Eight => BitDepth::Eight,
            BitDepthArg::Sixteen => BitDepth::Sixteen,
        }
    }
}

/// `--integrator`'s values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum IntegratorArg {
    /// The lab's rayTrace (Whitted-style): local Blinn-Phong, shadows,
    /// mirrors, glass
    Whitted,
    /// Path tracing with light sampling and MIS: objects light each other
    Path,
}

impl From<IntegratorArg> for scene_format::Integrator {
    fn from(i: IntegratorArg) -> scene_format::Integrator {
        match i {
            IntegratorArg::Whitted => scene_format::Integrator::Whitted,
            IntegratorArg::Path => scene_format::Integrator::Path,
        }
    }
}

/// The AOV names on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum AovArg {
    /// (dir.x + 1) / 2 of each primary ray in red (the lab's gradient-OX.png)
    RayDirX,
    /// (dir.y + 1) / 2 in green (gradient-OY.png)
    RayDirY,
    /// (dir.z + 1) / 2 in blue (gradient-OZ.png)
    RayDirZ,
    /// (n + 1) / 2 of the surface normal at the nearest hit (the lab's,
    /// geometric, not turned toward the ray)
    Normal,
    /// Distance to the nearest hit: near bright, far dark, no hit black (in
    /// .exr and .hdr the distances themselves, 0 for no hit)
    Depth,
    /// Albedo of the first surface seen that is not a perfect mirror or
    /// smooth glass (seen through them): the denoiser's guide
    Albedo,
    /// (n + 1) / 2 of that surface's shading normal, turned toward the ray;
    /// grey where nothing is hit: the denoiser's guide
    ShadingNormal,
    /// Light given off by what each pixel sees (emitting surfaces, the
    /// environment or background), through mirrors and smooth glass: the
    /// part the denoiser leaves as it is
    Emission,
}

impl From<AovArg> for Aov {
    fn from(a: AovArg) -> Aov {
        match a {
            AovArg::RayDirX => Aov::RayDirX,
            AovArg::RayDirY => Aov::RayDirY,
            AovArg::RayDirZ => Aov::RayDirZ,
            AovArg::Normal => Aov::Normal,
            AovArg::Depth => Aov::Depth,
            AovArg::Albedo => Aov::Albedo,
            AovArg::ShadingNormal => Aov::ShadingNormal,
            AovArg::Emission => Aov::Emission,
        }
    }
}

/// Write the calibration chart: five equal grey patches 0, 0.25, 0.5, 0.75, 1.
#[derive(Args)]
pub struct CalibChartArgs {
    /// Output PNG
    #[arg(short, long, value_name = "OUT.png", default_value = "chart.png")]
    pub output: PathBuf,
    /// Encode with display gamma G (c^(1/G)); without it no gamma encoding
    #[arg(long, value_name = "G", allow_negative_numbers = true)]
    pub gamma: Option<f32>,
    /// Image width in pixels (a multiple of 5 gives equal patches)
    #[arg(long, default_value_t = DEFAULT_CHART_SIZE.0)]
    pub width: u32,
    /// Image height in pixels
    #[arg(long, default_value_t = DEFAULT_CHART_SIZE.1)]
    pub height: u32,
}

/// Measure a display's gamma.
#[derive(Subcommand)]
pub enum GammaCommand {
    Fit(FitArgs),
}

/// Fit y = x^gamma to luminances measured on the calibration chart.
///
/// The CSV has one row per patch: level (0 to 1), luminance (cd/m2) and
/// optionally the luminance measured after gamma correction; a header row
/// and `#` comment lines are allowed. Luminances are normalised by their
/// maximum before the least-squares fit.
#[derive(Args)]
pub struct FitArgs {
    /// Measurements, CSV
    pub measurements: PathBuf,
    /// Also draw the measured, fitted and correcting curves to this PNG
    #[arg(long, value_name = "gamma.png")]
    pub plot: Option<PathBuf>,
}

/// Check scene files for mistakes without rendering them; every problem
/// found is reported, with its file, line, column and key.
#[derive(Args)]
pub struct CheckArgs {
    /// Scene files (.toml or .json, glTF models (.gltf, .glb), or .zip
    /// archives made by `tracer pack`): 3D scenes, 2D canvas scenes, or
    /// files a scene includes
    /// (checked on their own: their keys, values, includes and meshes; a
    /// material named from another file is left to the scene)
    #[arg(required = true, value_name = "SCENE")]
    pub scenes: Vec<PathBuf>,
    /// Print each 3D scene's summary as a line of JSON on stdout: its
    /// `objects`, `triangles`, `lights`, `cameras` and `bounds` (`{"min":
    /// [x, y, z], "max": [x, y, z]}`; a glTF file's in its own
    /// coordinates, +Y up)
    #[arg(long)]
    pub json: bool,
    /// The files are parts that scenes include: one without a `[camera]`
    /// passes (exit 0). Without this, a file without one is a warning
    /// (exit 1): rendering it needs a `[camera]`
    #[arg(long)]
    pub part: bool,
}

/// Render a scene, then again whenever the scene file or a file it reads
/// (included files, meshes, textures) changes: a quick preview first, then
/// the full image
///
/// The output is rewritten whole each time, so an image viewer that
/// reloads changed files shows every render. A bad edit prints its error
/// and keeps the last good image. Ctrl-C stops watching.
#[derive(Args)]
pub struct WatchArgs {
    /// Scene file (.toml or .json)
    pub scene: PathBuf,
    /// Output image, its format by its extension (.png, .jpg, .exr, .hdr)
    /// [default: the scene's file name with .png, in the current folder]
    #[arg(short, long, value_name = "OUT.png")]
    pub output: Option<PathBuf>,
    #[command(flatten)]
    pub view: ViewArgs,
    #[command(flatten)]
    pub denoise: WatchDenoiseArgs,
    /// Also serve a live page at ADDR (a browser shows each render as it
    /// comes, and the scene's errors): loopback only unless ADDR says
    /// otherwise; port 0 picks a free one
    #[arg(long, value_name = "ADDR", num_args = 0..=1, default_missing_value = "127.0.0.1:7878")]
    pub serve: Option<SocketAddr>,
}

/// `tracer watch`, resolved.
pub struct Watch {
    pub scene: PathBuf,
    pub output: PathBuf,
    pub options: Options,
    pub pool: rayon::ThreadPool,
    pub serve: Option<SocketAddr>,
}

impl WatchArgs {
    pub fn resolve(self) -> anyhow::Result<Watch> {
        let output = self
            .output
            .unwrap_or_else(|| tracer_pipeline::default_output(&self.scene, None));
        Ok(Watch {
            scene: self.scene,
            output,
            options: Options {
                denoise: self.denoise.denoise,
                denoise_quality: self.denoise.denoise_quality.map(Into::into),
                denoise_prefilter: self.denoise.denoise_prefilter.map(Into::into),
                ..self.view.options()
            },
            pool: pool(self.view.threads)?,
            serve: self.serve,
        })
    }
}

/// The render pool: `threads` threads, or one per core.
fn pool(threads: Option<u32>) -> anyhow::Result<rayon::ThreadPool> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        pool = pool.num_threads(n as usize);
    }
    Ok(pool.build()?)
}

/// Pack a scene file and every file it reads (included files, meshes) into
/// one zip archive, which `tracer render` and `tracer check` read as they
/// read the scene. A scene with errors is not packed.
#[derive(Args)]
pub struct PackArgs {
    /// Scene file (.toml or .json)
    #[arg(value_name = "SCENE")]
    pub scene: PathBuf,
    /// The archive to write [default: the scene's file name with .zip, in
    /// the current folder]
    #[arg(short, long, value_name = "OUT.zip")]
    pub output: Option<PathBuf>,
    /// Print no summary, only warnings and errors
    #[arg(short, long)]
    pub quiet: bool,
}

/// `tracer render`, resolved.
pub struct Render {
    pub input: Input,
    /// `None`: named after the scene (`tracer_pipeline::default_output`).
    pub output: Option<PathBuf>,
    pub options: Options,
    pub bit_depth: BitDepth,
    /// The one pool every path renders on, so `--threads` holds for all.
    pub pool: rayon::ThreadPool,
    pub skip_existing: bool,
    /// `--denoising-data`: the denoiser's inputs kept as EXR layers.
    pub denoising_data: bool,
    /// `--cache`: where prepared scenes are kept.
    pub cache: Option<PathBuf>,
    /// `--time-limit`, in seconds.
    pub time_limit: Option<f64>,
    /// `--reference`: an image to print the error against, pass by pass.
    pub reference: Option<PathBuf>,
    pub quiet: bool,
}

impl Render {
    /// The files the command line names for reading: the scene and the
    /// reference. The output may be none of them (nor any file the scene
    /// reads, known once it is loaded).
    pub fn inputs(&self) -> Vec<&Path> {
        let scene = match &self.input {
            Input::File(scene) => Some(scene.as_path()),
            Input::DefaultScene => None,
        };
        scene.into_iter().chain(self.reference.as_deref()).collect()
    }
}

impl RenderArgs {
    pub fn resolve(self) -> anyhow::Result<Render> {
        Ok(Render {
            input: Input::from_arg(self.scene),
            output: self.output,
            options: Options {
                gamma: checked(self.gamma)?,
                aov: self.aov.map(Aov::from),
                part: match (self.region, self.tile) {
                    (Some(region), _) => Some(Part::Region(region)),
                    (None, Some((index, count))) => Some(Part::Tile { index, count }),
                    (None, None) => None,
                },
                ..self.denoise.apply(self.view.options())
            },
            bit_depth: self.bit_depth.into(),
            pool: pool(self.view.threads)?,
            skip_existing: self.skip_existing,
            denoising_data: self.denoising_data,
            cache: self.cache,
            time_limit: self.time_limit,
            reference: self.reference,
            quiet: self.quiet,
        })
    }
}

/// `tracer calib-chart`, resolved.
pub struct CalibChart {
    pub output: PathBuf,
    pub gamma: Option<Gamma>,
    pub width: u32,
    pub height: u32,
}

impl CalibChartArgs {
    pub fn resolve(self) -> anyhow::Result<CalibChart> {
        Ok(CalibChart {
            output: self.output,
            gamma: checked(self.gamma)?,
            width: self.width,
            height: self.height,
        })
    }
}

/// The one check of `--gamma`, wherever it is given.
fn checked(gamma: Option<f32>) -> Result<Option<Gamma>, tracer_pipeline::Error> {
    gamma.map(Gamma::new).transpose()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_aov_of_the_core_has_its_name_on_the_command_line() {
        let names: Vec<(String, &str)> = AovArg::value_variants()
            .iter()
            .map(|&a| {
                let clap_name = a.to_possible_value().expect("not hidden");
                (clap_name.get_name().to_string(), Aov::from(a).name())
            })
            .collect();
        for (clap_name, aov_name) in &names {
            assert_eq!(clap_name, aov_name);
        }
        assert_eq!(names.len(), Aov::ALL.len());
    }
}
