//! Path mode's estimator where the scene file leaves it to the renderer:
//! one rule, decided by `cargo xtask bench --only path` on its four scenes
//! (error at equal time, docs/src/performance.md). Path reuse and more
//! camera rays take noise off a room lit by its lamps (the Cornell box's
//! error at equal time falls to about 0.4 of the plain estimator's, the
//! bunny in it to 0.9) and cost time for nothing where an environment
//! lights an open scene (its direct light dominates, and its sky seen
//! directly changes gently): there they stay off.

/// The pixels of a row that share their indirect light
/// (`render.path_reuse`) when the file does not say.
pub fn path_reuse(environment: bool) -> u32 {
    if environment {
        1
    } else {
        8
    }
}

/// The camera rays of a path for what a pixel sees directly
/// (`render.camera_rays`) when the file does not say: only where lamps
/// can be seen (emitting surfaces) and no environment lights the scene.
pub fn camera_rays(environment: bool, emitters: bool) -> u32 {
    if !environment && emitters {
        8
    } else {
        1
    }
}
