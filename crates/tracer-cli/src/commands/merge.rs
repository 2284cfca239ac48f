//! `tracer merge`: render-farm tiles in, the whole image out, written whole
//! or not at all once every tile is checked.

use crate::args::MergeArgs;
use crate::console::note;
use anyhow::Result;
use tracer_pipeline::output::{check_not_an_input, PendingOutput};
use tracer_pipeline::{tiles, Error};

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
    let picture = tiles::merge(&read).map_err(Error::from)?;
    if let Some(warning) = pending.picture_warning(&picture) {
        note!("warning: {}: {warning}", args.output.display());
    }
    pending
        .write_picture(&picture, depth)
        .map_err(Error::from)?;
    let (width, height) = picture.dimensions();
    note!(
        "merged {} tiles ({width}x{height}) -> {}",
        read.len(),
        args.output.display()
    );
    Ok(())
}
