//! The workbench's menu bar, status bar, banner and modal windows.

use super::*;

impl Workbench {
    pub(super) fn menu_bar(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        let ctx = ui.ctx().clone();
        let sc = |s: &KeyboardShortcut| ctx.format_shortcut(s);
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                let has_log = self.state.shown.log.is_some();
                let has_fit = self.state.shown.fit.is_some();
                if ui
                    .add(egui::Button::new("Open log…").shortcut_text(sc(&shortcuts::OPEN)))
                    .on_hover_text("Open a chamber log: preview, fix the mapping, then read it")
                    .clicked()
                {
                    actions.push(Action::OpenLog);
                    ui.close();
                }
                if ui
                    .add_enabled(has_log, egui::Button::new("Add run…"))
                    .on_hover_text(
                        "Add another chamber run of the same gyro: the runs are calibrated \
                         together as one campaign (each run's smoothing, derivatives and \
                         plateaus its own; K0 from every run's plateaus)",
                    )
                    .clicked()
                {
                    actions.push(Action::AddRun);
                    ui.close();
                }
                if ui
                    .add_enabled(has_log, egui::Button::new("Open validation log…"))
                    .on_hover_text("A second log of the same gyro, to judge the calibration held out")
                    .clicked()
                {
                    actions.push(Action::OpenValidation);
                    ui.close();
                }
                if ui
                    .add_enabled(has_log, egui::Button::new("Column mapping…"))
                    .on_hover_text("Reopen the import view on the loaded log: columns, units, separator, decimal comma")
                    .clicked()
                {
                    actions.push(Action::ColumnMapping(Target::Calibration));
                    ui.close();
                }
                self.gyro_menu(ui, actions);
                if ui
                    .add(egui::Button::new("Open calibration…").shortcut_text(sc(&shortcuts::OPEN_CALIBRATION)))
                    .on_hover_text("Open a calibration file (JSON) beside the current fit: its figures and corrected drift on the open logs, to compare")
                    .clicked()
                {
                    actions.push(Action::OpenCalibration);
                    ui.close();
                }
                if self.state.opened.is_some()
                    && ui
                        .button("Close opened calibration")
                        .on_hover_text("Put the opened calibration away (the current fit stays)")
                        .clicked()
                {
                    actions.push(Action::CloseCalibration);
                    ui.close();
                }
                if ui
                    .button("Open lot…")
                    .on_hover_text("Open a lot's output folder (lot.json or lot.csv, as `driftlab lot` writes them): the table of units sorted by any column, each figure's distribution; a click opens a unit on the Calibration page")
                    .clicked()
                {
                    actions.push(Action::OpenLot);
                    ui.close();
                }
                if self.state.lot.is_some()
                    && ui
                        .button("Close lot")
                        .on_hover_text("Put the lot away (the work on the Calibration page stays)")
                        .clicked()
                {
                    actions.push(Action::CloseLot);
                    ui.close();
                }
                ui.menu_button("Recent", |ui| {
                    if self.window.settings.recent.is_empty() {
                        ui.weak("No recent files");
                    }
                    for p in self.window.settings.recent.clone() {
                        let label = crate::gui::widgets::file_name(&p);
                        if ui.button(label).on_hover_text(p.display().to_string()).clicked() {
                            actions.push(if is_json(&p) {
                                super::opened::json_action(p)
                            } else {
                                Action::OpenLogPath(p)
                            });
                            ui.close();
                        }
                    }
                });
                ui.separator();
                if ui
                    .add(egui::Button::new("Open session…").shortcut_text(sc(&shortcuts::OPEN_SESSION)))
                    .on_hover_text("Reopen a saved session exactly as it was left")
                    .clicked()
                {
                    actions.push(Action::OpenSession);
                    ui.close();
                }
                if ui
                    .add_enabled(has_log, egui::Button::new("Save session").shortcut_text(sc(&shortcuts::SAVE)))
                    .on_hover_text("Save the log path, mapping, plateaus and every choice")
                    .clicked()
                {
                    actions.push(Action::SaveSession);
                    ui.close();
                }
                if ui
                    .add_enabled(has_log, egui::Button::new("Save session as…"))
                    .on_hover_text("Save the session under a new name")
                    .clicked()
                {
                    actions.push(Action::SaveSessionAs);
                    ui.close();
                }
                ui.separator();
                if ui
                    .add_enabled(has_fit, egui::Button::new("Export calibration…").shortcut_text(sc(&shortcuts::EXPORT)))
                    .on_hover_text("Write the calibration file (JSON) the gyro's processor and `driftlab apply` read")
                    .clicked()
                {
                    actions.push(Action::ExportCalibration);
                    ui.close();
                }
                for (format, label, hover) in [
                    (crate::export::firmware::Format::Px4Params, "Export PX4 parameters…", "Write PX4's TC_G* thermal compensation (K0(T) alone) as a QGroundControl .params file; the gyro id must be the gyro's device_id"),
                    (crate::export::firmware::Format::ArdupilotParm, "Export ArduPilot parameters…", "Write ArduPilot's INS_TCALn_* temperature calibration, n the IMU of the DataFlash log it was fitted on, else 1 (K0(T) alone, up to its constant)"),
                ] {
                    if ui.add_enabled(has_fit, egui::Button::new(label)).on_hover_text(hover).clicked() {
                        actions.push(Action::ExportFlight(format));
                        ui.close();
                    }
                }
                // Either log corrected; the shortcut writes the one the drift plot shows.
                let has_validation = self.state.shown.validation.is_some();
                let showing = if self.state.view.show_validation && has_validation {
                    OpenLog::Validation
                } else {
                    OpenLog::Calibration
                };
                for (which, label, enabled) in [
                    (OpenLog::Calibration, "Export corrected calibration log…", has_fit),
                    (OpenLog::Validation, "Export corrected validation log…", has_fit && has_validation),
                ] {
                    let mut button = egui::Button::new(label);
                    if which == showing {
                        button = button.shortcut_text(sc(&shortcuts::EXPORT_CSV));
                    }
                    if ui
                        .add_enabled(enabled, button)
                        .on_hover_text("Write time, raw, predicted and corrected rate and temperature as CSV, as `driftlab apply` writes it")
                        .clicked()
                    {
                        actions.push(Action::ExportCsv(Some(which)));
                        ui.close();
                    }
                }
                let has_models = self
                    .state
                    .shown.models
                    .as_ref()
                    .is_some_and(|c| c.reports.iter().any(|r| r.fitted.is_some()));
                if ui
                    .add_enabled(has_models, egui::Button::new("Export model…"))
                    .on_hover_text("Write the model chosen on the Models page as a calibration file")
                    .clicked()
                {
                    actions.push(Action::ExportModel);
                    ui.close();
                }
                if ui
                    .add_enabled(has_fit, egui::Button::new("Export test report…"))
                    .on_hover_text("Write a folder with the figures (PNG and SVG) and one self-contained HTML page: gyro, recipe, coefficients, figures of merit of the calibration log and of the validation log, Allan deviation")
                    .clicked()
                {
                    actions.push(Action::ExportReport);
                    ui.close();
                }
                if ui
                    .add(egui::Button::new("Save screenshot…").shortcut_text(format!("{} / {}", sc(&shortcuts::SHOT_F12), sc(&shortcuts::SHOT))))
                    .on_hover_text("Save the whole window as a PNG picture")
                    .clicked()
                {
                    actions.push(Action::Screenshot);
                    ui.close();
                }
                ui.separator();
                if ui.add(egui::Button::new("Quit").shortcut_text(sc(&shortcuts::QUIT))).on_hover_text("Close the workbench (asks first when the session has unsaved changes)").clicked() {
                    actions.push(Action::Quit);
                    ui.close();
                }
            });
            ui.menu_button("Edit", |ui| {
                if ui
                    .add_enabled(self.state.shown.history.can_undo(), egui::Button::new("Undo").shortcut_text(sc(&shortcuts::UNDO)))
                    .on_hover_text("Undo the last change of plateaus, filters or approximations")
                    .clicked()
                {
                    actions.push(Action::Undo);
                    ui.close();
                }
                if ui
                    .add_enabled(self.state.shown.history.can_redo(), egui::Button::new("Redo").shortcut_text(sc(&shortcuts::REDO)))
                    .on_hover_text("Redo the change undone last (Ctrl+Y or Ctrl+Shift+Z)")
                    .clicked()
                {
                    actions.push(Action::Redo);
                    ui.close();
                }
                ui.separator();
                if ui
                    .add_enabled(self.state.shown.fit.is_some(), egui::Button::new("Suggest plateaus"))
                    .on_hover_text("Fill the plateau table from the engine's detector")
                    .clicked()
                {
                    actions.push(Action::SuggestPlateaus);
                    ui.close();
                }
                if ui
                    .button("Reset all choices")
                    .on_hover_text("Filters, plateaus and approximations back to the defaults (undoable)")
                    .clicked()
                {
                    actions.push(Action::ResetRecipe);
                    ui.close();
                }
            });
            ui.menu_button("View", |ui| {
                for p in Page::ALL {
                    if ui
                        .add(egui::Button::selectable(self.views.page == p, p.title()).shortcut_text(sc(&p.shortcut())))
                        .on_hover_text(p.tip())
                        .clicked()
                    {
                        actions.push(Action::ShowPage(p));
                        ui.close();
                    }
                }
                ui.separator();
                for (t, name) in [
                    (ThemeChoice::System, "Follow the system theme"),
                    (ThemeChoice::Light, "Light theme"),
                    (ThemeChoice::Dark, "Dark theme"),
                ] {
                    if ui.radio(self.window.settings.theme == t, name).clicked() {
                        actions.push(Action::Theme(t));
                        ui.close();
                    }
                }
                ui.separator();
                if ui.button("Show the whole log").on_hover_text("Whole log on the time axis (Home)").clicked() {
                    self.views.time.x_command = Some(XCommand::Fit);
                    ui.close();
                }
            });
            ui.menu_button("Help", |ui| {
                if ui.button("Keyboard and mouse").on_hover_text("Every shortcut and mouse gesture of the workbench").clicked() {
                    self.modals.help = true;
                    ui.close();
                }
            });
            ui.separator();
            self.page_tabs(ui, actions);
            ui.separator();
            // A short window: a unit's axes in the menu bar (the strip's row goes to the plots).
            if self.window.compact
                && self.views.page == Page::Calibration
                && self.state.has_axis_strip()
            {
                // (what the right-hand end leaves, and a little for the log's name)
                let room = ui.available_width() - self.window.menu_right_w - 60.0;
                actions.extend(self.views.axes.ui_in(ui, &self.state, room));
                ui.separator();
            }
            if let Some(l) = &self.state.shown.log {
                let name = l.name();
                let dirty = if self.state.dirty() { " •" } else { "" };
                let details = format!(
                    "{} samples · {} h · step {} s{}",
                    l.log.len(),
                    crate::number::fixed(l.log.duration_s() / 3600.0, 2),
                    num(l.log.nominal_dt_s()),
                    match self.state.unit.as_ref() {
                        Some(u) => format!(" · {} gyro axes", u.names.len()),
                        None => String::new(),
                    } + &match &l.drone {
                        Some(d) => format!(" · gyro {} ({} in the log)", d.chosen, d.instances.len()),
                        None => String::new(),
                    }
                );
                let tip = format!("{}{}\n{details}", l.path.display(), if dirty.is_empty() { "" } else { "\nunsaved changes" });
                // In what the right-hand end leaves (as wide as last frame), cut short with "…"
                // rather than drawn under the theme button.
                let room = ui.available_width() - self.window.menu_right_w - 2.0 * ui.spacing().item_spacing.x;
                if room > 16.0 {
                    let row_h = ui.spacing().interact_size.y;
                    ui.allocate_ui_with_layout(egui::vec2(room, row_h), Layout::left_to_right(Align::Center), |ui| {
                        ui.add(egui::Label::new(RichText::new(format!("{name}{dirty}")).strong()).truncate())
                            .on_hover_text(&tip);
                        // A short window's menu bar holds the axes of a unit: the details on hover.
                        if !(self.window.compact && self.state.has_axis_strip()) {
                            ui.add(egui::Label::new(RichText::new(details).weak()).truncate()).on_hover_text(&tip);
                        }
                    });
                }
            }
            ui.with_layout(Layout::right_to_left(Align::Center), |ui| {
                let dark = ui.visuals().dark_mode;
                if ui
                    .small_button(if dark { "Light theme" } else { "Dark theme" })
                    .on_hover_text(if dark { "Switch to the light theme" } else { "Switch to the dark theme" })
                    .clicked()
                {
                    actions.push(Action::Theme(if dark { ThemeChoice::Light } else { ThemeChoice::Dark }));
                }
                // (the spinner's room kept whether it turns or not: the name does not jump)
                let spinner = ui.spacing().interact_size.y + ui.spacing().item_spacing.x;
                let fitting = self.jobs.fitting();
                if fitting {
                    ui.spinner().on_hover_text("Refitting on the worker thread");
                }
                self.window.menu_right_w = ui.min_rect().width() + if fitting { 0.0 } else { spinner };
            });
        });
    }

    pub(super) fn status_bar(&mut self, ui: &mut Ui, banner: bool) {
        ui.horizontal(|ui| {
            if let Some(h) = self.jobs.loading.clone() {
                let name = h
                    .path
                    .file_name()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_default();
                ui.add(
                    egui::ProgressBar::new(h.progress() as f32)
                        .desired_width(260.0)
                        .text(format!("Reading {name} … {:.0}%", h.progress() * 100.0)),
                );
                if ui
                    .button("Cancel")
                    .on_hover_text("Stop reading (Esc); the current work stays")
                    .clicked()
                {
                    self.jobs.cancel_load();
                }
                ui.separator();
            }
            // One line whatever the message: the status bar never grows. With the banner
            // beside it (a short window), the message takes at most half the row.
            let row_h = ui.spacing().interact_size.y;
            let width = if banner {
                0.5 * ui.available_width()
            } else {
                ui.available_width()
            };
            ui.allocate_ui_with_layout(
                egui::vec2(width, row_h),
                Layout::left_to_right(Align::Center),
                |ui| {
                    if banner {
                        ui.set_min_size(egui::vec2(width, row_h));
                    }
                    if let Some((sev, msg)) = &self.state.status {
                        let color = match sev {
                            Severity::Info => ui.visuals().text_color(),
                            Severity::Warning => ui.visuals().warn_fg_color,
                            Severity::Error => ui.visuals().error_fg_color,
                        };
                        ui.add(egui::Label::new(RichText::new(msg).color(color)).truncate())
                            .on_hover_text(msg.as_str());
                    }
                },
            );
            if banner {
                ui.separator();
                self.banner(ui);
            }
        });
    }

    /// One line in a fixed slot above the Calibration page (beside the status line on a
    /// short window): why the calibration failed, that
    /// the figures are provisional while a refit is on its way, or what the fit had to work
    /// around. It never moves what is below it.
    pub(super) fn banner(&mut self, ui: &mut Ui) {
        let row_h = ui.spacing().interact_size.y;
        ui.allocate_ui_with_layout(
            egui::vec2(ui.available_width(), row_h),
            Layout::left_to_right(Align::Center),
            |ui| {
                ui.set_min_size(egui::vec2(ui.available_width(), row_h));
                let (color, text, tip) = if let Some(e) = &self.state.shown.fit_error {
                    (
                        ui.visuals().error_fg_color,
                        format!("Calibration failed: {e}"),
                        format!(
                            "{e}\n\nThe plots show the last calibration that worked (or the raw \
                             log); change the choice that caused it, or Ctrl+Z."
                        ),
                    )
                } else if self.state.shown.log.is_some() && self.state.shown.fit.is_none() {
                    (
                        ui.visuals().weak_text_color(),
                        "Calibrating…".to_string(),
                        "The first calibration of this log is on its way".to_string(),
                    )
                } else if self.state.shown.fit.is_some()
                    && self.window.plateau_drag
                    && self.window.pointer_down
                {
                    (
                        ui.visuals().warn_fg_color,
                        "Moving a plateau edge: its plateaus and K0 follow it; the figures are \
                         those before the drag until it is released"
                            .to_string(),
                        "Only the plateaus' statistics and K0 are recomputed while the edge moves; \
                         every axis is refitted when the mouse button is released"
                            .to_string(),
                    )
                } else if self.state.shown.fit.is_some() && !self.state.fit_current() {
                    (
                        ui.visuals().warn_fg_color,
                        "Refitting: the figures shown are provisional (the choices as they were a \
                         moment ago)"
                            .to_string(),
                        "The worker is refitting with the current choices; the figures are \
                         exact again as soon as it answers"
                            .to_string(),
                    )
                } else if let Some(w) = self.state.shown.fit.as_ref().and_then(|f| {
                    (!f.outcome.warnings.is_empty()).then(|| f.outcome.warnings.join("\n"))
                }) {
                    let n = self
                        .state
                        .shown
                        .fit
                        .as_ref()
                        .map_or(0, |f| f.outcome.warnings.len());
                    (
                        ui.visuals().warn_fg_color,
                        format!(
                            "{n} warning{} from the fit: {}",
                            if n == 1 { "" } else { "s" },
                            w.lines().next().unwrap_or_default()
                        ),
                        w,
                    )
                } else if self.state.shown.fit.is_some() {
                    (
                        ui.visuals().weak_text_color(),
                        "Calibrated: the figures below are those of the current choices"
                            .to_string(),
                        "Every figure and plot answers the choices as they are now".to_string(),
                    )
                } else {
                    (ui.visuals().weak_text_color(), String::new(), String::new())
                };
                ui.add(egui::Label::new(RichText::new(text).color(color)).truncate())
                    .on_hover_text(tip);
            },
        );
    }

    pub(super) fn modals(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        let ctx = ui.ctx().clone();
        let ctx = &ctx;
        self.recovery_modal(ctx);
        self.file_dialog_modal(ctx);
        if let Some(view) = &mut self.modals.import {
            actions.extend(view.ui(ui));
        }
        if let Some(action) = self.modals.confirm.clone() {
            let mut answer: Option<u8> = None;
            egui::Modal::new(egui::Id::unique("confirm_discard")).show(ctx, |ui| {
                ui.heading("Unsaved work");
                ui.label(
                    "The plateaus and choices of this calibration are not saved in a session.",
                );
                ui.label(match action {
                    Action::Quit => "Save them before closing?",
                    _ => "Save them before opening another file?",
                });
                ui.add_space(8.0);
                ui.horizontal(|ui| {
                    if ui.button(RichText::new("Save session…").strong()).clicked() {
                        answer = Some(0);
                    }
                    if ui
                        .button("Discard")
                        .on_hover_text("Go on without saving")
                        .clicked()
                    {
                        answer = Some(1);
                    }
                    if ui
                        .button("Cancel")
                        .on_hover_text("Stay with the current work (Esc)")
                        .clicked()
                    {
                        answer = Some(2);
                    }
                });
            });
            match answer {
                Some(0) => {
                    self.modals.confirm = None;
                    self.save_session(ctx, false, Some(action));
                }
                Some(1) => {
                    self.modals.confirm = None;
                    self.state.mark_saved();
                    self.run_confirmed(ctx, action);
                }
                Some(_) => self.modals.confirm = None,
                None => {}
            }
        }
        if let Some(msg) = self.modals.error.clone() {
            let r = egui::Modal::new(egui::Id::unique("error")).show(ctx, |ui| {
                ui.set_max_width(640.0);
                ui.heading("Something went wrong");
                ui.label(msg.as_str());
                ui.add_space(8.0);
                ui.button("OK").clicked()
            });
            if r.inner || r.should_close() {
                self.modals.error = None;
            }
        }
        if self.modals.help {
            egui::Window::new("Keyboard and mouse")
                .open(&mut self.modals.help)
                .resizable(false)
                .show(ctx, |ui| {
                    egui::Grid::new("help").striped(true).show(ui, |ui| {
                        for (k, what) in [
                            ("Ctrl+O", "open a log (preview and mapping first)"),
                            ("Ctrl+Shift+O", "open a session"),
                            (
                                "Ctrl+Alt+O",
                                "open a calibration beside the current fit, to compare",
                            ),
                            ("Ctrl+S", "save the session"),
                            (
                                "Ctrl+1 / Ctrl+2 / Ctrl+3",
                                "pages: Calibration / Models / Allan deviation",
                            ),
                            ("F5 (Models page)", "compare the models ticked"),
                            (
                                "Alt+1 … Alt+9, [ / ]",
                                "gyro axis of a unit: that one / the previous, the next",
                            ),
                            (
                                "Ctrl+E / Ctrl+Shift+E",
                                "export the calibration / the corrected log",
                            ),
                            ("F12 or Ctrl+Shift+S", "save the window as PNG"),
                            (
                                "Ctrl+Z / Ctrl+Y",
                                "undo / redo a change of plateaus or choices",
                            ),
                            ("Home, +, −, ←, →", "time axis: whole log, zoom, pan"),
                            (
                                "mouse wheel / drag",
                                "zoom / pan the time axis (all time plots together)",
                            ),
                            ("Shift+drag on a time plot", "mark a new plateau"),
                            (
                                "drag a plateau edge",
                                "move it; Delete removes the selected plateau",
                            ),
                            (
                                "drag a knot",
                                "sideways: move it (refitted there); up or down: set its value",
                            ),
                            (
                                "Ctrl+click / right-click a knot",
                                "add a knot to the nearest curve / remove it, or type the knots",
                            ),
                            ("right-click a plot", "save that plot as PNG"),
                            ("Esc", "cancel reading a log, close dialogs"),
                        ] {
                            ui.monospace(k);
                            ui.label(what);
                            ui.end_row();
                        }
                    });
                });
        }
    }

    /// Offers back the work an earlier workbench left unsaved.
    pub(super) fn recovery_modal(&mut self, ctx: &egui::Context) {
        let Some(left) = self.recovery.offered.first().cloned() else {
            return;
        };
        if self.shots.auto.is_some() || self.modals.import.is_some() {
            return;
        }
        let mut answer: Option<bool> = None;
        egui::Modal::new(egui::Id::unique("recover_autosave")).show(ctx, |ui| {
            ui.heading("Unsaved work from last time");
            ui.label("The workbench did not close cleanly, and it had work that was not saved.");
            if let Some(log) = &left.log {
                ui.label(format!("Log: {}", log.display()));
            }
            if let Some(t) = left.modified {
                ui.label(format!(
                    "Autosaved: {}",
                    humantime::format_rfc3339_seconds(t)
                ));
            }
            ui.add_space(8.0);
            ui.horizontal(|ui| {
                if ui
                    .button(RichText::new("Restore").strong())
                    .on_hover_text("Open that log with its plateaus and choices")
                    .clicked()
                {
                    answer = Some(true);
                }
                if ui
                    .button("Discard")
                    .on_hover_text("Forget that work")
                    .clicked()
                {
                    answer = Some(false);
                }
            });
        });
        match answer {
            Some(true) => self.restore_autosave(),
            Some(false) => {
                // That one is removed; the next left behind, if any, is offered next.
                let left = self.recovery.offered.remove(0);
                self.recovery.autosave.discard(left);
            }
            None => {}
        }
    }
}
