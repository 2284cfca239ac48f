//! What the `tracer` command shares with the project's tools (`xtask`):
//! writing output files whole or not at all.

pub mod output;
