//! What the workbench asks of its worker and what it does with the answers: refits, loads,
//! comparisons and Allan curves, and the messages when one fails.

use super::*;

impl Workbench {
    /// Sends the refit the current choices need, once.
    pub(super) fn refit_if_needed(&mut self) {
        if let Some(req) = self.state.request() {
            self.jobs.refit(req);
        }
    }

    pub(super) fn handle(&mut self, r: JobResult) {
        match r {
            JobResult::Loaded(Target::Calibration, l) => {
                let l = *l;
                let path = l.path.clone();
                let msg = format!(
                    "Read {} samples from {} in {:.2} s{}{}",
                    l.log.info.rows_read.max(l.log.len()),
                    file_name(&path),
                    l.seconds,
                    if l.log.info.problems.is_empty() {
                        String::new()
                    } else {
                        format!(
                            "; {} kind(s) of problems worked around (see Data)",
                            l.log.info.problems.len()
                        )
                    },
                    l.resampled
                        .as_ref()
                        .map(|n| format!("; {n}"))
                        .unwrap_or_default()
                );
                self.look_at_columns(&l, Target::Calibration);
                // The same file read again with another mapping keeps the work on it.
                let remapped = self.opening.session.is_none()
                    && self
                        .state
                        .log
                        .as_ref()
                        .is_some_and(|old| same_file(&old.path, &path));
                self.state.log = Some(l);
                self.state.fit = None;
                self.state.fit_error = None;
                self.views.time.selected = None;
                match self.opening.session.take() {
                    Some((spath, s))
                        if s.log.as_ref().is_some_and(|r| same_file(&r.path, &path)) =>
                    {
                        self.state.choices = Choices {
                            recipe: s.recipe.clone(),
                            knots: s.knots.clone(),
                        };
                        self.state.view = s.view.clone();
                        self.views.time.x_command = Some(match s.view.time_range_s {
                            Some([a, b]) => XCommand::Range(a, b),
                            None => XCommand::Fit,
                        });
                        self.state.validation = None;
                        if self.opening.autosaved {
                            // Autosaved work is not saved work: no session file, still dirty.
                            self.opening.autosaved = false;
                            self.state.session_path = None;
                            self.state.mark_unsaved();
                        } else {
                            self.state.session_path = Some(spath.clone());
                            self.state.mark_saved();
                        }
                        if let Some(v) = &s.validation {
                            self.opening.validation_shown = Some(s.view.show_validation);
                            let options = LoadOptions {
                                read: v.read.clone(),
                                bin_s: v.bin_s,
                            };
                            self.start_load(v.path.clone(), options, Target::Validation);
                        }
                        if self.state.session_path.is_some() {
                            self.window.settings.add_recent(&spath);
                        }
                    }
                    _ if remapped => {
                        self.views.time.x_command = Some(XCommand::Fit);
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
                        self.views.time.x_command = Some(XCommand::Fit);
                        self.window.settings.add_recent(&path);
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
                self.look_at_columns(&l, Target::Validation);
                self.state.validation = Some(*l);
                match self.opening.validation_shown.take() {
                    Some(shown) => {
                        self.state.view.show_validation = shown;
                        self.state.mark_saved();
                    }
                    None => self.state.view.show_validation = true,
                }
                self.state.say(Severity::Info, msg);
            }
            JobResult::LoadFailed(_, path, message) => {
                self.opening.session = None;
                self.opening.validation_shown = None;
                self.state.say(
                    Severity::Error,
                    format!("Could not read {}", file_name(&path)),
                );
                if self.shots.auto.is_some() {
                    self.finish_auto(Err(message));
                } else {
                    self.fail(format!(
                        "Could not read the log. Nothing was changed.\n\n{message}"
                    ));
                }
            }
            JobResult::LoadCancelled(_, path) => {
                self.opening.session = None;
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
                        self.views.time.x_command = Some(XCommand::Fit);
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
                            self.views.models.adopt(&c);
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
                    if what == "screenshot" && self.shots.auto.is_some() {
                        self.finish_auto(Err(e));
                    } else {
                        self.fail(e);
                    }
                }
            },
        }
    }

    /// Opens the import view on a log just read when the reader found something about its
    /// columns to look at (not the rows and time steps it works around), with what it said.
    fn look_at_columns(&mut self, l: &Loaded, target: Target) {
        let doubts = l.log.info.problems.iter().any(|p| about_columns(p.kind));
        if doubts && self.modals.import.is_none() && self.shots.auto.is_none() {
            self.modals.import = Some(
                ImportView::new(l.path.clone(), target, l.options.clone())
                    .with_warnings(read_warnings(l)),
            );
        }
    }

    pub(super) fn fail(&mut self, message: String) {
        if self.shots.auto.is_some() {
            self.finish_auto(Err(message));
        } else {
            self.modals.error = Some(message);
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
        let choices = match self.views.models.choices() {
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
        let recipe = match self.state.recipe().clone().checked() {
            Ok(r) => r,
            Err(e) => {
                self.state.say(Severity::Warning, e.to_string());
                return;
            }
        };
        let n = choices.len();
        let names = crate::gui::view_models::log_names(&log.log, &tests);
        self.jobs.compare(crate::gui::jobs::CompareRequest {
            train: log.log.clone(),
            tests,
            choices,
            recipe,
            merit: self.state.merit(),
        });
        self.state
            .say(Severity::Info, format!("Fitting {n} models on {names} …"));
    }
}

/// Whether a problem the reader reports is about the columns it chose (a role's values that
/// role cannot have) rather than rows or time steps it worked around.
fn about_columns(kind: crate::log::ProblemKind) -> bool {
    use crate::log::ProblemKind::*;
    match kind {
        Implausible | DuplicateName => true,
        MissingValue | BadExtraValue | TimeBackwards | TimeRepeated | Gap | RaggedRow => false,
    }
}

/// What the reader said about a log it read, for the import view: each problem it worked
/// around (with its line, column and count), and how the log was averaged after the read.
pub(super) fn read_warnings(l: &Loaded) -> Vec<ReadWarning> {
    let mut out: Vec<ReadWarning> = l
        .log
        .info
        .problems
        .iter()
        .map(|p| {
            let at = match (p.line, p.column) {
                (0, None) => String::new(),
                (0, Some(c)) => format!("column {c}: "),
                (l, None) => format!("line {l}: "),
                (l, Some(c)) => format!("line {l}, column {c}: "),
            };
            let times = if p.count == 1 {
                String::new()
            } else {
                format!(" ({}×)", p.count)
            };
            ReadWarning {
                about_columns: about_columns(p.kind),
                text: format!("{at}{}{times}", p.message),
            }
        })
        .collect();
    if let Some(note) = &l.resampled {
        out.push(ReadWarning {
            about_columns: false,
            text: format!("After the read: {note}"),
        });
    }
    out
}
