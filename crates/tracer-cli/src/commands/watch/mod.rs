//! `tracer watch`: render a scene, then render it again whenever the scene
//! file or a file it reads changes. A preview (a quarter of the resolution,
//! one sample) comes first, then the full render; an edit cancels the
//! render in progress. A bad edit prints its located error and keeps the
//! last good image; the command never stops on a bad scene.

mod changes;
mod server;

use crate::args::Watch;
use crate::commands::render::summary;
use crate::console::{self, note};
use crate::report;
use anyhow::Result;
use changes::Changes;
use scene_format::SceneError;
use server::Server;
use std::path::PathBuf;
use std::time::Instant;
use tracer_pipeline::output::{check_not_an_input, encode, BitDepth, ImageFormat, PendingOutput};
use tracer_pipeline::{Error, Input, Loaded, Options, Rendered, Summary};

/// The preview's size: this fraction of the image's width and height.
const PREVIEW_DIVISOR: u32 = 4;

pub fn run(args: &Watch) -> Result<()> {
    ImageFormat::for_path(&args.output).map_err(Error::from)?;
    check_not_an_input(&args.output, &[&args.scene]).map_err(Error::from)?;
    let mut changes = Changes::new()?;
    // What the last good load read: still watched after a bad edit, so
    // that fixing an included file or a mesh renders again.
    let mut last_read = vec![args.scene.clone()];
    let server = args.serve.map(Server::start).transpose()?;
    if let Some(server) = &server {
        note!("the live page: http://{}/", server.addr);
    }
    loop {
        let input = Input::File(args.scene.clone());
        match tracer_pipeline::load(&input) {
            Ok(loaded) => {
                last_read.clone_from(&loaded.files_read);
                changes.watch(&loaded.files_read);
                report::warnings(&loaded, &args.options);
                // Watch renders every pass, as a preview would.
                report::time_limit_unused(&loaded, &args.options);
                if let Some(server) = &server {
                    let (scene, options) = (loaded.clone(), args.options);
                    server.explain_with(std::sync::Arc::new(move |x, y| {
                        tracer_pipeline::explain_text::tree_text(&scene, &options, (x, y), 0)
                            .map_err(|e| e.to_string())
                    }));
                }
                // Writing over a texture the scene reads would render
                // again and again.
                match check_not_an_input(&args.output, &loaded.files_read) {
                    Ok(()) => render_passes(args, &loaded, &changes, server.as_ref()),
                    Err(e) => note!("error: {e}; not rendering until that changes"),
                }
            }
            Err(e) => {
                // Still watched: the fix is an edit of the same file(s).
                changes.watch(&files_of_failed_load(&last_read, &e));
                console::stderr_report(&report::render(&e, report::color_wanted()));
                note!("keeping the last good image; waiting for the next edit");
                if let Some(server) = &server {
                    server.error(&report::render(&e, false));
                }
            }
        }
        changes.wait();
    }
}

/// What to watch when the scene did not load: what the last good load
/// read (the scene file first), and the files the error is in.
fn files_of_failed_load(last_read: &[PathBuf], error: &SceneError) -> Vec<PathBuf> {
    let mut files = last_read.to_vec();
    for e in error.files() {
        let file = match e {
            SceneError::Io { file, .. }
            | SceneError::UnknownFormat { file }
            | SceneError::Invalid { file, .. } => file,
            SceneError::Several(_) => continue,
        };
        if !files.contains(file) {
            files.push(file.clone());
        }
    }
    files
}

/// The preview, then the full render, each written whole to the output;
/// stops as soon as a watched file changes.
fn render_passes(args: &Watch, loaded: &Loaded, changes: &Changes, server: Option<&Server>) {
    let full = args.options;
    let passes = match preview_options(loaded, &full) {
        Some(preview) => vec![(preview, true), (full, false)],
        None => vec![(full, false)],
    };
    for (options, is_preview) in passes {
        if !is_preview && loaded.is_path_traced(&options) {
            return render_in_passes(args, loaded, changes, server);
        }
        let start = Instant::now();
        let cancel = changes.pending();
        let rendered = args
            .pool
            .install(|| tracer_pipeline::render_cancellable(loaded, &options, &|_| {}, cancel));
        match rendered {
            Ok(Some(rendered)) => {
                let pass = Pass {
                    is_preview,
                    start,
                    samples: None,
                };
                if let Err(e) = write(args, loaded, rendered, pass, server) {
                    note!("error: {e:#}");
                    return;
                }
            }
            // A watched file changed: the next loop reads it.
            Ok(None) => return,
            Err(e) => {
                note!("error: {e:#}");
                return;
            }
        }
    }
}

