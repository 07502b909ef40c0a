//! The engineer's requests, from menus, shortcuts, dropped files and the close button, and the
//! unsaved-work question some of them ask first.

use super::files::Purpose;
use super::results::read_warnings;
use super::*;

impl Workbench {
    pub(super) fn shortcuts(&mut self, ctx: &egui::Context, actions: &mut Vec<Action>) {
        if self.modals.import.is_some()
            || self.modals.confirm.is_some()
            || self.modals.file_dialog.is_some()
        {
            if ctx.input(|i| i.key_pressed(Key::Escape)) {
                self.modals.confirm = None;
            }
            return;
        }
        let text_focus = ctx.egui_wants_keyboard_input();
        ctx.input_mut(|i| {
            // Shift variants first: Ctrl+S also matches Ctrl+Shift+S.
            if i.consume_shortcut(&shortcuts::OPEN_SESSION) {
                actions.push(Action::OpenSession);
            }
            if i.consume_shortcut(&shortcuts::OPEN_CALIBRATION) {
                actions.push(Action::OpenCalibration);
            }
            if i.consume_shortcut(&shortcuts::OPEN) {
                actions.push(Action::OpenLog);
            }
            if i.consume_shortcut(&shortcuts::SHOT) || i.consume_shortcut(&shortcuts::SHOT_F12) {
                actions.push(Action::Screenshot);
            }
            if i.consume_shortcut(&shortcuts::SAVE) {
                actions.push(Action::SaveSession);
            }
            if i.consume_shortcut(&shortcuts::EXPORT_CSV) {
                actions.push(Action::ExportCsv(None));
            }
            if i.consume_shortcut(&shortcuts::EXPORT) {
                actions.push(Action::ExportCalibration);
            }
            if i.consume_shortcut(&shortcuts::QUIT) {
                actions.push(Action::Quit);
            }
            for p in Page::ALL {
                if i.consume_shortcut(&p.shortcut()) {
                    actions.push(Action::ShowPage(p));
                }
            }
            if self.views.page == Page::Models && i.consume_shortcut(&shortcuts::COMPARE) {
                actions.push(Action::CompareModels);
            }
            // The axes of a unit: Alt+1 … Alt+9, and [ and ] outside a text field.
            for k in 0..self.state.axis_count().min(9) {
                if self.state.unit.is_some()
                    && let Some(sc) = shortcuts::axis(k)
                    && i.consume_shortcut(&sc)
                {
                    actions.push(Action::SelectAxis(k));
                }
            }
            if self.state.unit.is_some() && !text_focus {
                if i.consume_shortcut(&shortcuts::AXIS_PREV) {
                    actions.push(Action::StepAxis(false));
                }
                if i.consume_shortcut(&shortcuts::AXIS_NEXT) {
                    actions.push(Action::StepAxis(true));
                }
            }
            if !text_focus {
                if i.consume_shortcut(&shortcuts::REDO2) || i.consume_shortcut(&shortcuts::REDO) {
                    actions.push(Action::Redo);
                }
                if i.consume_shortcut(&shortcuts::UNDO) {
                    actions.push(Action::Undo);
                }
            }
            if i.key_pressed(Key::Escape) && self.jobs.loading.is_some() {
                self.jobs.cancel_load();
            }
        });
    }

