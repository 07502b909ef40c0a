//! The desktop workbench (eframe/egui): a face over the engine that holds no calculation.
//!
//! From the bottom up:
//! * [`action`]: what the engineer can ask for ([`Action`], with [`action::Edit`] for a change
//!   of choices) and the pages ([`Page`]); it names only engine types, so every view can use
//!   it without importing the window;
//! * [`state`]: the application data in one plain struct (logs, choices, newest fit, undo);
//! * [`jobs`]: reading logs, refitting (newest request wins) and exports on worker threads;
//!   [`crate::refit::Same`]: the identity of a shared value, for their cache keys;
//! * [`plot_items`]: plot items drawn from level-of-detail data ([`crate::signal::lod`]), and
//!   the number formats; [`widgets`]: the widgets more than one view draws;
//! * one module per view: [`view_import`], [`view_axes`] (a unit's axes: the switch and each
//!   axis's figures, the accelerometer axes beside the gyro axes), [`view_accel`] (an
//!   accelerometer axis, in m/s²), [`view_time`] (the run over time),
//!   [`view_controls`] (the log, the signal settings and the plateau table), [`view_coeffs`]
//!   (K0, K1±, K2±), [`view_result`] (the drift before and after), [`view_figures`] (the
//!   figures of merit), [`view_models`] (the Models page), [`view_allan`] (the Allan page) and
//!   [`view_opened`] (a calibration opened beside the current fit, to compare: what it holds
//!   and is judged on is [`opened`]), [`view_lot`] (the Lot page: a lot's table and each
//!   figure's distribution);
//! * [`export`], [`dialogs`] (which file dialog can appear), [`file_dialog`] (the workbench's
//!   own, where no system dialog can), [`settings`], [`autosave`];
//! * [`app`]: the window, on top — menus, shortcuts, layout, job results, unsaved-work
//!   questions, screenshots.
//!
//! # How a view is written
//! A view is a struct that owns only its view state (zoom, a drag under way, a selection).
//! It draws with one method,
//!
//! ```text
//! fn ui(&mut self, ui: &mut egui::Ui, state: &AppState, /* what other views show */) -> Vec<Action>
//! ```
//!
//! It reads what it shows from the application data by shared reference (plus, by value,
//! what another view holds that it shows too, such as the time range on screen), never
//! changes that data, and returns what the engineer asked for. A change of a choice is an
//! [`Action::Edit`]; the window carries every action out once all views have drawn, so undo,
//! the unsaved mark and the refit see each change in one place. A view that moves something
//! under the pointer (a plateau edge, a knot) draws the value its action carries, so nothing
//! lags a frame behind the mouse. Views never call into each other; what two of them draw
//! lives in [`widgets`] or [`plot_items`]. Modal views (the import view) use the same method
//! and show themselves over the window through `ui.ctx()`.
//!
//! Fitting is a pure function of (log, recipe, knots moved by hand), run by
//! [`crate::refit::Pipeline`] on the worker; a GUI edit changes the recipe and the next frame
//! sends the refit.
//!
//! [`action`]: crate::gui::action
//! [`Action`]: crate::gui::action::Action
//! [`action::Edit`]: crate::gui::action::Edit
//! [`Page`]: crate::gui::action::Page
//! [`state`]: crate::gui::state
//! [`jobs`]: crate::gui::jobs
//! [`plot_items`]: crate::gui::plot_items
//! [`widgets`]: crate::gui::widgets
//! [`view_import`]: crate::gui::view_import
//! [`view_axes`]: crate::gui::view_axes
//! [`view_accel`]: crate::gui::view_accel
//! [`view_time`]: crate::gui::view_time
//! [`view_controls`]: crate::gui::view_controls
//! [`view_coeffs`]: crate::gui::view_coeffs
//! [`view_result`]: crate::gui::view_result
//! [`view_figures`]: crate::gui::view_figures
//! [`view_models`]: crate::gui::view_models
//! [`view_allan`]: crate::gui::view_allan
//! [`view_opened`]: crate::gui::view_opened
//! [`opened`]: crate::gui::opened
//! [`view_lot`]: crate::gui::view_lot
//! [`export`]: crate::gui::export
//! [`dialogs`]: crate::gui::dialogs
//! [`file_dialog`]: crate::gui::file_dialog
//! [`settings`]: crate::gui::settings
//! [`autosave`]: crate::gui::autosave
//! [`app`]: crate::gui::app
//! [`Action::Edit`]: crate::gui::action::Action::Edit

