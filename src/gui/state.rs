//! The workbench's application data, in one plain struct: the logs, every choice (the recipe,
//! the knots placed and set by hand among them), the newest fit result, the undo history and
//! what was last saved.
//! Views read it and change the choices; the app turns changed choices into refit requests.

use super::action::Edit;
use super::jobs::{AllanView, Compared, FitView, Loaded, PreviewView};
use crate::files::session::{AxisChoices, KnotEdits, LogRef, Session, ViewState};
use crate::judge::metrics::MeritOptions;
use crate::models::approx::ApproxSpec;
use crate::models::recipe::{PlateauChoice, Recipe};
use crate::refit::Request;
use crate::signal::plateau::{PlateauRange, PlateauStats};
use std::path::PathBuf;
use std::sync::Arc;

mod accel;
mod unit_files;
pub use accel::AccelAxes;

/// Everything the engineer chose: what undo and redo step through.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Choices {
    /// The recipe, with the knots placed and set by hand.
    pub recipe: Recipe,
}

/// Undo and redo of choices. Changes are committed once they settle (no mouse button held),
/// so a drag is one step however many frames it lasts.
#[derive(Debug, Default)]
pub struct History {
    undo: Vec<Choices>,
    redo: Vec<Choices>,
    committed: Choices,
}

const HISTORY_DEPTH: usize = 200;

impl History {
    /// Starts afresh from `current`.
    pub fn reset(&mut self, current: &Choices) {
        *self = History {
            committed: current.clone(),
            ..History::default()
        };
    }

    /// Commits `current` as a step when it differs from the last commit and has settled.
    pub fn observe(&mut self, current: &Choices, settled: bool) {
        if settled && *current != self.committed {
            self.undo
                .push(std::mem::replace(&mut self.committed, current.clone()));
            if self.undo.len() > HISTORY_DEPTH {
                self.undo.remove(0);
            }
            self.redo.clear();
        }
    }

    /// Steps back; false when there is nothing to undo.
    pub fn undo(&mut self, current: &mut Choices) -> bool {
        self.observe(&current.clone(), true);
        match self.undo.pop() {
            Some(prev) => {
                self.redo
                    .push(std::mem::replace(&mut self.committed, prev.clone()));
                *current = prev;
                true
            }
            None => false,
        }
    }

    /// Steps forward again; false when there is nothing to redo.
    pub fn redo(&mut self, current: &mut Choices) -> bool {
        match self.redo.pop() {
            Some(next) => {
                self.undo
                    .push(std::mem::replace(&mut self.committed, next.clone()));
                *current = next;
                true
            }
            None => false,
        }
    }

    /// Whether undo has a step.
    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    /// Whether redo has a step.
    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }
}

/// Plateaus as the table keeps them: sorted by start, empty and reversed ranges dropped.
pub fn sorted_ranges(mut ranges: Vec<PlateauRange>) -> Vec<PlateauRange> {
    ranges.retain(|r| r.start_s.is_finite() && r.end_s.is_finite() && r.end_s > r.start_s);
    ranges.sort_by(|a, b| a.start_s.total_cmp(&b.start_s));
    ranges
}

/// How serious a status message is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Severity {
    /// Something done.
    Info,
    /// Something the engineer should look at.
    Warning,
    /// Something that failed.
    Error,
}

/// The application data.
#[derive(Default)]
pub struct AppState {
    /// The axis shown: its logs, choices, fit and pages' results (the one axis of a log of
    /// one; for a unit, the others are parked in [`Unit::parked`]).
    pub shown: AxisLive,
    /// The session as last opened or saved, to tell unsaved work.
    pub baseline: Option<Session>,
    /// Where the session was last saved or opened from.
    pub session_path: Option<PathBuf>,
    /// The last status message.
    pub status: Option<(Severity, String)>,
    /// The choices a status message was about, when it holds only for them.
    pub status_choices: Option<Choices>,
    /// What was on screen (kept in sessions).
    pub view: ViewState,
    /// The windows of the figures of merit, s, as the session opened gives them (`None`:
    /// 10 minutes); the filter is always the recipe's.
    pub merit_window_s: Option<f64>,
    /// The gyro axes of a log of several (none for a log of one axis): the fields above
    /// hold the axis shown, the others wait here.
    pub unit: Option<Unit>,
    /// The validation log as read, every axis (each axis above holds its own view of it):
    /// an opened calibration may be judged on any of them.
    pub validation_file: Option<Loaded>,
    /// Why the calibration log's sketch cannot tell whether the validation log is the
    /// calibration log (its figures are then marked: they may not be held out).
    pub validation_doubt: Option<String>,
    /// A calibration opened beside the current fit, to compare ([`super::opened`]).
    pub opened: Option<super::opened::Opened>,
    /// A lot opened on the Lot page ([`crate::lot::open`]).
    pub lot: Option<crate::lot::open::LotTable>,
    /// The accelerometer axes of the calibration log, when it has accelerometer columns and
    /// several gyro axes (a unit).
    pub accel: Option<AccelAxes>,
    /// The accelerometer axes left out of the unit (turned off in the axis strip; kept in
    /// sessions). They are in it by default: an engineer who logged them wants them
    /// calibrated, and a log without them is not changed by it.
    pub accel_off: bool,
}

