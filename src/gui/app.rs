//! The workbench window: its state, its pages and the frame that draws them. It holds no
//! calculation: choices go to the worker as refit requests, results come back and are drawn.
//!
//! Each frame the views draw what the application data holds and return what the engineer
//! asked for ([`Action`]); the window carries the actions out once every view has drawn.
//! The rest of the window, one file a concern: `layout` (menus, status bar, the panels of
//! the Calibration page and modals), `page` (the Calibration page's panels), `validation`
//! (which axis of the validation log each axis is judged on), `actions` (carrying out what the engineer asks for,
//! and the unsaved-work question), `results` (what the worker is asked and what its answers
//! change), `k0_default` (K0's kind chosen once from a fresh log's plateaus), `files` (what is
//! written and opened), `lot` (a lot opened, and a unit of it opened on the Calibration page)
//! and `screenshot` (PNG of the window, and the `--screenshot` mode).

mod actions;
mod files;
mod gyro_menu;
mod k0_default;
mod layout;
mod lot;
mod opened;
mod page;
mod results;
mod screenshot;
mod validation;

pub use screenshot::ScreenshotOutcome;
use screenshot::{PendingShot, Shots};

use super::action::{Action, Edit, OpenLog, Page, shortcuts};
use super::autosave::{Autosave, LeftBehind};
use super::dialogs::FileDialogs;
use super::export;
use super::jobs::LoadOptions;
use super::jobs::{JobResult, Jobs, Loaded, Target};
use super::plot_items::num;
use super::settings::{Settings, ThemeChoice, WindowGeometry};
use super::state::{AppState, Choices, Severity};
use super::view_allan::AllanPage;
use super::view_axes::AxesView;
use super::view_coeffs::CoeffView;
use super::view_controls::{ControlsView, PlateauFocus};
use super::view_figures::FiguresView;
use super::view_import::{ImportView, ReadWarning};
use super::view_models::ModelsView;
use super::view_result::ResultView;
use super::view_runs::RunsView;
use super::view_time::{TimeView, XCommand};
use super::widgets::file_name;
use crate::files::session::{self, Session};
use eframe::egui::{
    self, Align, Color32, ColorImage, Key, KeyboardShortcut, Layout, Panel, Rect, RichText,
    ScrollArea, Ui, ViewportCommand,
};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The workbench: the application data, and the parts of the window that show it and act on
/// it.
pub struct Workbench {
    /// The application data.
    pub state: AppState,
    /// The workers (reading, refitting, comparing, exporting).
    jobs: Jobs,
    /// The views and the page shown.
    views: Views,
    /// What shows over the page and asks the engineer something.
    modals: Modals,
    /// The window itself: what it remembers, its theme and title, where it drew what.
    window: Window,
    /// A session on its way in, while its log is read.
    opening: Opening,
    /// Unsaved work kept on disk, and the work an earlier workbench left behind.
    recovery: Recovery,
    /// Pictures of the window: asked for, on their way, and the `--screenshot` mode.
    shots: Shots,
}

/// The views of the pages, each with its own view state (zoom, drag, selection).
#[derive(Default)]
struct Views {
    page: Page,
    axes: AxesView,
    accel: super::view_accel::AccelView,
    runs: RunsView,
    time: TimeView,
    controls: ControlsView,
    coeffs: CoeffView,
    result: ResultView,
    figures: FiguresView,
    models: ModelsView,
    allan: AllanPage,
    opened: super::view_opened::OpenedView,
    lot: super::view_lot::LotView,
}

/// What shows over the page: the import view, the file dialogs, the unsaved-work question,
/// an error, the help.
struct Modals {
    /// The file dialogs of the desktop (or none, and the workbench's own then).
    dialogs: Box<dyn FileDialogs>,
    import: Option<ImportView>,
    /// The workbench's own file dialog, open, with what the path is for.
    file_dialog: Option<(super::file_dialog::FileDialog, files::Purpose)>,
    /// An action waiting for the answer to "Unsaved work".
    confirm: Option<Action>,
    error: Option<String>,
    help: bool,
}

