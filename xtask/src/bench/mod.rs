//! `cargo xtask bench`: the tracer against its peers on the benchmark
//! scenes, all in one run (the machines are noisy: only figures of the same
//! run compare). See `docs/src/performance.md`.
//!
//! For each scene (the bunny, at 1 and at 16 samples per pixel, its
//! 1.1M-triangle variant, the lab's reflectance2): BVH build time, render
//! time and Mrays/s (primary, shadow and reflected rays) on 1 and 2 threads,
//! medians of `--reps` runs; POV-Ray 3.7's render-only time for the same
//! scene at the same samples per pixel, written from the same scene data,
//! when `povray` is installed; Embree 3's figures on the 1-sample bunnies
//! when `libembree-dev` and `g++` are. A peer that is not installed is
//! skipped, with a line saying so.
//!
//! - `scenes`: the bench scenes and their samples per pixel, the
//!   1.1M-triangle bunny.
//! - `measure`: timing the tracer (with `path`, the files that call
//!   tracer-core).
//! - `path`, `path_peers`: the path tracer on four scenes against
//!   Mitsuba 3 (and Blender Cycles) at equal time (`--only path`).
//! - `process`: timing the whole `tracer render` process on a small scene.
//! - `pov_scene`: a scene file as POV-Ray SDL.
//! - `povray`: timing POV-Ray.
//! - `embree`: building and timing the Embree harness (`xtask/peers/`).
//! - `packets`: primary rays at 16 samples per pixel, ours against
//!   Embree's packet kernels on the same rays.
//! - `memory`: peak memory of `tracer render` on one bunny and on 1,000
//!   instances of it (the scene written into `target/bench/`).
//! - `print`: the report.
//! - `rusage`: CPU time and peak memory of this process and its children.
//! - `denoise`: Open Image Denoise on the path tracer's images against the
//!   Mitsuba references, and (`denoise_time`) its time against
//!   `oidnBenchmark`.

mod denoise;
pub mod denoise_figure;
mod denoise_time;
mod embree;
mod measure;
pub mod memory;
mod packets;
mod path;
pub mod path_peers;
mod pov_scene;
mod povray;
mod print;
mod process;
pub(crate) mod rusage;
mod scenes;
mod stats;
mod web;

pub use pov_scene::pov_scene;
pub use scenes::subdivide;

use anyhow::{bail, Context, Result};
use packets::PACKETS;

/// Options of `cargo xtask bench`.
#[derive(Debug, Clone, clap::Args)]
pub struct BenchArgs {
    /// Runs of each measurement; the median is reported
    #[arg(long, default_value_t = 5)]
    pub reps: usize,
    /// Skip POV-Ray even when it is installed
    #[arg(long)]
    pub no_povray: bool,
    /// Skip Embree even when it can be built (libembree-dev and g++)
    #[arg(long)]
    pub no_embree: bool,
    /// Keep the .pov files written for POV-Ray, and its images, in DIR
    #[arg(long, value_name = "DIR")]
    pub keep_pov: Option<std::path::PathBuf>,
    /// Only these scenes (bunny, bunny-16spp, bunny-1.1m, reflectance2) or
    /// measurements (instancing: peak memory of 1 and 1,000 bunnies;
    /// packets: primary rays at 16 samples per pixel against Embree's
    /// packet kernels on the same rays; path: the path tracer on four
    /// scenes against Mitsuba 3 at equal time; web: the playground in
    /// headless Chromium against native, one thread, and its workers;
    /// denoise: Open Image Denoise's RMSE against the Mitsuba references and
    /// its time against oidnBenchmark; denoise-time: that time alone)
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// With path: also Mitsuba 3's scalar_rgb, and Blender Cycles on the
    /// Cornell box (pip install bpy)
    #[arg(long)]
    pub all_peers: bool,
}

/// The `--only` name of the instancing memory measurement.
const INSTANCING: &str = "instancing";

/// The thread counts every scene is measured on.
const THREADS: [usize; 2] = [1, 2];

/// Everything measured on one scene: ours, and the peers' when they ran.
#[derive(Debug)]
struct Row {
    scene: &'static str,
    ours: measure::Ours,
    povray: Option<povray::PovRay>,
    embree: Option<embree::Embree>,
}

