//! The workbench's menu bar, status bar, left-hand controls and modal windows.

use super::*;

impl Workbench {
    pub(super) fn menu_bar(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        let ctx = ui.ctx().clone();
        let sc = |s: &KeyboardShortcut| ctx.format_shortcut(s);
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                let has_log = self.state.log.is_some();
                let has_fit = self.state.fit.is_some();
                if ui
                    .add(egui::Button::new("Open log…").shortcut_text(sc(&SC_OPEN)))
                    .on_hover_text("Open a chamber log: preview, fix the mapping, then read it")
                    .clicked()
                {
                    actions.push(Action::OpenLog);
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
                ui.menu_button("Recent", |ui| {
                    if self.settings.recent.is_empty() {
                        ui.weak("No recent files");
                    }
                    for p in self.settings.recent.clone() {
                        let label = p.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
                        if ui.button(label).on_hover_text(p.display().to_string()).clicked() {
                            actions.push(if is_json(&p) {
                                Action::OpenSessionPath(p)
                            } else {
                                Action::OpenLogPath(p)
                            });
                            ui.close();
                        }
                    }
                });
                ui.separator();
                if ui
                    .add(egui::Button::new("Open session…").shortcut_text(sc(&SC_OPEN_SESSION)))
                    .on_hover_text("Reopen a saved session exactly as it was left")
                    .clicked()
                {
                    actions.push(Action::OpenSession);
                    ui.close();
                }
                if ui
                    .add_enabled(has_log, egui::Button::new("Save session").shortcut_text(sc(&SC_SAVE)))
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
                    .add_enabled(has_fit, egui::Button::new("Export calibration…").shortcut_text(sc(&SC_EXPORT)))
                    .on_hover_text("Write the calibration file (JSON) the gyro's processor and `driftlab apply` read")
                    .clicked()
                {
                    actions.push(Action::ExportCalibration);
                    ui.close();
                }
                if ui
                    .add_enabled(has_fit, egui::Button::new("Export corrected log…").shortcut_text(sc(&SC_EXPORT_CSV)))
                    .on_hover_text("Write time, raw, predicted and corrected rate and temperature as CSV")
                    .clicked()
                {
                    actions.push(Action::ExportCsv);
                    ui.close();
                }
                let has_models = self
                    .state
                    .models
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
                    .add(egui::Button::new("Save screenshot…").shortcut_text(format!("{} / {}", sc(&SC_SHOT_F12), sc(&SC_SHOT))))
                    .on_hover_text("Save the whole window as a PNG picture")
                    .clicked()
                {
                    actions.push(Action::Screenshot);
                    ui.close();
                }
                ui.separator();
                if ui.add(egui::Button::new("Quit").shortcut_text(sc(&SC_QUIT))).on_hover_text("Close the workbench (asks first when the session has unsaved changes)").clicked() {
                    actions.push(Action::Quit);
                    ui.close();
                }
            });
            ui.menu_button("Edit", |ui| {
                if ui
                    .add_enabled(self.state.history.can_undo(), egui::Button::new("Undo").shortcut_text(sc(&SC_UNDO)))
                    .on_hover_text("Undo the last change of plateaus, filters or approximations")
                    .clicked()
                {
                    actions.push(Action::Undo);
                    ui.close();
                }
                if ui
                    .add_enabled(self.state.history.can_redo(), egui::Button::new("Redo").shortcut_text(sc(&SC_REDO)))
                    .on_hover_text("Redo the change undone last (Ctrl+Y or Ctrl+Shift+Z)")
                    .clicked()
                {
                    actions.push(Action::Redo);
                    ui.close();
                }
                ui.separator();
                if ui
                    .add_enabled(self.state.fit.is_some(), egui::Button::new("Suggest plateaus"))
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
                        .add(egui::Button::selectable(self.page == p, p.title()).shortcut_text(sc(&p.shortcut())))
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
                    if ui.radio(self.settings.theme == t, name).clicked() {
                        actions.push(Action::Theme(t));
                        ui.close();
                    }
                }
                ui.separator();
                if ui.button("Show the whole log").on_hover_text("Whole log on the time axis (Home)").clicked() {
                    self.time.x_command = Some(XCommand::Fit);
                    ui.close();
                }
            });
            ui.menu_button("Help", |ui| {
                if ui.button("Keyboard and mouse").on_hover_text("Every shortcut and mouse gesture of the workbench").clicked() {
                    self.show_help = true;
                    ui.close();
                }
            });
            ui.separator();
            if let Some(l) = &self.state.log {
                let name = l.path.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
                let dirty = if self.state.dirty() { " •" } else { "" };
                ui.label(RichText::new(format!("{name}{dirty}")).strong())
                    .on_hover_text(format!("{}{}", l.path.display(), if dirty.is_empty() { "" } else { "\nunsaved changes" }));
                ui.weak(format!(
                    "{} samples · {} h · step {} s",
                    l.log.len(),
                    crate::number::fixed(l.log.duration_s() / 3600.0, 2),
                    num(l.log.nominal_dt_s())
                ));
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
                if self.jobs.fitting() {
                    ui.spinner().on_hover_text("Refitting on the worker thread");
                }
            });
        });
    }

    pub(super) fn status_bar(&mut self, ui: &mut Ui) {
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
            // One line whatever the message: the status bar never grows.
            if let Some((sev, msg)) = &self.state.status {
                let color = match sev {
                    Severity::Info => ui.visuals().text_color(),
                    Severity::Warning => ui.visuals().warn_fg_color,
                    Severity::Error => ui.visuals().error_fg_color,
                };
                ui.add(egui::Label::new(RichText::new(msg).color(color)).truncate())
                    .on_hover_text(msg.as_str());
            }
        });
    }

    /// One line in a fixed slot above the Calibration page: why the calibration failed, that
    /// the figures are provisional while a refit is on its way, or what the fit had to work
    /// around. It never moves what is below it.
    pub(super) fn banner(&mut self, ui: &mut Ui) {
        let row_h = ui.spacing().interact_size.y;
        ui.allocate_ui_with_layout(
            egui::vec2(ui.available_width(), row_h),
            Layout::left_to_right(Align::Center),
            |ui| {
                ui.set_min_size(egui::vec2(ui.available_width(), row_h));
                let (color, text, tip) = if let Some(e) = &self.state.fit_error {
                    (
                        ui.visuals().error_fg_color,
                        format!("Calibration failed: {e}"),
                        format!(
                            "{e}\n\nThe plots show the last calibration that worked (or the raw \
                             log); change the choice that caused it, or Ctrl+Z."
                        ),
                    )
                } else if self.state.log.is_some() && self.state.fit.is_none() {
                    (
                        ui.visuals().weak_text_color(),
                        "Calibrating…".to_string(),
                        "The first calibration of this log is on its way".to_string(),
                    )
                } else if self.state.fit.is_some() && !self.state.fit_current() {
                    (
                        ui.visuals().warn_fg_color,
                        "Refitting: the figures shown are provisional (the choices as they were a \
                         moment ago)"
                            .to_string(),
                        "The worker is refitting with the current choices; the figures are \
                         exact again as soon as it answers"
                            .to_string(),
                    )
                } else if let Some(w) = self.state.fit.as_ref().and_then(|f| {
                    (!f.outcome.warnings.is_empty()).then(|| f.outcome.warnings.join("\n"))
                }) {
                    let n = self
                        .state
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
                } else if self.state.fit.is_some() {
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

    pub(super) fn controls(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        egui::CollapsingHeader::new("Data")
            .default_open(true)
            .show(ui, |ui| {
                match &self.state.log {
                    Some(l) => {
                        let log = &l.log;
                        let (tmin, tmax) = l
                            .lods
                            .temp
                            .range_min_max(&log.temp_c, 0, log.len())
                            .unwrap_or((f64::NAN, f64::NAN));
                        ui.label(format!(
                            "{} samples, {} h, T {} … {} °C",
                            log.len(),
                            crate::number::fixed(log.duration_s() / 3600.0, 2),
                            crate::number::fixed(tmin, 1),
                            crate::number::fixed(tmax, 1)
                        ))
                        .on_hover_text(l.path.display().to_string());
                        if ui
                            .small_button("Column mapping…")
                            .on_hover_text("Reopen the import view on this log: columns, units, separator, decimal comma")
                            .clicked()
                        {
                            actions.push(Action::ColumnMapping(Target::Calibration));
                        }
                        let problems = &log.info.problems;
                        if !problems.is_empty() {
                            let text: Vec<String> = problems
                                .iter()
                                .map(|p| format!("line {}: {} ({}×)", p.line, p.message, p.count))
                                .collect();
                            ui.colored_label(
                                ui.visuals().warn_fg_color,
                                format!("{} kind(s) of problems worked around", problems.len()),
                            )
                            .on_hover_text(text.join("\n"));
                        }
                    }
                    None => {
                        ui.weak("No log.");
                    }
                }
                ui.horizontal(|ui| match &self.state.validation {
                    Some(v) => {
                        let name = v
                            .path
                            .file_name()
                            .map(|s| s.to_string_lossy().into_owned())
                            .unwrap_or_default();
                        ui.label(format!("Validation: {name}"))
                            .on_hover_text(v.path.display().to_string());
                        if ui
                            .small_button("mapping…")
                            .on_hover_text("Reopen the import view on the validation log")
                            .clicked()
                        {
                            actions.push(Action::ColumnMapping(Target::Validation));
                        }
                        if ui
                            .small_button("×")
                            .on_hover_text("Forget the validation log")
                            .clicked()
                        {
                            actions.push(Action::CloseValidation);
                        }
                    }
                    None => {
                        if ui
                            .add_enabled(
                                self.state.log.is_some(),
                                egui::Button::new("Open validation log…"),
                            )
                            .on_hover_text(
                                "A second log of the same gyro, to judge the calibration held out",
                            )
                            .clicked()
                        {
                            actions.push(Action::OpenValidation);
                        }
                    }
                });
            });
        let dt = self
            .state
            .log
            .as_ref()
            .map_or(1.0, |l| l.log.nominal_dt_s());
        egui::CollapsingHeader::new("Derivatives").default_open(true).show(ui, |ui| {
            let r = self.state.recipe_mut();
            egui::Grid::new("deriv_grid").num_columns(3).spacing([8.0, 4.0]).show(ui, |ui| {
                let samples = |s: f64| format!("{} samples", crate::signal::seconds_to_samples(s, dt));
                ui.label("Ω filter").on_hover_text("Centred moving average of Ω before the pointwise coefficients and in the figures");
                ui.add(egui::DragValue::new(&mut r.filter_s).range(dt..=100_000.0).speed(1.0).suffix(" s"))
                    .on_hover_text("Ω moving-average window, s (the paper: 100 recording intervals)");
                ui.weak(samples(r.filter_s));
                ui.end_row();
                ui.label("T smoothing").on_hover_text("Causal moving average of T before differentiating");
                ui.add(egui::DragValue::new(&mut r.temp_smoothing_s).range(dt..=100_000.0).speed(1.0).suffix(" s"))
                    .on_hover_text("T smoothing window, s: longer quietens dT/dt and d²T/dt² but delays them");
                ui.weak(samples(r.temp_smoothing_s));
                ui.end_row();
                ui.label("Step H").on_hover_text("Step of the 3-point backward derivative");
                ui.add(egui::DragValue::new(&mut r.step_h_s).range(dt..=10_000.0).speed(0.5).suffix(" s"))
                    .on_hover_text("Derivative step H, s: H = 1 sample makes d²T/dt² pure quantisation noise on a 1 Hz log");
                ui.weak(samples(r.step_h_s));
                ui.end_row();
            });
            let resolved = self.state.fit.as_ref().map(|f| f.outcome.calibration.resolved);
            for (name, tip, is_tdot) in [
                ("K1 dead-band |dT/dt|", "Points with |dT/dt| below this are left out of the K1 fits, °C/s", true),
                ("K2 dead-band |d²T/dt²|", "Points with |d²T/dt²| below this are left out of the K2 fits, °C/s²", false),
            ] {
                ui.horizontal(|ui| {
                    let r = self.state.recipe_mut();
                    let slot = if is_tdot { &mut r.deadband_tdot } else { &mut r.deadband_tddot };
                    let used = resolved.map(|r| if is_tdot { r.deadband_tdot } else { r.deadband_tddot });
                    let mut auto = slot.is_none();
                    ui.label(name).on_hover_text(tip);
                    if ui
                        .checkbox(&mut auto, "auto")
                        .on_hover_text("Automatic: a fifth of the 95th percentile of the rate outside plateaus")
                        .changed()
                    {
                        *slot = if auto { None } else { Some(used.unwrap_or(0.0)) };
                    }
                    match slot {
                        Some(v) => {
                            let speed = (v.abs() * 0.01).max(1e-9);
                            ui.add(egui::DragValue::new(v).range(0.0..=f64::MAX).speed(speed).max_decimals(10))
                                .on_hover_text(tip);
                        }
                        None => {
                            ui.weak(used.map(num).unwrap_or_default());
                        }
                    }
                });
            }
        });
        egui::CollapsingHeader::new("Plateaus (K0 points)")
            .default_open(true)
            .show(ui, |ui| {
                self.plateaus
                    .table(ui, &mut self.state, &mut self.time, actions);
            });
        egui::CollapsingHeader::new("Fit").default_open(true).show(ui, |ui| {
            let r = self.state.recipe_mut();
            ui.horizontal(|ui| {
                ui.label("Gyro id");
                ui.add(egui::TextEdit::singleline(&mut r.gyro_id).desired_width(140.0).hint_text("serial number"))
                    .on_hover_text("Identifier of the gyro, written into the calibration file");
            });
            ui.horizontal(|ui| {
                ui.label("Weighting");
                egui::ComboBox::from_id_salt("weighting")
                    .selected_text(match r.weighting {
                        Weighting::Drift => "drift",
                        Weighting::Ratio => "ratio (paper)",
                    })
                    .show_ui(ui, |ui| {
                        ui.selectable_value(&mut r.weighting, Weighting::Drift, "drift")
                            .on_hover_text("Each ratio weighted by its denominator squared: minimises the error of the predicted drift");
                        ui.selectable_value(&mut r.weighting, Weighting::Ratio, "ratio (paper)")
                            .on_hover_text("Every pointwise ratio counts alike, as the paper fits them");
                    })
                    .response
                    .on_hover_text("How the pointwise K1/K2 values are weighed in their least-squares fits");
            });
            ui.horizontal(|ui| {
                ui.label("Refinements");
                ui.add(egui::DragValue::new(&mut r.refinements).range(0..=10).speed(0.05))
                    .on_hover_text("Extra passes refitting K1 with the K2 term removed, then K2 (0: the paper's single pass)");
            });
        });
    }

    pub(super) fn modals(&mut self, ctx: &egui::Context, actions: &mut Vec<Action>) {
        self.recovery_modal(ctx);
        self.file_dialog_modal(ctx);
        if let Some(view) = &mut self.import {
            match view.show(ctx) {
                Some(ImportDecision::Load(path, read, target)) => {
                    self.import = None;
                    self.start_load(path, read, target);
                }
                Some(ImportDecision::Cancel) => self.import = None,
                None => {}
            }
        }
        if let Some(action) = self.confirm.clone() {
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
                    self.confirm = None;
                    self.save_session(ctx, false, Some(action));
                }
                Some(1) => {
                    self.confirm = None;
                    self.state.mark_saved();
                    self.run_confirmed(ctx, action);
                }
                Some(_) => self.confirm = None,
                None => {}
            }
        }
        if let Some(msg) = self.error.clone() {
            let r = egui::Modal::new(egui::Id::unique("error")).show(ctx, |ui| {
                ui.set_max_width(640.0);
                ui.heading("Something went wrong");
                ui.label(msg.as_str());
                ui.add_space(8.0);
                ui.button("OK").clicked()
            });
            if r.inner || r.should_close() {
                self.error = None;
            }
        }
        if self.show_help {
            egui::Window::new("Keyboard and mouse")
                .open(&mut self.show_help)
                .resizable(false)
                .show(ctx, |ui| {
                    egui::Grid::new("help").striped(true).show(ui, |ui| {
                        for (k, what) in [
                            ("Ctrl+O", "open a log (preview and mapping first)"),
                            ("Ctrl+Shift+O", "open a session"),
                            ("Ctrl+S", "save the session"),
                            (
                                "Ctrl+1 / Ctrl+2 / Ctrl+3",
                                "pages: Calibration / Models / Allan deviation",
                            ),
                            ("F5 (Models page)", "compare the models ticked"),
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
                                "set a spline or piecewise-linear knot by hand",
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
        let _ = actions;
    }

    /// Offers back the work an earlier workbench left unsaved.
    pub(super) fn recovery_modal(&mut self, ctx: &egui::Context) {
        let Some(left) = self.recover.clone() else {
            return;
        };
        if self.auto.is_some() || self.import.is_some() {
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
                self.recover = None;
                self.autosave.clear();
            }
            None => {}
        }
    }
}