    pub(super) fn files_dropped(&mut self, ctx: &egui::Context, actions: &mut Vec<Action>) {
        let (hovered, dropped) =
            ctx.input(|i| (!i.raw.hovered_files.is_empty(), i.raw.dropped_files.clone()));
        let logs: Vec<PathBuf> = dropped
            .iter()
            .map(|f| f.path().to_path_buf())
            .filter(|p| !p.as_os_str().is_empty() && !is_json(p))
            .collect();
        if logs.len() > 1 {
            // Several logs dropped at once: the runs of one campaign, in the order given.
            actions.push(Action::OpenRunPaths(logs));
        } else if let Some(path) = dropped.first().map(|f| f.path().to_path_buf()) {
            // A `.json` is opened as what it says it is: a calibration or a session.
            actions.push(if is_json(&path) {
                super::opened::json_action(path)
            } else {
                Action::OpenLogPath(path)
            });
        }
        if hovered {
            let painter = ctx.layer_painter(egui::LayerId::new(
                egui::Order::Foreground,
                egui::Id::unique("drop"),
            ));
            let r = ctx.content_rect();
            painter.rect_filled(r, 0.0, Color32::from_black_alpha(150));
            painter.text(
                r.center(),
                egui::Align2::CENTER_CENTER,
                "Drop a log to import it (several: the runs of one campaign; a calibration .json to compare, a session .json to reopen)",
                egui::FontId::proportional(22.0),
                Color32::WHITE,
            );
        }
    }

    pub(super) fn close_requested(&mut self, ctx: &egui::Context) {
        if ctx.input(|i| i.viewport().close_requested())
            && !self.window.quitting
            && self.shots.auto.is_none()
        {
            if self.state.dirty() {
                ctx.send_viewport_cmd(ViewportCommand::CancelClose);
                self.modals.confirm = Some(Action::Quit);
            } else {
                self.close_cleanly();
            }
        }
    }

    /// Runs `action` now, or asks first when it would drop unsaved work.
    pub(super) fn run_action(&mut self, ctx: &egui::Context, action: Action) {
        let drops_work = matches!(
            action,
            Action::OpenLog
                | Action::OpenLogPath(_)
                | Action::OpenRunPaths(_)
                | Action::OpenSession
                | Action::OpenSessionPath(_)
                | Action::OpenLotUnit(_)
                | Action::Quit
        );
        if drops_work && self.state.dirty() && self.modals.confirm.is_none() {
            self.modals.confirm = Some(action);
            return;
        }
        self.run_confirmed(ctx, action);
    }