pub fn run(args: &BenchArgs) -> Result<()> {
    if args.reps == 0 {
        bail!("--reps: expected at least 1");
    }
    rusage::fix_mmap_threshold();
    let root = crate::workspace_root();
    let mut scenes = scenes::scenes(&root)?;
    // The packet measurement's bunny, whichever scenes are chosen.
    let bunny = scenes
        .iter()
        .find(|s| s.name == "bunny")
        .map(|s| s.file.clone());
    let only = |name: &str| args.only.is_empty() || args.only.iter().any(|o| o == name);
    if !args.only.is_empty() {
        if let Some(unknown) = args.only.iter().find(|o| {
            ![
                INSTANCING,
                PACKETS,
                path::PATH,
                web::WEB,
                denoise::DENOISE,
                denoise_time::DENOISE_TIME,
            ]
            .contains(&o.as_str())
                && !scenes.iter().any(|s| s.name == *o)
        }) {
            let names: Vec<&str> = scenes.iter().map(|s| s.name).collect();
            bail!(
                "--only: no scene `{unknown}` (the scenes: {}; or {INSTANCING}, {PACKETS}, {}, {}, {}, {})",
                names.join(", "),
                path::PATH,
                web::WEB,
                denoise::DENOISE,
                denoise_time::DENOISE_TIME
            );
        }
        scenes.retain(|s| only(s.name));
    }
    let povray = !args.no_povray && povray::available();
    // The memory measurement runs Embree's harness too.
    let embree_wanted =
        only(INSTANCING) || only(PACKETS) || scenes.iter().any(|s| s.embree_subdiv.is_some());
    let embree = if args.no_embree || !embree_wanted {
        None
    } else {
        embree::build(&root, &crate::target_dir().join("peers"))
    };
    // The binary as a user runs it, for the scenes whose whole process is timed.
    let tracer = if scenes.iter().any(|s| s.process.is_some()) {
        eprintln!("bench: building the tracer binary ...");
        Some(crate::farm::build_tracer(&root)?)
    } else {
        None
    };
    let out_dir = tempfile::tempdir()?;
    let ours = if scenes.is_empty() {
        Vec::new()
    } else {
        measure::measure(&scenes, args.reps, tracer.as_deref(), out_dir.path())?
    };
    let mut rows = Vec::new();
    for (scene, ours) in scenes.iter().zip(ours) {
        let povray = if povray {
            eprintln!("bench: POV-Ray on {} ...", scene.name);
            let figures = povray::measure(
                &scene.file,
                scene.name,
                scene.samples,
                args.reps,
                args.keep_pov.as_deref(),
            )
            .with_context(|| format!("POV-Ray on {}", scene.name))?;
            Some(figures)
        } else {
            None
        };
        let embree = match (&embree, scene.embree_subdiv) {
            (Some(exe), Some(subdiv)) => {
                eprintln!("bench: Embree on {} ...", scene.name);
                let obj = root.join(scenes::BUNNY_OBJ);
                let figures = embree::measure(exe, &obj, subdiv, args.reps)
                    .with_context(|| format!("Embree on {}", scene.name))?;
                Some(figures)
            }
            _ => None,
        };
        rows.push(Row {
            scene: scene.name,
            ours,
            povray,
            embree,
        });
    }
    if !rows.is_empty() {
        print::report(&rows, args.reps);
    }
    if only(PACKETS) {
        let bunny = bunny.context("no bunny scene")?;
        let obj = root.join(scenes::BUNNY_OBJ);
        let figures = packets::measure(&bunny, &obj, embree.as_deref(), args.reps, out_dir.path())?;
        packets::report(&figures);
    }
    if only(INSTANCING) {
        memory::report(&memory::measure(&root, embree.as_deref())?);
    }
    if only(web::WEB) {
        if let Some(figures) = web::measure(&root, args.reps)? {
            web::report(&figures);
        }
    }
    if only(path::PATH) {
        path::report(&path::measure(&root, out_dir.path(), args.all_peers)?);
    }
    if only(denoise::DENOISE) {
        denoise::report(&denoise::measure(&root)?);
    } else if only(denoise_time::DENOISE_TIME) {
        denoise_time::report(&denoise_time::measure()?);
    }
    Ok(())
}