pub mod action;
pub mod app;
pub mod autosave;
pub mod dialogs;
pub mod export;
pub mod file_dialog;
pub mod jobs;
pub mod opened;
pub mod plot_axes;
pub mod plot_items;
pub mod settings;
pub mod state;
pub mod view_accel;
pub mod view_allan;
pub mod view_axes;
pub mod view_coeffs;
pub mod view_controls;
pub mod view_figures;
pub mod view_import;
pub mod view_lot;
pub mod view_models;
pub mod view_opened;
pub mod view_result;
pub mod view_runs;
pub mod view_time;
pub mod widgets;

pub use action::{Action, Page};
pub use app::{ScreenshotOutcome, Workbench, default_log};
pub use dialogs::{Answer, FileDialogs, FileKind, ScriptedDialogs, SystemDialogs};
pub use jobs::Target;

use eframe::egui;
use settings::Settings;
use std::path::PathBuf;

/// How the workbench is started.
#[derive(Debug, Clone, Default)]
pub struct GuiOptions {
    /// Log to open at start (default: the bundled calibration sample log when present).
    pub log: Option<PathBuf>,
    /// A calibration file to open beside the fit of the log, to compare.
    pub calibration: Option<PathBuf>,
    /// Render the loaded, calibrated workbench, save the window as PNG here, and exit (with
    /// the page named by the environment variable `DRIFTLAB_GUI_PAGE` shown, its work done
    /// first: the Models page compares the models ticked by default).
    pub screenshot: Option<PathBuf>,
    /// How to read the log (columns, units, dialect): the import view starts from these, and
    /// the log is read with them when its columns need no look. A session keeps its own.
    pub read: crate::log::ingest::ReadOptions,
    /// Average the log into bins of this many seconds once read (a session keeps its own).
    pub bin_s: Option<f64>,
    /// The gyro and temperature of a drone or robot log (`--gyro`, `--temp-from`), for the
    /// log and the validation log alike.
    pub instance: crate::log::read::InstanceChoice,
    /// A validation log to open beside the log, read as the log is.
    pub validation: Option<PathBuf>,
    /// A campaign's runs after the first (`log`), read as it is and joined after it: the
    /// workbench calibrates them as one campaign.
    pub more_runs: Vec<PathBuf>,
    /// The columns read as accelerometer axes and their unit (`--accel-col`, `--accel-unit`),
    /// for the log and the validation log alike; the default: every column named as one.
    pub accel: crate::log::accel_axes::AccelAsk,
    /// The window's inner size, points (at least 900×620).
    pub window_size: Option<[f32; 2]>,
    /// A lot to open on the Lot page: its output folder, or its `lot.json` or `lot.csv`.
    pub lot: Option<PathBuf>,
}

/// `1280x800` as points, when at least the window's smallest size and at most 16384 points
/// a side (no screen is larger).
pub fn parse_size(s: &str) -> Option<[f32; 2]> {
    let (w, h) = s.trim().split_once(['x', 'X'])?;
    let (w, h): (f32, f32) = (w.trim().parse().ok()?, h.trim().parse().ok()?);
    let fits = |v: f32, min: f32| (min..=16384.0).contains(&v);
    (fits(w, 900.0) && fits(h, 620.0)).then_some([w, h])
}

/// The files `driftlab gui FILE...` was given, told apart by what they are: a log or a
/// session (what the workbench works on), a campaign's further runs, and a calibration to open
/// beside its fit.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct StartFiles {
    /// The log or session (a `.json` that says it is one); with several logs, the first run.
    pub log: Option<PathBuf>,
    /// Logs after the first: the runs of one campaign, joined after it in the order given.
    pub more_runs: Vec<PathBuf>,
    /// The calibration (a `.json` that says it is one, or says nothing readable and is not
    /// named as a session: its loader then says where it is not a calibration).
    pub calibration: Option<PathBuf>,
}

