//! Autosave: while there is unsaved work the workbench writes the session beside its settings
//! every few seconds, and removes the file when the work is saved or discarded or the window
//! closes cleanly. Each running workbench has its own file, locked while it runs
//! ([`crate::files::autosave`]): a file still there whose lock is free means its workbench
//! did not close cleanly (a crash, a killed process, a power cut), and the next workbench to
//! start offers the work in it back. A second workbench never touches the first one's file.

use super::state::AppState;
use crate::files::autosave::{self, Instance};
use crate::files::session;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Receiver};
use std::time::{Duration, Instant, SystemTime};

/// How often unsaved work is written.
pub const INTERVAL: Duration = Duration::from_secs(15);

/// The autosave of one workbench.
pub struct Autosave {
    /// This workbench's file and lock; none when autosave is off.
    instance: Option<Instance>,
    /// Work of an ended workbench restored here: its file stays (claimed) until this
    /// workbench's own autosave holds the work, or the work is saved or discarded.
    adopted: Vec<autosave::LeftBehind>,
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
    /// Its lock, held while it is offered, so no other workbench offers it too.
    claim: autosave::LeftBehind,
}

impl Autosave {
    /// Autosave in the folder of the settings file `settings`; `None` turns it off (tests,
    /// screenshots). A folder where it cannot start turns it off too, and says why once.
    pub fn beside(settings: Option<&Path>) -> Autosave {
        let mut a = Autosave {
            instance: None,
            adopted: Vec::new(),
            last_check: None,
            written: None,
            writing: None,
            error: None,
        };
        let dir = settings.map(|s| match s.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        });
        if let Some(dir) = dir {
            match Instance::start(dir) {
                Ok(i) => a.instance = Some(i),
                Err(e) => a.error = Some(format!("autosave is off: {e}")),
            }
        }
        a
    }

    /// The work earlier workbenches left behind, newest first: those whose files read as
    /// a session that names a log.
    pub fn left_behind(&self) -> Vec<LeftBehind> {
        let Some(instance) = &self.instance else {
            return Vec::new();
        };
        instance
            .left_behind()
            .into_iter()
            .filter_map(|claim| {
                let s = session::load(claim.session_path()).ok()?;
                let log = s.log.map(|l| l.path)?;
                Some(LeftBehind {
                    path: claim.session_path().to_path_buf(),
                    modified: claim.modified(),
                    log: Some(log),
                    claim,
                })
            })
            .collect()
    }

    /// The work `left` is being restored here: its file goes once this workbench's own
    /// autosave holds the work, or the work is saved or discarded.
    pub fn adopt(&mut self, left: LeftBehind) {
        self.adopted.push(left.claim);
    }

    /// The work `left` is discarded: its file is removed.
    pub fn discard(&mut self, left: LeftBehind) {
        if let Err(e) = left.claim.remove() {
            self.error = Some(format!("{}: {e}", left.path.display()));
        }
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
        let Some(path) = self.path().map(Path::to_path_buf) else {
            return;
        };
        if let Some(rx) = &self.writing {
            match rx.try_recv() {
                Ok(r) => self.written_back(r),
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
            self.written_back(r);
        }
    }

    /// A write's answer: its error, or the restored work now held by this workbench's own
    /// autosave (the file it came from is no longer needed).
    fn written_back(&mut self, result: Result<(), String>) {
        match result {
            Ok(()) => self.drop_adopted(),
            Err(e) => self.error = Some(e),
        }
    }

    /// Removes the files of restored work.
    fn drop_adopted(&mut self) {
        for left in std::mem::take(&mut self.adopted) {
            if let Err(e) = left.remove() {
                self.error = Some(format!("{}: {e}", left.session_path().display()));
            }
        }
    }

    /// Removes the file, and those of restored work: the work was saved, discarded, or the
    /// window closed cleanly.
    pub fn clear(&mut self) {
        self.flush();
        self.written = None;
        if let Some(p) = self.path() {
            let _ = std::fs::remove_file(p);
        }
        self.drop_adopted();
    }

    /// This workbench's autosave file, when autosave is on.
    pub fn path(&self) -> Option<&Path> {
        self.instance.as_ref().map(Instance::session_path)
    }
}
