//! Headless Chromium for the project's own tests and bench, never for
//! rendering: finding it, the DOM of a local page once its scripts ran
//! (`dom.rs`, with what a report page's image check records there), and a
//! DevTools session that scripts a live page (`browser.rs`).

mod browser;
mod dom;

pub use browser::{base64_decode, Browser};
pub use dom::{dump_dom, image_check, ImageCheck};

use std::io::Write;
use std::path::PathBuf;

/// Names Chromium goes by, Debian's first; `CHROMIUM` names a binary explicitly.
const NAMES: [&str; 3] = ["chromium", "chromium-browser", "google-chrome"];

/// The Chromium binary, if there is one.
pub fn find_chromium() -> Option<PathBuf> {
    if let Some(path) = std::env::var_os("CHROMIUM").filter(|p| !p.is_empty()) {
        return Some(PathBuf::from(path));
    }
    let dirs: Vec<PathBuf> = std::env::split_paths(&std::env::var_os("PATH")?).collect();
    NAMES
        .iter()
        .flat_map(|name| dirs.iter().map(move |dir| dir.join(name)))
        .find(|path| path.is_file())
}

/// Chromium for a test of `what`, or None with a notice. Under CI (env
/// `CI` set) a missing Chromium fails the test instead: `.ci/run` installs
/// it.
pub fn chromium_for_test(what: &str) -> Option<PathBuf> {
    let found = find_chromium();
    if found.is_none() {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI is set but Chromium is missing: .ci/run installs Debian's `chromium` package"
        );
        // Straight to the stderr handle: libtest captures eprintln! of passing tests.
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED: {what} needs Chromium (Debian: apt-get install chromium; \
             or set CHROMIUM=/path/to/binary)"
        );
    }
    found
}
