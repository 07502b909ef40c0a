//! What the workbench asks of its worker and what it does with the answers: refits, loads,
//! comparisons and Allan curves, and the messages when one fails.

use super::*;

impl Workbench {
    pub(super) fn refit_if_needed(&mut self) {
        let Some(log) = &self.state.log else {
            return;
        };
        let key = (
            self.state.choices.clone(),
            arc_addr(&log.log),
            self.state
                .validation
                .as_ref()
                .map_or(0, |v| arc_addr(&v.log)),
        );
        if self.last_request.as_ref() != Some(&key)
            && let Some(req) = self.state.request()
        {
            self.jobs.fit(req);
            self.last_request = Some(key);
        }
    }

    pub(super) fn handle(&mut self, r: JobResult) {
        match r {
            JobResult::Loaded(Target::Calibration, l) => {
                let l = *l;
                let path = l.path.clone();
                let msg = format!(
                    "Read {} samples from {} in {:.2} s{}",
                    l.log.len(),
                    file_name(&path),
                    l.seconds,
                    if l.log.info.problems.is_empty() {
                        String::new()
                    } else {
                        format!(
                            "; {} kind(s) of problems worked around (see Data)",
                            l.log.info.problems.len()
                        )
                    }
                );
                // The same file read again with another mapping keeps the work on it.
                let remapped = self.pending_session.is_none()
                    && self
                        .state
                        .log
                        .as_ref()
                        .is_some_and(|old| same_file(&old.path, &path));
                self.state.log = Some(l);
                self.state.fit = None;
                self.state.fit_error = None;
                self.time.selected = None;
                match self.pending_session.take() {
                    Some((spath, s))
                        if s.log.as_ref().is_some_and(|r| same_file(&r.path, &path)) =>
                    {
                        self.state.choices = Choices {
                            recipe: s.recipe.clone(),
                            knots: s.knots.clone(),
                        };
                        self.state.view = s.view.clone();
                        self.time.x_command = Some(match s.view.time_range_s {
                            Some([a, b]) => XCommand::Range(a, b),
                            None => XCommand::Fit,
                        });
                        self.state.validation = None;
                        if self.restoring_autosave {
                            // Autosaved work is not saved work: no session file, still dirty.
                            self.restoring_autosave = false;
                            self.state.session_path = None;
                            self.state.mark_unsaved();
                        } else {
                            self.state.session_path = Some(spath.clone());
                            self.state.mark_saved();
                        }
                        if let Some(v) = &s.validation {
                            self.restoring_validation = Some(s.view.show_validation);
                            self.start_load(v.path.clone(), v.read.clone(), Target::Validation);
                        }
                        if self.state.session_path.is_some() {
                            self.settings.add_recent(&spath);
                        }
                    }
                    _ if remapped => {
                        self.time.x_command = Some(XCommand::Fit);
                    }
                    _ => {
                        // Choices carry over to the new log, except what belonged to the old one.
                        if !self.state.plateaus_auto() {
                            self.state.recipe_mut().plateaus =
                                crate::models::recipe::PlateauChoice::default();
                        }
                        self.state.choices.knots = Default::default();
                        self.state.session_path = None;
                        self.state.mark_saved();
                        self.time.x_command = Some(XCommand::Fit);
                        self.settings.add_recent(&path);
                    }
                }
                if !remapped {
                    self.state.history.reset(&self.state.choices);
                }
                self.state.say(Severity::Info, msg);
            }
            JobResult::Loaded(Target::Validation, l) => {
                let msg = format!(
                    "Validation log {} ({} samples)",
                    file_name(&l.path),
                    l.log.len()
                );
                self.state.validation = Some(*l);
                match self.restoring_validation.take() {
                    Some(shown) => {
                        self.state.view.show_validation = shown;
                        self.state.mark_saved();
                    }
                    None => self.state.view.show_validation = true,
                }
                self.state.say(Severity::Info, msg);
            }
            JobResult::LoadFailed(_, path, message) => {
                self.pending_session = None;
                self.restoring_validation = None;
                self.state.say(
                    Severity::Error,
                    format!("Could not read {}", file_name(&path)),
                );
                if self.auto.is_some() {
                    self.finish_auto(Err(message));
                } else {
                    self.fail(format!(
                        "Could not read the log. Nothing was changed.\n\n{message}"
                    ));
                }
            }
            JobResult::LoadCancelled(_, path) => {
                self.pending_session = None;
                self.state.say(
                    Severity::Info,
                    format!("Reading {} cancelled", file_name(&path)),
                );
            }
            JobResult::Fitted(view) => {
                let newer = self
                    .state
                    .fit
                    .as_ref()
                    .is_none_or(|f| f.generation < view.generation);
                if newer {
                    if view.generation == self.jobs.requested {
                        self.state.fit_error = None;
                    }
                    self.state.fit = Some(view);
                }
            }
            JobResult::FitFailed(generation, message) => {
                if generation == self.jobs.requested {
                    if self.state.fit.is_none() {
                        // No calibration to show: the raw log, fitted to the window.
                        self.time.x_command = Some(XCommand::Fit);
                    }
                    self.state.fit_error = Some(message.clone());
                    self.state
                        .say(Severity::Error, format!("Calibration failed: {message}"));
                    // A screenshot of a failed calibration is not what was asked for.
                    self.finish_auto(Err(format!("the calibration failed: {message}")));
                }
            }
            JobResult::Compared(generation, result) => {
                if generation == self.jobs.compare_requested() {
                    match result {
                        Ok(c) => {
                            let failed = c.reports.iter().filter(|r| r.error.is_some()).count();
                            self.state.say(
                                Severity::Info,
                                format!(
                                    "Compared {} models in {:.1} s{}",
                                    c.reports.len(),
                                    c.seconds,
                                    if failed > 0 {
                                        format!("; {failed} could not be fitted")
                                    } else {
                                        String::new()
                                    }
                                ),
                            );
                            self.models.adopt(&c);
                            self.state.models = Some(c);
                            self.state.models_error = None;
                        }
                        Err(e) if e == crate::gui::jobs::CANCELLED => {
                            self.state.say(
                                Severity::Info,
                                if self.state.models.is_some() {
                                    "Comparison cancelled: the table shows the comparison before"
                                } else {
                                    "Comparison cancelled"
                                },
                            );
                        }
                        Err(e) => {
                            self.state
                                .say(Severity::Error, format!("Comparison failed: {e}"));
                            self.state.models_error = Some(e);
                        }
                    }
                }
            }
            JobResult::Allan(v) => {
                self.state.allan = Some(v);
            }
            JobResult::Exported(what, result) => match result {
                Ok(path) => {
                    self.state
                        .say(Severity::Info, format!("Saved {what}: {}", path.display()));
                    if what == "screenshot" {
                        self.finish_auto(Ok(()));
                    }
                }
                Err(e) => {
                    self.state.say(
                        Severity::Error,
                        format!("Could not save {what}, nothing was written: {e}"),
                    );
                    if what == "screenshot" && self.auto.is_some() {
                        self.finish_auto(Err(e));
                    } else {
                        self.fail(e);
                    }
                }
            },
        }
    }

