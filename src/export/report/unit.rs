//! The report of a unit: every gyro axis of one calibration judged on the same logs, in one
//! page with a summary of every axis at the top.
//!
//! Each axis is reported as a single-axis calibration of it would be ([`super::write_model`]:
//! the same figures and figures of merit, computed by the same code on the log's matching axis,
//! put into `omega_dph` with [`Log::select_axis`]); its figures go into a folder of its own
//! (`gx/k0.png`, `gx/drift-LOG.png`, ...) beside the page, since every axis has a K0 and a drift
//! figure of each log.

use super::folder::{self, Relocate, moved};
use super::page::{self, PageAxis};
use super::{LeftOutLog, LogReport, ReportOptions, ReportSummary, build, calibration};
use crate::error::{Error, Invalid, Result};
use crate::judge::metrics::MeritOptions;
use crate::judge::verify;
use crate::log::Log;
use crate::models::UnitCalibration;
use std::path::{Path, PathBuf};

/// How a unit's report computes its figures of merit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnitMerit {
    /// Moving-average window of the filtered drift, s; `None`: each axis's own, as
    /// [`super::default_merit_for`] gives it (its recipe's filter, 100 s for a regression model).
    pub filter_s: Option<f64>,
    /// Length of the consecutive mean/RMS windows, s.
    pub window_s: f64,
}

impl UnitMerit {
    /// The merit options of an axis whose model is `model`.
    pub fn for_model(&self, model: &crate::models::DriftModel) -> MeritOptions {
        MeritOptions {
            filter_s: self
                .filter_s
                .unwrap_or(super::default_merit_for(model).filter_s),
            window_s: self.window_s,
        }
    }
}

/// One axis of a unit's report.
#[derive(Debug, Clone)]
pub struct AxisReport {
    /// The calibration's name of the axis (`gx`).
    pub name: String,
    /// The rate column it was calibrated from (`gx_dps`), empty when not known.
    pub rate_column: String,
    /// The model's name.
    pub model: String,
    /// The axis of each log it was judged on, in the order of the logs.
    pub log_axes: Vec<String>,
    /// Its figures and figures of merit, as a single-axis report of it holds them.
    pub summary: ReportSummary,
}

/// What [`write_unit`] wrote.
#[derive(Debug, Clone)]
pub struct UnitReportSummary {
    /// The HTML page.
    pub html: PathBuf,
    /// Every file written, the page last (the folder's [`super::MARKER`] aside).
    pub files: Vec<PathBuf>,
    /// Every axis, in the calibration's order.
    pub axes: Vec<AxisReport>,
}

impl UnitReportSummary {
    /// The log reports of every axis for log `k`: (axis name, its report of that log).
    pub fn log(&self, k: usize) -> Vec<(&str, &LogReport)> {
        self.axes
            .iter()
            .filter_map(|a| {
                let l = a.summary.logs.iter().find(|l| l.index == k)?;
                Some((a.name.as_str(), l))
            })
            .collect()
    }

    /// The axes that left log `k` out, with why: (axis name, what was left out).
    pub fn left_out(&self, k: usize) -> Vec<(&str, &LeftOutLog)> {
        self.axes
            .iter()
            .filter_map(|a| {
                let l = a.summary.left_out.iter().find(|l| l.index == k)?;
                Some((a.name.as_str(), l))
            })
            .collect()
    }
}

/// Writes the report of every axis of `unit` judged on `logs` into the folder `out_dir`: each
/// axis's figures in a folder named after it (beside the page for the one axis of a
/// calibration that names none), and one `report.html` with a summary table of every axis on
/// every log, then a section per axis as the single-axis page has it. The folder
/// is replaced whole, as [`super::write_model`] replaces it. Each
/// log's axes are selected in turn (the logs come back with the last axis in `omega_dph`).
/// `sha256`: each log's hash, when the caller has it (see [`ReportOptions::sha256`]).
/// `tolerance_c`: within what two plateaus of a campaign share a temperature, for the
/// campaign section of a calibration fitted on several runs (°C, above 0;
/// [`crate::models::campaign::DEFAULT_TOLERANCE_C`] is `calibrate`'s default).
///
/// # Errors
/// A log without an axis of the unit (by name, or by the rate column the axis was read from),
/// a log lacking a channel a model reads, a file that cannot be written, an `out_dir` that is
/// a file or a folder holding other things than a report, a `tolerance_c` not above 0.
pub fn write_unit(
    unit: &UnitCalibration,
    logs: &mut [(PathBuf, Log)],
    out_dir: &Path,
    merit: UnitMerit,
    sha256: Option<Vec<String>>,
    tolerance_c: f64,
) -> Result<UnitReportSummary> {
    unit.validate()?;
    crate::models::campaign::check_tolerance("tolerance_c", tolerance_c).map_err(Error::Invalid)?;
    let hashes: Vec<String> = match sha256 {
        Some(h) if h.len() == logs.len() => h,
        _ => logs
            .iter()
            .map(|(p, _)| calibration::sha256_file(p).unwrap_or_default())
            .collect(),
    };
    // Every log's axis of every axis of the unit, before anything is drawn: the rule that
    // `apply` follows (`corrected_csv::log_axes`).
    let mut log_axes: Vec<Vec<String>> = vec![Vec::with_capacity(logs.len()); unit.axes.len()];
    for (path, log) in logs.iter() {
        let found = crate::files::corrected_csv::log_axes(log, unit).map_err(|e| match e {
            crate::files::corrected_csv::WriteError::MissingAxis {
                axis,
                rate_column,
                log_axes,
                ..
            } => Error::Invalid(Invalid::new(
                format!("axes[{axis}]"),
                format!(
                    "{} has no gyro axis {axis} (column {}) (its axes: {})",
                    path.display(),
                    if rate_column.is_empty() {
                        "?"
                    } else {
                        &rate_column
                    },
                    log_axes.join(", ")
                ),
            )),
            other => Error::Invalid(Invalid::new("axes", other.to_string())),
        })?;
        for (axis, name) in log_axes.iter_mut().zip(found) {
            axis.push(name);
        }
    }
    folder::replace(out_dir, |dir| {
        write_axes(unit, logs, dir, (merit, tolerance_c), &hashes, log_axes)
    })
}

