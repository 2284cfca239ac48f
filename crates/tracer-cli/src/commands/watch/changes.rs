//! Which files the scene reads, and whether any of them changed: a
//! `notify` watcher on their folders, a flag a render in progress reads
//! (so an edit cancels it at once), and a channel the loop waits on.

use anyhow::{Context, Result};
use notify::{RecursiveMode, Watcher};
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, Receiver};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// How long the files must stay quiet before the scene is read again: an
/// editor's save is often several writes (truncate, write, rename).
const SETTLE: Duration = Duration::from_millis(80);

pub struct Changes {
    watcher: notify::RecommendedWatcher,
    /// The files watched, by absolute path.
    files: Arc<Mutex<HashSet<PathBuf>>>,
    folders: HashSet<PathBuf>,
    /// Set as soon as a watched file changes; the render reads it.
    pending: Arc<AtomicBool>,
    events: Receiver<()>,
}

impl Changes {
    pub fn new() -> Result<Changes> {
        let files: Arc<Mutex<HashSet<PathBuf>>> = Arc::default();
        let pending = Arc::new(AtomicBool::new(false));
        let (send, events) = channel();
        let (watched, flag) = (files.clone(), pending.clone());
        let watcher = notify::recommended_watcher(move |event: notify::Result<notify::Event>| {
            let Ok(event) = event else { return };
            if event.kind.is_access() {
                return;
            }
            let files = watched.lock().expect("the watch list");
            if event.paths.iter().any(|p| files.contains(p)) {
                flag.store(true, Ordering::Relaxed);
                let _ = send.send(());
            }
        })
        .context("cannot watch files for changes")?;
        Ok(Changes {
            watcher,
            files,
            folders: HashSet::new(),
            pending,
            events,
        })
    }

    /// Watches `files` (and stops watching the others). Their folders are
    /// watched rather than the files themselves: editors save by writing a
    /// new file and renaming it over the old one, which ends a watch on it.
    /// A folder that cannot be watched (gone, or inside an archive's name)
    /// is left out: it cannot change what renders.
    pub fn watch(&mut self, files: &[PathBuf]) {
        let absolute: HashSet<PathBuf> = files.iter().map(|f| absolute(f)).collect();
        let folders: HashSet<PathBuf> = absolute
            .iter()
            .filter_map(|f| f.parent().map(Path::to_path_buf))
            .collect();
        for gone in self.folders.difference(&folders) {
            let _ = self.watcher.unwatch(gone);
        }
        let mut watched = HashSet::new();
        for folder in folders {
            let ok = self.folders.contains(&folder)
                || self
                    .watcher
                    .watch(&folder, RecursiveMode::NonRecursive)
                    .is_ok();
            if ok {
                watched.insert(folder);
            }
        }
        self.folders = watched;
        *self.files.lock().expect("the watch list") = absolute;
    }

    /// The flag that says a watched file changed: a render reads it to stop.
    pub fn pending(&self) -> &AtomicBool {
        &self.pending
    }

    /// Waits for a change to a watched file, then for the files to settle.
    pub fn wait(&self) {
        if !self.pending.load(Ordering::Relaxed) && self.events.recv().is_err() {
            return;
        }
        self.settle();
    }

    /// Waits until no change came for `SETTLE`, then clears the flag.
    fn settle(&self) {
        // Ends on a quiet spell (or a watcher gone).
        while self.events.recv_timeout(SETTLE).is_ok() {}
        self.pending.store(false, Ordering::Relaxed);
    }
}

/// `path` made absolute and its folder resolved (symbolic links, `..`), as
/// the watcher reports paths; the file itself may be missing for a while.
fn absolute(path: &Path) -> PathBuf {
    let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    match (path.parent(), path.file_name()) {
        (Some(folder), Some(name)) => folder.canonicalize().map(|f| f.join(name)).unwrap_or(path),
        _ => path,
    }
}
