//! The workbench window: its state, its pages and the frame that draws them. It holds no
//! calculation: choices go to the worker as refit requests, results come back and are drawn.
//!
//! The rest of the window, one file a concern: [`layout`] (menus, status bar, controls and
//! modals), [`actions`] (what the engineer asks for, and the unsaved-work question),
//! [`results`] (what the worker is asked and what its answers change), [`files`] (what is
//! written and opened) and [`screenshot`] (PNG of the window, and the `--screenshot` mode).

mod actions;
mod files;
mod layout;
mod results;
mod screenshot;

pub use screenshot::ScreenshotOutcome;
use screenshot::{AutoShot, PendingShot, Shot};

use super::autosave::{Autosave, LeftBehind};
use super::dialogs::FileDialogs;
use super::export;
use super::jobs::{JobResult, Jobs, Target};
use super::plot_items::num;
use super::settings::{Settings, ThemeChoice, WindowGeometry};
use super::state::{AppState, Choices, Severity};
use super::view_allan::AllanPage;
use super::view_coeffs::{CoeffView, Pair};
use super::view_import::{ImportDecision, ImportView};
use super::view_models::ModelsView;
use super::view_plateaus::PlateauView;
use super::view_result::ResultView;
use super::view_time::{TimeView, XCommand};
use crate::files::session::{self, Session};
use crate::log::ingest::ReadOptions;
use crate::models::recipe::Weighting;
use eframe::egui::{
    self, Align, Color32, ColorImage, Key, KeyboardShortcut, Layout, Modifiers, Panel, Rect,
    RichText, ScrollArea, Ui, ViewportCommand,
};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, Sender};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Something the engineer asked for, from a menu, a shortcut, a button or a view.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Pick a log to open (import view next).
    OpenLog,
    /// Open this log (import view next).
    OpenLogPath(PathBuf),
    /// Pick a validation log.
    OpenValidation,
    /// Forget the validation log.
    CloseValidation,
    /// Pick a session to open.
    OpenSession,
    /// Open this session.
    OpenSessionPath(PathBuf),
    /// Save the session (asking where the first time).
    SaveSession,
    /// Save the session under a new name.
    SaveSessionAs,
    /// Write the calibration file.
    ExportCalibration,
    /// Write the corrected log.
    ExportCsv,
    /// Write the test report (figures and an HTML page) into a folder.
    ExportReport,
    /// Save the window as PNG.
    Screenshot,
    /// Save one plot (by name) as PNG, cropped to this rectangle.
    SavePlot(String, Rect),
    /// Save one plot (by name) as PNG, at its last known rectangle.
    SavePlotNamed(String),
    /// Where a plot was drawn this frame (for [`Action::SavePlotNamed`]).
    PlotRect(String, Rect),
    /// Undo the last change of choices.
    Undo,
    /// Redo.
    Redo,
    /// Fill the plateau table from the detector.
    SuggestPlateaus,
    /// Every choice back to the defaults.
    ResetRecipe,
    /// Close the workbench.
    Quit,
    /// Change the theme.
    Theme(ThemeChoice),
    /// Show a page of the workbench.
    ShowPage(Page),
    /// Fit and judge the models ticked on the Models page (in the background).
    CompareModels,
    /// Write the model chosen on the Models page as a calibration file.
    ExportModel,
    /// Reopen the import view on the loaded log (or the validation log) to change its
    /// column mapping, units or format.
    ColumnMapping(Target),
}

/// The pages of the workbench.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Page {
    /// The Vakhrameev calibration: time plots, plateaus, coefficients, result.
    #[default]
    Calibration,
    /// Several models side by side.
    Models,
    /// Allan deviation, raw and corrected.
    Allan,
}

impl Page {
    /// Every page, in tab order.
    pub const ALL: [Page; 3] = [Page::Calibration, Page::Models, Page::Allan];

