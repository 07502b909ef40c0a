//! The workbench's application data, in one plain struct: the logs, every choice (the recipe
//! and knots moved by hand), the newest fit result, the undo history and what was last saved.
//! Views read it and change the choices; the app turns changed choices into refit requests.

use super::jobs::{AllanView, Compared, FitView, Loaded};
use crate::files::session::{KnotEdits, LogRef, Session, ViewState};
use crate::judge::metrics::MeritOptions;
use crate::live::Request;
use crate::models::recipe::{PlateauChoice, Recipe};
use crate::signal::plateau::PlateauRange;
use std::path::PathBuf;
use std::sync::Arc;

/// Everything the engineer chose: what undo and redo step through.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Choices {
    /// The recipe.
    pub recipe: Recipe,
    /// Knots moved by hand.
    pub knots: KnotEdits,
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
    /// The calibration log.
    pub log: Option<Loaded>,
    /// The held-out validation log.
    pub validation: Option<Loaded>,
    /// Every choice.
    pub choices: Choices,
    /// The newest fit result (may lag the choices by a refit).
    pub fit: Option<Arc<FitView>>,
    /// Why the newest refit failed, if it did.
    pub fit_error: Option<String>,
    /// Undo and redo.
    pub history: History,
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
    /// The newest comparison of models (Models view).
    pub models: Option<Arc<Compared>>,
    /// Why the newest comparison failed, if it did.
    pub models_error: Option<String>,
    /// The newest Allan deviations (Allan view).
    pub allan: Option<Arc<AllanView>>,
}

impl AppState {
    /// Shows a status message.
    pub fn say(&mut self, severity: Severity, message: impl Into<String>) {
        self.status = Some((severity, message.into()));
        self.status_choices = None;
    }

    /// The recipe.
    pub fn recipe(&self) -> &Recipe {
        &self.choices.recipe
    }

    /// The recipe, to change it.
    pub fn recipe_mut(&mut self) -> &mut Recipe {
        &mut self.choices.recipe
    }

    /// The plateau ranges in effect: the recipe's own, or those the detector found in the
    /// newest fit.
    pub fn ranges(&self) -> Vec<PlateauRange> {
        match &self.choices.recipe.plateaus {
            PlateauChoice::Manual { ranges } => ranges.clone(),
            PlateauChoice::Auto(_) => self
                .fit
                .as_ref()
                .map(|f| f.outcome.ranges.clone())
                .unwrap_or_default(),
        }
    }

    /// True while the plateaus come from the detector.
    pub fn plateaus_auto(&self) -> bool {
        matches!(self.choices.recipe.plateaus, PlateauChoice::Auto(_))
    }

    /// Sets the plateaus by hand (sorted by start; empty and reversed ranges dropped).
    pub fn set_ranges(&mut self, mut ranges: Vec<PlateauRange>) {
        ranges.retain(|r| r.start_s.is_finite() && r.end_s.is_finite() && r.end_s > r.start_s);
        ranges.sort_by(|a, b| a.start_s.total_cmp(&b.start_s));
        self.choices.recipe.plateaus = PlateauChoice::Manual { ranges };
    }

    /// The refit request for the current choices, when a log is loaded.
    pub fn request(&self) -> Option<Request> {
        let log = self.log.as_ref()?;
        Some(Request {
            log: log.log.clone(),
            recipe: self.choices.recipe.clone(),
            knots: self.choices.knots.clone(),
            merit: self.merit(),
            validation: self.validation.as_ref().map(|v| v.log.clone()),
        })
    }

    /// How the figures of merit are computed: the recipe's filter, 10-minute windows.
    pub fn merit(&self) -> MeritOptions {
        MeritOptions {
            filter_s: self.choices.recipe.filter_s,
            ..MeritOptions::default()
        }
    }

    /// The session as it stands.
    pub fn session(&self) -> Session {
        let log_ref = |l: &Option<Loaded>| {
            l.as_ref().map(|l| LogRef {
                path: std::path::absolute(&l.path).unwrap_or_else(|_| l.path.clone()),
                read: l.read.clone(),
            })
        };
        Session {
            log: log_ref(&self.log),
            validation: log_ref(&self.validation),
            recipe: self.choices.recipe.clone(),
            knots: self.choices.knots.clone(),
            merit: self.merit(),
            view: self.view.clone(),
        }
    }

    /// True when there are choices that are not saved in a session.
    pub fn dirty(&self) -> bool {
        if self.log.is_none() {
            return false;
        }
        let strip = |s: Session| Session {
            view: ViewState::default(),
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
        self.fit.as_ref().is_some_and(|f| {
            let same_log = self
                .log
                .as_ref()
                .is_some_and(|l| Arc::ptr_eq(&l.log, &f.outcome.in_sample.log));
            let same_validation = match (&self.validation, &f.outcome.held_out) {
                (Some(v), Some(h)) => Arc::ptr_eq(&v.log, &h.log),
                (None, None) => true,
                _ => false,
            };
            same_log
                && same_validation
                && f.outcome.calibration.recipe == self.choices.recipe
                && f.knots == self.choices.knots
        })
    }

    /// Shows a status message that holds only for the choices as they are: it is cleared once
    /// they change (the detector's suggestion, after the plateaus are edited by hand).
    pub fn say_about_choices(&mut self, severity: Severity, message: impl Into<String>) {
        self.say(severity, message);
        self.status_choices = Some(self.choices.clone());
    }

    /// Clears a status message said about choices that have changed since.
    pub fn forget_stale_status(&mut self) {
        if self
            .status_choices
            .as_ref()
            .is_some_and(|c| *c != self.choices)
        {
            self.status = None;
            self.status_choices = None;
        }
    }
}
