//! `tracer render`: scene file in, image out (its format by extension); a
//! 3D scene shaded or as an AOV, or a 2D canvas scene drawn. Every path
//! loads (or reads the scene kept by `--cache`), warns, renders on the one
//! thread pool, writes and (unless quiet) sums up the same way.

use super::passes::{self, Plan};
use crate::args::Render;
use crate::console::note;
use crate::progress::Progress;
use anyhow::Result;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use tracer_pipeline::cache::{CacheEntry, Cached, SceneCache};
use tracer_pipeline::output::{check_not_an_input, ImageFormat, OutputError, PendingOutput};
use tracer_pipeline::{
    default_output, denoising_data, tiles, Error, Part, PreparedScene, Rendered, ShadedStats,
    Summary,
};

pub fn run(args: &Render) -> Result<()> {
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(&args.input.name(), args.options.aov));
    // The output is checked (and its temporary file made) before any work,
    // so a wrong path does not cost a render.
    check_not_an_input(&output, &args.inputs()).map_err(Error::from)?;
    let pending = PendingOutput::create(&output).map_err(Error::from)?;
    // A tile keeps --gamma in its header, for the 8-bit file of the merge.
    let is_tile = args.options.part.is_some() && pending.format() == ImageFormat::Exr;
    let gamma_given = args.options.gamma.is_some() && !is_tile;
    pending
        .check_render_options(args.bit_depth, gamma_given)
        .map_err(Error::from)?;
    pending
        .check_denoising_data(args.denoising_data)
        .map_err(Error::from)?;
    let linear = pending.format().is_linear();
    let options = tracer_pipeline::Options {
        raw_depth: linear,
        ..args.options
    };
    let entry = args
        .cache
        .as_ref()
        .and_then(|dir| SceneCache::new(dir.clone()).entry(&args.input, &options));
    let scene = open(args, &options, entry.as_ref(), &output, pending.format())?;
    // With --denoise, a render that is not denoised is refused by its own
    // error (Whitted mode).
    if args.denoising_data && !options.denoise && !scene.is_denoised(&options) {
        return Err(Error::from(OutputError::NotDenoised).into());
    }
    let (size, region, digest) = (scene.size, scene.region, scene.digest.clone());
    let tile = match (region, pending.format(), &digest) {
        (Some(region), ImageFormat::Exr, Some(digest)) => Some((region, digest.clone())),
        _ => None,
    };
    if args.skip_existing {
        let Some((region, digest)) = &tile else {
            return Err(Error::from(tiles::TileError::SkipWithoutTile).into());
        };
        if tiles::is_done(&output, digest, *region) {
            if !args.quiet {
                note!("skipped: {} already holds this tile", output.display());
            }
            return Ok(());
        }
    }
    let plan = plan(args, &scene, size)?;
    let rows = region.map_or(size.1, |r| r.height());
    // In passes, each pass says what it did instead.
    let progress = Progress::new(rows.into(), args.quiet || plan.is_some());
    let name = args.input.name();
    let rows_done = |n| progress.rows_done(n);
    let rendered = args.pool.install(|| {
        let how = How {
            options: &options,
            quiet: args.quiet,
            rows_done: &rows_done,
            plan: plan.as_ref(),
        };
        rendered(scene, entry.as_ref(), how)
    });
    progress.finish();
    let rendered = rendered?;
    // A float file keeps the values over 1: nothing is made white.
    if let Summary::Shaded(stats) = &rendered.summary {
        // A part's mean says nothing of the image's (a region of sky).
        let dark = stats.dark_warning().filter(|_| region.is_none());
        for warning in [stats.dropped_warning(), stats.cut_trees_warning(), dark]
            .into_iter()
            .flatten()
        {
            note!("warning: {}: {warning}", name.display());
        }
    }
    if let (Summary::Shaded(stats), false) = (&rendered.summary, linear) {
        if let Some(warning) = stats.forced_white_warning() {
            note!("warning: {}: {warning}", name.display());
        }
    }
    match &tile {
        Some((region, digest)) => {
            let index = match options.part {
                Some(Part::Tile { index, count }) => Some((index, count)),
                _ => None,
            };
            let guides = rendered.denoising.as_ref().map(|d| (&d.guides, d.settings));
            let bytes = tiles::encode(&rendered.image, *region, size, digest, index, guides)
                .map_err(Error::from)?;
            pending.write_bytes(&bytes).map_err(Error::from)?;
        }
        None if args.denoising_data => {
            let denoising = rendered.denoising.as_ref().ok_or(OutputError::NotDenoised);
            let bytes = denoising
                .and_then(|d| denoising_data::encode(&rendered.image.linear, d))
                .map_err(Error::from)?;
            pending.write_bytes(&bytes).map_err(Error::from)?;
        }
        None => {
            if let Some(warning) = pending.picture_warning(&rendered.image) {
                note!("warning: {}: {warning}", output.display());
            }
            pending
                .write_picture(&rendered.image, args.bit_depth)
                .map_err(Error::from)?
        }
    }
    if !args.quiet {
        let threads = args.pool.current_num_threads();
        note!("{}", summary(&name, &rendered, threads, &output));
    }
    let part_not_denoised = rendered
        .denoising
        .as_ref()
        .is_some_and(|d| d.noisy.is_none());
    if part_not_denoised && tile.is_none() {
        note!("note: a region is not denoised alone (its edges would not match its neighbours'); render the parts as .exr tiles, which carry the denoiser's guides, and denoise the whole with `tracer merge --denoise`");
    }
    Ok(())
}

