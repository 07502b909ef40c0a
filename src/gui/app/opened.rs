//! The calibration opened beside the current fit, as the window carries it: opening it (a path
//! asked for, dropped, picked from the recent files or given on the command line), the
//! answers of its file read and of its judging, the axis the engineer places it on, and
//! closing it. What it holds and what it is judged on is [`crate::gui::opened`].

use super::*;
use crate::files::kind::{JsonKind, json_kind, named_as_session};
use crate::gui::jobs::Verified;
use crate::gui::opened::Opened;

impl Workbench {
    /// Opens the calibration file at `path` beside the current fit: read on a worker, then
    /// judged on the open logs. One that cannot be read (malformed, of another kind) leaves
    /// everything as it was, the calibration opened before too, and says why with the file,
    /// line and column.
    pub fn open_calibration(&mut self, path: PathBuf) {
        self.state.say(
            Severity::Info,
            format!("Reading the calibration {} …", file_name(&path)),
        );
        self.jobs.read_calibration(path);
    }

    /// The calibration file read (or not) by the worker.
    pub(super) fn calibration_read(
        &mut self,
        path: PathBuf,
        read: Result<Arc<crate::models::UnitCalibration>, String>,
    ) {
        match read {
            Ok(unit) => {
                let opened = Opened::new(path.clone(), unit);
                let on = match &self.state.shown.log {
                    Some(l) => format!("; judging it on {} …", file_name(&l.path)),
                    None => "; open a log to judge it on".to_string(),
                };
                self.state.say(
                    Severity::Info,
                    format!(
                        "Opened the calibration {} ({}) beside the current fit{on}",
                        opened.name(),
                        opened.what()
                    ),
                );
                self.state.opened = Some(opened);
                self.jobs.forget_verify();
                self.window.settings.add_recent(&path);
                if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                    self.window.settings.last_dir = Some(dir.to_path_buf());
                }
            }
            Err(message) => {
                self.state.say(
                    Severity::Error,
                    format!(
                        "Could not open the calibration {}: nothing was changed",
                        file_name(&path)
                    ),
                );
                self.fail(format!(
                    "Could not open the calibration. Nothing was changed.\n\n{message}"
                ));
            }
        }
    }

    /// Asks the worker to judge the opened calibration on the logs open now, once for each
    /// change of them, of the figures' options or of an axis placed by hand.
    pub(super) fn verify_if_needed(&mut self) {
        if let Some(request) = crate::gui::opened::request(&self.state) {
            self.jobs.verify(request);
        }
    }

    /// The opened calibration judged: kept when it answers the newest request for the
    /// calibration still open.
    pub(super) fn verified(&mut self, v: Arc<Verified>) {
        if v.generation != self.jobs.verify_requested {
            return;
        }
        let Some(o) = &mut self.state.opened else {
            return;
        };
        if !v.key.of_unit(&o.unit) {
            return;
        }
        let failed = v
            .failed
            .as_ref()
            .map(|why| format!("The opened calibration {} was not judged: {why}", o.name()));
        o.verified = Some(v);
        if let Some(message) = failed {
            self.state.say(Severity::Error, message);
        }
    }

    /// Puts the opened calibration away.
    pub(super) fn close_calibration(&mut self) {
        if let Some(o) = self.state.opened.take() {
            self.jobs.forget_verify();
            self.state.say(
                Severity::Info,
                format!("Closed the opened calibration {}", o.name()),
            );
        }
    }

    /// Judges axis `k` of the opened calibration on the axis `axis` of log `which` (`None`:
    /// on none of its axes).
    pub(super) fn choose_opened_axis(&mut self, which: OpenLog, k: usize, axis: Option<String>) {
        let Some(o) = &mut self.state.opened else {
            return;
        };
        match axis {
            Some(a) => o.chosen.insert((which, k), a),
            None => o.chosen.remove(&(which, k)),
        };
    }

    /// The opened calibration (tests read what it holds and how it was judged).
    pub fn opened(&self) -> Option<&Opened> {
        self.state.opened.as_ref()
    }
}

/// What opening the JSON file `path` means, by what it says it is: a calibration is opened
/// beside the current fit, a session reopened. One that says nothing readable is taken for
/// a session when named like one, else for a calibration; its loader then names the line and
/// column where it is not one.
pub(super) fn json_action(path: PathBuf) -> Action {
    match json_kind(&path) {
        JsonKind::Session => Action::OpenSessionPath(path),
        JsonKind::Calibration => Action::OpenCalibrationPath(path),
        JsonKind::Other(_) | JsonKind::Unknown if named_as_session(&path) => {
            Action::OpenSessionPath(path)
        }
        JsonKind::Other(_) | JsonKind::Unknown => Action::OpenCalibrationPath(path),
    }
}
