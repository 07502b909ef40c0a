//! What the engineer can ask of the workbench, and the pages it shows: the words the views
//! speak to the window. This module sits below every view (it names only engine types), so a
//! view never imports the window: it returns these, and the window carries them out at the end
//! of the frame.

use super::jobs::{LoadOptions, Target};
use super::settings::ThemeChoice;
use crate::files::session::Coefficient;
use crate::models::approx::ApproxSpec;
use crate::models::recipe::Recipe;
use crate::signal::plateau::PlateauRange;
use eframe::egui::{Key, KeyboardShortcut, Modifiers, Rect};
use std::path::PathBuf;

/// One of the logs open in the workbench.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum OpenLog {
    /// The log the calibration is fitted on.
    Calibration,
    /// The held-out log it is judged on.
    Validation,
}

/// Something the engineer asked for, from a menu, a shortcut, a button or a view.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    /// Pick a log to open (import view next).
    OpenLog,
    /// Open this log (import view next).
    OpenLogPath(PathBuf),
    /// Open these logs as the runs of one campaign, in this order (import view next, for the
    /// first: the others are read as it is).
    OpenRunPaths(Vec<PathBuf>),
    /// Pick a log to add to the open log as another run of its campaign.
    AddRun,
    /// Add this log to the open log as another run of its campaign (read as the first run).
    AddRunPath(PathBuf),
    /// Show run `k` of a campaign on the time plots (its span), or every run (`None`).
    ShowRun(Option<usize>),
    /// Read this log with these options into this slot (the import view's Load).
    ReadLog(PathBuf, LoadOptions, Target),
    /// Close the import view without reading.
    CloseImport,
    /// Pick a validation log.
    OpenValidation,
    /// Forget the validation log.
    CloseValidation,
    /// Pick a calibration file to open beside the current fit.
    OpenCalibration,
    /// Open this calibration file beside the current fit.
    OpenCalibrationPath(PathBuf),
    /// Put the opened calibration away.
    CloseCalibration,
    /// Judge axis `.1` (its index) of the opened calibration on this axis of log `.0` (`None`:
    /// on none), where the files do not say which it corrects.
    ChooseOpenedAxis(OpenLog, usize, Option<String>),
    /// Pick a lot to open (its output folder's `lot.json` or `lot.csv`).
    OpenLot,
    /// Open the lot at this path (its output folder, or either table), on the Lot page.
    OpenLotPath(PathBuf),
    /// Open unit `.0` (its row in the lot's order) on the Calibration page: its log(s), and
    /// its calibration beside the fit.
    OpenLotUnit(usize),
    /// Put the lot away.
    CloseLot,
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
    /// Write the calibration as a flight controller's parameter file (PX4, ArduPilot).
    ExportFlight(crate::export::firmware::Format),
    /// Write the corrected log of the calibration or the validation log (`None`: the one
    /// the drift plot shows).
    ExportCsv(Option<OpenLog>),
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
    /// Change a choice (the recipe, a plateau, a knot): undo, the unsaved mark and the refit
    /// follow from it.
    Edit(Edit),
    /// Select a plateau (highlighted on the time plots and in the table), or none.
    SelectPlateau(Option<usize>),
    /// Add this plateau by hand and select it.
    AddPlateau(PlateauRange),
    /// Show the result on the validation log (true) or on the calibration log.
    ShowValidation(bool),
    /// Tell the engineer why what they asked was not done (a range typed backwards).
    Warn(String),
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
    /// Show this gyro axis of a unit (its index in the log's order).
    SelectAxis(usize),
    /// Show the next (true) or the previous gyro axis of a unit.
    StepAxis(bool),
    /// Show this accelerometer axis of a unit (its index among them) on the Calibration page.
    SelectAccel(usize),
    /// Calibrate the unit's accelerometer axes (true) or leave them out (false).
    AccelOn(bool),
    /// Reopen the import view on the loaded log (or the validation log) to change its
    /// column mapping, units or format.
    ColumnMapping(Target),
}

/// A change of the engineer's choices, as a view asks for it.
#[derive(Debug, Clone, PartialEq)]
pub enum Edit {
    /// The recipe as the Calibration page's controls left it (filters, step H, dead-bands,
    /// gyro id, weighting, refinements).
    Recipe(Box<Recipe>),
    /// A coefficient's approximation (kind, knot count, extrapolation, the knots placed and set
    /// by hand, as the engine's knot edits make them); hand-set lists that no longer fit it
    /// are forgotten ([`ApproxSpec::consistent`]).
    Approx(Coefficient, ApproxSpec),
    /// A coefficient's knot values set by hand (`None`: the fitted ones again), its positions
    /// kept.
    Knots(Coefficient, Option<Vec<f64>>),
    /// The plateaus, set by hand (sorted; empty and reversed ones dropped).
    Plateaus(Vec<PlateauRange>),
    /// The plateaus while a drag lasts: unsorted, so that the one being edited keeps its
    /// place.
    PlateausDragged(Vec<PlateauRange>),
    /// The plateaus back to the detector.
    AutoPlateaus,
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
    /// A lot of units: the table, and each figure's distribution.
    Lot,
}