/// Tells the files given to `driftlab gui` apart, in any order: one session or any number of
/// logs (two or more: the runs of one campaign), and at most one calibration
/// ([`crate::files::kind`] reads what a `.json` says it is).
///
/// # Errors
/// Two sessions, a session and a log, two calibrations, or more logs than a campaign joins,
/// named.
pub fn split_files(files: &[PathBuf]) -> Result<StartFiles, String> {
    use crate::files::kind::{JsonKind, json_kind, named_as_session};
    let mut out = StartFiles::default();
    let mut logs: Vec<PathBuf> = Vec::new();
    let mut session: Option<PathBuf> = None;
    for f in files {
        let json = app::is_json(f);
        let calibration = json
            && match json_kind(f) {
                JsonKind::Calibration => true,
                JsonKind::Session => false,
                JsonKind::Other(_) | JsonKind::Unknown => !named_as_session(f),
            };
        if calibration {
            if let Some(first) = out.calibration.replace(f.clone()) {
                return Err(format!(
                    "two calibrations given ({}): the workbench opens one calibration beside \
                     the fit to compare",
                    names(&[first, f.clone()])
                ));
            }
        } else if json {
            if let Some(first) = session.replace(f.clone()) {
                return Err(format!(
                    "two sessions given ({}): the workbench opens one session",
                    names(&[first, f.clone()])
                ));
            }
        } else {
            logs.push(f.clone());
        }
    }
    if let (Some(s), Some(l)) = (&session, logs.first()) {
        return Err(format!(
            "two logs or sessions given ({}): a session names its own logs; open the session, \
             then File › Add run to join a run to its campaign",
            names(&[s.clone(), l.clone()])
        ));
    }
    if logs.len() > crate::log::campaign::MAX_RUNS {
        return Err(format!(
            "{} logs given: a campaign joins at most {} runs",
            logs.len(),
            crate::log::campaign::MAX_RUNS
        ));
    }
    let mut logs = logs.into_iter();
    out.log = session.or_else(|| logs.next());
    out.more_runs = logs.collect();
    Ok(out)
}

/// File names for a message, joined.
fn names(files: &[PathBuf]) -> String {
    files
        .iter()
        .map(|f| f.display().to_string())
        .collect::<Vec<_>>()
        .join(" and ")
}

/// What `driftlab gui [LOG|SESSION] [--screenshot PNG]` opens in a new workbench: screenshot
/// mode first, when asked (so that a session or log that fails to open ends the run with its
/// message instead of an error dialog nobody will close), then the session (a `.json` file)
/// or the log, read with `read` (in screenshot mode without the import view).
pub fn start(
    wb: &mut Workbench,
    log: Option<PathBuf>,
    read: jobs::LoadOptions,
    shot: Option<(PathBuf, ScreenshotOutcome)>,
) {
    let interactive = shot.is_none();
    if let Some((path, outcome)) = shot {
        wb.screenshot_mode(path, outcome);
    }
    match log {
        // `driftlab gui run7.session.json` reopens a saved session.
        Some(p)
            if p.extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("json")) =>
        {
            wb.open_session(p)
        }
        Some(p) => wb.open_log(p, read, interactive),
        None => {}
    }
}