    /// The tab's title.
    pub fn title(self) -> &'static str {
        match self {
            Page::Calibration => "Calibration",
            Page::Models => "Models",
            Page::Allan => "Allan deviation",
        }
    }

    /// The page named `name` (`calibration`, `models`, `allan`), for the command line and
    /// the environment.
    pub fn from_name(name: &str) -> Option<Page> {
        match name.trim().to_ascii_lowercase().as_str() {
            "calibration" | "main" => Some(Page::Calibration),
            "models" => Some(Page::Models),
            "allan" => Some(Page::Allan),
            _ => None,
        }
    }

    fn shortcut(self) -> KeyboardShortcut {
        match self {
            Page::Calibration => SC_PAGE1,
            Page::Models => SC_PAGE2,
            Page::Allan => SC_PAGE3,
        }
    }

    fn tip(self) -> &'static str {
        match self {
            Page::Calibration => {
                "The Vakhrameev calibration: time plots, plateaus, K0/K1±/K2±, the result"
            }
            Page::Models => {
                "The models of the papers and a custom one side by side, in-sample and held out; \
                 export any of them"
            }
            Page::Allan => {
                "Allan deviation of the raw and the corrected rate, with ARW, bias \
                 instability and RRW"
            }
        }
    }
}

const SC_OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
const SC_OPEN_SESSION: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::O);
const SC_SAVE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
const SC_SHOT: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::S);
const SC_SHOT_F12: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F12);
const SC_EXPORT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::E);
const SC_EXPORT_CSV: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::E);
const SC_UNDO: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Z);
const SC_REDO: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Y);
const SC_REDO2: KeyboardShortcut =
    KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::Z);
const SC_QUIT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Q);
const SC_PAGE1: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Num1);
const SC_PAGE2: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Num2);
const SC_PAGE3: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Num3);
const SC_COMPARE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F5);

/// The workbench: application data, views, workers.
pub struct Workbench {
    /// The application data.
    pub state: AppState,
    jobs: Jobs,
    dialogs: Box<dyn FileDialogs>,
    settings: Settings,
    settings_path: Option<PathBuf>,
    time: TimeView,
    plateaus: PlateauView,
    coeffs: CoeffView,
    result: ResultView,
    import: Option<ImportView>,
    /// The window title last sent.
    title: Option<String>,
    /// Height of the coefficient panel's rows other than its three plots, last frame.
    coeff_overhead: Option<f32>,
    /// The workbench's own file dialog, open, with what the path is for.
    file_dialog: Option<(super::file_dialog::FileDialog, files::Purpose)>,
    confirm: Option<Action>,
    error: Option<String>,
    pending_session: Option<(PathBuf, Session)>,
    /// A session's validation log on its way: whether the session showed it.
    restoring_validation: Option<bool>,
    plot_rects: HashMap<String, Rect>,
    /// Where each panel of the Calibration page was drawn last frame.
    panel_rects: HashMap<&'static str, Rect>,
    last_request: Option<(Choices, usize, usize)>,
    pending_shot: Option<PendingShot>,
    shot_tx: Sender<Shot>,
    shot_rx: Receiver<Shot>,
    auto: Option<AutoShot>,
    quitting: bool,
    theme_applied: Option<ThemeChoice>,
    show_help: bool,
    autosave: Autosave,
    /// Work an earlier workbench left behind, offered back until answered.
    recover: Option<LeftBehind>,
    /// The session being opened is autosaved work: it stays unsaved, with no session file.
    restoring_autosave: bool,
    page: Page,
    models: ModelsView,
    allan: AllanPage,
}

fn arc_addr<T>(a: &Arc<T>) -> usize {
    Arc::as_ptr(a) as usize
}

impl Workbench {
    /// A workbench with these remembered settings (saved back to `settings_path` on exit)
    /// and file dialogs.
    pub fn new(
        settings: Settings,
        settings_path: Option<PathBuf>,
        dialogs: Box<dyn FileDialogs>,
    ) -> Workbench {
        let (shot_tx, shot_rx) = std::sync::mpsc::channel();
        let autosave = Autosave::new(settings_path.as_deref().map(Autosave::path_beside));
        let recover = autosave.left_behind();
        Workbench {
            state: AppState::default(),
            jobs: Jobs::new(),
            dialogs,
            settings,
            settings_path,
            time: TimeView::default(),
            plateaus: PlateauView,
            coeffs: CoeffView::default(),
            result: ResultView,
            import: None,
            file_dialog: None,
            coeff_overhead: None,
            title: None,
            confirm: None,
            error: None,
            pending_session: None,
            restoring_validation: None,
            plot_rects: HashMap::new(),
            panel_rects: HashMap::new(),
            last_request: None,
            pending_shot: None,
            shot_tx,
            shot_rx,
            auto: None,
            quitting: false,
            theme_applied: None,
            show_help: false,
            autosave,
            recover,
            restoring_autosave: false,
            page: Page::Calibration,
            models: ModelsView::default(),
            allan: AllanPage::default(),
        }
    }

