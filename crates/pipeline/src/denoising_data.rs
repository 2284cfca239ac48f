//! `tracer render --denoise --denoising-data -o OUT.exr`: the denoised
//! image and what went into the denoiser, in one OpenEXR file (Blender's
//! "Denoising Data" pass keeps the same beside its denoised image).
//!
//! One part, of 32-bit float channels: `R`, `G`, `B`, OpenEXR's default
//! layer (the one a viewer shows, and the one a reader of plain RGB
//! files reads), hold the denoised image; the layers `noisy`, `albedo`,
//! `normal` and `emission` (channels `noisy.R`, ...) the render before
//! denoising and the guides as rendered (not OIDN's prefiltered copies):
//! the albedo as `--aov albedo` gives it, the normal as OIDN takes it, -1
//! to 1 (`--aov shading-normal` writes `(n + 1) / 2`), and the light seen
//! directly that the denoiser left out and added back (`--aov emission`
//! gives it sampled apart; here it is what the render's own camera rays
//! met, and what mirrors and glass show: `denoise/emission.rs`). Layers in one part rather than one part each:
//! every OpenEXR reader reads one part, older ones only that.

use crate::output::{exr_error, OutputError};
use crate::rendered::Denoising;
use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, LayerAttributes, SmallVec,
    WritableImage,
};
use tracer_core::LinearImage;

/// The layers beside the default one, as the file names them.
pub const NOISY: &str = "noisy";
pub const ALBEDO: &str = "albedo";
pub const NORMAL: &str = "normal";
pub const EMISSION: &str = "emission";

/// The bytes of the file of `denoised`, the render's image after
/// `denoising` (which holds the image before, as a whole image denoised
/// does: a tile, not denoised, has no data to keep).
pub fn encode(denoised: &LinearImage, denoising: &Denoising) -> Result<Vec<u8>, OutputError> {
    let noisy = denoising.noisy.as_ref().ok_or(OutputError::NotDenoised)?;
    let guides = &denoising.guides;
    let layers = [
        (None, denoised),
        (Some(NOISY), noisy),
        (Some(ALBEDO), &guides.albedo),
        (Some(NORMAL), &guides.normal),
        (Some(EMISSION), &guides.emission),
    ];
    let mut channels = SmallVec::new();
    for (layer, image) in layers {
        for (axis, name) in ["R", "G", "B"].into_iter().enumerate() {
            let name = match layer {
                Some(layer) => format!("{layer}.{name}"),
                None => name.to_string(),
            };
            let samples = image.pixels.iter().map(|c| c[axis]).collect();
            channels.push(AnyChannel::new(name.as_str(), FlatSamples::F32(samples)));
        }
    }
    let size = (denoised.width as usize, denoised.height as usize);
    let layer = Layer::new(
        size,
        LayerAttributes::default(),
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(channels),
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .non_parallel()
        .to_buffered(&mut bytes)
        .map_err(exr_error)?;
    Ok(bytes.into_inner())
}
