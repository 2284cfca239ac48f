//! Path mode's estimator where the scene file leaves it to the renderer:
//! one rule, decided by `cargo xtask bench --only path` on its four scenes
//! (error at equal time, docs/src/performance.md). Path reuse and more
//! camera rays take noise off a room lit by its lamps (the Cornell box's
//! error at equal time falls to about 0.4 of the plain estimator's).
//! Path reuse takes off the caustics of rough metals too, under an
//! environment as well (the courtyard's sun in its copper: 0.6), but not
//! where glass is under an environment: the noise is in the glass then,
//! which it cannot share, and it costs time for nothing (the materials
//! scene). More camera rays cost time for nothing under an environment
//! (its sky seen directly changes gently). Both stay off too where
//! the image is denoised: the denoiser takes that noise off anyway and
//! adds back the light a pixel sees directly from its own finer guide, and
//! path reuse's noise, alike along a row's groups, is harder for it (the
//! Cornell box at 16 paths, denoised: RMSE 0.0065 in 2.2 s with both off,
//! 0.0075 in 2.6 s with both on).

/// The pixels of a row that share their indirect light
/// (`render.path_reuse`) when the file does not say, in a scene lit by an
/// `environment` or not, holding `glass` (some material lets light
/// through) or not, `denoised` or not.
pub fn path_reuse(environment: bool, glass: bool, denoised: bool) -> u32 {
    if (environment && glass) || denoised {
        1
    } else {
        8
    }
}

/// The camera rays of a path for what a pixel sees directly
/// (`render.camera_rays`) when the file does not say: where the image is
/// denoised, `DENOISED_CAMERA_RAYS` (the denoiser is given the render less
/// that light, and adds back what the camera rays saw: at a lamp's edge
/// that is the edge's noise, which it would not remove); otherwise only
/// where lamps can be seen (emitting surfaces) and no environment lights
/// the scene.
pub fn camera_rays(environment: bool, emitters: bool, denoised: bool) -> u32 {
    if denoised {
        DENOISED_CAMERA_RAYS
    } else if !environment && emitters {
        8
    } else {
        1
    }
}

/// Camera rays a path where the image is denoised: the Cornell box at 16
/// paths, denoised, RMSE 0.0192 with 1 (the lamp's edges as noisy as the
/// render has them), 0.0039 with 8, 0.0031 with 16, 0.0029 with 32 or 64
/// (against noisy 0.0266).
pub const DENOISED_CAMERA_RAYS: u32 = 16;

/// Whether path mode samples adaptively (`render.adaptive`, `adaptive.rs`)
/// when the file does not say: where the noise gathers in a few places
/// while the rest is clean. That is under an environment (glass, glossy
/// reflections and shadows under a clean sky: error at equal time about
/// 0.7 to 0.8 of even sampling's), and in a room whose lamps (`emitters`)
/// some `glossy` material (more than a Lambertian lobe) throws about: the
/// bunny's room's gold ball casts its lamp on the floor (0.63 against
/// 0.74 on 1 thread, 0.65 against 0.80 on 2), the glass ball of
/// `global-illumination.toml` focuses its panel (0.84). Not in a matte
/// room, whose noise is spread evenly (the Cornell box, 0.41 against 0.37),
/// nor where only point lights shine on glossy things (a point light is
/// never met by chance; `gltf-box.toml`, 1.02), nor where the image is
/// denoised (the denoiser was measured on even noise).
pub fn adaptive(environment: bool, emitters: bool, glossy: bool, denoised: bool) -> bool {
    (environment || (emitters && glossy)) && !denoised
}