/// A path-traced scene's full render in passes of doubling samples per
/// pixel, each written whole and shown with the samples done so far; an
/// edit stops it at once.
fn render_in_passes(args: &Watch, loaded: &Loaded, changes: &Changes, server: Option<&Server>) {
    let start = Instant::now();
    let cancel = changes.pending();
    let prepared = args
        .pool
        .install(|| tracer_pipeline::prepare_taking(loaded.clone(), &args.options, "watch"));
    let prepared = match prepared {
        Ok(prepared) => prepared,
        Err(e) => return note!("error: {e:#}"),
    };
    let mut failed = None;
    // Each pass is denoised when the scene asks for it, with the guides
    // rendered once.
    let mut guides = None;
    let mut on_pass = |pass: tracer_pipeline::Pass| {
        let picture =
            tracer_pipeline::denoise_picture(&prepared, &mut guides, pass.picture, pass.samples);
        let picture = match picture {
            Ok(picture) => picture,
            Err(e) => {
                failed = Some(e.into());
                return false;
            }
        };
        let rendered = Rendered {
            image: picture,
            summary: Summary::Shaded(pass.stats.clone()),
            denoising: None,
        };
        let pass = Pass {
            is_preview: false,
            start,
            samples: Some((pass.samples, pass.total)),
        };
        match write(args, loaded, rendered, pass, server) {
            Ok(()) => true,
            Err(e) => {
                failed = Some(e);
                false
            }
        }
    };
    let rendered = args.pool.install(|| {
        tracer_pipeline::render_prepared_progressive(
            &prepared,
            &args.options,
            cancel,
            (&|_| {}, &mut on_pass),
        )
    });
    if let Some(e) = failed {
        note!("error: {e:#}");
    } else if let Err(e) = rendered {
        note!("error: {e:#}");
    }
}

/// The options of the preview pass, or None when the scene is a canvas
/// (drawn at once) or already small.
fn preview_options(loaded: &Loaded, full: &Options) -> Option<Options> {
    let (width, height) = tracer_pipeline::image_size(loaded, full).ok()?;
    if matches!(loaded.kind, scene_format::SceneKind::Canvas(_)) || width < 2 * PREVIEW_DIVISOR {
        return None;
    }
    Some(Options {
        samples: Some(1),
        width: Some(width.div_ceil(PREVIEW_DIVISOR)),
        height: Some(height.div_ceil(PREVIEW_DIVISOR)),
        ..*full
    })
}

/// Which pass a render was, and when it began.
struct Pass {
    is_preview: bool,
    start: Instant,
    /// In path mode, the samples per pixel done, of how many.
    samples: Option<(u32, u32)>,
}

/// Writes a pass to the output (a preview blown up to the full size, so a
/// viewer keeps its zoom), prints its summary line and shows it on the page.
fn write(
    args: &Watch,
    loaded: &Loaded,
    mut rendered: Rendered,
    pass: Pass,
    server: Option<&Server>,
) -> Result<()> {
    let seconds = pass.start.elapsed().as_secs_f64();
    let (width, height) = rendered.image.dimensions();
    if pass.is_preview {
        let size = tracer_pipeline::image_size(loaded, &args.options)?;
        rendered.image = rendered.image.enlarged(size);
    }
    let pending = PendingOutput::create(&args.output).map_err(Error::from)?;
    if let Some(warning) = pending.picture_warning(&rendered.image) {
        note!("warning: {}: {warning}", args.output.display());
    }
    pending
        .write_picture(&rendered.image, BitDepth::Eight)
        .map_err(Error::from)?;
    if pass.is_preview {
        note!("preview in {seconds:.3} s");
    } else if let Some((done, total)) = pass.samples.filter(|(d, t)| d < t) {
        note!("{done} of {total} samples a pixel in {seconds:.3} s");
    } else {
        let threads = args.pool.current_num_threads();
        note!(
            "{}",
            summary(&loaded.name, &rendered, threads, &args.output)
        );
    }
    if let Some(server) = server {
        let png = encode(&rendered.image.to_rgb8(), ImageFormat::Png).map_err(Error::from)?;
        let mrays = match &rendered.summary {
            Summary::Shaded(stats) => {
                Some(stats.rays as f64 / stats.render_seconds.max(1e-9) / 1e6)
            }
            _ => None,
        };
        let info = serde_json::json!({
            "scene": scene_format::visible::escape_controls(&loaded.name.display().to_string()),
            "pass": if pass.is_preview { "preview" } else { "full" },
            "width": width,
            "height": height,
            "seconds": seconds,
            "mrays": mrays,
            "samples": pass.samples.map(|s| s.0),
            "total_samples": pass.samples.map(|s| s.1),
        });
        server.image(png, info);
    }
    Ok(())
}
