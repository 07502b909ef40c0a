//! Autosave: while there is unsaved work the workbench writes the session beside its settings
//! every few seconds, and removes the file when the work is saved or discarded or the window
//! closes cleanly. A file still there at the next start means the workbench did not close
//! cleanly (a crash, a killed process, a power cut), and the work in it is offered back.

use super::state::AppState;
use crate::files::session;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Receiver};
use std::time::{Duration, Instant, SystemTime};

/// How often unsaved work is written.
pub const INTERVAL: Duration = Duration::from_secs(15);

/// The autosave file of one workbench.
pub struct Autosave {
    path: Option<PathBuf>,
    last_check: Option<Instant>,
    /// The session last written (its JSON), to skip writing the same work again.
    written: Option<String>,
    /// A write on its way: the worker answers with its error, if any.
    writing: Option<Receiver<Result<(), String>>>,
    /// The last write's error, shown once in the status bar.
    pub error: Option<String>,
}

/// Work left behind by a workbench that did not close cleanly.
#[derive(Debug, Clone)]
pub struct LeftBehind {
    /// The autosave file.
    pub path: PathBuf,
    /// When it was written.
    pub modified: Option<SystemTime>,
    /// The log it was working on.
    pub log: Option<PathBuf>,
}

impl Autosave {
    /// Autosave to `path`; `None` turns it off (tests, screenshots).
    pub fn new(path: Option<PathBuf>) -> Autosave {
        Autosave {
            path,
            last_check: None,
            written: None,
            writing: None,
            error: None,
        }
    }

    /// The autosave file beside a settings file.
    pub fn path_beside(settings: &Path) -> PathBuf {
        settings.with_file_name("autosave.session.json")
    }

    /// The work an earlier workbench left behind, when its file is there and reads as a
    /// session that names a log.
    pub fn left_behind(&self) -> Option<LeftBehind> {
        let path = self.path.as_ref()?;
        let s = session::load(path).ok()?;
        let log = s.log.map(|l| l.path)?;
        Some(LeftBehind {
            path: path.clone(),
            modified: std::fs::metadata(path).and_then(|m| m.modified()).ok(),
            log: Some(log),
        })
    }

    /// Called every frame: every [`INTERVAL`], writes the session when there is unsaved work
    /// that differs from the last write, and removes the file when there is none.
    pub fn tick(&mut self, state: &AppState) {
        let now = Instant::now();
        if self.last_check.is_some_and(|t| now < t + INTERVAL) {
            return;
        }
        self.last_check = Some(now);
        self.save_now(state);
    }

    /// Writes (or removes) the autosave file now, in the background.
    pub fn save_now(&mut self, state: &AppState) {
        let Some(path) = self.path.clone() else {
            return;
        };
        if let Some(rx) = &self.writing {
            match rx.try_recv() {
                Ok(r) => self.error = r.err(),
                Err(mpsc::TryRecvError::Empty) => return,
                Err(mpsc::TryRecvError::Disconnected) => {}
            }
            self.writing = None;
        }
        if !state.dirty() {
            if self.written.take().is_some() || path.exists() {
                let _ = std::fs::remove_file(&path);
            }
            return;
        }
        let s = state.session();
        let json = session::to_json(&s);
        if self.written.as_ref() == Some(&json) {
            return;
        }
        self.written = Some(json);
        let (tx, rx) = mpsc::channel();
        self.writing = Some(rx);
        let spawned = std::thread::Builder::new()
            .name("driftlab-autosave".into())
            .spawn(move || {
                if let Some(dir) = path.parent() {
                    let _ = std::fs::create_dir_all(dir);
                }
                let _ = tx.send(session::save(&path, &s).map_err(|e| e.to_string()));
            });
        if spawned.is_err() {
            self.writing = None;
            self.error = Some("could not start the autosave".into());
        }
    }

    /// Waits for a write on its way (tests, and before removing the file).
    pub fn flush(&mut self) {
        if let Some(rx) = self.writing.take()
            && let Ok(r) = rx.recv_timeout(Duration::from_secs(10))
        {
            self.error = r.err();
        }
    }

    /// Removes the file: the work was saved, discarded, or the window closed cleanly.
    pub fn clear(&mut self) {
        self.flush();
        self.written = None;
        if let Some(p) = &self.path {
            let _ = std::fs::remove_file(p);
        }
    }

    /// The autosave file, when autosave is on.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }
}
