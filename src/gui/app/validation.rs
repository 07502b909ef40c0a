//! The validation log beside the calibration log: the view of it each axis is judged on, found
//! by the engine's rule for where a calibration's axis is in a log ([`Log::matching_axis`]:
//! the axis of the same name, or of the rate column it was read from, as `driftlab evaluate`
//! finds a unit's axes through `judge::verify::find_axes`), never by place. Matched when the
//! validation log is read and again when another calibration log is: a validation log that
//! matches none of the new log's axes (or is that log itself) is put away, one that matches
//! some is kept for those, and the status line says which.
//!
//! [`Log::matching_axis`]: crate::log::Log::matching_axis

use super::*;
use crate::gui::state::unmatched_validation;

/// How a validation log matches the calibration log's axes.
struct Matching {
    /// The view each axis (in the unit's order; one for a log of one axis) is judged on.
    views: Vec<Option<Loaded>>,
    /// The axes without one, in words (`it has no axis gq (its axes: gx, gy, gz)`).
    missing: Option<String>,
}

/// The view of validation log `l` that the calibration log's axis `name` (read from its rate
/// column `column`) is judged on: a log of one axis when the calibration log has one too (a
/// calibration of one unnamed axis, as the engine judges it); else the log's axis of that
/// name or rate column (`None` when it has none).
fn view_for(l: &Loaded, unit: bool, name: &str, column: &str) -> Option<Loaded> {
    if !unit && l.axis_views.is_empty() {
        return Some(l.clone());
    }
    let axis = l.log.matching_axis(name, column)?;
    if l.axis_views.is_empty() {
        Some(l.clone())
    } else {
        l.axis_view(&axis).cloned()
    }
}

/// What the calibration log's sketch tells of a validation log.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Provenance {
    /// The calibration log itself (its file, or most of its samples under other bytes):
    /// figures judged on it would not be held out.
    Own,
    /// The sketch cannot tell, and why (too few of its values compared, a column written
    /// coarser than the calibration log's).
    CannotTell(String),
    /// Another run.
    Other,
}

impl Provenance {
    /// Why the sketch cannot tell, when it cannot: what the figures panel marks.
    fn doubt(self) -> Option<String> {
        match self {
            Provenance::CannotTell(why) => Some(why),
            _ => None,
        }
    }
}

impl Workbench {
    /// Whether validation log `l` is the calibration log shown, by the calibration log's
    /// sketch (as `driftlab compare` and `evaluate` tell it: the sketch is of the calibration
    /// log, the log judged is measured against it), on the view of `l` the shown axis is
    /// judged on.
    pub(super) fn provenance(&self, l: &Loaded) -> Provenance {
        let Some(c) = self.state.shown.log.as_ref() else {
            return Provenance::Other;
        };
        if crate::files::atomic::is_same_file(&l.path, &c.path) {
            return Provenance::Own;
        }
        let unit = self.state.unit.is_some();
        let active = self.state.active_axis();
        let view = self
            .calibrated_axes()
            .get(active)
            .and_then(|(name, column)| view_for(l, unit, name, column));
        let judged = view.as_ref().map_or(&l.log, |v| &v.log);
        let shared = c.log.run_shared(judged);
        if shared.in_sample() {
            Provenance::Own
        } else if let Some(why) = shared.cannot_tell() {
            Provenance::CannotTell(why)
        } else {
            Provenance::Other
        }
    }

    /// Each axis of the calibration log: its name and the rate column it was read from.
    fn calibrated_axes(&self) -> Vec<(String, String)> {
        let unit = self.state.unit.is_some();
        (0..self.state.axis_count())
            .filter_map(|k| self.state.axis(k))
            .map(|a| {
                let log = a.log.map(|l| &l.log);
                let name = match (unit, log) {
                    (false, Some(l)) => l.axis.clone(),
                    _ => a.name.to_string(),
                };
                (name, log.and_then(|l| l.rate_column()).unwrap_or_default())
            })
            .collect()
    }

    /// Which view of validation log `l` each axis is judged on.
    fn match_validation(&self, l: &Loaded) -> Matching {
        let unit = self.state.unit.is_some();
        let axes = self.calibrated_axes();
        let views: Vec<Option<Loaded>> = axes
            .iter()
            .map(|(name, column)| view_for(l, unit, name, column))
            .collect();
        let missing: Vec<(&str, &str)> = axes
            .iter()
            .zip(&views)
            .filter(|(_, v)| v.is_none())
            .map(|((n, c), _)| (n.as_str(), c.as_str()))
            .collect();
        let missing =
            (!missing.is_empty()).then(|| unmatched_validation(&l.log, unit, &missing, "it"));
        Matching { views, missing }
    }

