#![no_main]
//! A zip pack on any bytes: the scene inside loads or is refused with a
//! reason, never a panic, and the archive is never read past its bytes.

use scene_format::source::Archive;
use std::path::Path;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(archive) = Archive::from_bytes(Path::new("fuzz.zip"), data.to_vec()) else {
        return;
    };
    let scene = archive.scene().to_path_buf();
    if let Err(e) = scene_format::load_from(&archive, &scene) {
        let _ = e.to_string();
    }
});