    pub(super) fn run_confirmed(&mut self, ctx: &egui::Context, action: Action) {
        match action {
            Action::OpenLog => self.ask(ctx, Purpose::OpenLog, ""),
            Action::OpenLogPath(p) => self.open_import(p, Target::Calibration),
            Action::OpenRunPaths(paths) => self.open_runs(paths),
            Action::AddRun => {
                if self.state.shown.log.is_none() {
                    self.state
                        .say(Severity::Warning, "Open the first run first");
                } else {
                    self.ask(ctx, Purpose::AddRun, "");
                }
            }
            Action::AddRunPath(p) => self.add_run(p),
            Action::ShowRun(k) => self.show_run(k),
            Action::ReadLog(path, options, target) => {
                self.modals.import = None;
                self.start_load(path, options, target);
            }
            Action::CloseImport => {
                self.modals.import = None;
                self.opening.calibration = None;
            }
            Action::OpenValidation => {
                if self.state.shown.log.is_none() {
                    self.state
                        .say(Severity::Warning, "Open the calibration log first");
                } else {
                    self.ask(ctx, Purpose::OpenValidation, "");
                }
            }
            Action::CloseValidation => self.forget_validation(),
            Action::OpenCalibration => self.ask(ctx, Purpose::OpenCalibration, ""),
            Action::OpenCalibrationPath(p) => self.open_calibration(p),
            Action::CloseCalibration => self.close_calibration(),
            Action::ChooseOpenedAxis(which, k, axis) => self.choose_opened_axis(which, k, axis),
            Action::OpenLot => self.ask(ctx, Purpose::OpenLot, ""),
            Action::OpenLotPath(p) => self.open_lot(p),
            Action::OpenLotUnit(k) => self.open_lot_unit(k),
            Action::CloseLot => self.close_lot(),
            Action::OpenSession => self.ask(ctx, Purpose::OpenSession, ""),
            Action::OpenSessionPath(p) => self.open_session(p),
            Action::SaveSession => self.save_session(ctx, false, None),
            Action::SaveSessionAs => self.save_session(ctx, true, None),
            Action::ExportCalibration => self.export_calibration(ctx),
            Action::ExportFlight(format) => self.export_flight(ctx, format),
            Action::ExportCsv(which) => self.export_csv(ctx, which),
            Action::ExportReport => self.export_report(ctx),
            Action::Screenshot => {
                let name = self.name_beside_log("workbench.png");
                self.ask(ctx, Purpose::Screenshot, &name);
            }
            Action::SavePlot(name, rect) => {
                if rect.is_positive() {
                    let file = self.name_beside_log(&format!("{name}.png"));
                    self.ask(ctx, Purpose::SavePlot(name, rect), &file);
                } else {
                    self.state.say(
                        Severity::Warning,
                        format!("Plot {name} not saved: it is not on screen"),
                    );
                }
            }
            Action::SavePlotNamed(name) => match self.window.plot_rects.get(&name).copied() {
                Some(r) => self.run_confirmed(ctx, Action::SavePlot(name, r)),
                None => self.state.say(
                    Severity::Warning,
                    format!("Plot {name} not saved: it is not on screen"),
                ),
            },
            Action::PlotRect(name, rect) => {
                self.window.plot_rects.insert(name, rect);
            }
            Action::Edit(edit) => {
                self.window.plateau_drag = matches!(edit, Edit::PlateausDragged(_));
                self.state.apply(edit)
            }
            Action::SelectPlateau(k) => self.views.time.selected = k,
            Action::AddPlateau(r) => {
                let mut all = self.state.ranges();
                all.push(r);
                self.state.set_ranges(all);
                self.views.time.selected = self
                    .state
                    .ranges()
                    .iter()
                    .position(|x| (x.start_s - r.start_s).abs() < 1e-9);
            }
            Action::ShowValidation(shown) => self.state.view.show_validation = shown,
            // A refusal of an edit holds for the choices it refused: it goes once an edit is
            // taken.
            Action::Warn(message) => self.state.say_about_choices(Severity::Warning, message),
            Action::Undo => {
                if !self.state.shown.history.undo(&mut self.state.shown.choices) {
                    self.state.say(Severity::Info, "Nothing to undo");
                }
            }
            Action::Redo => {
                if !self.state.shown.history.redo(&mut self.state.shown.choices) {
                    self.state.say(Severity::Info, "Nothing to redo");
                }
            }
            Action::SuggestPlateaus => self.suggest_plateaus(),
            Action::ResetRecipe => {
                // Of the axis shown (a unit's other axes keep theirs, but for the T settings
                // and plateaus they share).
                self.state.shown.choices = Choices::default();
            }
            Action::Quit => {
                self.close_cleanly();
                ctx.send_viewport_cmd(ViewportCommand::Close);
            }
            Action::Theme(t) => {
                self.window.settings.theme = t;
            }
            Action::ShowPage(p) => self.views.page = p,
            Action::CompareModels => self.compare_models(),
            Action::SelectAxis(k) => self.select_axis(k),
            Action::SelectAccel(k) => {
                if let Some(a) = &mut self.state.accel
                    && k < a.names.len()
                {
                    a.shown = Some(k);
                    self.views.page = Page::Calibration;
                }
            }
            Action::AccelOn(on) => {
                self.state.accel_off = !on;
                if let Some(a) = &mut self.state.accel
                    && !on
                {
                    a.shown = None;
                }
            }
            Action::StepAxis(next) => {
                let n = self.state.axis_count();
                let k = self.state.active_axis();
                self.select_axis(if next { (k + 1) % n } else { (k + n - 1) % n });
            }
            Action::ExportModel => self.export_model(ctx),
            Action::ColumnMapping(target) => {
                let loaded = match target {
                    Target::Calibration => self.state.shown.log.as_ref(),
                    Target::Validation => self.state.shown.validation.as_ref(),
                };
                match loaded {
                    Some(l) if is_drone_log(&l.path) => self.state.say(
                        Severity::Info,
                        format!(
                            "{} is a drone or robot log: it has no columns to map (its gyro, \
                             axes and temperature are read as recorded)",
                            file_name(&l.path)
                        ),
                    ),
                    Some(l) => {
                        self.modals.import = Some(
                            ImportView::new(l.path.clone(), target, l.options.clone())
                                .with_warnings(read_warnings(l)),
                        )
                    }
                    None => self.state.say(Severity::Warning, "Open a log first"),
                }
            }
        }
    }