/// The window: its remembered settings, theme and title, and where it drew what last frame.
struct Window {
    settings: Settings,
    /// Where the settings are saved back (none in tests and screenshots).
    settings_path: Option<PathBuf>,
    theme_applied: Option<ThemeChoice>,
    /// The window title last sent.
    title: Option<String>,
    /// The window is closing cleanly (nothing left to recover).
    quitting: bool,
    /// Where each plot was drawn last frame (for saving one as PNG, and tests).
    plot_rects: HashMap<String, Rect>,
    /// Where each panel of the Calibration page was drawn last frame.
    panel_rects: HashMap<&'static str, Rect>,
    /// A mouse button is held (a drag under way): only the axis shown is refitted.
    pointer_down: bool,
    /// A plateau edge is being dragged (the last edit was one of its moves): the plateaus and
    /// K0 are previewed, and the axes refitted on release.
    plateau_drag: bool,
    /// The window is short: the page is laid out compact (see [`COMPACT_BELOW_H`]).
    compact: bool,
    /// The size asked for on the command line, until the window is seen to have it or not.
    asked_size: Option<[f32; 2]>,
    /// The width the menu bar's right-hand end (theme button, spinner) took last frame.
    menu_right_w: f32,
    /// The heights the figures and the opened strip at the controls' foot (a short window)
    /// asked for last frame.
    foot_h: [f32; 2],
}

/// A session being opened: its log is read first, then the rest of it is restored.
#[derive(Default)]
struct Opening {
    /// The session file and what it holds.
    session: Option<(PathBuf, Session)>,
    /// A session's validation log on its way: whether the session showed it.
    validation_shown: Option<bool>,
    /// The session being opened is autosaved work: it stays unsaved, with no session file.
    autosaved: bool,
    /// A validation log asked for at start (`driftlab gui LOG --validation VAL`), read once
    /// the calibration log is.
    validation: Option<(PathBuf, LoadOptions)>,
    /// Whether K0 is still the window's to choose from a log's plateaus.
    k0: k0_default::K0Default,
    /// A lot's unit being opened: its calibration, opened beside the fit once its log is
    /// read (a log that cannot be read leaves the opened calibration as it was too).
    calibration: Option<PathBuf>,
}

/// Unsaved work written to disk every few seconds, and work left behind offered back.
struct Recovery {
    autosave: Autosave,
    /// Work earlier workbenches left behind, newest first, offered back one at a time
    /// until answered.
    offered: Vec<LeftBehind>,
}

/// A window shorter than this, points, is laid out compact (see [`Workbench::ui`]).
const COMPACT_BELOW_H: f32 = 860.0;
/// The height each time plot keeps when the window allows it, points.
const TIME_PLOT_H: f32 = 120.0;
/// The central panel's margin above and below on a short window, points (egui's 8 would take
/// the drift plot 12 points of the 120 it needs at 1280×720).
const COMPACT_MARGIN_Y: i8 = 2;
/// A window at least this wide starts its controls panel wide enough for the whole plateau
/// table (narrower, the table scrolls sideways and the plots keep their width).
const WHOLE_TABLE_FROM_W: f32 = 1280.0;
/// The drift plot's least height, points (with its time axis): that of every plot, the
/// result being the plot to read. A window too short for five plots this tall (1024×640)
/// takes the height from the time plots.
const DRIFT_PLOT_H: f32 = 120.0;

impl Workbench {
    /// A workbench with these remembered settings (saved back to `settings_path` on exit)
    /// and file dialogs.
    pub fn new(
        settings: Settings,
        settings_path: Option<PathBuf>,
        dialogs: Box<dyn FileDialogs>,
    ) -> Workbench {
        let autosave = Autosave::beside(settings_path.as_deref());
        let offered = autosave.left_behind();
        Workbench {
            state: AppState::default(),
            jobs: Jobs::new(),
            views: Views::default(),
            modals: Modals {
                dialogs,
                import: None,
                file_dialog: None,
                confirm: None,
                error: None,
                help: false,
            },
            window: Window {
                settings,
                settings_path,
                theme_applied: None,
                title: None,
                quitting: false,
                plot_rects: HashMap::new(),
                panel_rects: HashMap::new(),
                pointer_down: false,
                plateau_drag: false,
                compact: false,
                asked_size: None,
                menu_right_w: 100.0,
                foot_h: [f32::INFINITY; 2],
            },
            opening: Opening::default(),
            recovery: Recovery { autosave, offered },
            shots: Shots::new(),
        }
    }

