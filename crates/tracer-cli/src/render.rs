//! `tracer render`: scene file in, PNG out.

use crate::progress::Progress;
use crate::BadInput;
use anyhow::Result;
use clap::Args;
use scene_format::{Format, SceneKind};
use std::path::{Path, PathBuf};
use std::time::Instant;
use tracer_cli::output::write_png_atomically;
use tracer_core::RenderJob;

/// The scene rendered when none is given: the lab's final scene (table 1.10).
const DEFAULT_SCENE: &str = include_str!("../../../scenes/reflectance2.toml");
const DEFAULT_SCENE_NAME: &str = "reflectance2.toml";

/// Render a scene file to a PNG image.
#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (.toml or .json). Without one, the lab's final scene
    /// (table 1.10, reflectance2) is rendered.
    pub scene: Option<PathBuf>,
    /// Output PNG [default: the scene's file name with .png, in the current folder]
    #[arg(short, long, value_name = "OUT.png")]
    pub output: Option<PathBuf>,
    /// Display gamma for encoding, overriding the scene's `[render] gamma`
    /// (1 writes linear values)
    #[arg(long, value_name = "G")]
    pub gamma: Option<f32>,
    /// Write one quantity per pixel instead of the shaded colour (linear,
    /// unless --gamma is given)
    #[arg(long, value_name = "NAME")]
    pub aov: Option<crate::aov::AovArg>,
    /// Threads to render with [default: one per core]
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Print no progress bar and no summary, only warnings and errors
    #[arg(short, long)]
    pub quiet: bool,
}

pub fn run(args: &RenderArgs) -> Result<()> {
    let (scene_name, mut file) = match load(args.scene.as_deref())? {
        (name, SceneKind::Scene3d(file)) => (name, file),
        (name, SceneKind::Canvas(canvas)) => return crate::canvas::draw(args, &name, &canvas),
    };
    if let Some(aov) = args.aov {
        return crate::aov::run(args, aov, &scene_name, &file);
    }
    if let Some(gamma) = args.gamma {
        if !(gamma.is_finite() && gamma > 0.0) {
            return Err(BadInput(format!("--gamma: expected a number > 0, found {gamma}")).into());
        }
        file.render.gamma = gamma;
    }
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(&scene_name));
    for w in scene_format::mesh_warnings(&file) {
        eprintln!(
            "warning: {}: `{}`: {}",
            scene_name.display(),
            w.path,
            w.message
        );
    }
    let pool = thread_pool(args.threads)?;
    let start = Instant::now();
    let scene = pool
        .install(|| tracer_core::prepare(&file))
        .map_err(|e| BadInput(format!("{}: {e}", scene_name.display())))?;
    let prepared = start.elapsed();
    let camera = scene.camera();
    let progress = Progress::new(camera.height.into(), args.quiet);
    let start = Instant::now();
    let job = RenderJob::full(&scene);
    let rendered = pool.install(|| tracer_core::render(&scene, &job, &|n| progress.rows_done(n)));
    let (image, rays) = (rendered.image, rendered.rays);
    let elapsed = start.elapsed().as_secs_f64();
    progress.finish();
    write_png_atomically(&image.encode(scene.encoding()), &output)?;
    if !args.quiet {
        eprintln!(
            "rendered {} ({}x{}, {}) in {:.3} s ({:.3} s to prepare), \
             {:.1} Mrays/s on {} threads -> {}",
            scene_name.display(),
            camera.width,
            camera.height,
            objects_summary(file.objects.len(), scene.objects().len()),
            elapsed,
            prepared.as_secs_f64(),
            rays.total() as f64 / elapsed.max(1e-9) / 1e6,
            pool.current_num_threads(),
            output.display()
        );
    }
    Ok(())
}

/// "5 objects", or with meshes "2 objects, 69667 primitives": a mesh is one
/// object of the scene file and many triangles to the tracer.
fn objects_summary(objects: usize, primitives: usize) -> String {
    let plural = if objects == 1 { "" } else { "s" };
    if primitives == objects {
        format!("{objects} object{plural}")
    } else {
        format!("{objects} object{plural}, {primitives} primitives")
    }
}

fn thread_pool(threads: Option<u32>) -> Result<rayon::ThreadPool> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        builder = builder.num_threads(n as usize);
    }
    Ok(builder.build()?)
}

/// The scene's name (for messages and the default output) and its contents.
fn load(path: Option<&Path>) -> Result<(PathBuf, SceneKind)> {
    let name = path.map_or_else(|| PathBuf::from(DEFAULT_SCENE_NAME), Path::to_path_buf);
    let scene = match path {
        Some(path) => scene_format::load_any(path),
        None => scene_format::load_any_str(DEFAULT_SCENE, Format::Toml, &name),
    }?;
    Ok((name, scene))
}

pub(crate) fn default_output(scene: &Path) -> PathBuf {
    let stem = scene.file_stem().unwrap_or(scene.as_os_str());
    PathBuf::from(stem).with_extension("png")
}
