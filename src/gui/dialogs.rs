//! File dialogs behind a small interface: the desktop uses rfd's native dialogs; tests (and
//! scripts) inject the paths a person would have picked.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// What a file dialog is for (its title and file-type filter).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    /// A chamber log (CSV or text).
    Log,
    /// A held-out validation log.
    ValidationLog,
    /// A workbench session (JSON).
    Session,
    /// A calibration file (JSON).
    Calibration,
    /// A calibration file of a model chosen in the Models view (JSON).
    Model,
    /// The corrected log (CSV).
    CorrectedCsv,
    /// A picture (PNG).
    Png,
    /// The test report (a folder of figures and one HTML page).
    Report,
}

impl FileKind {
    /// Dialog title.
    pub fn title(self) -> &'static str {
        match self {
            FileKind::Log => "Open chamber log",
            FileKind::ValidationLog => "Open validation log",
            FileKind::Session => "Workbench session",
            FileKind::Calibration => "Export calibration",
            FileKind::Model => "Export model",
            FileKind::CorrectedCsv => "Export corrected log",
            FileKind::Png => "Save picture",
            FileKind::Report => "Export test report (a folder)",
        }
    }

    /// Filter name and extensions.
    pub fn filter(self) -> (&'static str, &'static [&'static str]) {
        match self {
            FileKind::Log | FileKind::ValidationLog => {
                ("Logs", &["csv", "txt", "dat", "tsv", "log"])
            }
            FileKind::Session => ("driftlab session", &["json"]),
            FileKind::Calibration | FileKind::Model => ("Calibration", &["json"]),
            FileKind::CorrectedCsv => ("CSV", &["csv"]),
            FileKind::Png => ("PNG image", &["png"]),
            FileKind::Report => ("Report folder", &["*"]),
        }
    }
}

/// The dialogs the workbench needs.
pub trait FileDialogs {
    /// Asks for an existing file; `None` when cancelled (or no dialog can be shown).
    fn open(&mut self, kind: FileKind, dir: Option<&Path>) -> Option<PathBuf>;
    /// Asks where to write a file, suggesting `name`; `None` when cancelled.
    fn save(&mut self, kind: FileKind, dir: Option<&Path>, name: &str) -> Option<PathBuf>;
}

/// Native dialogs (through the desktop portal). With no portal (a bare X server, CI) they
/// return `None` at once.
#[derive(Debug, Default)]
pub struct RfdDialogs;

impl FileDialogs for RfdDialogs {
    fn open(&mut self, kind: FileKind, dir: Option<&Path>) -> Option<PathBuf> {
        let (name, ext) = kind.filter();
        let mut d = rfd::FileDialog::new()
            .set_title(kind.title())
            .add_filter(name, ext)
            .add_filter("All files", &["*"]);
        if let Some(dir) = dir {
            d = d.set_directory(dir);
        }
        d.pick_file()
    }

    fn save(&mut self, kind: FileKind, dir: Option<&Path>, name: &str) -> Option<PathBuf> {
        let (filter, ext) = kind.filter();
        let mut d = rfd::FileDialog::new()
            .set_title(kind.title())
            .add_filter(filter, ext)
            .set_file_name(name);
        if let Some(dir) = dir {
            d = d.set_directory(dir);
        }
        d.save_file()
    }
}

/// Dialogs answered from a queue, for tests: each question takes the next answer (`None`
/// once the queue is empty) and is recorded.
#[derive(Debug, Default, Clone)]
pub struct ScriptedDialogs {
    inner: Arc<Mutex<Script>>,
}

#[derive(Debug, Default)]
struct Script {
    answers: VecDeque<Option<PathBuf>>,
    asked: Vec<FileKind>,
}

impl ScriptedDialogs {
    /// Dialogs with no answers yet; clone it to keep a handle for pushing answers.
    pub fn new() -> ScriptedDialogs {
        ScriptedDialogs::default()
    }

    /// Queues the answer to the next question.
    pub fn answer(&self, path: Option<PathBuf>) {
        if let Ok(mut s) = self.inner.lock() {
            s.answers.push_back(path);
        }
    }

    /// The questions asked so far.
    pub fn asked(&self) -> Vec<FileKind> {
        self.inner
            .lock()
            .map(|s| s.asked.clone())
            .unwrap_or_default()
    }

    fn next(&self, kind: FileKind) -> Option<PathBuf> {
        let mut s = self.inner.lock().ok()?;
        s.asked.push(kind);
        s.answers.pop_front().flatten()
    }
}

impl FileDialogs for ScriptedDialogs {
    fn open(&mut self, kind: FileKind, _dir: Option<&Path>) -> Option<PathBuf> {
        self.next(kind)
    }

    fn save(&mut self, kind: FileKind, _dir: Option<&Path>, _name: &str) -> Option<PathBuf> {
        self.next(kind)
    }
}
