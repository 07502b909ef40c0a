//! What the workbench writes and opens on the engineer's request: calibrations, models,
//! corrected logs, reports, pictures and sessions. Each request asks for a path first (the
//! system dialog, or the workbench's own where none can appear) and ends with a status line
//! naming the file written, or saying that nothing was written and why.

use super::*;
use crate::gui::dialogs::{Answer, FileKind};
use crate::gui::file_dialog::{self, FileDialog, Mode};

/// What a path is asked for: the work to do once the engineer has chosen it.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Purpose {
    /// A calibration log to import.
    OpenLog,
    /// A validation log to import.
    OpenValidation,
    /// Another run of the open log's campaign.
    AddRun,
    /// A calibration to open beside the current fit.
    OpenCalibration,
    /// A lot to open.
    OpenLot,
    /// A session to open.
    OpenSession,
    /// Where to save the session; then the action that waited for it (quit, open another).
    SaveSession { then: Option<Box<Action>> },
    /// The calibration file.
    ExportCalibration,
    /// The calibration as a flight controller's parameter file.
    ExportFlight(crate::export::firmware::Format),
    /// The corrected log of one of the open logs.
    ExportCsv(OpenLog),
    /// The test report's folder.
    ExportReport,
    /// The calibration file of this model of the Models page.
    ExportModel(String),
    /// The window as PNG.
    Screenshot,
    /// One plot as PNG, cropped to this rectangle.
    SavePlot(String, Rect),
}

impl Purpose {
    fn kind(&self) -> FileKind {
        match self {
            Purpose::OpenLog => FileKind::Log,
            Purpose::OpenValidation => FileKind::ValidationLog,
            Purpose::AddRun => FileKind::Run,
            Purpose::OpenCalibration => FileKind::OpenCalibration,
            Purpose::OpenLot => FileKind::Lot,
            Purpose::OpenSession | Purpose::SaveSession { .. } => FileKind::Session,
            Purpose::ExportCalibration => FileKind::Calibration,
            Purpose::ExportFlight(_) => FileKind::FlightParams,
            Purpose::ExportCsv(_) => FileKind::CorrectedCsv,
            Purpose::ExportReport => FileKind::Report,
            Purpose::ExportModel(_) => FileKind::Model,
            Purpose::Screenshot | Purpose::SavePlot(..) => FileKind::Png,
        }
    }

    fn mode(&self) -> Mode {
        match self {
            Purpose::OpenLog
            | Purpose::AddRun
            | Purpose::OpenValidation
            | Purpose::OpenCalibration
            | Purpose::OpenLot
            | Purpose::OpenSession => Mode::Open,
            _ => Mode::Save,
        }
    }

    /// What would have been written or opened, for "nothing was …" lines.
    fn what(&self) -> String {
        match self {
            Purpose::OpenLog => "No log opened".into(),
            Purpose::OpenValidation => "No validation log opened".into(),
            Purpose::AddRun => "No run added".into(),
            Purpose::OpenCalibration => "No calibration opened".into(),
            Purpose::OpenLot => "No lot opened".into(),
            Purpose::OpenSession => "No session opened".into(),
            Purpose::SaveSession { .. } => "Session not saved".into(),
            Purpose::ExportCalibration => "Calibration not exported".into(),
            Purpose::ExportFlight(f) => format!("{f} file not exported"),
            Purpose::ExportCsv(_) => "Corrected log not exported".into(),
            Purpose::ExportReport => "Report not written".into(),
            Purpose::ExportModel(m) => format!("Model {m} not exported"),
            Purpose::Screenshot => "Screenshot not saved".into(),
            Purpose::SavePlot(name, _) => format!("Plot {name} not saved"),
        }
    }
}