    /// A workbench for tests: no remembered settings, scripted dialogs, `log` read and
    /// calibrated before it returns.
    ///
    /// # Panics
    /// When the log cannot be read or calibrated (a test should fail then).
    pub fn new_for_test(log: &Path) -> Workbench {
        Workbench::new_for_test_in(log, None)
    }

    /// [`Workbench::new_for_test`] with a settings file (and so an autosave file beside it).
    ///
    /// # Panics
    /// When the log cannot be read or calibrated.
    pub fn new_for_test_in(log: &Path, settings_path: Option<PathBuf>) -> Workbench {
        let mut wb = Workbench::new(
            Settings::default(),
            settings_path,
            Box::new(super::dialogs::ScriptedDialogs::new()),
        );
        wb.start_load(
            log.to_path_buf(),
            ReadOptions::default(),
            Target::Calibration,
        );
        wb.wait_for_jobs();
        assert!(
            wb.state.log.is_some(),
            "the test log could not be read: {:?}",
            wb.state.status
        );
        wb.refit_if_needed();
        wb.wait_for_jobs();
        assert!(
            wb.state.fit.is_some(),
            "the test log could not be calibrated: {:?}",
            wb.state.fit_error
        );
        wb
    }

    /// Replaces the file dialogs (tests inject [`super::dialogs::ScriptedDialogs`]).
    pub fn set_dialogs(&mut self, dialogs: Box<dyn FileDialogs>) {
        self.dialogs = dialogs;
    }

    /// Sends the refit the current choices need, if not sent yet, then waits until every
    /// job (read, refit, export) has answered, handling the answers (for tests and scripts).
    pub fn wait_for_jobs(&mut self) {
        let deadline = Instant::now() + Duration::from_secs(120);
        loop {
            self.refit_if_needed();
            while let Some(r) = self.jobs.next(Duration::ZERO) {
                self.handle(r);
            }
            self.refit_if_needed();
            if !self.jobs.busy() || Instant::now() > deadline {
                break;
            }
            if let Some(r) = self.jobs.next(Duration::from_millis(20)) {
                self.handle(r);
            }
        }
    }

    /// True while a read, refit or export runs.
    pub fn busy(&self) -> bool {
        self.jobs.busy()
    }

    /// The import view, when open (tests read its preview and press its buttons).
    pub fn import_view(&mut self) -> Option<&mut ImportView> {
        self.import.as_mut()
    }

    /// Where a plot (`time_omega`, `time_temp`, `time_tdot`, `time_tddot`, `k0`, `k1`, `k2`,
    /// `result`) was drawn last frame.
    pub fn plot_rect(&self, name: &str) -> Option<Rect> {
        self.plot_rects.get(name).copied()
    }

    /// Where a panel of the Calibration page (`controls`, `coefficients`, `central`) was drawn
    /// last frame.
    pub fn panel_rect(&self, name: &str) -> Option<Rect> {
        self.panel_rects.get(name).copied()
    }

    /// The time range the time plots show, s (as drawn last frame).
    pub fn visible_time_s(&self) -> Option<(f64, f64)> {
        self.time.visible_s
    }

    /// Screen x of time `t_s` on the time plots as drawn last frame (tests aim the mouse).
    pub fn time_plot_x(&self, t_s: f64) -> Option<f32> {
        self.time.screen_x(t_s)
    }

    /// Where knot `j` of a K1/K2 coefficient is on screen (tests aim the mouse).
    pub fn knot_screen_pos(
        &self,
        c: crate::files::session::Coefficient,
        j: usize,
    ) -> Option<egui::Pos2> {
        self.coeffs.knot_pos(&self.state, c, j)
    }

    /// The page shown.
    pub fn page(&self) -> Page {
        self.page
    }

    /// Shows a page.
    pub fn set_page(&mut self, page: Page) {
        self.page = page;
    }