    pub(super) fn open_import(&mut self, path: PathBuf, target: Target) {
        let options = match (target, &self.state.shown.log) {
            // A second log of the same stand is likely written and averaged alike.
            // (Its runs are the calibration log's own: a held-out log is one run.)
            (Target::Validation, Some(l)) => LoadOptions {
                more_runs: Vec::new(),
                ..l.options.clone()
            },
            _ => LoadOptions::default(),
        };
        // A drone or robot log (told by its first bytes) has no columns to map: it is read
        // at once, its first gyro with a temperature, as every command reads it.
        if is_drone_log(&path) {
            self.start_load(path, options, target);
            return;
        }
        self.modals.import = Some(ImportView::new(path, target, options));
    }

    /// Opens `paths` as the runs of one campaign: the first through the import view (a drone
    /// or robot log read at once), the others read as it is.
    fn open_runs(&mut self, mut paths: Vec<PathBuf>) {
        if paths.is_empty() {
            return;
        }
        let first = paths.remove(0);
        let options = LoadOptions {
            more_runs: paths,
            ..LoadOptions::default()
        };
        if is_drone_log(&first) {
            self.start_load(first, options, Target::Calibration);
        } else {
            self.modals.import = Some(ImportView::new(first, Target::Calibration, options));
        }
    }

    /// Reads the open log again with `path` joined after its runs, as they were read; the
    /// work on the runs before stays (their times on the joined axis do not move). A run the
    /// engine refuses (another gyro, the same file) leaves everything as it was.
    pub(super) fn add_run(&mut self, path: PathBuf) {
        let Some(l) = &self.state.shown.log else {
            self.state
                .say(Severity::Warning, "Open the first run first");
            return;
        };
        let mut options = l.options.clone();
        options.more_runs.push(path);
        let first = l.path.clone();
        self.start_load(first, options, Target::Calibration);
    }

    /// Shows run `k` of the campaign on the time plots (its span on the joined time), or the
    /// whole log.
    fn show_run(&mut self, k: Option<usize>) {
        let Some(l) = &self.state.shown.log else {
            return;
        };
        let span = k.and_then(|k| l.log.runs().get(k)).and_then(|r| {
            let t = &l.log.time_s[r.samples.clone()];
            Some((*t.first()?, *t.last()?))
        });
        self.views.time.x_command = Some(match span {
            Some((a, b)) => XCommand::Range(a, b),
            None => XCommand::Fit,
        });
        self.views.runs.shown = span.and(k);
    }

    pub(super) fn suggest_plateaus(&mut self) {
        let (Some(log), Some(fit)) = (self.state.shown.log.clone(), self.state.shown.fit.clone())
        else {
            self.state.say(Severity::Warning, "Open a log first");
            return;
        };
        let found = crate::refit::suggest_plateaus(&log.log, &fit.outcome.prepared);
        let n = found.len();
        self.state.set_ranges(found);
        self.views.time.selected = None;
        self.state.say_about_choices(
            Severity::Info,
            format!(
                "The detector suggests {n} plateau{}; edit them in the table or on the time plots",
                if n == 1 { "" } else { "s" }
            ),
        );
    }
}

/// Whether `path` is a PX4 ULog, ArduPilot DataFlash, ROS bag or MCAP log (by its first bytes).
pub(super) fn is_drone_log(path: &std::path::Path) -> bool {
    crate::log::read::drone_format(path).is_ok_and(|f| f.is_some())
}