/// What the workbench holds for one gyro axis: its view of the logs, its choices, its fit
/// and the pages' results. The axis shown is [`AppState::shown`] (so that every view reads one
/// axis of a unit as it reads a log of one); the others are parked in [`Unit::parked`].
#[derive(Default)]
pub struct AxisLive {
    /// The calibration log's view of this axis.
    pub log: Option<Loaded>,
    /// The validation log's view of the axis of the same name, when it has one.
    pub validation: Option<Loaded>,
    /// The axis's choices.
    pub choices: Choices,
    /// Its newest fit.
    pub fit: Option<Arc<FitView>>,
    /// Why its newest refit failed.
    pub fit_error: Option<String>,
    /// The plateaus and K0 of a plateau edge drag, newer than `fit` (until the refit that
    /// follows the release arrives).
    pub preview: Option<Arc<PreviewView>>,
    /// Its undo and redo.
    pub history: History,
    /// Its comparison of models.
    pub models: Option<Arc<Compared>>,
    /// Why its comparison failed.
    pub models_error: Option<String>,
    /// Its Allan deviations.
    pub allan: Option<Arc<AllanView>>,
}

/// The gyro axes of a log of several. They share T, and so what a calibration takes from
/// it: how T is smoothed and differentiated and the plateaus ([`share_temperature`]); the
/// rest of the choices is each axis's own.
#[derive(Default)]
pub struct Unit {
    /// The axes' names, in the log's order.
    pub names: Vec<String>,
    /// The axis shown.
    pub active: usize,
    /// Every axis's state but the shown one's (`parked[active]` is empty: its state is
    /// [`AppState::shown`]).
    pub parked: Vec<AxisLive>,
    /// The calibration log with every axis (the corrected CSV of the unit reads it).
    pub full_log: Option<Arc<crate::log::Log>>,
}

/// Gives `to` the settings every axis of a unit takes from T (smoothing, step H, plateaus)
/// as `from` has them; true when anything changed.
pub fn share_temperature(from: &Recipe, to: &mut Recipe) -> bool {
    if crate::models::unit::differing_temperature_setting(from, to).is_none() {
        return false;
    }
    to.temp_smoothing_s = from.temp_smoothing_s;
    to.step_h_s = from.step_h_s;
    to.plateaus = from.plateaus.clone();
    true
}

/// What an axis of the unit holds, read whichever axis is shown.
pub struct AxisRef<'a> {
    /// The axis's name.
    pub name: &'a str,
    /// The calibration log's view of it.
    pub log: Option<&'a Loaded>,
    /// The validation log's view of it.
    pub validation: Option<&'a Loaded>,
    /// Its choices.
    pub choices: &'a Choices,
    /// Its newest fit.
    pub fit: Option<&'a Arc<FitView>>,
    /// Why its newest refit failed.
    pub fit_error: Option<&'a String>,
    /// The windows of its figures of merit, s (`None`: 10 minutes).
    pub window_s: Option<f64>,
}

impl AxisRef<'_> {
    /// The refit request of the axis's choices.
    pub fn request(&self) -> Option<Request> {
        request(self.log, self.validation, self.choices, self.window_s)
    }

    /// Whether its fit answers its choices and logs exactly.
    pub fn fit_current(&self) -> bool {
        fit_current(self.fit, self.log, self.validation, self.choices)
    }
}