    pub(super) fn fail(&mut self, message: String) {
        if self.auto.is_some() {
            self.finish_auto(Err(message));
        } else {
            self.error = Some(message);
        }
    }

    /// Asks the worker for the Allan deviations of the log the Allan page shows.
    pub(super) fn request_allan(&mut self, key: (u64, bool)) {
        let Some(fit) = &self.state.fit else {
            return;
        };
        let judged = if key.1 {
            fit.outcome.held_out.as_ref()
        } else {
            Some(&fit.outcome.in_sample)
        };
        if let Some(j) = judged {
            self.jobs.allan(crate::gui::jobs::AllanRequest {
                key,
                log: j.log.clone(),
                corrected: j.corrected.clone(),
            });
        }
    }

    /// Sends the comparison of the models ticked on the Models page to a worker.
    pub(super) fn compare_models(&mut self) {
        let Some(log) = &self.state.log else {
            self.state.say(Severity::Warning, "Open a log first");
            return;
        };
        if self.jobs.comparing.is_some() {
            self.state.say(
                Severity::Info,
                "A comparison is running; wait for it to finish",
            );
            return;
        }
        let choices = match self.models.choices() {
            Ok(c) => c,
            Err(e) => {
                self.state.say(Severity::Warning, e);
                return;
            }
        };
        let tests: Vec<Arc<crate::log::Log>> = self
            .state
            .validation
            .iter()
            .map(|v| v.log.clone())
            .collect();
        let n = choices.len();
        let names = crate::gui::view_models::log_names(&log.log, &tests);
        self.jobs.compare(crate::gui::jobs::CompareRequest {
            train: log.log.clone(),
            tests,
            choices,
            recipe: self.state.recipe().clone(),
            merit: self.state.merit(),
        });
        self.state
            .say(Severity::Info, format!("Fitting {n} models on {names} …"));
    }
}