    /// A workbench for tests: no remembered settings, scripted dialogs, `log` read and
    /// calibrated before it returns.
    ///
    /// # Panics
    /// When the log cannot be read or calibrated (a test should fail then).
    #[doc(hidden)]
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
            LoadOptions::default(),
            Target::Calibration,
        );
        wb.wait_for_jobs();
        assert!(
            wb.state.shown.log.is_some(),
            "the test log could not be read: {:?}",
            wb.state.status
        );
        wb.refit_if_needed();
        wb.wait_for_jobs();
        assert!(
            wb.state.shown.fit.is_some(),
            "the test log could not be calibrated: {:?}",
            wb.state.shown.fit_error
        );
        wb
    }

    /// Replaces the file dialogs (tests inject [`super::dialogs::ScriptedDialogs`]).
    pub fn set_dialogs(&mut self, dialogs: Box<dyn FileDialogs>) {
        self.modals.dialogs = dialogs;
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
            self.verify_if_needed();
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
        self.modals.import.as_mut()
    }

    /// Where a plot (`time_omega`, `time_temp`, `time_tdot`, `time_tddot`, `k0`, `k1`, `k2`,
    /// `result`) was drawn last frame.
    pub fn plot_rect(&self, name: &str) -> Option<Rect> {
        self.window.plot_rects.get(name).copied()
    }

    /// Where the frame of a plot (the rectangle inside its axes) was drawn last frame: the
    /// time plots' and the drift plot's (`result`), for tests that check the linked plots
    /// put one time at one x.
    pub fn plot_frame(&self, name: &str) -> Option<Rect> {
        self.window
            .plot_rects
            .get(&format!("{name}.frame"))
            .copied()
    }

    /// Where a panel of the Calibration page (`controls`, `coefficients`, `central`) was drawn
    /// last frame.
    pub fn panel_rect(&self, name: &str) -> Option<Rect> {
        self.window.panel_rects.get(name).copied()
    }

    /// The time range the time plots show, s (as drawn last frame).
    pub fn visible_time_s(&self) -> Option<(f64, f64)> {
        self.views.time.visible_s
    }

    /// Screen x of time `t_s` on the time plots as drawn last frame (tests aim the mouse).
    pub fn time_plot_x(&self, t_s: f64) -> Option<f32> {
        self.views.time.screen_x(t_s)
    }

    /// Where knot `j` of a coefficient is on screen (tests aim the mouse).
    pub fn knot_screen_pos(
        &self,
        c: crate::files::session::Coefficient,
        j: usize,
    ) -> Option<egui::Pos2> {
        self.views.coeffs.knot_pos(&self.state, c, j)
    }

    /// Where the point `(x, y)` of a coefficient's plot is on screen (tests aim the mouse).
    pub fn coeff_plot_pos(
        &self,
        c: crate::files::session::Coefficient,
        x: f64,
        y: f64,
    ) -> Option<egui::Pos2> {
        self.views.coeffs.plot_pos(c, x, y)
    }

    /// The page shown.
    pub fn page(&self) -> Page {
        self.views.page
    }

    /// Shows a page.
    pub fn set_page(&mut self, page: Page) {
        self.views.page = page;
    }

    /// The Models page's choices and selection (tests and scripts set them).
    pub fn models_view(&mut self) -> &mut ModelsView {
        &mut self.views.models
    }

    /// Runs an action as if chosen from the menu.
    pub fn act(&mut self, ctx: &egui::Context, action: Action) {
        self.run_action(ctx, action);
    }

    /// Opens a log as the command line does: read with `read` at once, unless `ask_when_unsure`
    /// and its columns need a look (no header, two candidates for a role, implausible values,
    /// no mapping): then the import view shows first.
    pub fn open_log(&mut self, path: PathBuf, options: LoadOptions, ask_when_unsure: bool) {
        if actions::is_drone_log(&path) {
            self.start_load(path, options, Target::Calibration);
            return;
        }
        let view = ImportView::new(path.clone(), Target::Calibration, options.clone());
        if ask_when_unsure && view.needs_a_look() {
            self.state.say(
                Severity::Warning,
                format!(
                    "Check the columns of {} before it is read",
                    file_name(&path)
                ),
            );
            self.modals.import = Some(view);
        } else {
            self.start_load(path, options, Target::Calibration);
        }
    }

    /// Reads `path` as the validation log, with `options`, once the calibration log being
    /// opened is read (`driftlab gui LOG --validation VAL`).
    pub fn open_validation_after(&mut self, path: PathBuf, options: LoadOptions) {
        self.opening.validation = Some((path, options));
    }

    /// Remembers the window size asked for, so that a window the screen cannot hold (and a
    /// screenshot of another size than asked) is said rather than passed over.
    pub fn ask_window_size(&mut self, size: [f32; 2]) {
        self.window.asked_size = Some(size);
    }

    /// Once the window has settled (a few frames in), says when it is smaller than the size
    /// asked for: the screen or the window system made it so.
    fn check_window_size(&mut self, ctx: &egui::Context) {
        let Some([w, h]) = self.window.asked_size else {
            return;
        };
        if ctx.cumulative_frame_nr() < 3 {
            return;
        }
        self.window.asked_size = None;
        let (inner, monitor) = ctx.input(|i| (i.viewport().inner_rect, i.viewport().monitor_size));
        let Some(inner) = inner else {
            return;
        };
        if inner.width() + 1.0 >= w && inner.height() + 1.0 >= h {
            return;
        }
        let screen = monitor
            .map(|m| format!(": the screen is {:.0}×{:.0}", m.x, m.y))
            .unwrap_or_default();
        let message = format!(
            "The window is {:.0}×{:.0}, smaller than the {w:.0}×{h:.0} asked for{screen}",
            inner.width(),
            inner.height()
        );
        if self.shots.auto.is_some() {
            eprintln!("warning: {message}");
        }
        self.state.say(Severity::Warning, message);
    }

    /// Starts reading a log (no import view: the options are given).
    pub fn start_load(&mut self, path: PathBuf, options: LoadOptions, target: Target) {
        self.state
            .say(Severity::Info, format!("Reading {} …", file_name(&path)));
        self.jobs.load(path, options, target);
    }

    /// The whole window, for one frame.
    pub fn ui(&mut self, ui: &mut Ui) {
        let ctx = ui.ctx().clone();
        self.jobs.set_context(&ctx);
        self.check_window_size(&ctx);
        self.apply_theme(&ctx);
        while let Some(r) = self.jobs.next(Duration::ZERO) {
            self.handle(r);
        }
        let mut actions = Vec::new();
        self.shortcuts(&ctx, &mut actions);
        self.files_dropped(&ctx, &mut actions);
        self.close_requested(&ctx);

        // A short window (1280×720, 1024×640) gives the plots every row it can: the page tabs
        // sit in the menu bar always; on the Calibration page the banner shares the status
        // bar and the figures move into the controls panel.
        let compact = ctx.content_rect().height() < COMPACT_BELOW_H;
        let banner_below = compact && self.views.page == Page::Calibration;
        self.window.compact = compact;
        Panel::top("menu").show(ui, |ui| self.menu_bar(ui, &mut actions));
        Panel::bottom("status").show(ui, |ui| self.status_bar(ui, banner_below));
        match self.views.page {
            Page::Calibration => self.calibration_page(ui, &mut actions, compact),
            Page::Models => {
                let running = self.jobs.comparing.clone();
                actions.extend(self.views.models.ui(ui, &self.state, running.as_ref()));
            }
            Page::Allan => {
                if let Some(key) = self.views.allan.wanted(&self.state)
                    && self.state.shown.allan.as_ref().is_none_or(|a| a.key != key)
                    && self.jobs.allan != Some(key)
                {
                    self.request_allan(key);
                }
                let running = self.jobs.allan.is_some();
                actions.extend(self.views.allan.ui(ui, &self.state, running));
            }
            Page::Lot => actions.extend(self.views.lot.ui(ui, &self.state)),
        }
        for (name, rect) in &self.views.time.rects {
            self.window.plot_rects.insert((*name).to_string(), *rect);
        }
        for (name, frame) in &self.views.time.frames {
            self.window
                .plot_rects
                .insert(format!("{name}.frame"), *frame);
        }

        self.modals(ui, &mut actions);
        for a in actions {
            self.run_action(&ctx, a);
        }
        let settled = !ctx.input(|i| i.pointer.any_down());
        self.window.pointer_down = !settled;
        self.k0_watch();
        self.state
            .shown
            .history
            .observe(&self.state.shown.choices, settled);
        self.state.forget_stale_status();
        self.refit_if_needed();
        self.verify_if_needed();
        if self.shots.auto.is_none() {
            self.recovery.autosave.tick(&self.state);
            if let Some(e) = self.recovery.autosave.error.take() {
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

    fn page_tabs(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        let ctx = ui.ctx().clone();
        ui.horizontal(|ui| {
            for p in Page::ALL {
                // The Lot tab while a lot is open (or its page shown).
                if p == Page::Lot && self.state.lot.is_none() && self.views.page != Page::Lot {
                    continue;
                }
                if ui
                    .selectable_label(self.views.page == p, RichText::new(p.title()).size(15.0))
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
        if self.window.theme_applied != Some(self.window.settings.theme) {
            ctx.set_theme(match self.window.settings.theme {
                ThemeChoice::System => egui::ThemePreference::System,
                ThemeChoice::Light => egui::ThemePreference::Light,
                ThemeChoice::Dark => egui::ThemePreference::Dark,
            });
            self.window.theme_applied = Some(self.window.settings.theme);
        }
    }

    /// Opens the autosaved work (see [`Workbench::recovery`]).
    pub fn restore_autosave(&mut self) {
        if self.recovery.offered.is_empty() {
            return;
        }
        let left = self.recovery.offered.remove(0);
        // The others are let go: the next workbench to start offers them.
        self.recovery.offered.clear();
        self.opening.autosaved = true;
        self.open_session(left.path.clone());
        self.recovery.autosave.adopt(left);
    }

    /// Work left behind by an earlier workbench, while it is being offered back.
    pub fn recovery(&self) -> Option<&LeftBehind> {
        self.recovery.offered.first()
    }

    /// Writes the autosave file now and waits for it (tests).
    pub fn autosave_now(&mut self) {
        self.recovery.autosave.save_now(&self.state);
        self.recovery.autosave.flush();
    }

    /// The window closes cleanly: settings written, nothing left to recover.
    pub fn close_cleanly(&mut self) {
        self.window.quitting = true;
        self.save_settings();
    }

    /// Where this workbench autosaves, when it does.
    pub fn autosave_path(&self) -> Option<&Path> {
        self.recovery.autosave.path()
    }

    /// The window's title names the log and says when its calibration is ready (scripts
    /// that drive the window wait for it).
    fn window_title(&mut self, ctx: &egui::Context) {
        let title = match &self.state.shown.log {
            None => "driftlab workbench".to_string(),
            Some(l) => format!(
                "{}{} — driftlab workbench{}",
                l.name(),
                if self.state.dirty() { " •" } else { "" },
                match (&self.state.shown.fit, &self.state.shown.fit_error) {
                    (_, Some(_)) => " (calibration failed)",
                    (None, None) => " (calibrating…)",
                    (Some(_), None) => "",
                }
            ),
        };
        if self.window.title.as_deref() != Some(title.as_str()) {
            ctx.send_viewport_cmd(ViewportCommand::Title(title.clone()));
            self.window.title = Some(title);
        }
    }

    fn remember_window(&mut self, ctx: &egui::Context) {
        if self.shots.auto.is_some() {
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
                if let Some(w) = &mut self.window.settings.window {
                    w.maximized = true;
                }
            } else {
                self.window.settings.window = Some(g);
            }
        }
    }

    /// Writes the remembered settings (theme, recent files, window).
    pub fn save_settings(&mut self) {
        if self.window.quitting {
            // A clean close: nothing is left to recover at the next start.
            self.recovery.autosave.clear();
        }
        if let Some(p) = &self.window.settings_path
            && let Err(e) = self.window.settings.save(p)
        {
            eprintln!("warning: could not save the workbench settings: {e}");
        }
    }
}

impl eframe::App for Workbench {
    fn ui(&mut self, ui: &mut Ui, _frame: &mut eframe::Frame) {
        Workbench::ui(self, ui);
    }

    fn raw_input_hook(&mut self, _ctx: &egui::Context, raw_input: &mut egui::RawInput) {
        if self.shots.auto.is_some() {
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
        if self.shots.auto.is_none() {
            self.save_settings();
        }
    }
}

pub(crate) fn is_json(p: &Path) -> bool {
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