/// Where the scene comes from: its files, or `--cache`.
enum Source {
    Loaded(tracer_pipeline::Loaded),
    Kept(Cached),
}

/// The scene, from `--cache` or from its files, with what is checked of it
/// before the work.
struct Opened {
    source: Source,
    size: (u32, u32),
    region: Option<tracer_pipeline::Region>,
    /// Its tiles' digest: for a tile, or to keep the scene.
    digest: Option<String>,
    /// The warnings its loading gave (printed).
    warnings: Vec<String>,
}

/// Reads the scene kept in `entry`, or else loads it; checks that the
/// output is none of its files and that the part is in the image; prints
/// its warnings.
fn open(
    args: &Render,
    options: &tracer_pipeline::Options,
    entry: Option<&CacheEntry>,
    output: &Path,
    format: ImageFormat,
) -> Result<Opened> {
    let source = match entry.and_then(|e| read_kept(e, args, options)) {
        Some(cached) => Source::Kept(cached),
        None => Source::Loaded(tracer_pipeline::load(&args.input)?),
    };
    let (files_read, size, warnings) = match &source {
        Source::Kept(c) => (&c.files_read, c.prepared.size(), c.warnings.clone()),
        Source::Loaded(loaded) => (
            &loaded.files_read,
            tracer_pipeline::image_size(loaded, options)?,
            loaded.warning_lines(options),
        ),
    };
    // The scene's meshes are known only now.
    check_not_an_input(output, files_read).map_err(Error::from)?;
    warnings.iter().for_each(|line| note!("{line}"));
    // Checked before the work, as the output is.
    let region = options.part.map(|p| p.region(size)).transpose()?;
    let wanted = region.is_some() && format == ImageFormat::Exr || entry.is_some();
    let digest = match &source {
        Source::Kept(cached) => Some(cached.digest.clone()),
        Source::Loaded(loaded) if wanted => {
            Some(tiles::digest(&args.input, loaded, options).map_err(Error::from)?)
        }
        Source::Loaded(_) => None,
    };
    Ok(Opened {
        source,
        size,
        region,
        digest,
        warnings,
    })
}

impl Opened {
    /// Whether its render with `options` is denoised.
    fn is_denoised(&self, options: &tracer_pipeline::Options) -> bool {
        match &self.source {
            Source::Kept(cached) => cached.prepared.denoise().is_some(),
            Source::Loaded(loaded) => loaded.is_denoised(options),
        }
    }
}

/// How the opened scene is rendered: with what options, quietly or not,
/// reporting rows done, and in passes or not.
struct How<'a> {
    options: &'a tracer_pipeline::Options,
    quiet: bool,
    rows_done: &'a (dyn Fn(u32) + Sync),
    plan: Option<&'a Plan>,
}

/// The render of the opened scene; a scene loaded for `--cache` is
/// prepared and kept first.
fn rendered(scene: Opened, entry: Option<&CacheEntry>, how: How) -> Result<Rendered, Error> {
    let options = how.options;
    match (scene.source, entry, &scene.digest) {
        (Source::Kept(cached), _, _) => render_prepared(&cached.prepared, &how),
        (Source::Loaded(loaded), Some(entry), Some(digest)) => {
            let files_read = loaded.files_read.clone();
            let prepared = tracer_pipeline::prepare_taking(loaded, options, "--cache")?;
            keep(
                entry,
                &prepared,
                &files_read,
                digest,
                &scene.warnings,
                how.quiet,
            );
            render_prepared(&prepared, &how)
        }
        (Source::Loaded(loaded), _, _) if how.plan.is_some() => {
            let prepared = tracer_pipeline::prepare_taking(loaded, options, "--time-limit")?;
            render_prepared(&prepared, &how)
        }
        // Taken: a large mesh's triangles are let go before its BVH is built.
        (Source::Loaded(loaded), _, _) => {
            tracer_pipeline::render_taking(loaded, options, how.rows_done)
        }
    }
}

/// A prepared scene rendered at once, or in passes by the plan.
fn render_prepared(prepared: &PreparedScene, how: &How) -> Result<Rendered, Error> {
    let Some(plan) = how.plan else {
        return tracer_pipeline::render_prepared(prepared, how.options, how.rows_done);
    };
    let never = AtomicBool::new(false);
    let mut on_pass = passes::on_pass(plan, how.quiet);
    let rendered = tracer_pipeline::render_prepared_progressive(
        prepared,
        how.options,
        &never,
        (&|_| {}, &mut on_pass),
    )?;
    let rendered = rendered.expect("never cancelled");
    let rendered = tracer_pipeline::denoise_rendered(prepared, how.options, rendered)?;
    if let (Some(reference), Some(_)) = (&plan.reference, &rendered.denoising) {
        let error = tracer_pipeline::reference::rmse(&rendered.image.linear, reference);
        note!("denoised: RMSE {error:.5} against the reference");
    }
    Ok(rendered)
}