    /// Gives axis `k` the view `views[k]` (none to an axis past the list).
    fn set_validation_views(&mut self, mut views: Vec<Option<Loaded>>) {
        let n = self.state.axis_count();
        views.resize(n, None);
        let active = self.state.active_axis();
        for (k, view) in views.into_iter().enumerate() {
            if k == active {
                self.state.shown.validation = view;
            } else if let Some(p) = self.state.unit.as_mut().and_then(|u| u.parked.get_mut(k)) {
                p.validation = view;
            }
        }
    }

    /// No validation log: none read, none judged on.
    pub(super) fn forget_validation(&mut self) {
        self.state.validation_file = None;
        self.state.validation_doubt = None;
        self.set_validation_views(Vec::new());
        self.state.view.show_validation = false;
    }

    /// A validation log just read (not the calibration log itself): every axis judged on its
    /// view of it, the axes it lacks said.
    pub(super) fn validation_read(&mut self, l: Loaded) {
        let provenance = self.provenance(&l);
        if provenance == Provenance::Own {
            // Figures judged on the calibration's own log would be shown as held out.
            self.opening.validation_shown = None;
            self.state.say(
                Severity::Warning,
                format!(
                    "{} is the calibration log itself: figures judged on it are not held \
                     out, so it is not opened as the validation log; open another run",
                    file_name(&l.path)
                ),
            );
            return;
        }
        let mut msg = format!(
            "Validation log {} ({} samples)",
            file_name(&l.path),
            l.log.len()
        );
        if let Provenance::CannotTell(why) = &provenance {
            msg = format!(
                "{msg}; it cannot be told whether it is the calibration log ({why}): its \
                 figures may not be held out"
            );
        }
        self.state.validation_doubt = provenance.doubt();
        if let Some(doubt) = self.look_at_columns(&l, Target::Validation) {
            msg = format!("{msg}; {doubt}");
        }
        let m = self.match_validation(&l);
        let judged = m.views.iter().filter(|v| v.is_some()).count();
        let msg = match m.missing {
            Some(why) => format!(
                "{msg}; {why}, so {} judged on it{}",
                match (judged, self.state.unit.is_some()) {
                    (0, _) => "nothing is",
                    (_, true) if m.views.len() - judged == 1 => "that one is not",
                    _ => "those are not",
                },
                if self.state.unit.is_none() {
                    ": choose its rate column in Open validation log's import view"
                } else {
                    ""
                }
            ),
            None => msg,
        };
        self.set_validation_views(m.views);
        // Every axis of it, for a calibration opened to compare.
        self.state.validation_file = Some(l);
        let with_session = self.opening.validation_shown.is_some();
        match self.opening.validation_shown.take() {
            Some(shown) => {
                self.state.view.show_validation = shown;
                self.state.mark_saved();
            }
            None => self.state.view.show_validation = true,
        }
        match &self.state.status {
            // A warning from opening the session stays in sight.
            Some((Severity::Warning, earlier)) if with_session => {
                let both = format!("{earlier}. {msg}");
                self.state.say(Severity::Warning, both);
            }
            _ => self.state.say(Severity::Info, msg),
        }
    }

    /// Another calibration log just read (not from a session, which opens its own validation
    /// log): the validation log open is matched to its axes again, kept where it matches and
    /// put away where it matches none. What happened to it, for the status line (empty with
    /// none open), and whether it was put away.
    pub(super) fn validation_after_new_log(&mut self) -> Option<(String, bool)> {
        let Some(file) = self.state.validation_file.take() else {
            self.forget_validation();
            return None;
        };
        let name = file_name(&file.path);
        let provenance = self.provenance(&file);
        if provenance == Provenance::Own {
            self.forget_validation();
            return Some((
                format!(
                    "; validation log {name} put away: it is the calibration log itself, and \
                     figures judged on it would not be held out"
                ),
                true,
            ));
        }
        let m = self.match_validation(&file);
        if m.views.iter().all(Option::is_none) {
            self.forget_validation();
            let why = m.missing.unwrap_or_default();
            return Some((
                format!("; validation log {name} put away: {why}, so nothing is judged on it"),
                true,
            ));
        }
        let note = match &m.missing {
            Some(why) => format!(
                "; validation log {name} kept for the axes it has: {why}, so {} judged on it",
                if m.views.iter().filter(|v| v.is_none()).count() == 1 {
                    "that one is not"
                } else {
                    "those are not"
                }
            ),
            None => match &provenance {
                Provenance::CannotTell(why) => format!(
                    "; validation log {name} kept, though it cannot be told whether it is this \
                     log ({why}): its figures may not be held out"
                ),
                _ => format!("; validation log {name} kept: held out for this log too"),
            },
        };
        self.state.validation_doubt = provenance.doubt();
        self.set_validation_views(m.views);
        self.state.validation_file = Some(file);
        Some((note, false))
    }
}
