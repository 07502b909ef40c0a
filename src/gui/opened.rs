//! A calibration opened beside the current fit (File › Open calibration, a dropped `.json`,
//! `driftlab gui CAL.json LOG`): what the workbench holds of it, what it asks the worker to
//! judge it on, and what each view reads back of the answer. It changes no choice of the
//! current fit: it is a second calibration's figures and drift shown beside the first.
//!
//! It is not kept in the session nor in the autosave: it is a file already on disk, not work
//! that could be lost, and a session that named it would be unsaved work the moment a file
//! was opened only to look at it (quitting would ask to save). Its path is kept among the
//! recent files instead (File › Recent), one click away.

use super::action::OpenLog;
use super::jobs::{AxisVerdict, JudgedAxis, LogInput, Verified, VerifyKey, VerifyRequest};
use super::state::AppState;
use crate::models::UnitCalibration;
use crate::models::summary::{SummaryLine, summary};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;

/// The calibration opened beside the current fit.
pub struct Opened {
    /// Its file.
    pub path: PathBuf,
    /// What it holds.
    pub unit: Arc<UnitCalibration>,
    /// Each axis's summary (its name, empty for the one axis of a single-axis calibration).
    pub summaries: Vec<(String, Vec<SummaryLine>)>,
    /// Per open log and axis of the calibration (its index), the log's axis the engineer chose
    /// where the files do not say.
    pub chosen: BTreeMap<(OpenLog, usize), String>,
    /// Its newest judging on the open logs.
    pub verified: Option<Arc<Verified>>,
}

impl Opened {
    /// The calibration at `path`, as read.
    pub fn new(path: PathBuf, unit: Arc<UnitCalibration>) -> Opened {
        let summaries = unit
            .axes
            .iter()
            .map(|a| (a.name.clone(), summary(&a.model)))
            .collect();
        Opened {
            path,
            unit,
            summaries,
            chosen: BTreeMap::new(),
            verified: None,
        }
    }

    /// Its file's name, as the window shows names.
    pub fn name(&self) -> String {
        super::widgets::file_name(&self.path)
    }

    /// What it is, in a few words: `one axis (vakhrameev)`, `3 axes: gx, gy, gz`.
    pub fn what(&self) -> String {
        let models: Vec<&str> = self.unit.axes.iter().map(|a| a.model.name()).collect();
        let mut distinct = models.clone();
        distinct.dedup();
        if self.unit.is_unit() {
            format!(
                "{} axes: {} ({})",
                self.unit.axes.len(),
                self.unit.axis_names().join(", "),
                distinct.join(", ")
            )
        } else {
            format!("one axis ({})", distinct.join(", "))
        }
    }
}

/// The calibration log as the opened calibration is judged on it: the log with every axis,
/// and each axis's view the workbench holds.
fn calibration_input(state: &AppState) -> Option<LogInput> {
    let shown = state.shown.log.as_ref()?;
    // (with the log's accelerometer axes, whatever the unit's switch says: the opened file's
    // own may be judged on them; a log of one gyro axis has them too)
    let accel_log = state.accel.as_ref().and_then(|a| a.log.clone());
    let accel_views = state.accel.iter().flat_map(|a| a.views.iter().cloned());
    let (full, views) = match &state.unit {
        Some(u) => (
            accel_log.or_else(|| u.full_log.clone())?,
            (0..u.names.len())
                .filter_map(|k| state.axis(k)?.log.map(|l| l.log.clone()))
                .chain(accel_views)
                .collect(),
        ),
        None => (
            accel_log.unwrap_or_else(|| shown.log.clone()),
            std::iter::once(shown.log.clone())
                .chain(accel_views)
                .collect(),
        ),
    };
    Some(LogInput {
        which: OpenLog::Calibration,
        path: shown.path.clone(),
        name: shown.name(),
        sha256: shown.sha256.clone().unwrap_or_default(),
        full,
        views,
    })
}

/// The validation log as the opened calibration is judged on it, while the workbench judges
/// the current fit on it (some axis holds a view of it).
fn validation_input(state: &AppState) -> Option<LogInput> {
    let file = state.validation_file.as_ref()?;
    let views: Vec<Arc<crate::log::Log>> = if file.axis_views.is_empty() {
        vec![file.log.clone()]
    } else {
        file.axis_views.iter().map(|v| v.log.clone()).collect()
    };
    let held = (0..state.axis_count())
        .filter_map(|k| state.axis(k)?.validation)
        .any(|v| views.iter().any(|w| Arc::ptr_eq(w, &v.log)));
    held.then(|| LogInput {
        which: OpenLog::Validation,
        path: file.path.clone(),
        name: file.name(),
        sha256: file.sha256.clone().unwrap_or_default(),
        full: file.log.clone(),
        views,
    })
}