    /// The Models page's choices and selection (tests and scripts set them).
    pub fn models_view(&mut self) -> &mut ModelsView {
        &mut self.models
    }

    /// Runs an action as if chosen from the menu.
    pub fn act(&mut self, ctx: &egui::Context, action: Action) {
        self.run_action(ctx, action);
    }

    /// Opens a log as the command line does: read with `read` at once, unless `ask_when_unsure`
    /// and its columns need a look (no header, two candidates for a role, implausible values,
    /// no mapping): then the import view shows first.
    pub fn open_log(&mut self, path: PathBuf, read: ReadOptions, ask_when_unsure: bool) {
        let view = ImportView::new(path.clone(), Target::Calibration, read.clone());
        if ask_when_unsure && view.needs_a_look() {
            self.state.say(
                Severity::Warning,
                format!(
                    "Check the columns of {} before it is read",
                    file_name(&path)
                ),
            );
            self.import = Some(view);
        } else {
            self.start_load(path, read, Target::Calibration);
        }
    }

    /// Starts reading a log (no import view: the options are given).
    pub fn start_load(&mut self, path: PathBuf, read: ReadOptions, target: Target) {
        self.state
            .say(Severity::Info, format!("Reading {} …", file_name(&path)));
        self.jobs.load(path, read, target);
    }

    /// The whole window, for one frame.
    pub fn ui(&mut self, ui: &mut Ui) {
        let ctx = ui.ctx().clone();
        self.jobs.set_context(&ctx);
        self.apply_theme(&ctx);
        while let Some(r) = self.jobs.next(Duration::ZERO) {
            self.handle(r);
        }
        let mut actions = Vec::new();
        self.shortcuts(&ctx, &mut actions);
        self.files_dropped(&ctx, &mut actions);
        self.close_requested(&ctx);

        Panel::top("menu").show(ui, |ui| self.menu_bar(ui, &mut actions));
        Panel::top("pages").show(ui, |ui| self.page_tabs(ui, &mut actions));
        Panel::bottom("status").show(ui, |ui| self.status_bar(ui));
        match self.page {
            Page::Calibration => self.calibration_page(ui, &mut actions),
            Page::Models => {
                let running = self.jobs.comparing.clone();
                self.models
                    .ui(ui, &self.state, running.as_ref(), &mut actions);
            }
            Page::Allan => {
                if let Some(key) = self.allan.wanted(&self.state)
                    && self.state.allan.as_ref().is_none_or(|a| a.key != key)
                    && self.jobs.allan != Some(key)
                {
                    self.request_allan(key);
                }
                let running = self.jobs.allan.is_some();
                self.allan.ui(ui, &self.state, running, &mut actions);
            }
        }
        for (name, rect) in &self.time.rects {
            self.plot_rects.insert((*name).to_string(), *rect);
        }

        self.modals(&ctx, &mut actions);
        for a in actions {
            self.run_action(&ctx, a);
        }
        let settled = !ctx.input(|i| i.pointer.any_down());
        self.state.history.observe(&self.state.choices, settled);
        self.state.forget_stale_status();
        self.refit_if_needed();
        if self.auto.is_none() {
            self.autosave.tick(&self.state);
            if let Some(e) = self.autosave.error.take() {
                self.state
                    .say(Severity::Warning, format!("Autosave failed: {e}"));
            }
        }
        self.screenshots(&ctx);
        self.remember_window(&ctx);
        self.window_title(&ctx);
        if self.jobs.busy() {
            // A comparison's progress at four frames a second; the rest at ten.
            let only_comparing = self.jobs.comparing.is_some()
                && self.jobs.loading.is_none()
                && !self.jobs.fitting();
            ctx.request_repaint_after(Duration::from_millis(if only_comparing {
                250
            } else {
                100
            }));
        }
    }

