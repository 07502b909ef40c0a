//! What the workbench asks of its worker and what it does with the answers: refits, loads,
//! comparisons and Allan curves, and the messages when one fails.

use super::*;

impl Workbench {
    /// Sends the refit the current choices need, once: the shown axis's at once; the other
    /// axes of a unit (a change of the T settings or plateaus they share) once the pointer is
    /// released, so that a drag refits only the axis it edits.
    pub(super) fn refit_if_needed(&mut self) {
        self.state.share_temperature();
        let active = self.state.active_axis();
        if self.window.pointer_down && self.window.plateau_drag {
            // While an edge moves: its plateaus and K0 alone; every axis is refitted on release.
            if let Some(l) = &self.state.shown.log {
                let ranges = self.state.ranges();
                self.jobs
                    .preview(active, &l.log, &ranges, &self.state.shown.choices.recipe);
            }
            return;
        }
        if let Some(req) = self.state.request() {
            self.jobs.refit(active, req);
        }
        if self.window.pointer_down {
            return;
        }
        for k in (0..self.state.axis_count()).filter(|&k| k != active) {
            if let Some(req) = self.state.axis(k).and_then(|a| a.request()) {
                self.jobs.refit(k, req);
            }
        }
        // The accelerometer axes, with the unit's recipe (the first gyro axis's).
        if let Some(req) = self.state.accel_request() {
            self.jobs.accel(req);
        }
    }

    /// Shows axis `k` of the unit (nothing is refitted: each axis keeps its fit).
    pub(super) fn select_axis(&mut self, k: usize) {
        // A gyro axis chosen: the accelerometer axis shown makes way for it.
        if let Some(a) = &mut self.state.accel {
            a.shown = None;
        }
        if self.state.unit.is_none() || k == self.state.active_axis() {
            return;
        }
        if !self.state.switch_axis(k) {
            return;
        }
        // A plateau selected on one axis is the same plateau on every other (they share
        // them); the Models page's selection belongs to the comparison of the axis shown.
        if let Some(c) = self.state.shown.models.clone() {
            self.views.models.adopt(&c);
        }
    }

    /// The unit of a log of several axes just read: its first axis shown (`state.shown.log`), the
    /// others parked with `choices` (or those of `by_name`, for an axis named there).
    fn make_unit(
        &mut self,
        views: Vec<Loaded>,
        choices: &Choices,
        by_name: &std::collections::HashMap<String, Choices>,
        shown: Option<&str>,
    ) {
        let full_log = self.state.shown.log.as_ref().map(|l| l.log.clone());
        let names: Vec<String> = views.iter().map(|v| v.log.axis.clone()).collect();
        let parked = views
            .into_iter()
            .enumerate()
            .map(|(k, v)| {
                if k == 0 {
                    return crate::gui::state::AxisLive::default();
                }
                let choices = by_name
                    .get(&names[k])
                    .cloned()
                    .unwrap_or_else(|| choices.clone());
                let mut history = crate::gui::state::History::default();
                history.reset(&choices);
                crate::gui::state::AxisLive {
                    log: Some(v),
                    choices,
                    history,
                    ..Default::default()
                }
            })
            .collect();
        if let Some(c) = by_name.get(&names[0]) {
            self.state.shown.choices = c.clone();
        }
        // The first axis's undo starts afresh too (it may be parked below).
        self.state.shown.history.reset(&self.state.shown.choices);
        self.jobs.set_axes(names.len());
        self.state.unit = Some(crate::gui::state::Unit {
            names,
            active: 0,
            parked,
            full_log,
        });
        if let Some(k) =
            shown.and_then(|n| self.state.unit.as_ref()?.names.iter().position(|x| x == n))
        {
            self.state.switch_axis(k);
        }
    }

