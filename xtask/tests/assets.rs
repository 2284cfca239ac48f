//! The generated files in the repository are what `cargo xtask assets`
//! makes today.

#[test]
fn committed_assets_are_current() {
    let stale = xtask::assets::stale(&xtask::workspace_root());
    assert!(
        stale.is_empty(),
        "{stale:?} differ from what the generator makes: run `cargo xtask assets`"
    );
}
