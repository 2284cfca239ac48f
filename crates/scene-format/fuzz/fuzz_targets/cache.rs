#![no_main]
//! A `--cache` entry's payload on any bytes (as a writer holding the
//! checksum's key could make it): refused with a reason, or a scene that
//! renders a few pixels without a panic.

use tracer_pipeline::{cache, render_prepared, Options, Part, Region};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Ok(prepared) = cache::decode_payload(data) else {
        return;
    };
    let (width, height) = prepared.size();
    let options = Options {
        part: Some(Part::Region(Region {
            x0: 0,
            y0: 0,
            x1: width.min(3),
            y1: height.min(3),
        })),
        ..Options::default()
    };
    let _ = render_prepared(&prepared, &options, &|_| {});
});
