//! File dialogs behind a small interface: the desktop's own dialog where one can appear (rfd,
//! through the desktop portal or zenity), driftlab's dialog inside the window where none can,
//! and dialogs answered from a script for tests.
//!
//! rfd asks the desktop portal (`org.freedesktop.portal.Desktop` on the D-Bus session bus) and,
//! failing that, runs `zenity`; with neither (a plain X session, XFCE or i3, remote X, CI) it
//! returns at once as if the engineer had pressed Cancel. So whether a system dialog can appear
//! is found out up front, at start, on a thread ([`SystemDialogs::detect`]), and where none can
//! the workbench draws its own ([`super::file_dialog`]).

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

/// What a file dialog is for (its title and file-type filter).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    /// A chamber log (CSV or text).
    Log,
    /// A held-out validation log.
    ValidationLog,
    /// Another run of the open log's campaign.
    Run,
    /// A workbench session (JSON).
    Session,
    /// A calibration file (JSON).
    Calibration,
    /// A calibration file of a model chosen in the Models view (JSON).
    Model,
    /// A calibration file to open beside the current fit (JSON).
    OpenCalibration,
    /// A flight controller's parameter file (PX4 `.params`, ArduPilot `.parm`).
    FlightParams,
    /// The corrected log (CSV).
    CorrectedCsv,
    /// A picture (PNG).
    Png,
    /// The test report (a folder of figures and one HTML page).
    Report,
    /// A lot's table (`lot.json` or `lot.csv` in its output folder).
    Lot,
}

impl FileKind {
    /// Dialog title.
    pub fn title(self) -> &'static str {
        match self {
            FileKind::Log => "Open chamber log",
            FileKind::ValidationLog => "Open validation log",
            FileKind::Run => "Add a run of the same gyro (calibrated together as one campaign)",
            FileKind::Session => "Workbench session",
            FileKind::Calibration => "Export calibration",
            FileKind::Model => "Export model",
            FileKind::OpenCalibration => "Open calibration to compare",
            FileKind::FlightParams => "Export flight-controller parameters",
            FileKind::CorrectedCsv => "Export corrected log",
            FileKind::Png => "Save picture",
            FileKind::Report => "Export test report (a folder)",
            FileKind::Lot => "Open lot (lot.json or lot.csv in its output folder)",
        }
    }

    /// Filter name and extensions (`*`: anything, for a folder).
    pub fn filter(self) -> (&'static str, &'static [&'static str]) {
        match self {
            // Drone and robot logs too: they are told by their first bytes.
            FileKind::Log | FileKind::ValidationLog | FileKind::Run => (
                "Logs",
                &[
                    "csv", "txt", "dat", "tsv", "log", "ulg", "bin", "bag", "mcap",
                ],
            ),
            FileKind::Session => ("driftlab session", &["json"]),
            FileKind::Calibration | FileKind::Model | FileKind::OpenCalibration => {
                ("Calibration", &["json"])
            }
            FileKind::CorrectedCsv => ("CSV", &["csv"]),
            FileKind::FlightParams => ("Parameters", &["params", "parm"]),
            FileKind::Png => ("PNG image", &["png"]),
            FileKind::Report => ("Report folder", &["*"]),
            FileKind::Lot => ("Lot table", &["json", "csv"]),
        }
    }

    /// True when the answer is a folder (the report) rather than a file.
    pub fn is_folder(self) -> bool {
        self == FileKind::Report
    }

    /// Whether `path` has one of this kind's extensions (any name for a folder).
    pub fn matches(self, path: &Path) -> bool {
        let (_, ext) = self.filter();
        ext.contains(&"*")
            || path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| ext.iter().any(|x| x.eq_ignore_ascii_case(e)))
    }

    /// The extension a saved file gets when its name has none.
    pub fn default_extension(self) -> Option<&'static str> {
        match self {
            FileKind::Session
            | FileKind::Calibration
            | FileKind::Model
            | FileKind::OpenCalibration => Some("json"),
            FileKind::CorrectedCsv => Some("csv"),
            FileKind::Png => Some("png"),
            FileKind::Log
            | FileKind::ValidationLog
            | FileKind::Run
            | FileKind::Report
            | FileKind::Lot => None,
            // The suggested name carries the format's own (.params, .parm).
            FileKind::FlightParams => None,
        }
    }
}

/// What a dialog answered.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Answer {
    /// The engineer chose this file (or folder).
    Chosen(PathBuf),
    /// The engineer cancelled.
    Cancelled,
    /// No system dialog can appear here: the workbench is to show its own.
    InWindow,
}

/// The dialogs the workbench needs.
pub trait FileDialogs {
    /// Asks for an existing file, starting in `dir`.
    fn open(&mut self, kind: FileKind, dir: Option<&Path>) -> Answer;
    /// Asks where to write a file (or, for [`FileKind::Report`], a folder), suggesting `name`
    /// in `dir`.
    fn save(&mut self, kind: FileKind, dir: Option<&Path>, name: &str) -> Answer;
}