    fn calibration_page(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        Panel::top("banner")
            .resizable(false)
            .show(ui, |ui| self.banner(ui));
        Panel::bottom("figures")
            .resizable(false)
            .show(ui, |ui| ResultView::figures(ui, &self.state));
        // Side panels keep the width they are given (their contents fill it, whatever they
        // are): an egui panel otherwise takes its contents' width, so a narrow first frame
        // (the log still loading) or a wider row (a button appearing) would change it.
        let r = Panel::left("controls")
            .default_size(340.0)
            .size_range(340.0..=520.0)
            .show(ui, |ui| {
                ScrollArea::vertical()
                    .auto_shrink([false, false])
                    .show(ui, |ui| {
                        ui.set_min_width(ui.available_width());
                        self.controls(ui, actions)
                    });
            });
        self.panel_rects.insert("controls", r.response.rect);
        let r = Panel::right("coefficients")
            .default_size(470.0)
            .size_range(320.0..=800.0)
            .show(ui, |ui| {
                ui.set_min_width(ui.available_width());
                self.coefficient_panel(ui, actions)
            });
        self.panel_rects.insert("coefficients", r.response.rect);
        let r = egui::CentralPanel::default().show(ui, |ui| {
            if self.state.log.is_none() {
                self.welcome(ui, actions);
                return;
            }
            let h = ui.available_height();
            let time_h = (h * 0.66).max(240.0);
            ui.allocate_ui(egui::vec2(ui.available_width(), time_h), |ui| {
                self.time.ui(ui, &mut self.state, actions);
            });
            ui.separator();
            self.result.ui(ui, &mut self.state, actions);
        });
        self.panel_rects.insert("central", r.response.rect);
    }

    fn page_tabs(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        let ctx = ui.ctx().clone();
        ui.horizontal(|ui| {
            for p in Page::ALL {
                if ui
                    .selectable_label(self.page == p, RichText::new(p.title()).size(15.0))
                    .on_hover_text(format!(
                        "{} ({})",
                        p.tip(),
                        ctx.format_shortcut(&p.shortcut())
                    ))
                    .clicked()
                {
                    actions.push(Action::ShowPage(p));
                }
            }
            if let Some(h) = &self.jobs.comparing {
                // No spinner: it redraws the window every frame, and a comparison takes
                // seconds of both cores (the counts below change as models finish).
                ui.separator();
                ui.label(format!("fitting models… {} of {}", h.done(), h.total));
            }
        });
    }

    fn apply_theme(&mut self, ctx: &egui::Context) {
        if self.theme_applied != Some(self.settings.theme) {
            ctx.set_theme(match self.settings.theme {
                ThemeChoice::System => egui::ThemePreference::System,
                ThemeChoice::Light => egui::ThemePreference::Light,
                ThemeChoice::Dark => egui::ThemePreference::Dark,
            });
            self.theme_applied = Some(self.settings.theme);
        }
    }

    /// Opens the autosaved work (see [`Workbench::recovery`]).
    pub fn restore_autosave(&mut self) {
        if let Some(left) = self.recover.take() {
            self.restoring_autosave = true;
            self.open_session(left.path);
        }
    }

    /// Work left behind by an earlier workbench, while it is being offered back.
    pub fn recovery(&self) -> Option<&LeftBehind> {
        self.recover.as_ref()
    }

    /// Writes the autosave file now and waits for it (tests).
    pub fn autosave_now(&mut self) {
        self.autosave.save_now(&self.state);
        self.autosave.flush();
    }

    /// The window closes cleanly: settings written, nothing left to recover.
    pub fn close_cleanly(&mut self) {
        self.quitting = true;
        self.save_settings();
    }

    /// Where this workbench autosaves, when it does.
    pub fn autosave_path(&self) -> Option<&Path> {
        self.autosave.path()
    }

    /// The window's title names the log and says when its calibration is ready (scripts
    /// that drive the window wait for it).
    fn window_title(&mut self, ctx: &egui::Context) {
        let title = match &self.state.log {
            None => "driftlab workbench".to_string(),
            Some(l) => format!(
                "{}{} — driftlab workbench{}",
                file_name(&l.path),
                if self.state.dirty() { " •" } else { "" },
                match (&self.state.fit, &self.state.fit_error) {
                    (_, Some(_)) => " (calibration failed)",
                    (None, None) => " (calibrating…)",
                    (Some(_), None) => "",
                }
            ),
        };
        if self.title.as_deref() != Some(title.as_str()) {
            ctx.send_viewport_cmd(ViewportCommand::Title(title.clone()));
            self.title = Some(title);
        }
    }

