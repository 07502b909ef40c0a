//! What the workbench writes and opens on the engineer's request: calibrations, models,
//! corrected logs, reports and sessions.

use super::*;

impl Workbench {
    pub(super) fn export_calibration(&mut self) {
        let (Some(log), Some(fit)) = (self.state.log.clone(), self.state.fit.clone()) else {
            self.state
                .say(Severity::Warning, "Nothing to export yet: no calibration");
            return;
        };
        if !self.state.fit_current() || self.jobs.fitting() {
            // The newest choices first: wait for the refit on its way (milliseconds on a
            // sample log, a second or two on ten million samples).
            self.refit_if_needed();
            let deadline = Instant::now() + Duration::from_secs(60);
            while self.jobs.fitting() && Instant::now() < deadline {
                if let Some(r) = self.jobs.next(Duration::from_millis(20)) {
                    self.handle(r);
                }
            }
        }
        let fit = self.state.fit.clone().unwrap_or(fit);
        let name = export::suggested_name(Some(&log.path), "calibration.json");
        if let Some(p) = self
            .dialogs
            .save(FileKind::Calibration, self.dir().as_deref(), &name)
        {
            match export::save_calibration(
                &p,
                &fit.outcome.calibration,
                &log.path,
                log.sha256.as_deref(),
            ) {
                Ok(p) => {
                    self.settings.last_dir = p.parent().map(Path::to_path_buf);
                    self.state.say(
                        Severity::Info,
                        format!("Calibration written: {}", p.display()),
                    );
                }
                Err(e) => self.fail(format!("Could not write the calibration.\n\n{e}")),
            }
        }
    }

    /// Writes the model chosen on the Models page, asking where.
    pub(super) fn export_model(&mut self) {
        let (Some(log), Some(c)) = (self.state.log.clone(), self.state.models.clone()) else {
            self.state.say(
                Severity::Warning,
                "Nothing to export yet: compare the models first",
            );
            return;
        };
        let Some(model) = self.models.export.as_ref().and_then(|n| {
            c.reports
                .iter()
                .find(|r| &r.model == n)
                .and_then(|r| r.fitted.clone())
        }) else {
            self.state
                .say(Severity::Warning, "Choose a fitted model to export");
            return;
        };
        if !Arc::ptr_eq(&log.log, &c.logs[0].log) {
            self.state.say(
                Severity::Warning,
                "The log changed since the comparison: compare the models again first",
            );
            return;
        }
        let name = export::suggested_name(Some(&log.path), &format!("{}.json", model.name()));
        if let Some(p) = self
            .dialogs
            .save(FileKind::Model, self.dir().as_deref(), &name)
        {
            self.settings.last_dir = p.parent().map(Path::to_path_buf);
            let what = format!("model {}", model.name());
            let (log_path, sha) = (log.path.clone(), log.sha256.clone());
            self.jobs.spawn_export(&what, move || {
                export::save_model(&p, &model, &log_path, sha.as_deref())
            });
        }
    }

    pub(super) fn export_report(&mut self) {
        let (Some(log), Some(fit)) = (self.state.log.clone(), self.state.fit.clone()) else {
            self.state
                .say(Severity::Warning, "Nothing to report yet: no calibration");
            return;
        };
        let name = export::suggested_name(Some(&log.path), "report");
        let Some(dir) = self
            .dialogs
            .save(FileKind::Report, self.dir().as_deref(), &name)
        else {
            return;
        };
        // A name typed as "x.html" means the folder "x".
        let dir = dir.with_extension("");
        let cal = match export::stamped(&fit.outcome.calibration, &log.path, log.sha256.as_deref())
        {
            Ok(c) => c,
            Err(e) => return self.fail(format!("Could not write the report.\n\n{e}")),
        };
        let mut logs = vec![(log.path.clone(), (*log.log).clone())];
        if let Some(v) = &self.state.validation {
            logs.push((v.path.clone(), (*v.log).clone()));
        }
        self.state.say(
            Severity::Info,
            format!("Writing the report into {} …", dir.display()),
        );
        self.jobs
            .spawn_export("report", move || export::write_report(&dir, &cal, &logs));
    }

    pub(super) fn export_csv(&mut self) {
        let (Some(log), Some(fit)) = (self.state.log.clone(), self.state.fit.clone()) else {
            self.state
                .say(Severity::Warning, "Nothing to export yet: no calibration");
            return;
        };
        let name = export::suggested_name(Some(&log.path), "corrected.csv");
        if let Some(p) = self
            .dialogs
            .save(FileKind::CorrectedCsv, self.dir().as_deref(), &name)
        {
            self.state
                .say(Severity::Info, format!("Writing {} …", p.display()));
            let l = log.log.clone();
            self.jobs.spawn_export("corrected log", move || {
                export::write_corrected_csv(&p, &l, &fit.outcome.in_sample.corrected)
            });
        }
    }

    /// Saves the session; true when written.
    pub(super) fn save_session(&mut self, ask: bool) -> bool {
        if self.state.log.is_none() {
            self.state
                .say(Severity::Warning, "Nothing to save: no log is open");
            return false;
        }
        let path = match (&self.state.session_path, ask) {
            (Some(p), false) => Some(p.clone()),
            _ => {
                let name = export::suggested_name(
                    self.state.log.as_ref().map(|l| l.path.as_path()),
                    "session.json",
                );
                self.dialogs
                    .save(FileKind::Session, self.dir().as_deref(), &name)
            }
        };
        let Some(path) = path else {
            return false;
        };
        match session::save(&path, &self.state.session()) {
            Ok(()) => {
                self.state.session_path = Some(path.clone());
                self.state.mark_saved();
                self.autosave.clear();
                self.settings.add_recent(&path);
                self.state
                    .say(Severity::Info, format!("Session saved: {}", path.display()));
                true
            }
            Err(e) => {
                self.fail(format!("Could not save the session.\n\n{e}"));
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
                    self.pending_session = Some((path.clone(), s));
                    self.start_load(log.path, log.read, Target::Calibration);
                }
                None => self.fail(format!("{}: the session names no log", path.display())),
            },
            Err(e) => self.fail(format!(
                "Could not open the session. Nothing was changed.\n\n{e}"
            )),
        }
    }
}
