//! A source of no files: what a fuzz input names is never read from the
//! machine's file system.

use scene_format::source::Source;
use std::io::{self, BufRead};
use std::path::{Path, PathBuf};

pub struct Nothing;

impl Source for Nothing {
    fn open(&self, _: &Path, _: u64) -> io::Result<Box<dyn BufRead + '_>> {
        Err(io::Error::new(io::ErrorKind::NotFound, "no files in a fuzz run"))
    }
    fn name(&self, path: &Path) -> PathBuf {
        path.to_path_buf()
    }
    fn identity(&self, path: &Path) -> PathBuf {
        path.to_path_buf()
    }
    fn files_read(&self) -> Vec<PathBuf> {
        Vec::new()
    }
}