/// What the opened calibration is to be judged on now: the open logs, with the workbench's
/// options of the figures (the current fit's), so that both calibrations are judged alike.
/// `None` with no calibration opened or no log open.
pub fn request(state: &AppState) -> Option<VerifyRequest> {
    let opened = state.opened.as_ref()?;
    let mut logs = vec![calibration_input(state)?];
    logs.extend(validation_input(state));
    Some(VerifyRequest {
        path: opened.path.clone(),
        unit: opened.unit.clone(),
        logs,
        merit: state.merit(),
        chosen: opened.chosen.clone(),
    })
}

/// Whether the opened calibration's figures answer the logs and options shown now (else a
/// judging is on its way and they are provisional).
pub fn current(state: &AppState) -> bool {
    match (
        state.opened.as_ref().and_then(|o| o.verified.as_ref()),
        request(state),
    ) {
        (Some(v), Some(r)) => v.key == VerifyKey::of(&r),
        _ => false,
    }
}

/// What the opened calibration shows beside the current fit on one open log, for the axis
/// shown.
pub enum Column<'a> {
    /// Judged there, on the axis shown (`axis`: its axis in the calibration, empty for one
    /// unnamed axis).
    Judged {
        /// The calibration's axis.
        axis: &'a str,
        /// The judging.
        judged: &'a JudgedAxis,
    },
    /// Not judged there: why (not yet, an axis to choose, a refusal).
    Not(String),
}

/// The opened calibration on log `which` for the axis the workbench shows; `None` with no
/// calibration opened.
pub fn column(state: &AppState, which: OpenLog) -> Option<Column<'_>> {
    let opened = state.opened.as_ref()?;
    let view = match which {
        OpenLog::Calibration => state.shown.log.as_ref(),
        OpenLog::Validation => state.shown.validation.as_ref(),
    };
    let Some(view) = view else {
        return Some(Column::Not("no log".into()));
    };
    let Some(verified) = &opened.verified else {
        return Some(Column::Not("judging…".into()));
    };
    if let Some(why) = &verified.failed {
        return Some(Column::Not(why.clone()));
    }
    let Some(on) = verified.logs.iter().find(|l| l.which == which) else {
        return Some(Column::Not("judging…".into()));
    };
    // The axis of the calibration judged on the view shown.
    let judged = on.axes.iter().enumerate().find_map(|(k, v)| match v {
        AxisVerdict::Judged(j) if Arc::ptr_eq(&j.log, &view.log) => Some((k, j)),
        _ => None,
    });
    if let Some((k, j)) = judged {
        let axis = opened.unit.axes.get(k).map_or("", |a| a.name.as_str());
        return Some(Column::Judged { axis, judged: j });
    }
    let shown = &view.log.axis;
    let failed = on.axes.iter().find_map(|v| match v {
        AxisVerdict::Failed { log_axis, why } if log_axis == shown => Some(why.clone()),
        _ => None,
    });
    if let Some(why) = failed {
        return Some(Column::Not(why));
    }
    let unplaced = on
        .axes
        .iter()
        .any(|v| matches!(v, AxisVerdict::Unplaced(_)));
    Some(Column::Not(if unplaced {
        format!("no axis placed on {shown}: choose its axis under Opened calibration")
    } else if opened.unit.is_unit() {
        format!("no axis of it is {shown}")
    } else {
        format!("it corrects another axis than {shown}")
    }))
}

/// The opened calibration's corrected drift on the log the drift plot shows (`log`: the
/// current fit's judged view), when it was judged there.
pub fn drift_line<'a>(state: &'a AppState, log: &Arc<crate::log::Log>) -> Option<&'a JudgedAxis> {
    let verified = state.opened.as_ref()?.verified.as_ref()?;
    verified.logs.iter().find_map(|l| {
        l.axes.iter().find_map(|v| match v {
            AxisVerdict::Judged(j) if Arc::ptr_eq(&j.log, log) => Some(&**j),
            _ => None,
        })
    })
}
