#![no_main]
//! The MTL reader on any bytes: materials with warnings, or an error, never
//! a panic. (cargo fuzz builds with debug assertions, so the reader's own
//! check that each material it makes passes the scene file's checks runs
//! on every input.)

mod nothing;

use scene_format::images::ImageCache;
use std::path::Path;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let mut images = ImageCache::default();
    let source = nothing::Nothing;
    if let Ok(found) = scene_format::mtl::read_mtl_bytes(data, Path::new("m"), &source, &mut images) {
        let _ = found.warnings.join("\n");
    }
});