fn merit_of(choices: &Choices, window_s: Option<f64>) -> MeritOptions {
    let d = MeritOptions::default();
    MeritOptions {
        filter_s: choices.recipe.filter_s,
        window_s: window_s.unwrap_or(d.window_s),
    }
}

fn request(
    log: Option<&Loaded>,
    validation: Option<&Loaded>,
    choices: &Choices,
    window_s: Option<f64>,
) -> Option<Request> {
    let log = log?;
    Some(Request {
        log: log.log.clone(),
        recipe: choices.recipe.clone(),
        merit: merit_of(choices, window_s),
        validation: validation.map(|v| v.log.clone()),
    })
}

fn fit_current(
    fit: Option<&Arc<FitView>>,
    log: Option<&Loaded>,
    validation: Option<&Loaded>,
    choices: &Choices,
) -> bool {
    fit.is_some_and(|f| {
        let same_log = log.is_some_and(|l| Arc::ptr_eq(&l.log, &f.outcome.in_sample.log));
        let same_validation = match (validation, &f.outcome.held_out) {
            (Some(v), Some(h)) => Arc::ptr_eq(&v.log, &h.log),
            (None, None) => true,
            _ => false,
        };
        same_log && same_validation && f.outcome.calibration.recipe == choices.recipe
    })
}

/// Why validation log `log` holds none of the calibration log's axes `missing` (each its name
/// and the rate column it was read from), `subject` naming the log: "it has no axis gq (its
/// axes: gx, gy, gz)" for a unit's axes, "it has 3 gyro axes (…) and none is the calibrated
/// axis omega (column omega_dph)" for the one axis of a log of one.
pub fn unmatched_validation(
    log: &crate::log::Log,
    unit: bool,
    missing: &[(&str, &str)],
    subject: &str,
) -> String {
    let axes = log.axis_names();
    if unit {
        let names: Vec<&str> = missing.iter().map(|(n, _)| *n).collect();
        return format!(
            "{subject} has no axis {} (its axes: {})",
            names.join(", "),
            axes.join(", ")
        );
    }
    let (axis, column) = missing.first().copied().unwrap_or_default();
    format!(
        "{subject} has {} gyro axes ({}) and none is the calibrated axis {axis}{}",
        axes.len(),
        axes.join(", "),
        if column.is_empty() || column == axis {
            String::new()
        } else {
            format!(" (column {column})")
        }
    )
}

impl AppState {
    /// Why the axis shown is judged on no view of the validation log open (it matches none
    /// of its axes), in words for where its held-out figures would be; `None` when it is
    /// judged there or no validation log is open.
    pub fn validation_unmatched(&self) -> Option<String> {
        let file = self.validation_file.as_ref()?;
        let log = self.shown.log.as_ref()?;
        if self.shown.validation.is_some() {
            return None;
        }
        let unit = self.unit.is_some();
        let name = self
            .active_axis_name()
            .map_or_else(|| log.log.axis.clone(), str::to_string);
        let column = log.log.rate_column().unwrap_or_default();
        Some(unmatched_validation(
            &file.log,
            unit,
            &[(&name, &column)],
            &super::widgets::file_name(&file.path),
        ))
    }

    /// Shows a status message.
    pub fn say(&mut self, severity: Severity, message: impl Into<String>) {
        self.status = Some((severity, message.into()));
        self.status_choices = None;
    }

    /// The recipe.
    pub fn recipe(&self) -> &Recipe {
        &self.shown.choices.recipe
    }

    /// The recipe, to change it.
    pub fn recipe_mut(&mut self) -> &mut Recipe {
        &mut self.shown.choices.recipe
    }

    /// The plateau ranges in effect: the recipe's own, or those the detector found in the
    /// newest fit.
    pub fn ranges(&self) -> Vec<PlateauRange> {
        match &self.shown.choices.recipe.plateaus {
            PlateauChoice::Manual { ranges } => ranges.clone(),
            PlateauChoice::Auto(_) => self
                .shown
                .fit
                .as_ref()
                .map(|f| f.outcome.ranges.clone())
                .unwrap_or_default(),
        }
    }

    /// The plateaus' statistics shown: a drag's preview while it is newer than the fit.
    pub fn plateau_stats(&self) -> Vec<PlateauStats> {
        match (&self.shown.preview, &self.shown.fit) {
            (Some(p), _) => p.preview.plateaus.clone(),
            (None, Some(f)) => f.outcome.calibration.plateaus.clone(),
            (None, None) => Vec::new(),
        }
    }

