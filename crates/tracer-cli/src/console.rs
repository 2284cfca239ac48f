//! Writing to stdout and stderr without panicking (`println!` panics when
//! the write fails: a full disk, a closed pipe).
//!
//! stderr carries messages only: a failed write there is ignored, so a
//! full stderr never stops a render or loses its image. stdout carries a
//! command's result: a failed write is an error (exit 1), except a closed
//! pipe (`tracer schema | head -1`), which ends the command quietly.
//!
//! A message often holds a name from a file (a path, a material): its
//! control and bidirectional characters are written as visible escapes
//! (`scene_format::visible`), so none reaches the terminal as such.

use scene_format::visible::VisibleWriter;
use std::fmt;
use std::io::{self, Write};

/// One line on stderr, as `eprintln!` without the panic.
macro_rules! note {
    ($($arg:tt)*) => {
        $crate::console::stderr(format_args!("{}\n", format_args!($($arg)*)))
    };
}
pub(crate) use note;

/// Text on stderr, control characters made visible; a failure to write it
/// is ignored (see the module).
pub fn stderr(args: fmt::Arguments) {
    let mut err = io::stderr().lock();
    let mut out = VisibleWriter {
        inner: Bytes(&mut err),
    };
    let _ = fmt::Write::write_fmt(&mut out, args);
}

/// A scene error's report on stderr as `report::render` made it: its
/// colours are escape sequences of its own, and the names and lines it
/// quotes from the file are escaped already.
pub fn stderr_report(text: &str) {
    let _ = io::stderr().lock().write_all(text.as_bytes());
}

/// `fmt::Write` onto an `io::Write`.
pub struct Bytes<'a, W>(pub &'a mut W);

impl<W: Write> fmt::Write for Bytes<'_, W> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.0.write_all(s.as_bytes()).map_err(|_| fmt::Error)
    }
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

/// What `write` writes, on stdout (buffered), flushed: a long result
/// written as it is made; a closed pipe is [`ClosedPipe`].
pub fn stdout_streamed(write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> anyhow::Result<()> {
    let mut out = io::BufWriter::new(io::stdout().lock());
    match write(&mut out).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Err(ClosedPipe.into()),
        Err(e) => Err(anyhow::Error::new(e).context("cannot write to stdout")),
    }
}

/// `text` on stdout, flushed; a closed pipe is [`ClosedPipe`].
pub fn stdout(text: &str) -> anyhow::Result<()> {
    let mut out = io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Err(ClosedPipe.into()),
        Err(e) => Err(anyhow::Error::new(e).context("cannot write to stdout")),
    }
}