/// Opens the workbench window and runs until it is closed.
///
/// # Errors
/// When no window can be opened, or (screenshot mode) when the log cannot be read or
/// calibrated or the picture cannot be written.
pub fn run(options: GuiOptions) -> Result<(), String> {
    // A lot given alone opens on its page, with no sample log behind it.
    let log = match &options.lot {
        Some(_) => options.log.clone(),
        None => options.log.clone().or_else(default_log),
    };
    // DRIFTLAB_GUI_PAGE=models|allan|calibration: the page to start on (a screenshot of it).
    let page = match std::env::var("DRIFTLAB_GUI_PAGE") {
        Ok(name) if !name.trim().is_empty() => Some(Page::from_name(&name).ok_or_else(|| {
            format!("DRIFTLAB_GUI_PAGE={name}: pages are calibration, models and allan")
        })?),
        _ => None,
    };
    let shot = options.screenshot.clone();
    if shot.is_some() && log.is_none() {
        // (no log, no sample next to us: nothing to render)
        return Err(
            "a screenshot needs a log (none given, and no sample_logs/calibration.csv found)"
                .into(),
        );
    }
    for l in log
        .iter()
        .chain(&options.more_runs)
        .chain(&options.validation)
        .chain(&options.calibration)
    {
        if !l.exists() {
            return Err(format!("{}: no such file", l.display()));
        }
        if !l.is_file() {
            // A folder, a device (/dev/zero), a socket: nothing a log is read from.
            return Err(format!(
                "{}: not a file (a folder or a device)",
                l.display()
            ));
        }
    }
    let load = jobs::LoadOptions {
        read: options.read.clone(),
        bin_s: options.bin_s,
        instance: options.instance,
        more_runs: Vec::new(),
        accel: options.accel.clone(),
    };
    // Screenshot mode renders with the engineer's theme but writes no settings back.
    let settings = Settings::default_path()
        .as_deref()
        .map(Settings::load)
        .unwrap_or_default();
    let settings_path = if shot.is_some() {
        None
    } else {
        Settings::default_path()
    };

    let mut viewport = egui::ViewportBuilder::default()
        .with_title("driftlab workbench")
        .with_app_id("driftlab")
        .with_drag_and_drop(true)
        .with_min_inner_size([900.0, 620.0]);
    // DRIFTLAB_GUI_SIZE=WxH: the window's size (a screenshot at 1280x800, say).
    let size = match std::env::var("DRIFTLAB_GUI_SIZE") {
        Ok(s) if !s.trim().is_empty() => Some(parse_size(&s).ok_or_else(|| {
            format!(
                "DRIFTLAB_GUI_SIZE={s}: give the window's size as WIDTHxHEIGHT, at least 900x620"
            )
        })?),
        _ => None,
    };
    let size = options.window_size.or(size);
    viewport = match (&shot, settings.window, size) {
        (_, _, Some([w, h])) => viewport.with_inner_size([w, h]),
        (None, Some(w), None) if w.width >= 900.0 && w.height >= 620.0 => viewport
            .with_inner_size([w.width, w.height])
            .with_position([w.x, w.y])
            .with_maximized(w.maximized),
        _ => viewport.with_inner_size([1600.0, 1000.0]),
    };
    if shot.is_some() {
        viewport = viewport.with_resizable(false);
    }
    let native = eframe::NativeOptions {
        viewport,
        ..Default::default()
    };
    let outcome = ScreenshotOutcome::default();
    let slot = outcome.clone();
    let validation = options.validation.clone();
    let calibration = options.calibration.clone();
    let lot = options.lot.clone();
    let more_runs = options.more_runs.clone();
    eframe::run_native(
        "driftlab",
        native,
        Box::new(move |_cc| {
            let mut wb = Workbench::new(settings, settings_path, Box::new(SystemDialogs::detect()));
            let shot = shot.map(|s| (s, slot));
            // A campaign's further runs are read as the first; the validation log alone.
            let runs = jobs::LoadOptions {
                more_runs,
                ..load.clone()
            };
            start(&mut wb, log, runs, shot);
            if let Some(v) = validation {
                wb.open_validation_after(v, load);
            }
            if let Some(c) = calibration {
                wb.open_calibration(c);
            }
            if let Some(l) = lot {
                wb.open_lot(l);
            }
            if let Some(s) = size {
                wb.ask_window_size(s);
            }
            if let Some(p) = page {
                wb.set_page(p);
            }
            // DRIFTLAB_GUI_MODEL=NAME: the model the Models page shows the details of.
            if let Ok(name) = std::env::var("DRIFTLAB_GUI_MODEL")
                && !name.trim().is_empty()
            {
                wb.models_view().selected = Some(name.trim().to_string());
            }
            Ok(Box::new(wb))
        }),
    )
    .map_err(|e| format!("cannot open the workbench window: {e}"))?;
    if options.screenshot.is_some() {
        return outcome
            .take()
            .unwrap_or_else(|| Err("the window closed before the screenshot was taken".into()));
    }
    Ok(())
}