impl Workbench {
    /// The folder a dialog starts in: a file to write goes beside the log; a file to open is
    /// looked for where the last one was.
    fn start_dir(&self, mode: Mode) -> PathBuf {
        let log_dir = self
            .state
            .shown
            .log
            .as_ref()
            .and_then(|l| std::path::absolute(&l.path).ok())
            .and_then(|p| p.parent().map(Path::to_path_buf));
        let last = self.window.settings.last_dir.clone().filter(|d| d.is_dir());
        let first = match mode {
            Mode::Save => log_dir.or(last),
            Mode::Open => last.or(log_dir),
        };
        first
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_else(|| PathBuf::from("."))
    }

    /// Asks for a path for `purpose` (suggesting `name` when writing) and goes on with it.
    pub(super) fn ask(&mut self, ctx: &egui::Context, purpose: Purpose, name: &str) {
        let (kind, mode) = (purpose.kind(), purpose.mode());
        let dir = self.start_dir(mode);
        let answer = match mode {
            Mode::Open => self.modals.dialogs.open(kind, Some(&dir)),
            Mode::Save => self.modals.dialogs.save(kind, Some(&dir), name),
        };
        match answer {
            Answer::Chosen(p) => self.chosen(ctx, purpose, p),
            Answer::Cancelled => self.not_chosen(purpose),
            Answer::InWindow => {
                let mut recent = self.window.settings.recent_dirs.clone();
                if !recent.contains(&dir) {
                    recent.insert(0, dir.clone());
                }
                recent.retain(|d| d.is_dir());
                recent.truncate(8);
                self.modals.file_dialog =
                    Some((FileDialog::new(mode, kind, &dir, name, recent), purpose));
            }
        }
    }

    /// The workbench's own file dialog, when open.
    pub(super) fn file_dialog_modal(&mut self, ctx: &egui::Context) {
        let Some((d, _)) = &mut self.modals.file_dialog else {
            return;
        };
        match d.show(ctx) {
            Some(file_dialog::Outcome::Accept(p)) => {
                if let Some((_, purpose)) = self.modals.file_dialog.take() {
                    self.chosen(ctx, purpose, p);
                }
            }
            Some(file_dialog::Outcome::Cancel) => {
                if let Some((_, purpose)) = self.modals.file_dialog.take() {
                    self.not_chosen(purpose);
                }
            }
            None => {}
        }
    }

    /// The workbench's own file dialog while it is open (tests type into it).
    pub fn file_dialog(&mut self) -> Option<&mut FileDialog> {
        self.modals.file_dialog.as_mut().map(|(d, _)| d)
    }

    fn not_chosen(&mut self, purpose: Purpose) {
        let verb = match purpose.mode() {
            Mode::Open => "nothing was opened",
            Mode::Save => "nothing was written",
        };
        self.state.say(
            Severity::Info,
            format!("{}: no file was chosen, {verb}", purpose.what()),
        );
    }