    fn remember_window(&mut self, ctx: &egui::Context) {
        if self.auto.is_some() {
            return;
        }
        let (inner, outer, maximized) = ctx.input(|i| {
            let v = i.viewport();
            (v.inner_rect, v.outer_rect, v.maximized.unwrap_or(false))
        });
        if let (Some(inner), Some(outer)) = (inner, outer) {
            let g = WindowGeometry {
                x: outer.min.x,
                y: outer.min.y,
                width: inner.width(),
                height: inner.height(),
                maximized,
            };
            if maximized {
                if let Some(w) = &mut self.settings.window {
                    w.maximized = true;
                }
            } else {
                self.settings.window = Some(g);
            }
        }
    }

    /// Writes the remembered settings (theme, recent files, window).
    pub fn save_settings(&mut self) {
        if self.quitting {
            // A clean close: nothing is left to recover at the next start.
            self.autosave.clear();
        }
        if let Some(p) = &self.settings_path
            && let Err(e) = self.settings.save(p)
        {
            eprintln!("warning: could not save the workbench settings: {e}");
        }
    }

    // ------------------------------------------------------------------ layout

    fn welcome(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        ui.vertical_centered(|ui| {
            ui.add_space(ui.available_height() * 0.3);
            ui.heading("driftlab workbench");
            ui.label("Calibrate the thermal drift of a gyroscope from a thermal-chamber log.");
            ui.add_space(12.0);
            if self.jobs.loading.is_some() {
                ui.spinner();
            } else if ui
                .button(RichText::new("Open log…").size(18.0))
                .on_hover_text("Ctrl+O — or drop a log file onto the window")
                .clicked()
            {
                actions.push(Action::OpenLog);
            }
            if let Some(s) = default_log()
                && ui
                    .button("Open the bundled sample log")
                    .on_hover_text(s.display().to_string())
                    .clicked()
            {
                self.start_load(s, ReadOptions::default(), Target::Calibration);
            }
        });
    }

    fn coefficient_panel(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        if self.state.log.is_none() {
            ui.weak("K0, K1± and K2± appear here once a log is loaded.");
            return;
        }
        // The three plots share what their control rows leave, as measured last frame (rows
        // wrap when the panel is narrow, rather than widening it).
        let top = ui.cursor().top();
        let h = ui.available_height();
        let row = ui.spacing().interact_size.y + ui.spacing().item_spacing.y;
        let overhead = self.coeff_overhead.unwrap_or(11.0 * row + 30.0);
        let plot_h = ((h - overhead) / 3.0).max(90.0).floor();
        self.plateaus.k0_plot(ui, &mut self.state, plot_h, actions);
        ui.separator();
        self.coeffs
            .ui(ui, &mut self.state, Pair::K1, plot_h, actions);
        ui.separator();
        self.coeffs
            .ui(ui, &mut self.state, Pair::K2, plot_h, actions);
        let used = ui.cursor().top() - top;
        self.coeff_overhead = Some((used - 3.0 * plot_h).max(0.0));
    }
}

impl eframe::App for Workbench {
    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        Workbench::ui(self, ui);
    }

    fn raw_input_hook(&mut self, _ctx: &egui::Context, raw_input: &mut egui::RawInput) {
        if self.auto.is_some() {
            // A picture for reports: no pointer hovering anything, whatever the X server's
            // pointer does.
            raw_input.events.retain(|e| {
                !matches!(
                    e,
                    egui::Event::PointerMoved(_)
                        | egui::Event::PointerButton { .. }
                        | egui::Event::MouseWheel { .. }
                )
            });
            raw_input.events.push(egui::Event::PointerGone);
        }
    }

    fn on_exit(&mut self, _gl: Option<&eframe::glow::Context>) {
        if self.auto.is_none() {
            self.save_settings();
        }
    }
}

/// A file's name for short messages (the full path is in tooltips).
fn file_name(p: &Path) -> String {
    p.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}

fn is_json(p: &Path) -> bool {
    p.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
}

fn same_file(a: &Path, b: &Path) -> bool {
    let canon = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
    canon(a) == canon(b)
}

/// The bundled calibration sample log: `sample_logs/calibration.csv` in the current folder,
/// else in the crate's folder.
pub fn default_log() -> Option<PathBuf> {
    let rel = Path::new("sample_logs").join("calibration.csv");
    if rel.is_file() {
        return Some(rel);
    }
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    p.is_file().then_some(p)
}
