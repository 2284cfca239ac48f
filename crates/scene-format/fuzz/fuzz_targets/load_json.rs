#![no_main]

mod check;

libfuzzer_sys::fuzz_target!(|data: &[u8]| check::check(data, scene_format::Format::Json));