/// The plan of a render in passes, when one is asked for: `--time-limit`,
/// `--reference`, or the scene's `[render] time_limit` (path mode only;
/// left out for a region or tile, whose pixels must be the whole render's).
fn plan(args: &Render, scene: &Opened, size: (u32, u32)) -> Result<Option<Plan>, Error> {
    let (path_traced, scene_limit) = match &scene.source {
        Source::Loaded(loaded) => (loaded.is_path_traced(&args.options), loaded.time_limit()),
        Source::Kept(cached) => (
            cached.prepared.is_path_traced(),
            cached.prepared.time_limit(),
        ),
    };
    for (option, given) in [
        ("--time-limit", args.time_limit.is_some()),
        ("--reference", args.reference.is_some()),
    ] {
        if given && !path_traced {
            return Err(Error::NeedsPathMode { option });
        }
    }
    let scene_limit = scene_limit.filter(|_| path_traced);
    if scene_limit.is_some() && args.time_limit.is_none() && scene.region.is_some() {
        note!("note: the scene's time_limit is not used for a region or tile: every sample is rendered, so that the parts merge into the whole render");
    }
    let time_limit = args
        .time_limit
        .or(scene_limit.filter(|_| scene.region.is_none()));
    let reference = args
        .reference
        .as_deref()
        .map(|path| tracer_pipeline::reference::read_reference(path, size))
        .transpose()?;
    Ok(
        (time_limit.is_some() || reference.is_some()).then_some(Plan {
            time_limit,
            limit_given: args.time_limit.is_some(),
            reference,
        }),
    )
}

/// The scene kept in `entry`, if it is there and can be used; a kept
/// scene that cannot is said, and prepared again.
fn read_kept(
    entry: &CacheEntry,
    args: &Render,
    options: &tracer_pipeline::Options,
) -> Option<Cached> {
    match entry.read(&args.input, options) {
        Ok(Some(cached)) => {
            if !args.quiet {
                note!("read the prepared scene from {}", entry.path.display());
            }
            Some(cached)
        }
        Ok(None) => None,
        Err(why) => {
            if !args.quiet {
                note!(
                    "{}: not used ({why}); preparing the scene again",
                    entry.path.display()
                );
            }
            None
        }
    }
}

/// Keeps the prepared scene in `entry`; a failure is a warning (the render
/// goes on).
fn keep(
    entry: &CacheEntry,
    prepared: &tracer_pipeline::PreparedScene,
    files_read: &[std::path::PathBuf],
    digest: &str,
    warnings: &[String],
    quiet: bool,
) {
    match entry.write(prepared, files_read, digest, warnings) {
        Ok(()) if !quiet => note!("kept the prepared scene in {}", entry.path.display()),
        Ok(()) => {}
        Err(e) => note!("warning: --cache: {e}"),
    }
}

/// The line that says what was written.
pub(crate) fn summary(scene: &Path, rendered: &Rendered, threads: usize, output: &Path) -> String {
    let (scene, output) = (scene.display(), output.display());
    let (width, height) = rendered.image.dimensions();
    match &rendered.summary {
        Summary::Shaded(stats) => format!(
            "rendered {scene} ({width}x{height}, {}) in {:.3} s ({:.3} s to prepare), \
             {:.1} Mrays/s on {threads} thread{}{}{} -> {output}",
            objects_summary(stats),
            stats.render_seconds,
            stats.prepare_seconds,
            stats.rays as f64 / stats.render_seconds.max(1e-9) / 1e6,
            plural(threads),
            stats
                .estimator
                .map(|e| format!(", {e}"))
                .unwrap_or_default(),
            rendered
                .denoising
                .as_deref()
                .map(denoise_summary)
                .unwrap_or_default(),
        ),
        Summary::Aov(aov) => format!(
            "rendered {} of {scene} on {threads} thread{} -> {output}",
            aov.name(),
            plural(threads)
        ),
        Summary::Canvas => format!("drew {scene} ({width}x{height}) -> {output}"),
    }
}

/// ", denoised (high, accurate prefilter) in 1.234 s (its guides 0.2 s)",
/// or for a tile the
/// guides alone.
fn denoise_summary(d: &tracer_pipeline::Denoising) -> String {
    match d.noisy {
        Some(_) => format!(
            ", denoised ({}) in {:.3} s (its guides {:.3} s)",
            d.settings.name(),
            d.denoise_seconds,
            d.guide_seconds
        ),
        None => format!(", the denoiser's guides in {:.3} s", d.guide_seconds),
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// "5 objects", or with meshes "2 objects, 69667 primitives": a mesh is one
/// object of the scene file and many triangles to the tracer.
fn objects_summary(stats: &ShadedStats) -> String {
    let objects = stats.objects;
    let plural = if objects == 1 { "" } else { "s" };
    if stats.primitives == objects {
        format!("{objects} object{plural}")
    } else {
        format!("{objects} object{plural}, {} primitives", stats.primitives)
    }
}