    pub(super) fn handle(&mut self, r: JobResult) {
        match r {
            JobResult::Loaded(Target::Calibration, l) => {
                let mut l = *l;
                let views = std::mem::take(&mut l.axis_views);
                // The choices of each axis of the unit shown before, when the same file is
                // read again with another mapping.
                let old_axes: std::collections::HashMap<String, Choices> = self
                    .state
                    .unit
                    .as_ref()
                    .map(|u| {
                        (0..u.names.len())
                            .filter_map(|k| self.state.axis(k))
                            .map(|a| (a.name.to_string(), a.choices.clone()))
                            .collect()
                    })
                    .unwrap_or_default();
                if self.state.unit.is_some() {
                    // Back to the first axis, then the old unit goes.
                    self.state.switch_axis(0);
                    self.state.unit = None;
                }
                let path = l.path.clone();
                let msg = format!(
                    "Read {} samples from {} in {:.2} s{}{}",
                    l.log.info.rows_read.max(l.log.len()),
                    match l.log.runs().len() {
                        n if n > 1 => format!(
                            "{n} runs ({})",
                            l.log
                                .runs()
                                .iter()
                                .map(|r| r.name.as_str())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                        _ => file_name(&path),
                    },
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
                let doubt = self.look_at_columns(&l, Target::Calibration);
                let msg = match &doubt {
                    Some(d) => format!("{msg}; {d}"),
                    None => msg,
                };
                // The same file read again with another mapping keeps the work on it.
                let remapped = self.opening.session.is_none()
                    && self
                        .state
                        .shown
                        .log
                        .as_ref()
                        .is_some_and(|old| same_file(&old.path, &path));
                self.state.shown.log = Some(l);
                self.state.shown.fit = None;
                self.state.shown.fit_error = None;
                self.views.time.selected = None;
                let mut by_name = std::collections::HashMap::new();
                let mut shown_axis = None;
                let mut from_session = false;
                match self.opening.session.take() {
                    Some((spath, s))
                        if s.log.as_ref().is_some_and(|r| same_file(&r.path, &path)) =>
                    {
                        self.state.shown.choices = Choices {
                            recipe: s.recipe.clone(),
                        };
                        for a in &s.axes {
                            by_name.insert(
                                a.name.clone(),
                                Choices {
                                    recipe: a.recipe.clone(),
                                },
                            );
                        }
                        shown_axis = s.view.axis.clone();
                        self.state.accel_off = s.accelerometers_off;
                        self.state.view = s.view.clone();
                        self.state.merit_window_s = Some(s.merit.window_s);
                        self.views.time.x_command = Some(match s.view.time_range_s {
                            Some([a, b]) => XCommand::Range(a, b),
                            None => XCommand::Fit,
                        });
                        // The session opens its own validation log, if any.
                        self.forget_validation();
                        from_session = true;
                        self.k0_from_session();
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
                                instance: v.instance,
                                more_runs: Vec::new(),
                                accel: v.accelerometers.clone(),
                            };
                            self.start_load(v.path.clone(), options, Target::Validation);
                        }
                        if self.state.session_path.is_some() {
                            self.window.settings.add_recent(&spath);
                        }
                    }
                    _ if remapped => {
                        by_name = old_axes;
                        self.views.time.x_command = Some(XCommand::Fit);
                    }
                    _ => {
                        // Choices carry over to the new log, except what belonged to the old one.
                        if !self.state.plateaus_auto() {
                            self.state.recipe_mut().plateaus =
                                crate::models::recipe::PlateauChoice::default();
                        }
                        let recipe = std::mem::take(&mut self.state.shown.choices.recipe);
                        self.state.shown.choices.recipe = recipe.without_hand_knots();
                        self.state.session_path = None;
                        self.state.mark_saved();
                        self.views.time.x_command = Some(XCommand::Fit);
                        self.window.settings.add_recent(&path);
                        self.k0_on_fresh_log();
                    }
                }
                // The accelerometer axes of a unit (on unless a session turned them off).
                if !remapped && !from_session {
                    self.state.accel_off = false;
                }
                // (a campaign calibrates its gyro axes alone: an accelerometer keeps the mean of
                // the one run it is fitted on)
                // A log of one gyro axis has them too: with them it is a unit of that axis
                // and its accelerometers, as `calibrate --accel` makes it.
                self.state.accel = self
                    .state
                    .shown
                    .log
                    .as_ref()
                    .filter(|l| l.log.runs().len() < 2)
                    .and_then(crate::gui::state::AccelAxes::of);
                if views.is_empty() {
                    self.jobs.set_axes(1);
                } else {
                    let choices = self.state.shown.choices.clone();
                    self.make_unit(views, &choices, &by_name, shown_axis.as_deref());
                    if self.state.baseline.is_some() && !remapped {
                        // Saved (or freshly opened) as it now stands, every axis included.
                        self.state.mark_saved();
                    }
                }
                if !remapped || self.state.unit.is_some() {
                    self.state.shown.history.reset(&self.state.shown.choices);
                }
                // The validation log open is kept only where it matches the new log's axes.
                let (validation, put_away) = match from_session {
                    true => None,
                    false => self.validation_after_new_log(),
                }
                .unwrap_or_default();
                let msg = format!("{msg}{validation}");
                // Choices kept for axes this log lacks are not applied to any: said, so that
                // the engineer knows the session's work on them is not on screen.
                let axes = match &self.state.unit {
                    Some(u) => u.names.clone(),
                    None => (self.state.shown.log.as_ref())
                        .map(|l| l.log.axis_names())
                        .unwrap_or_default(),
                };
                let mut lost: Vec<&String> = by_name.keys().filter(|n| !axes.contains(n)).collect();
                lost.sort();
                if lost.is_empty() {
                    let severity = if put_away || doubt.is_some() {
                        Severity::Warning
                    } else {
                        Severity::Info
                    };
                    self.state.say(severity, msg);
                } else {
                    let lost: Vec<&str> = lost.iter().map(|n| n.as_str()).collect();
                    self.state.say(
                        Severity::Warning,
                        format!(
                            "{msg}; the choices kept for axis {} are not used: this log has no \
                             such axis (its axes: {})",
                            lost.join(", "),
                            axes.join(", ")
                        ),
                    );
                }
                if let Some((path, options)) = self.opening.validation.take() {
                    self.start_load(path, options, Target::Validation);
                }
                if let Some(c) = self.opening.calibration.take() {
                    self.open_calibration(c);
                }
            }
            JobResult::Loaded(Target::Validation, l) => self.validation_read(*l),
            JobResult::LoadFailed(_, path, message) => {
                let message = crate::gui::view_import::in_labels(&message);
                self.opening.session = None;
                self.opening.validation_shown = None;
                self.opening.validation = None;
                self.opening.calibration = None;
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
                self.opening.calibration = None;
                self.state.say(
                    Severity::Info,
                    format!("Reading {} cancelled", file_name(&path)),
                );
            }
            JobResult::Fitted(view) if view.axis != self.state.active_axis() => {
                let newest = self.jobs.newest(view.axis);
                let k = view.axis;
                let log = self
                    .state
                    .axis(k)
                    .and_then(|a| a.log.map(|l| l.log.clone()));
                if let Some(p) = self.state.unit.as_mut().and_then(|u| u.parked.get_mut(k))
                    && log.is_some_and(|l| Arc::ptr_eq(&l, &view.outcome.in_sample.log))
                    && p.fit
                        .as_ref()
                        .is_none_or(|f| f.generation < view.generation)
                {
                    if view.generation == newest {
                        p.fit_error = None;
                    }
                    p.fit = Some(view);
                }
            }
            JobResult::AccelFitted(v) => {
                // The newest asked for alone (an older answer arriving late is stale).
                if v.generation == self.jobs.newest_accel()
                    && let Some(a) = &mut self.state.accel
                {
                    a.fit = Some(v);
                }
            }
            JobResult::Previewed(p) => {
                let newer = |g: Option<u64>| g.is_none_or(|g| g < p.generation);
                if p.axis == self.state.active_axis()
                    && newer(self.state.shown.fit.as_ref().map(|f| f.generation))
                    && newer(self.state.shown.preview.as_ref().map(|q| q.generation))
                {
                    self.state.shown.preview = Some(p);
                }
            }
            JobResult::Fitted(view) => {
                if self
                    .state
                    .shown
                    .preview
                    .as_ref()
                    .is_some_and(|p| p.generation < view.generation)
                {
                    self.state.shown.preview = None;
                }
                let newer = self
                    .state
                    .shown
                    .fit
                    .as_ref()
                    .is_none_or(|f| f.generation < view.generation);
                if newer {
                    if view.generation == self.jobs.newest(view.axis) {
                        self.state.shown.fit_error = None;
                    }
                    self.state.shown.fit = Some(view);
                    self.k0_from_first_fit();
                }
            }
            JobResult::FitFailed(axis, generation, message) if axis != self.state.active_axis() => {
                if generation == self.jobs.newest(axis)
                    && let Some(p) = self
                        .state
                        .unit
                        .as_mut()
                        .and_then(|u| u.parked.get_mut(axis))
                {
                    p.fit_error = Some(message);
                }
            }
            JobResult::FitFailed(axis, generation, message) => {
                if generation == self.jobs.newest(axis) {
                    if self.state.shown.fit.is_none() {
                        // No calibration to show: the raw log, fitted to the window.
                        self.views.time.x_command = Some(XCommand::Fit);
                    }
                    self.state.shown.fit_error = Some(message.clone());
                    self.state
                        .say(Severity::Error, format!("Calibration failed: {message}"));
                    // A screenshot of a failed calibration is not what was asked for.
                    self.finish_auto(Err(format!("the calibration failed: {message}")));
                }
            }
            JobResult::Compared(generation, Ok(c))
                if generation == self.jobs.compare_requested()
                    && self.state.unit.is_some()
                    && !self.state.shown.log.as_ref().is_some_and(|l| {
                        c.logs.first().is_some_and(|f| Arc::ptr_eq(&f.log, &l.log))
                    }) =>
            {
                // Another axis's comparison (asked before a switch) waits with that axis.
                if let Some(u) = &mut self.state.unit
                    && let Some(p) = u.parked.iter_mut().find(|p| {
                        p.log.as_ref().is_some_and(|l| {
                            c.logs.first().is_some_and(|f| Arc::ptr_eq(&f.log, &l.log))
                        })
                    })
                {
                    p.models = Some(c);
                    p.models_error = None;
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
                            self.state.shown.models = Some(c);
                            self.state.shown.models_error = None;
                        }
                        Err(crate::Error::Cancelled) => {
                            self.state.say(
                                Severity::Info,
                                if self.state.shown.models.is_some() {
                                    "Comparison cancelled: the table shows the comparison before"
                                } else {
                                    "Comparison cancelled"
                                },
                            );
                        }
                        Err(e) => {
                            self.state
                                .say(Severity::Error, format!("Comparison failed: {e}"));
                            self.state.shown.models_error = Some(e.to_string());
                        }
                    }
                }
            }
            JobResult::Allan(v) => {
                // Another axis's curves (asked before a switch) wait with that axis.
                let generation = v.key.0;
                let mine = self
                    .state
                    .shown
                    .fit
                    .as_ref()
                    .is_none_or(|f| f.generation == generation);
                match self.state.unit.as_mut().filter(|_| !mine) {
                    Some(u) => {
                        if let Some(p) = u
                            .parked
                            .iter_mut()
                            .find(|p| p.fit.as_ref().is_some_and(|f| f.generation == generation))
                        {
                            p.allan = Some(v);
                        }
                    }
                    None => self.state.shown.allan = Some(v),
                }
            }
            JobResult::CalibrationRead(path, read) => self.calibration_read(path, read),
            JobResult::Verified(v) => self.verified(v),
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
    /// For a drone or robot log, which has no columns to map (the import view would read it
    /// as text), what the reader doubts (an axis that reads one value throughout) is returned
    /// for the caller to say, and the log is worked on as read.
    pub(super) fn look_at_columns(&mut self, l: &Loaded, target: Target) -> Option<String> {
        let doubts = l.log.info.problems.iter().any(|p| about_columns(p.kind));
        if doubts && l.drone.is_some() {
            let said: Vec<String> = read_warnings(l)
                .into_iter()
                .filter(|w| w.about_columns)
                .map(|w| w.text)
                .collect();
            return Some(said.join("; "));
        }
        if doubts && self.modals.import.is_none() && self.shots.auto.is_none() {
            self.modals.import = Some(
                ImportView::new(l.path.clone(), target, l.options.clone())
                    .with_warnings(read_warnings(l)),
            );
        }
        None
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
        let Some(fit) = &self.state.shown.fit else {
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
        let Some(log) = &self.state.shown.log else {
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
            .shown
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
        Implausible | DuplicateName | UnitMismatch => true,
        MissingValue | BadExtraValue | TimeBackwards | TimeRepeated | Gap | RaggedRow | LeftOut
        | Unchecked => false,
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
                text: format!(
                    "{at}{}{times}",
                    crate::gui::view_import::in_labels(&p.message)
                ),
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