    /// True while the plateaus come from the detector.
    pub fn plateaus_auto(&self) -> bool {
        matches!(self.shown.choices.recipe.plateaus, PlateauChoice::Auto(_))
    }

    /// Sets the plateaus by hand (sorted by start; empty and reversed ranges dropped).
    pub fn set_ranges(&mut self, ranges: Vec<PlateauRange>) {
        self.shown.choices.recipe.plateaus = PlateauChoice::Manual {
            ranges: sorted_ranges(ranges),
        };
    }

    /// Makes the change a view asked for.
    pub fn apply(&mut self, edit: Edit) {
        let choices = &mut self.shown.choices;
        match edit {
            Edit::Recipe(recipe) => choices.recipe = *recipe,
            Edit::Approx(c, spec) => *c.spec_mut(&mut choices.recipe) = spec.consistent(),
            Edit::Knots(c, values) => {
                let spec = c.spec_mut(&mut choices.recipe);
                *spec = ApproxSpec {
                    values,
                    ..spec.clone()
                }
                .consistent();
            }
            Edit::Plateaus(ranges) => self.set_ranges(ranges),
            Edit::PlateausDragged(ranges) => {
                choices.recipe.plateaus = PlateauChoice::Manual { ranges };
            }
            Edit::AutoPlateaus => choices.recipe.plateaus = PlateauChoice::default(),
        }
    }

    /// The refit request for the current choices, when a log is loaded.
    pub fn request(&self) -> Option<Request> {
        request(
            self.shown.log.as_ref(),
            self.shown.validation.as_ref(),
            &self.shown.choices,
            self.merit_window_s,
        )
    }

    /// How the figures of merit are computed: the recipe's filter, 10-minute windows.
    pub fn merit(&self) -> MeritOptions {
        merit_of(&self.shown.choices, self.merit_window_s)
    }

    /// The session as it stands.
    pub fn session(&self) -> Session {
        let log_ref = |l: &Option<Loaded>| {
            l.as_ref().map(|l| LogRef {
                path: std::path::absolute(&l.path).unwrap_or_else(|_| l.path.clone()),
                read: l.options.read.clone(),
                bin_s: l.options.bin_s,
                instance: l.options.instance,
                more_runs: l
                    .options
                    .more_runs
                    .iter()
                    .map(|p| std::path::absolute(p).unwrap_or_else(|_| p.clone()))
                    .collect(),
                accelerometers: l.options.accel.clone(),
            })
        };
        let mut session = Session {
            log: log_ref(&self.shown.log),
            validation: log_ref(&self.shown.validation),
            recipe: self.shown.choices.recipe.clone(),
            knots: KnotEdits::default(),
            merit: self.merit(),
            view: self.view.clone(),
            axes: Vec::new(),
            accelerometers_off: self.accel_off && self.accel.is_some(),
        };
        if let Some(u) = &self.unit {
            // A unit: every axis's own choices, the first axis's at the top as well.
            session.axes = (0..u.names.len())
                .filter_map(|k| self.axis(k))
                .map(|a| AxisChoices {
                    name: a.name.to_string(),
                    recipe: a.choices.recipe.clone(),
                    knots: KnotEdits::default(),
                })
                .collect();
            if let Some(first) = session.axes.first() {
                session.recipe = first.recipe.clone();
                session.merit = merit_of(
                    &Choices {
                        recipe: first.recipe.clone(),
                    },
                    self.merit_window_s,
                );
            }
            if session.validation.is_none() {
                // The shown axis may have no match in the validation log; another may.
                session.validation = u.parked.iter().find_map(|p| log_ref(&p.validation));
            }
            session.view.axis = self.active_axis_name().map(str::to_string);
        }
        session
    }

    /// True when there are choices that are not saved in a session. What is on screen and
    /// the validation log are not: a validation log is a file on disk, opened (or closed) to
    /// look at the calibration, not work that could be lost (a session saved keeps it).
    pub fn dirty(&self) -> bool {
        if self.shown.log.is_none() {
            return false;
        }
        let strip = |s: Session| Session {
            view: ViewState::default(),
            validation: None,
            ..s
        };
        match &self.baseline {
            Some(b) => strip(b.clone()) != strip(self.session()),
            None => true,
        }
    }

