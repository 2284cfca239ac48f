//! The `tracer` command line as clap defines it, as a library so that
//! `cargo xtask man` makes the man pages from the very definition the
//! binary parses.

pub mod args;
mod cli;
pub mod compare_args;
pub mod tool_args;

pub use cli::{book_note, command, parse, Cli, Command};
