//! `tracer merge`: render-farm tiles in, the whole image out, written whole
//! or not at all once every tile is checked.

use crate::args::MergeArgs;
use crate::console::note;
use anyhow::Result;
use std::time::Instant;
use tracer_pipeline::output::{check_not_an_input, PendingOutput};
use tracer_pipeline::{denoise, tiles, Error};

pub fn run(args: &MergeArgs) -> Result<()> {
    check_not_an_input(&args.output, &args.tiles).map_err(Error::from)?;
    let pending = PendingOutput::create(&args.output).map_err(Error::from)?;
    let depth = args.bit_depth.into();
    pending
        .check_render_options(depth, false)
        .map_err(Error::from)?;
    let read = args
        .tiles
        .iter()
        .map(|path| Ok((path.clone(), tiles::read(path)?)))
        .collect::<Result<Vec<_>, tiles::TileError>>()
        .map_err(Error::from)?;
    let mut picture = tiles::merge(&read).map_err(Error::from)?;
    let guides = tiles::merged_guides(&read);
    if args.denoise && guides.is_none() {
        return Err(Error::from(tiles::TileError::NoGuides).into());
    }
    let mut denoised = String::new();
    if let Some((guides, tiles_settings)) = guides {
        let settings = denoise::Settings {
            quality: args
                .denoise_quality
                .map_or(tiles_settings.quality, Into::into),
            prefilter: args
                .denoise_prefilter
                .map_or(tiles_settings.prefilter, Into::into),
        };
        let start = Instant::now();
        let threads = rayon::current_num_threads();
        picture.linear =
            denoise::denoise(&picture.linear, &guides, settings, threads).map_err(Error::from)?;
        denoised = format!(
            ", denoised ({}) in {:.3} s",
            settings.name(),
            start.elapsed().as_secs_f64()
        );
    }
    if let Some(warning) = pending.picture_warning(&picture) {
        note!("warning: {}: {warning}", args.output.display());
    }
    pending
        .write_picture(&picture, depth)
        .map_err(Error::from)?;
    let (width, height) = picture.dimensions();
    note!(
        "merged {} tiles ({width}x{height}){denoised} -> {}",
        read.len(),
        args.output.display()
    );
    Ok(())
}
