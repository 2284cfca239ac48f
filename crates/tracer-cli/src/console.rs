//! Writing to stdout and stderr without panicking (`println!` panics when
//! the write fails: a full disk, a closed pipe).
//!
//! stderr carries messages only: a failed write there is ignored, so a
//! full stderr never stops a render or loses its image. stdout carries a
//! command's result: a failed write is an error (exit 1), except a closed
//! pipe (`tracer schema | head -1`), which ends the command quietly.

use std::fmt;
use std::io::{self, Write};

/// One line on stderr, as `eprintln!` without the panic.
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::console::stderr(format_args!("{}\n", format_args!($($arg)*)))
    };
}
pub(crate) use note;

/// Text on stderr; a failure to write it is ignored (see the module).
pub fn stderr(args: fmt::Arguments) {
    let _ = io::stderr().lock().write_fmt(args);
}

/// The reader of stdout went away: not an error, the command just stops.
#[derive(Debug)]
pub struct ClosedPipe;

impl fmt::Display for ClosedPipe {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("stdout was closed")
    }
}

impl std::error::Error for ClosedPipe {}

/// `text` on stdout, flushed; a closed pipe is [`ClosedPipe`].
pub fn stdout(text: &str) -> anyhow::Result<()> {
    let mut out = io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Err(ClosedPipe.into()),
        Err(e) => Err(anyhow::Error::new(e).context("cannot write to stdout")),
    }
}
