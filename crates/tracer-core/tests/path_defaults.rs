//! Path mode's estimator where a scene file leaves it (`integrate::path::defaults`):
//! path reuse and more camera rays in rooms lit by their lamps, neither
//! under an environment; adaptive sampling where the noise gathers; and a
//! key the file sets kept as it is.

use std::path::Path;
use tracer_core::prepare;

/// `render.path_reuse` and `render.camera_rays` as path mode takes them
/// for `scenes/NAME`, with the file's keys `set` (path reuse, camera rays).
fn estimator(name: &str, set: (Option<u32>, Option<u32>)) -> (u32, u32) {
    estimator_of(name, set, false)
}

/// `estimator`, the image `denoised` or not.
fn estimator_of(name: &str, set: (Option<u32>, Option<u32>), denoised: bool) -> (u32, u32) {
    let mut file = load(name);
    (file.render.path_reuse, file.render.camera_rays) = set;
    file.render.denoise = denoised;
    let scene = prepare(&file).expect("prepare");
    let trace = scene.trace_settings();
    (trace.path_reuse, trace.camera_rays)
}

/// `scenes/NAME`, as read.
fn load(name: &str) -> scene_format::SceneFile {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    scene_format::load_path(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Neither key set.
const SILENT: (Option<u32>, Option<u32>) = (None, None);

#[test]
fn rooms_lit_by_lamps_share_paths_and_look_again_at_lamp_edges() {
    assert_eq!(estimator("cornell-box.toml", SILENT), (8, 8));
    assert_eq!(estimator("global-illumination.toml", SILENT), (8, 8));
}

#[test]
fn without_an_emitting_surface_only_paths_are_shared() {
    // Its light is a point light: no lamp's edge to be seen.
    assert_eq!(estimator("gltf-box.toml", SILENT), (8, 1));
}

#[test]
fn under_an_environment_paths_are_shared_unless_glass_is_there() {
    // The materials scene's spheres of glass hold its noise: sharing
    // costs time for nothing. The courtyard's copper throws the sun.
    assert_eq!(estimator("materials.toml", SILENT), (1, 1));
    assert_eq!(estimator("courtyard.toml", SILENT), (8, 1));
}

#[test]
fn a_denoised_image_traces_every_path_alone_and_looks_again_at_edges() {
    // The denoiser takes that noise off; what the camera rays see directly
    // it is not given, so their edges want more of them.
    let rays = tracer_core::integrate::path::defaults::DENOISED_CAMERA_RAYS;
    assert_eq!(estimator_of("cornell-box.toml", SILENT, true), (1, rays));
    assert_eq!(estimator_of("materials.toml", SILENT, true), (1, rays));
    assert_eq!(
        estimator_of("cornell-box.toml", (Some(8), None), true),
        (8, rays)
    );
    assert_eq!(
        estimator_of("cornell-box.toml", (None, Some(2)), true),
        (1, 2)
    );
}

#[test]
fn what_the_file_says_is_kept() {
    assert_eq!(estimator("cornell-box.toml", (Some(1), Some(3))), (1, 3));
    assert_eq!(estimator("materials.toml", (Some(4), Some(2))), (4, 2));
    assert_eq!(estimator("materials.toml", (None, Some(2))), (1, 2));
}

/// Whether path mode samples `scenes/NAME` adaptively where the file is
/// silent, the image `denoised` or not.
fn adaptive(name: &str, denoised: bool) -> bool {
    let mut file = load(name);
    file.render.adaptive = None;
    file.render.denoise = denoised;
    prepare(&file).expect("prepare").trace_settings().adaptive
}

#[test]
fn paths_go_where_the_noise_gathers_under_a_sky_or_round_glossy_things_by_a_lamp() {
    // Under an environment, and where a lamp is thrown about by gold or glass.
    assert!(adaptive("materials.toml", false));
    assert!(adaptive("courtyard.toml", false));
    assert!(adaptive("cornell-bunny.toml", false));
    assert!(adaptive("global-illumination.toml", false));
    // A matte room's noise is even; a point light is never met by chance.
    assert!(!adaptive("cornell-box.toml", false));
    assert!(!adaptive("gltf-box.toml", false));
    // The denoiser was measured on even noise.
    assert!(!adaptive("cornell-bunny.toml", true));
    assert!(!adaptive("materials.toml", true));
}