    /// Marks the current state as saved (or freshly opened).
    pub fn mark_saved(&mut self) {
        self.baseline = Some(self.session());
    }

    /// Marks the current state as not saved anywhere (work recovered from an autosave).
    pub fn mark_unsaved(&mut self) {
        self.baseline = None;
    }

    /// Whether the fit shown answers the current choices and logs exactly (else a refit is on
    /// its way and what is shown is provisional).
    pub fn fit_current(&self) -> bool {
        fit_current(
            self.shown.fit.as_ref(),
            self.shown.log.as_ref(),
            self.shown.validation.as_ref(),
            &self.shown.choices,
        )
    }

    /// Whether every axis's fit answers its choices (the one axis of a log of one).
    pub fn all_current(&self) -> bool {
        (0..self.axis_count()).all(|k| self.axis(k).is_some_and(|a| a.fit_current()))
            && self.accel_current()
    }

    /// The number of gyro axes calibrated (1 for a log of one axis).
    pub fn axis_count(&self) -> usize {
        self.unit.as_ref().map_or(1, |u| u.names.len())
    }

    /// The axis shown (0 for a log of one axis).
    pub fn active_axis(&self) -> usize {
        self.unit.as_ref().map_or(0, |u| u.active)
    }

    /// The name of the axis shown, for a unit of several axes.
    pub fn active_axis_name(&self) -> Option<&str> {
        self.unit
            .as_ref()
            .and_then(|u| u.names.get(u.active))
            .map(String::as_str)
    }

    /// What axis `k` holds (`None` past the last axis). For a log of one axis, axis 0 is
    /// the log's own.
    pub fn axis(&self, k: usize) -> Option<AxisRef<'_>> {
        let shown = AxisRef {
            name: self.active_axis_name().unwrap_or_default(),
            log: self.shown.log.as_ref(),
            validation: self.shown.validation.as_ref(),
            choices: &self.shown.choices,
            fit: self.shown.fit.as_ref(),
            fit_error: self.shown.fit_error.as_ref(),
            window_s: self.merit_window_s,
        };
        match &self.unit {
            None => (k == 0).then_some(shown),
            Some(u) if k == u.active => Some(shown),
            Some(u) => {
                let p = u.parked.get(k)?;
                Some(AxisRef {
                    name: &u.names[k],
                    log: p.log.as_ref(),
                    validation: p.validation.as_ref(),
                    choices: &p.choices,
                    fit: p.fit.as_ref(),
                    fit_error: p.fit_error.as_ref(),
                    window_s: self.merit_window_s,
                })
            }
        }
    }

    /// Shows axis `k` of the unit: its state comes out of [`Unit::parked`], the shown axis's
    /// goes in. Nothing is refitted (each axis keeps its fit). False when there is no such
    /// axis.
    pub fn switch_axis(&mut self, k: usize) -> bool {
        let Some(mut unit) = self.unit.take() else {
            return k == 0;
        };
        let ok = k < unit.parked.len();
        if ok && k != unit.active {
            let next = std::mem::take(&mut unit.parked[k]);
            unit.parked[unit.active] = std::mem::replace(&mut self.shown, next);
            unit.active = k;
        }
        self.unit = Some(unit);
        ok
    }

    /// Gives every other axis of the unit the T settings of the shown axis (they share T);
    /// called after each change of choices.
    pub fn share_temperature(&mut self) {
        let Some(u) = &mut self.unit else {
            return;
        };
        for (k, p) in u.parked.iter_mut().enumerate() {
            if k != u.active {
                share_temperature(&self.shown.choices.recipe, &mut p.choices.recipe);
            }
        }
    }

    /// Shows a status message that holds only for the choices as they are: it is cleared once
    /// they change (the detector's suggestion, after the plateaus are edited by hand).
    pub fn say_about_choices(&mut self, severity: Severity, message: impl Into<String>) {
        self.say(severity, message);
        self.status_choices = Some(self.shown.choices.clone());
    }

    /// Clears a status message said about choices that have changed since.
    pub fn forget_stale_status(&mut self) {
        if self
            .status_choices
            .as_ref()
            .is_some_and(|c| *c != self.shown.choices)
        {
            self.status = None;
            self.status_choices = None;
        }
    }
}
