//! Scene file and options in, image out: the one way the tracer makes an
//! image, used by the `tracer` command and by `cargo xtask golden`, so the
//! goldens check exactly what `tracer` writes.
//!
//! [`load`] reads a scene (a file or the built-in one) and says which files
//! it read; [`render`] makes the linear image and its encoding; [`output`]
//! writes it in the format of its extension, whole or not at all. [`lab`]
//! makes the lab's calibration chart and gamma fit.

pub mod cache;
mod clock;
pub mod denoise;
pub mod denoising_data;
mod error;
pub mod explain;
pub mod explain_draw;
pub mod explain_scene;
pub mod explain_steps;
pub mod explain_text;
pub mod lab;
mod limits;
mod load;
mod model_summary;
mod options;
pub mod output;
pub mod pack;
pub mod reference;
mod render;
mod rendered;
mod scene3d;
pub mod tiles;

pub use error::{scene_error_is_bad_input, Error};
pub use limits::{BYTES_PER_PRIMITIVE, MAX_PRIMITIVES};
pub use load::{
    as_written, load, load_from, load_or_part, Checked, Input, Loaded, Warning, DEFAULT_SCENE_NAME,
};
pub use model_summary::{summary, Bounds, SceneSummary};
pub use options::{tile_region, Aov, Gamma, Options, Part, Region};
#[cfg(not(target_arch = "wasm32"))]
pub use render::denoise_picture;
pub use render::{
    default_output, denoise_rendered, image_size, next_pass_samples, next_pass_seconds,
    prepare_taking, render, render_cancellable, render_prepared, render_prepared_progressive,
    render_progressive, render_taking,
};
pub use rendered::{
    Denoising, Estimator, Picture, Rendered, ShadedStats, Summary, FORCED_WHITE_WARNING,
};
pub use scene3d::{Pass, PassCallbacks, PreparedScene};
pub use tracer_core::LinearImage;