impl Page {
    /// Every page, in tab order.
    pub const ALL: [Page; 4] = [Page::Calibration, Page::Models, Page::Allan, Page::Lot];

    /// The tab's title.
    pub fn title(self) -> &'static str {
        match self {
            Page::Calibration => "Calibration",
            Page::Models => "Models",
            Page::Allan => "Allan deviation",
            Page::Lot => "Lot",
        }
    }

    /// The page named `name` (`calibration`, `models`, `allan`), for the command line and
    /// the environment.
    pub fn from_name(name: &str) -> Option<Page> {
        match name.trim().to_ascii_lowercase().as_str() {
            "calibration" | "main" => Some(Page::Calibration),
            "models" => Some(Page::Models),
            "allan" => Some(Page::Allan),
            "lot" => Some(Page::Lot),
            _ => None,
        }
    }

    /// The shortcut that shows the page.
    pub fn shortcut(self) -> KeyboardShortcut {
        match self {
            Page::Calibration => shortcuts::PAGE1,
            Page::Models => shortcuts::PAGE2,
            Page::Allan => shortcuts::PAGE3,
            Page::Lot => shortcuts::PAGE4,
        }
    }

    /// What the page holds, for its tab's tooltip.
    pub fn tip(self) -> &'static str {
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
            Page::Lot => {
                "A lot of units (File › Open lot): each figure's distribution, the table of \
                 units sorted by any column; a click opens a unit"
            }
        }
    }
}

/// The keyboard shortcuts of the menus (the menus show them, the window listens for them).
pub mod shortcuts {
    use super::{Key, KeyboardShortcut, Modifiers};

    /// Open a log.
    pub const OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
    /// Open a calibration beside the current fit.
    pub const OPEN_CALIBRATION: KeyboardShortcut =
        KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::ALT), Key::O);
    /// Open a session.
    pub const OPEN_SESSION: KeyboardShortcut =
        KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::O);
    /// Save the session.
    pub const SAVE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
    /// Save the window as PNG.
    pub const SHOT: KeyboardShortcut =
        KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::S);
    /// Save the window as PNG (the other key).
    pub const SHOT_F12: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F12);
    /// Export the calibration.
    pub const EXPORT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::E);
    /// Export the corrected log.
    pub const EXPORT_CSV: KeyboardShortcut =
        KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::E);
    /// Undo.
    pub const UNDO: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Z);
    /// Redo.
    pub const REDO: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Y);
    /// Redo (the other keys).
    pub const REDO2: KeyboardShortcut =
        KeyboardShortcut::new(Modifiers::COMMAND.plus(Modifiers::SHIFT), Key::Z);
    /// Quit.
    pub const QUIT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Q);
    /// The Calibration page.
    pub const PAGE1: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Num1);
    /// The Models page.
    pub const PAGE2: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Num2);
    /// The Allan page.
    pub const PAGE3: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Num3);
    /// The Lot page.
    pub const PAGE4: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::Num4);
    /// Compare the models ticked (Models page).
    pub const COMPARE: KeyboardShortcut = KeyboardShortcut::new(Modifiers::NONE, Key::F5);
    /// The previous gyro axis of a unit.
    pub const AXIS_PREV: KeyboardShortcut =
        KeyboardShortcut::new(Modifiers::NONE, Key::OpenBracket);
    /// The next gyro axis of a unit.
    pub const AXIS_NEXT: KeyboardShortcut =
        KeyboardShortcut::new(Modifiers::NONE, Key::CloseBracket);

    /// Gyro axis `k` (0-based) of a unit: Alt+1 … Alt+9.
    pub fn axis(k: usize) -> Option<KeyboardShortcut> {
        const KEYS: [Key; 9] = [
            Key::Num1,
            Key::Num2,
            Key::Num3,
            Key::Num4,
            Key::Num5,
            Key::Num6,
            Key::Num7,
            Key::Num8,
            Key::Num9,
        ];
        KEYS.get(k)
            .map(|&key| KeyboardShortcut::new(Modifiers::ALT, key))
    }
}