/// Whether a system file dialog can appear on this desktop, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Availability {
    /// True when rfd's dialog can appear.
    pub system: bool,
    /// What was found (for the Help window and messages).
    pub reason: String,
}

/// The desktop's file dialogs (rfd) where one can appear, else [`Answer::InWindow`].
#[derive(Debug, Clone)]
pub struct SystemDialogs {
    found: Arc<OnceLock<Availability>>,
}

impl SystemDialogs {
    /// Starts finding out, on a thread, whether a system dialog can appear; the first dialog
    /// asked for waits for the answer (a few milliseconds: a D-Bus query and a PATH look-up).
    ///
    /// `DRIFTLAB_FILE_DIALOG=window` always uses the workbench's own dialog, `=system` always
    /// rfd's.
    pub fn detect() -> SystemDialogs {
        let found: Arc<OnceLock<Availability>> = Arc::default();
        let slot = found.clone();
        let spawned = std::thread::Builder::new()
            .name("driftlab-dialogs".into())
            .spawn(move || {
                let _ = slot.set(availability());
            });
        if spawned.is_err() {
            let _ = found.set(Availability {
                system: false,
                reason: "could not start the check for a system dialog".into(),
            });
        }
        SystemDialogs { found }
    }

    /// What was found (waiting for the check at most `wait`).
    pub fn availability(&self, wait: Duration) -> Availability {
        let deadline = Instant::now() + wait;
        loop {
            if let Some(a) = self.found.get() {
                return a.clone();
            }
            if Instant::now() >= deadline {
                return Availability {
                    system: false,
                    reason: "the check for a system dialog did not answer in time".into(),
                };
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    fn system(&self) -> bool {
        self.availability(Duration::from_secs(3)).system
    }
}

impl FileDialogs for SystemDialogs {
    fn open(&mut self, kind: FileKind, dir: Option<&Path>) -> Answer {
        if !self.system() {
            return Answer::InWindow;
        }
        let (name, ext) = kind.filter();
        let mut d = rfd::FileDialog::new()
            .set_title(kind.title())
            .add_filter(name, ext)
            .add_filter("All files", &["*"]);
        if let Some(dir) = dir {
            d = d.set_directory(dir);
        }
        d.pick_file().map_or(Answer::Cancelled, Answer::Chosen)
    }

    fn save(&mut self, kind: FileKind, dir: Option<&Path>, name: &str) -> Answer {
        if !self.system() {
            return Answer::InWindow;
        }
        let (filter, ext) = kind.filter();
        let mut d = rfd::FileDialog::new()
            .set_title(kind.title())
            .add_filter(filter, ext)
            .set_file_name(name);
        if let Some(dir) = dir {
            d = d.set_directory(dir);
        }
        d.save_file().map_or(Answer::Cancelled, Answer::Chosen)
    }
}

const PORTAL: &str = "org.freedesktop.portal.Desktop";

/// Whether rfd's dialog can appear: the desktop portal on the session bus (owned now, or
/// started on demand), or `zenity` on PATH.
fn availability() -> Availability {
    match std::env::var("DRIFTLAB_FILE_DIALOG").as_deref() {
        Ok("window") => {
            return Availability {
                system: false,
                reason: "DRIFTLAB_FILE_DIALOG=window".into(),
            };
        }
        Ok("system") => {
            return Availability {
                system: true,
                reason: "DRIFTLAB_FILE_DIALOG=system".into(),
            };
        }
        _ => {}
    }
    let portal = portal_on_bus();
    let zenity = on_path("zenity");
    match (portal, zenity) {
        (Ok(()), _) => Availability {
            system: true,
            reason: format!("the desktop portal ({PORTAL}) is on the session bus"),
        },
        (Err(_), Some(z)) => Availability {
            system: true,
            reason: format!("zenity is on PATH ({})", z.display()),
        },
        (Err(why), None) => Availability {
            system: false,
            reason: format!("{why}, and zenity is not on PATH"),
        },
    }
}

/// The first file called `name` in a folder of PATH.
pub fn on_path(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// Asks the session bus whether the portal's name is owned or can be started, with the
/// desktop's own D-Bus tools (`busctl`, `gdbus` or `dbus-send`: a desktop that runs a portal
/// has one of them). Any failure counts as "no portal": the workbench's own dialog always
/// works, while a system dialog that cannot appear does nothing at all.
fn portal_on_bus() -> Result<(), String> {
    let address = std::env::var_os("DBUS_SESSION_BUS_ADDRESS").filter(|a| !a.is_empty());
    let runtime_bus = std::env::var_os("XDG_RUNTIME_DIR")
        .map(|d| PathBuf::from(d).join("bus"))
        .filter(|p| p.exists());
    if address.is_none() && runtime_bus.is_none() {
        return Err("no D-Bus session bus (DBUS_SESSION_BUS_ADDRESS is unset)".into());
    }
    let queries: [(&str, Vec<&str>); 3] = [
        (
            "busctl",
            vec![
                "--user",
                "--no-pager",
                "--acquired",
                "--activatable",
                "list",
            ],
        ),
        (
            "gdbus",
            vec![
                "call",
                "--session",
                "--dest",
                "org.freedesktop.DBus",
                "--object-path",
                "/org/freedesktop/DBus",
                "--method",
                "org.freedesktop.DBus.ListActivatableNames",
            ],
        ),
        (
            "dbus-send",
            vec![
                "--session",
                "--print-reply",
                "--dest=org.freedesktop.DBus",
                "/org/freedesktop/DBus",
                "org.freedesktop.DBus.ListActivatableNames",
            ],
        ),
    ];
    let mut asked = false;
    for (tool, args) in queries {
        let Some(exe) = on_path(tool) else {
            continue;
        };
        asked = true;
        if let Some(out) = run_briefly(&exe, &args)
            && out.contains(PORTAL)
        {
            return Ok(());
        }
        // The portal may be running without being activatable: ask who owns its name.
        if tool == "dbus-send"
            && let Some(out) = run_briefly(
                &exe,
                &[
                    "--session",
                    "--print-reply",
                    "--dest=org.freedesktop.DBus",
                    "/org/freedesktop/DBus",
                    "org.freedesktop.DBus.NameHasOwner",
                    &format!("string:{PORTAL}"),
                ],
            )
            && out.contains("boolean true")
        {
            return Ok(());
        }
    }
    if asked {
        Err(format!("the session bus has no desktop portal ({PORTAL})"))
    } else {
        Err("no D-Bus tool (busctl, gdbus, dbus-send) to ask the session bus for a portal".into())
    }
}

/// Runs `exe args` with no input and returns what it printed, or `None` when it fails or
/// takes over two seconds (it is then killed).
fn run_briefly(exe: &Path, args: &[&str]) -> Option<String> {
    use std::io::Read as _;
    let mut child = std::process::Command::new(exe)
        .args(args)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .ok()?;
    let deadline = Instant::now() + Duration::from_secs(2);
    loop {
        match child.try_wait() {
            Ok(Some(status)) => {
                let mut out = String::new();
                child.stdout.take()?.read_to_string(&mut out).ok()?;
                return status.success().then_some(out);
            }
            Ok(None) if Instant::now() < deadline => std::thread::sleep(Duration::from_millis(5)),
            _ => {
                let _ = child.kill();
                let _ = child.wait();
                return None;
            }
        }
    }
}

/// Dialogs answered from a queue, for tests: each question takes the next answer
/// ([`Answer::Cancelled`] once the queue is empty) and is recorded with the name suggested.
#[derive(Debug, Default, Clone)]
pub struct ScriptedDialogs {
    inner: Arc<Mutex<Script>>,
}

#[derive(Debug, Default)]
struct Script {
    answers: VecDeque<Answer>,
    asked: Vec<(FileKind, Option<PathBuf>, String)>,
}

impl ScriptedDialogs {
    /// Dialogs with no answers yet; clone it to keep a handle for pushing answers.
    pub fn new() -> ScriptedDialogs {
        ScriptedDialogs::default()
    }

    /// Queues the answer to the next question: a path, or `None` for Cancel.
    pub fn answer(&self, path: Option<PathBuf>) {
        self.push(path.map_or(Answer::Cancelled, Answer::Chosen));
    }

    /// Queues "no system dialog here": the next question opens the workbench's own dialog.
    pub fn answer_in_window(&self) {
        self.push(Answer::InWindow);
    }

    fn push(&self, a: Answer) {
        if let Ok(mut s) = self.inner.lock() {
            s.answers.push_back(a);
        }
    }

    /// The questions asked so far.
    pub fn asked(&self) -> Vec<FileKind> {
        self.inner
            .lock()
            .map(|s| s.asked.iter().map(|a| a.0).collect())
            .unwrap_or_default()
    }

    /// The folder and file name each question suggested.
    pub fn suggested(&self) -> Vec<(Option<PathBuf>, String)> {
        self.inner
            .lock()
            .map(|s| s.asked.iter().map(|a| (a.1.clone(), a.2.clone())).collect())
            .unwrap_or_default()
    }

    fn next(&self, kind: FileKind, dir: Option<&Path>, name: &str) -> Answer {
        let Ok(mut s) = self.inner.lock() else {
            return Answer::Cancelled;
        };
        s.asked
            .push((kind, dir.map(Path::to_path_buf), name.to_string()));
        s.answers.pop_front().unwrap_or(Answer::Cancelled)
    }
}

impl FileDialogs for ScriptedDialogs {
    fn open(&mut self, kind: FileKind, dir: Option<&Path>) -> Answer {
        self.next(kind, dir, "")
    }

    fn save(&mut self, kind: FileKind, dir: Option<&Path>, name: &str) -> Answer {
        self.next(kind, dir, name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_match_their_extensions() {
        assert!(FileKind::Log.matches(Path::new("run7.CSV")));
        assert!(!FileKind::Log.matches(Path::new("run7.json")));
        assert!(FileKind::Report.matches(Path::new("anything")));
        assert_eq!(FileKind::Png.default_extension(), Some("png"));
    }

    #[test]
    fn a_missing_tool_is_not_found_on_path() {
        assert!(on_path("driftlab-no-such-tool-anywhere").is_none());
    }
}
