//! Whose autosave is whose: every running workbench has its own autosave file, and a lock
//! that says it is running; the autosaves of workbenches that ended without closing cleanly
//! are there for any later one to offer back.
//!
//! One file for every workbench of a user would let a second, clean workbench remove the
//! unsaved work of the first. Here each instance autosaves to `autosave-ID.session.json`
//! (ID random) in the settings' folder and holds an advisory lock (`flock`) on
//! `autosave-ID.lock` for as long as it runs. The kernel drops the lock when the process
//! ends, however it ends: an autosave whose lock can be taken belongs to no running
//! workbench, and a workbench that takes the lock owns that autosave from then on (no other
//! offers it meanwhile). One whose lock is held is never offered, nor removed. The single
//! `autosave.session.json` of earlier versions is found the same way (`autosave.lock`).
//!
//! Locks of `flock` belong to an open file description, not to a process, so two opens in
//! one process exclude each other as two processes do (byte-range `fcntl` locks would not).
//! Where the file system has no locks at all, no autosave is taken for abandoned.

use crate::files::atomic::{names_file, random};
use std::fs::{File, OpenOptions};
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::SystemTime;

/// The start of every autosave's name.
const PREFIX: &str = "autosave";
/// The end of an autosave's name.
const SESSION: &str = ".session.json";
/// The end of its lock's name.
const LOCK: &str = ".lock";

/// Names tried before giving up on a free one.
const ATTEMPTS: usize = 16;

/// A running workbench's autosave: its file, and the lock held while the workbench runs.
#[derive(Debug)]
pub struct Instance {
    dir: PathBuf,
    session: PathBuf,
    lock_path: PathBuf,
    /// Held for the instance's life; dropped (the lock with it) when the instance ends.
    _lock: File,
}

impl Instance {
    /// Starts an instance autosaving in `dir` (made if missing): a fresh name, locked.
    ///
    /// # Errors
    /// The folder or the lock file cannot be made, or the file system has no locks.
    pub fn start(dir: &Path) -> io::Result<Instance> {
        std::fs::create_dir_all(dir)?;
        for _ in 0..ATTEMPTS {
            let stem = format!("{PREFIX}-{:016x}", random());
            let lock_path = dir.join(format!("{stem}{LOCK}"));
            let file = match OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&lock_path)
            {
                Ok(f) => f,
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(e),
            };
            match file.try_lock() {
                // Still the file just made: a sweep of another instance may have taken the
                // unlocked file for an abandoned one and removed it in between.
                Ok(()) if names_file(&lock_path, &file) => {
                    return Ok(Instance {
                        dir: dir.to_path_buf(),
                        session: dir.join(format!("{stem}{SESSION}")),
                        lock_path,
                        _lock: file,
                    });
                }
                Ok(()) | Err(std::fs::TryLockError::WouldBlock) => {}
                Err(std::fs::TryLockError::Error(e)) => {
                    let _ = std::fs::remove_file(&lock_path);
                    return Err(io::Error::new(
                        e.kind(),
                        format!("{} cannot be locked: {e}", lock_path.display()),
                    ));
                }
            }
        }
        Err(io::Error::other(format!(
            "no free autosave name in {}",
            dir.display()
        )))
    }

    /// This instance's autosave file (there only while it has unsaved work).
    pub fn session_path(&self) -> &Path {
        &self.session
    }

    /// The autosaves of instances that are no longer running, newest first, each claimed
    /// (its lock held) for as long as the [`LeftBehind`] or a clone of it lives. Lock files
    /// of ended instances that left no autosave are removed on the way.
    pub fn left_behind(&self) -> Vec<LeftBehind> {
        let Ok(entries) = std::fs::read_dir(&self.dir) else {
            return Vec::new();
        };
        let mut found = Vec::new();
        for entry in entries.flatten() {
            let path = entry.path();
            if path == self.session || path == self.lock_path {
                continue;
            }
            let name = entry.file_name();
            let Some(name) = name.to_str() else { continue };
            if let Some(stem) = name.strip_suffix(SESSION).filter(|s| is_stem(s)) {
                let lock_path = self.dir.join(format!("{stem}{LOCK}"));
                if let Some(claim) = claim(&lock_path) {
                    found.push(LeftBehind {
                        modified: entry.metadata().and_then(|m| m.modified()).ok(),
                        session: path,
                        lock_path,
                        _claim: Arc::new(claim),
                    });
                }
            } else if let Some(stem) = name.strip_suffix(LOCK).filter(|s| is_stem(s))
                && !self.dir.join(format!("{stem}{SESSION}")).exists()
                && let Some(_claim) = claim(&path)
            {
                // An ended instance with nothing unsaved; removed while the lock is held.
                let _ = std::fs::remove_file(&path);
            }
        }
        found.sort_by_key(|l| std::cmp::Reverse(l.modified));
        found
    }
}

impl Drop for Instance {
    /// An instance that ends with nothing unsaved leaves nothing; one that ends with its
    /// autosave still there leaves it for a later one, as a crash would.
    fn drop(&mut self) {
        if !self.session.exists() {
            let _ = std::fs::remove_file(&self.lock_path);
        }
    }
}

/// The autosave of an instance that is no longer running, claimed by this one.
#[derive(Debug, Clone)]
pub struct LeftBehind {
    session: PathBuf,
    lock_path: PathBuf,
    modified: Option<SystemTime>,
    /// The lock, released when the last clone goes.
    _claim: Arc<File>,
}

impl LeftBehind {
    /// The autosave file.
    pub fn session_path(&self) -> &Path {
        &self.session
    }

    /// When it was last written.
    pub fn modified(&self) -> Option<SystemTime> {
        self.modified
    }

    /// Removes the autosave and its lock file: the work in it was discarded, or is this
    /// instance's own now. Still claimed meanwhile, so no other instance offers it.
    ///
    /// # Errors
    /// The autosave file is there and cannot be removed.
    pub fn remove(&self) -> io::Result<()> {
        match std::fs::remove_file(&self.session) {
            Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(e),
            _ => {}
        }
        let _ = std::fs::remove_file(&self.lock_path);
        Ok(())
    }
}

/// `autosave` (earlier versions' one file) or `autosave-ID`.
fn is_stem(stem: &str) -> bool {
    stem == PREFIX
        || stem
            .strip_prefix(PREFIX)
            .and_then(|s| s.strip_prefix('-'))
            .is_some_and(|id| !id.is_empty())
}

/// The lock at `lock_path` (made if missing: an autosave without one has no running
/// instance), when no running instance holds it.
fn claim(lock_path: &Path) -> Option<File> {
    let file = OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(lock_path)
        .ok()?;
    file.try_lock().ok()?;
    names_file(lock_path, &file).then_some(file)
}