    /// Goes on with the path the engineer chose for `purpose`.
    fn chosen(&mut self, ctx: &egui::Context, purpose: Purpose, path: PathBuf) {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            self.window.settings.add_recent_dir(dir);
        }
        match purpose {
            Purpose::OpenLog => self.open_import(path, Target::Calibration),
            Purpose::OpenValidation => self.open_import(path, Target::Validation),
            Purpose::AddRun => self.add_run(path),
            Purpose::OpenCalibration => self.open_calibration(path),
            Purpose::OpenLot => self.open_lot(path),
            Purpose::OpenSession => self.open_session(path),
            Purpose::SaveSession { then } => {
                if self.write_session(&path)
                    && let Some(a) = then
                {
                    self.run_confirmed(ctx, *a);
                }
            }
            Purpose::ExportCalibration => self.write_calibration(&path),
            Purpose::ExportFlight(format) => self.write_flight(format, &path),
            Purpose::ExportCsv(which) => self.write_csv(path, which),
            Purpose::ExportReport => self.write_report(path),
            Purpose::ExportModel(name) => self.write_model(&name, path),
            Purpose::Screenshot => {
                self.shots.pending = Some(PendingShot {
                    frames: 2,
                    path,
                    crop: None,
                    what: "screenshot".into(),
                });
            }
            Purpose::SavePlot(name, rect) => {
                self.shots.pending = Some(PendingShot {
                    frames: 2,
                    path,
                    crop: Some(rect),
                    what: format!("plot {name}"),
                });
            }
        }
    }

    /// A file name beside the log: `run7.csv` → `run7-<suffix>`.
    pub(super) fn name_beside_log(&self, suffix: &str) -> String {
        export::suggested_name(
            self.state.shown.log.as_ref().map(|l| l.path.as_path()),
            suffix,
        )
    }

    /// Waits (a second or two at most) for the refit the current choices need, so that what
    /// is written is what the figures show.
    fn settle_fit(&mut self) {
        if !self.state.all_current() || self.jobs.fitting() {
            self.refit_if_needed();
            let deadline = Instant::now() + Duration::from_secs(60);
            while self.jobs.fitting() && Instant::now() < deadline {
                if let Some(r) = self.jobs.next(Duration::from_millis(20)) {
                    self.handle(r);
                }
            }
        }
    }

    pub(super) fn export_calibration(&mut self, ctx: &egui::Context) {
        if self.state.shown.log.is_some() {
            self.settle_fit();
        }
        if self.state.shown.log.is_none() || self.state.shown.fit.is_none() {
            self.state.say(
                Severity::Warning,
                "Calibration not exported: there is no calibration yet",
            );
            return;
        }
        let name = self.name_beside_log("calibration.json");
        self.ask(ctx, Purpose::ExportCalibration, &name);
    }

    fn write_calibration(&mut self, path: &Path) {
        self.settle_fit();
        let (Some(log), Some(fit)) = (self.state.shown.log.clone(), self.state.shown.fit.clone())
        else {
            self.state.say(
                Severity::Warning,
                "Calibration not exported: there is no calibration any more",
            );
            return;
        };
        // A unit: every axis in one version-2 file; one axis: the file it always was.
        let written = match self.state.unit_calibration() {
            Some(unit) => unit.and_then(|u| {
                export::save_unit(path, &u)
                    .map(|p| (p, format!(" (axes {})", u.axis_names().join(", "))))
            }),
            None => export::save_calibration(path, &fit.outcome.calibration, &log)
                .map(|p| (p, String::new())),
        };
        match written {
            Ok((p, axes)) => {
                self.window.settings.last_dir = p.parent().map(Path::to_path_buf);
                self.state.say(
                    Severity::Info,
                    format!("Calibration written: {}{axes}", p.display()),
                );
            }
            Err(e) => {
                self.state.say(
                    Severity::Error,
                    format!("Calibration not exported, nothing was written: {e}"),
                );
                self.fail(format!(
                    "Could not write the calibration. Nothing was written.\n\n{e}"
                ));
            }
        }
    }

    pub(super) fn export_flight(
        &mut self,
        ctx: &egui::Context,
        format: crate::export::firmware::Format,
    ) {
        if self.state.shown.log.is_some() {
            self.settle_fit();
        }
        if self.state.shown.log.is_none() || self.state.shown.fit.is_none() {
            self.state.say(
                Severity::Warning,
                format!("{format} file not exported: there is no calibration yet"),
            );
            return;
        }
        let name = match format {
            crate::export::firmware::Format::Px4Params => "tc.params",
            _ => "tcal.parm",
        };
        let name = self.name_beside_log(name);
        self.ask(ctx, Purpose::ExportFlight(format), &name);
    }

    /// The calibration as `driftlab export --format px4-params|ardupilot-parm` writes it
    /// (the engine's [`crate::export::firmware::flight`]), atomically.
    fn write_flight(&mut self, format: crate::export::firmware::Format, path: &Path) {
        self.settle_fit();
        let (Some(log), Some(fit)) = (self.state.shown.log.clone(), self.state.shown.fit.clone())
        else {
            self.state.say(
                Severity::Warning,
                format!("{format} file not exported: there is no calibration any more"),
            );
            return;
        };
        let opts = crate::export::firmware::ExportOptions::default();
        let unit = self.state.unit_calibration();
        let is_unit = unit.is_some();
        let written = match unit {
            // A unit: its three axes as the firmware's X, Y and Z.
            Some(unit) => unit.and_then(|u| {
                crate::export::firmware::flight_unit(&u, format, &opts).map_err(|e| e.to_string())
            }),
            None => export::stamped(&fit.outcome.calibration, &log).and_then(|cal| {
                let model = crate::models::fitted::DriftModel::Vakhrameev(Box::new(cal));
                crate::export::firmware::flight(&model, format, &opts).map_err(|e| e.to_string())
            }),
        }
        .and_then(|file| {
            crate::files::atomic::write_bytes(path, file.text.as_bytes())
                .map(|_| file)
                .map_err(|e| format!("{}: {e}", path.display()))
        });
        match written {
            Ok(file) => {
                self.window.settings.last_dir = path.parent().map(Path::to_path_buf);
                // One status line: what was written, then what the firmware leaves out.
                let (severity, warned) = if file.warnings.is_empty() {
                    (Severity::Info, String::new())
                } else {
                    (Severity::Warning, format!("; {}", file.warnings.join("; ")))
                };
                let of_axis = if is_unit {
                    " (every axis of the unit, as the firmware's X, Y and Z)"
                } else {
                    ""
                };
                self.state.say(
                    severity,
                    format!("{format} file written: {}{of_axis}{warned}", path.display()),
                );
            }
            Err(e) => self.state.say(
                Severity::Error,
                format!("{format} file not exported, nothing was written: {e}"),
            ),
        }
    }

    /// Asks where to write the model selected on the Models page.
    pub(super) fn export_model(&mut self, ctx: &egui::Context) {
        let Some(c) = self.state.shown.models.clone() else {
            self.state.say(
                Severity::Warning,
                "Model not exported: compare the models first",
            );
            return;
        };
        let Some(name) = self.views.models.selected.clone() else {
            self.state.say(
                Severity::Warning,
                "Model not exported: select a model in the table first",
            );
            return;
        };
        if !c
            .reports
            .iter()
            .any(|r| r.model == name && r.fitted.is_some())
        {
            self.state.say(
                Severity::Warning,
                format!("Model {name} not exported: it could not be fitted"),
            );
            return;
        }
        let file = self.name_beside_log(&format!("{name}.json"));
        self.ask(ctx, Purpose::ExportModel(name), &file);
    }

    fn write_model(&mut self, name: &str, path: PathBuf) {
        let (Some(log), Some(c)) = (
            self.state.shown.log.clone(),
            self.state.shown.models.clone(),
        ) else {
            self.state.say(
                Severity::Warning,
                format!("Model {name} not exported: no comparison"),
            );
            return;
        };
        if !Arc::ptr_eq(&log.log, &c.logs[0].log) {
            self.state.say(
                Severity::Warning,
                format!(
                    "Model {name} not exported: the log changed since the comparison; \
                     compare the models again first"
                ),
            );
            return;
        }
        let Some(model) = c
            .reports
            .iter()
            .find(|r| r.model == name)
            .and_then(|r| r.fitted.clone())
        else {
            self.state.say(
                Severity::Warning,
                format!("Model {name} not exported: it was not fitted"),
            );
            return;
        };
        self.window.settings.last_dir = path.parent().map(Path::to_path_buf);
        let what = format!("model {}", model.name());
        self.state
            .say(Severity::Info, format!("Writing {} …", path.display()));
        // Its runs' plateaus are the ones the workbench's fit found or was given.
        let ranges: Vec<_> = self
            .state
            .shown
            .fit
            .as_ref()
            .map(|f| f.outcome.ranges.clone())
            .unwrap_or_default();
        self.jobs.spawn_export(&what, move || {
            export::save_model(&path, &model, &log, &ranges)
        });
    }

    pub(super) fn export_report(&mut self, ctx: &egui::Context) {
        if self.state.shown.log.is_none() || self.state.shown.fit.is_none() {
            self.state.say(
                Severity::Warning,
                "Report not written: there is no calibration yet",
            );
            return;
        }
        let name = self.name_beside_log("report");
        self.ask(ctx, Purpose::ExportReport, &name);
    }

    fn write_report(&mut self, dir: PathBuf) {
        self.settle_fit();
        let (Some(log), Some(fit)) = (self.state.shown.log.clone(), self.state.shown.fit.clone())
        else {
            return;
        };
        // A name typed as "x.html" means the folder "x".
        let dir = dir.with_extension("");
        let cal = match export::stamped(&fit.outcome.calibration, &log) {
            Ok(c) => c,
            Err(e) => {
                self.state.say(
                    Severity::Error,
                    format!("Report not written, nothing was written: {e}"),
                );
                return self.fail(format!("Could not write the report.\n\n{e}"));
            }
        };
        self.window.settings.last_dir = dir.parent().map(Path::to_path_buf);
        if let Some(unit) = self.state.unit_calibration() {
            // A unit: every axis on the calibration log and the validation log, one section
            // each, as `driftlab report` writes it.
            // (with its accelerometer axes, when the unit calibrates them)
            let full = self.state.unit_full_log();
            let (unit, full) = match (unit, full) {
                (Ok(u), Some(f)) => (u, f),
                (Err(e), _) => {
                    self.state.say(
                        Severity::Error,
                        format!("Report not written, nothing was written: {e}"),
                    );
                    return;
                }
                (_, None) => {
                    return self.state.say(
                        Severity::Warning,
                        "Corrected log not exported, nothing was written: the validation log \
                         lacks an axis of the unit",
                    );
                }
            };
            let mut logs = log.as_files(&full);
            let validation = self.state.unit_validation_log();
            let held_out = validation.is_some();
            logs.extend(validation);
            self.state.say(
                Severity::Info,
                format!(
                    "Writing the report of every axis into {}{} …",
                    dir.display(),
                    if held_out || self.state.shown.validation.is_none() {
                        ""
                    } else {
                        " (without the validation log: it lacks an axis of the unit)"
                    }
                ),
            );
            self.jobs.spawn_export("report", move || {
                export::write_unit_report(&dir, &unit, logs)
            });
            return;
        }
        let mut logs = log.as_files(&log.log);
        if let Some(v) = &self.state.shown.validation {
            logs.push((v.path.clone(), (*v.log).clone()));
        }
        self.state.say(
            Severity::Info,
            format!("Writing the report into {} …", dir.display()),
        );
        self.jobs
            .spawn_export("report", move || export::write_report(&dir, &cal, &logs));
    }

    /// Asks where to write the corrected log of `which` log (`None`: the one the drift plot
    /// shows), named after that log.
    pub(super) fn export_csv(&mut self, ctx: &egui::Context, which: Option<OpenLog>) {
        if self.state.shown.log.is_none() || self.state.shown.fit.is_none() {
            self.state.say(
                Severity::Warning,
                "Corrected log not exported: there is no calibration yet",
            );
            return;
        }
        let has_validation = self.state.shown.validation.is_some();
        let which = which.unwrap_or(if self.state.view.show_validation && has_validation {
            OpenLog::Validation
        } else {
            OpenLog::Calibration
        });
        let source = match which {
            OpenLog::Calibration => self.state.shown.log.as_ref(),
            OpenLog::Validation => self.state.shown.validation.as_ref(),
        };
        let Some(source) = source else {
            self.state.say(
                Severity::Warning,
                "Corrected validation log not exported: no validation log is open",
            );
            return;
        };
        let name = export::suggested_name(Some(&source.path), "corrected.csv");
        self.ask(ctx, Purpose::ExportCsv(which), &name);
    }

    /// Writes the corrected log of `which` log to `path`: every axis of a unit side by side,
    /// as `driftlab apply` writes it.
    fn write_csv(&mut self, path: PathBuf, which: OpenLog) {
        self.settle_fit();
        let log = match which {
            OpenLog::Calibration => self.state.shown.log.clone(),
            OpenLog::Validation => self.state.shown.validation.clone(),
        };
        let (Some(log), Some(fit)) = (log, self.state.shown.fit.clone()) else {
            return;
        };
        self.window.settings.last_dir = path.parent().map(Path::to_path_buf);
        self.state
            .say(Severity::Info, format!("Writing {} …", path.display()));
        if let Some(unit) = self.state.unit_calibration() {
            // A unit: every axis side by side, as `driftlab apply` writes it.
            let full = match which {
                OpenLog::Calibration => self.state.unit_full_log(),
                OpenLog::Validation => self
                    .state
                    .unit_validation_log()
                    .map(|(_, log)| std::sync::Arc::new(log)),
            };
            let (unit, full) = match (unit, full) {
                (Ok(u), Some(f)) => (u, f),
                (Err(e), _) => {
                    return self.state.say(
                        Severity::Warning,
                        format!("Corrected log not exported, nothing was written: {e}"),
                    );
                }
                (_, None) => return,
            };
            self.jobs.spawn_export("corrected log", move || {
                export::write_corrected_csv(&path, &full, &unit)
            });
            return;
        }
        let l = log.log.clone();
        self.jobs.spawn_export("corrected log", move || {
            let model =
                crate::models::DriftModel::Vakhrameev(Box::new(fit.outcome.calibration.clone()));
            let single = crate::models::UnitCalibration::single(model);
            export::write_corrected_csv(&path, &l, &single)
        });
    }

    /// Saves the session (asking where the first time, or always with `ask`); `then` runs
    /// once it is written.
    pub(super) fn save_session(&mut self, ctx: &egui::Context, ask: bool, then: Option<Action>) {
        if self.state.shown.log.is_none() {
            self.state.say(
                Severity::Warning,
                "Session not saved: no log is open, nothing was written",
            );
            return;
        }
        match (&self.state.session_path, ask) {
            (Some(p), false) => {
                let p = p.clone();
                if self.write_session(&p)
                    && let Some(a) = then
                {
                    self.run_confirmed(ctx, a);
                }
            }
            _ => {
                let name = self.name_beside_log("session.json");
                self.ask(
                    ctx,
                    Purpose::SaveSession {
                        then: then.map(Box::new),
                    },
                    &name,
                );
            }
        }
    }

    /// Writes the session file; true when written.
    fn write_session(&mut self, path: &Path) -> bool {
        match session::save(path, &self.state.session()) {
            Ok(()) => {
                self.state.session_path = Some(path.to_path_buf());
                self.state.mark_saved();
                self.recovery.autosave.clear();
                self.window.settings.add_recent(path);
                self.state
                    .say(Severity::Info, format!("Session saved: {}", path.display()));
                true
            }
            Err(e) => {
                self.state.say(
                    Severity::Error,
                    format!("Session not saved, nothing was written: {e}"),
                );
                self.fail(format!(
                    "Could not save the session. Nothing was written.\n\n{e}"
                ));
                false
            }
        }
    }

    /// Opens a session file: its log is read (with its mapping), then its choices applied;
    /// a session that cannot be read or whose log fails leaves the current work as it was.
    pub fn open_session(&mut self, path: PathBuf) {
        match session::load(&path) {
            Ok(s) => match s.log.clone() {
                Some(log) => {
                    self.opening.session = Some((path.clone(), s));
                    let options = LoadOptions {
                        read: log.read,
                        bin_s: log.bin_s,
                        instance: log.instance,
                        more_runs: log.more_runs,
                        accel: log.accelerometers,
                    };
                    self.start_load(log.path, options, Target::Calibration);
                }
                None => self.fail(format!("{}: the session names no log", path.display())),
            },
            Err(e) => self.fail(format!(
                "Could not open the session. Nothing was changed.\n\n{e}"
            )),
        }
    }
}