/// Writes every axis's figures into a folder of its own in `out_dir`, then the page (a
/// campaign's plateaus grouped within `tolerance_c`).
fn write_axes(
    unit: &UnitCalibration,
    logs: &mut [(PathBuf, Log)],
    out_dir: &Path,
    (merit, tolerance_c): (UnitMerit, f64),
    hashes: &[String],
    log_axes: Vec<Vec<String>>,
) -> Result<UnitReportSummary> {
    let in_sample = settled_in_sample(unit, logs, hashes, &log_axes)?;
    let mut taken: Vec<String> = vec!["report".into()];
    let mut axes = Vec::with_capacity(unit.axes.len());
    let mut files = Vec::new();
    for ((ax, found), in_sample) in unit.axes.iter().zip(log_axes).zip(&in_sample) {
        for ((_, log), name) in logs.iter_mut().zip(&found) {
            if !log.select_axis(name) {
                return Err(Error::Internal(
                    "an axis found in a log could not be selected",
                ));
            }
        }
        // The one axis of a calibration that names none is the page's own: its figures lie
        // beside the page, as they always have.
        let folder = if ax.name.is_empty() {
            out_dir.to_path_buf()
        } else {
            out_dir.join(folder_name(&ax.name, &mut taken))
        };
        let opts = ReportOptions {
            merit: Some(merit.for_model(&ax.model)),
            allan: None,
            sha256: Some(hashes.to_vec()),
            kind: ax.kind,
        };
        // Each log's readings of the axis checked as read, before an accelerometer's mean is
        // taken off (a mean of 10³⁶ taken off would make every reading look beyond).
        let refused = super::refusals(logs);
        // An accelerometer axis is reported about the mean its correction keeps, as it was
        // fitted and as `evaluate` judges it.
        let about: Option<Vec<(PathBuf, Log)>> = ax.kept_mean.map(|_| {
            logs.iter()
                .map(|(p, l)| (p.clone(), ax.as_fitted(l).into_owned()))
                .collect()
        });
        let summary = build(
            &ax.model,
            (about.as_deref().unwrap_or(logs), &refused),
            &folder,
            &opts,
            Some(in_sample),
        )
        .map_err(|e| match e {
            Error::Fit(e) => Error::Fit(e.on_axis(&ax.name)),
            other => other,
        })?;
        files.extend(summary.files.iter().cloned());
        axes.push(AxisReport {
            name: ax.name.clone(),
            rate_column: ax.rate_column.clone(),
            model: ax.model.name().to_string(),
            log_axes: found,
            summary,
        });
    }
    let html = out_dir.join("report.html");
    let page_axes: Vec<PageAxis<'_>> = unit
        .axes
        .iter()
        .zip(&axes)
        .map(|(ax, rep)| PageAxis {
            name: &ax.name,
            rate_column: &ax.rate_column,
            model: &ax.model,
            summary: &rep.summary,
            kind: ax.kind,
            kept_mean: ax.kept_mean,
        })
        .collect();
    let gravity = crate::models::accel::gravity(unit);
    page::write(&page_axes, &html, tolerance_c, gravity.as_ref())?;
    files.push(html.clone());
    Ok(UnitReportSummary { html, files, axes })
}

/// Whether each log (its hash in `hashes`, its axis of each of the unit's axes in
/// `log_axes`) is each axis's own, by axis then by log: each axis by its source, then a
/// log's axes settled together ([`verify::settle_axes`]), as `driftlab evaluate` judges
/// them.
fn settled_in_sample(
    unit: &UnitCalibration,
    logs: &mut [(PathBuf, Log)],
    hashes: &[String],
    log_axes: &[Vec<String>],
) -> Result<Vec<Vec<super::Told>>> {
    let mut in_sample = vec![vec![(false, None); logs.len()]; unit.axes.len()];
    for (k, ((path, log), hash)) in logs.iter_mut().zip(hashes).enumerate() {
        let name = super::file_name(path);
        let mut own = Vec::with_capacity(unit.axes.len());
        let mut shares = Vec::with_capacity(unit.axes.len());
        for (ax, found) in unit.axes.iter().zip(log_axes) {
            if !log.select_axis(&found[k]) {
                return Err(Error::Internal(
                    "an axis found in a log could not be selected",
                ));
            }
            let (is_own, share) = ax.model.source().judge_run(&ax.as_fitted(log), &name, hash);
            own.push(is_own);
            shares.push(share);
        }
        verify::settle_axes(&mut own, &mut shares);
        for ((axis, i), s) in in_sample.iter_mut().zip(own).zip(shares) {
            axis[k] = (i, s);
        }
    }
    Ok(in_sample)
}

impl Relocate for UnitReportSummary {
    fn relocate(&mut self, from: &Path, to: &Path) {
        self.html = moved(&self.html, from, to);
        for f in &mut self.files {
            *f = moved(f, from, to);
        }
        for a in &mut self.axes {
            a.summary.relocate(from, to);
        }
    }
}

/// A file-name-safe folder name for an axis, unique among `taken`.
fn folder_name(axis: &str, taken: &mut Vec<String>) -> String {
    super::log_section::safe_unique_name(axis, 40, "axis", taken)
}
