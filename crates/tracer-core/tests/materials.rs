//! `scenes/materials.toml` (rough and smooth metal and glass under a studio
//! environment) against Mitsuba 3: `tests/data/materials-mitsuba.exr` is
//! Mitsuba's render of the same file (`xtask/peers/toml_scene.py reference`,
//! which builds Mitsuba's scene from the TOML: `roughconductor`,
//! `roughdielectric`, `envmap`; see `tests/data/README.md`).

mod mitsuba;

use mitsuba::{assert_agrees, reference, scene};

#[test]
fn the_materials_scene_agrees_with_mitsuba_3() {
    // Many seeds of few paths: the spread of 32 renders estimates a block's
    // noise well enough for 450 blocks at 4 standard errors, even where the
    // rough glass throws fireflies.
    let reference = reference("materials-mitsuba.exr", 480, 240);
    assert_agrees(
        &scene("materials.toml"),
        &reference,
        (8448, 0.0),
        32,
        (4, 1, 1),
    );
}
