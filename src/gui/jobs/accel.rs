//! A unit's accelerometer axes calibrated on a worker, through the engine's one path of a
//! unit's calibration ([`crate::models::campaign::calibrate_runs`], the call `calibrate
//! --accel` makes), each with the static model the engine gives an accelerometer when none is
//! named ([`crate::models::accel::default_plans`]); then, with a validation log open, each
//! judged on it as `driftlab evaluate` judges a calibration's accelerometer axis
//! ([`crate::judge::verify::judge`] on the axis about the mean it keeps); then what the window
//! draws of each, in m/s², thinned here so that a frame draws a few thousand points whatever
//! the log's length.

use super::*;
use crate::judge::metrics::Evaluation;
use crate::judge::verify::{self, LogFile};
use crate::models::accel::{self, Gravity};
use crate::models::campaign::{CampaignOptions, JoinedRuns, UnitPlan, calibrate_runs};
use crate::models::{CalibratedAxis, Keep, UnitCalibration};

/// The validation log the accelerometer axes are judged on.
#[derive(Debug, Clone)]
pub struct AccelValidation {
    /// The log with its accelerometer axes (made of its columns as the calibration log's
    /// were), or why they could not be made (the window's words).
    pub log: Result<Arc<Log>, String>,
    /// Its file's name, as `evaluate` gives it to the in-sample rule.
    pub name: String,
    /// SHA-256 of the file (empty when not known).
    pub sha256: String,
}

/// What the accelerometer axes are calibrated with.
#[derive(Debug, Clone)]
pub struct AccelRequest {
    /// The calibration log with its accelerometer axes ([`Loaded::accel`]).
    pub log: Arc<Log>,
    /// The name the calibration records (the file's).
    pub name: String,
    /// SHA-256 of the file.
    pub sha256: String,
    /// The unit's recipe (its first gyro axis's: T, its smoothing and the plateaus are the
    /// unit's, and `calibrate` gives its one recipe to every axis). The figures are read
    /// with its filter over 10-minute windows, as `calibrate` reads them.
    pub recipe: Recipe,
    /// The validation log open, each axis judged on it held out.
    pub validation: Option<AccelValidation>,
}

/// What an accelerometer calibration answers: the same log (by identity) and recipe need
/// none again.
#[derive(Debug, Clone, PartialEq)]
pub struct AccelKey {
    log: Same<Log>,
    recipe: Recipe,
    validation: Option<Result<Same<Log>, String>>,
}

impl AccelKey {
    /// The key of `r`.
    pub fn of(r: &AccelRequest) -> AccelKey {
        AccelKey {
            log: Same::of(&r.log),
            recipe: r.recipe.clone(),
            validation: r
                .validation
                .as_ref()
                .map(|v| v.log.as_ref().map(Same::of).map_err(Clone::clone)),
        }
    }
}

/// An accelerometer axis judged on the validation log, as `evaluate` judges it.
#[derive(Debug, Clone)]
pub struct AccelHeldOut {
    /// Raw against corrected, about the mean the axis keeps, in m/s².
    pub evaluation: Evaluation,
    /// Whether the log is the calibration's own, in `evaluate`'s words (`held out`).
    pub label: String,
    /// Whether the log is the calibration's own run.
    pub in_sample: bool,
    /// The log's mean on the axis is another orientation's: its figures are of its change
    /// about its own mean (`evaluate`'s note).
    pub note: Option<String>,
}

/// The points of a plot drawn from it, in the plot's units.
pub type Line = Vec<[f64; 2]>;

/// What the window draws of one accelerometer axis.
#[derive(Debug, Clone)]
pub struct AccelAxisView {
    /// The axis as the engine fitted it: model, in-sample figures (m/s², about the kept
    /// mean), warnings, the mean it keeps.
    pub fitted: CalibratedAxis,
    /// Its samples less the kept mean against time, h: each column's least and greatest.
    pub raw_t: Line,
    /// Its corrected samples (less the kept mean) against time, h, alike.
    pub cor_t: Line,
    /// Its samples less the kept mean against T, °C, every n-th.
    pub raw_temp: Line,
    /// Its model's prediction over its fitted T range, °C.
    pub model_temp: Line,
    /// Judged on the validation log, or why it could not be; `None` without one.
    pub held_out: Option<Result<AccelHeldOut, String>>,
}

/// The accelerometer axes calibrated.
#[derive(Debug, Clone)]
pub struct AccelFit {
    /// Their calibration as files hold it (stamped as `calibrate` stamps it), for the
    /// exports, after the gyro axes.
    pub unit: UnitCalibration,
    /// Each axis, in the unit's order.
    pub axes: Vec<AccelAxisView>,
    /// The axis that carries gravity, and how its reading changes with T.
    pub gravity: Option<Gravity>,
    /// What the engine said of the log.
    pub warnings: Vec<String>,
    /// The options of every figure, in-sample and held out: the recipe's filter over
    /// 10-minute windows, as `calibrate` and `evaluate` read them.
    pub merit: MeritOptions,
}

/// One answer.
#[derive(Debug)]
pub struct AccelView {
    /// The request number it answers.
    pub generation: u64,
    /// What it was asked with.
    pub key: AccelKey,
    /// The axes calibrated, or the engine's refusal.
    pub result: Result<AccelFit, String>,
}

/// The columns a time plot is thinned to.
const COLUMNS: usize = 1500;
/// The most points of the plot against T.
const CLOUD: usize = 3000;

/// Calibrates the accelerometer axes of `req`.
pub(super) fn run_accel(req: &AccelRequest, generation: u64) -> AccelView {
    AccelView {
        generation,
        key: AccelKey::of(req),
        result: calibrate(req),
    }
}

fn calibrate(req: &AccelRequest) -> Result<AccelFit, String> {
    let recipe = req.recipe.clone().checked().map_err(|e| e.to_string())?;
    let plans = accel::default_plans(&req.log, &recipe);
    let plan = UnitPlan {
        recipe,
        plans,
        campaign: CampaignOptions::default(),
        keep: Keep::Corrected,
    };
    let merit = plan.merit();
    let mut runs = JoinedRuns {
        log: (*req.log).clone(),
        name: req.name.clone(),
        sha256: req.sha256.clone(),
    };
    let fitted = calibrate_runs(&mut runs, &plan).map_err(|e| e.to_string())?;
    let mut held_out = held_out(&fitted.unit, req.validation.as_ref(), merit).into_iter();
    let log = &req.log;
    let hours: Vec<f64> = log.time_s.iter().map(|t| t / 3600.0).collect();
    let axes = fitted
        .fit
        .axes
        .into_iter()
        .map(|mut f| {
            let corrected = f.corrected.take();
            let mean = f.kept_mean.unwrap_or(0.0);
            let about: Vec<f64> = log
                .axis_rate(&f.name)
                .unwrap_or_default()
                .iter()
                .map(|v| v - mean)
                .collect();
            let cor = corrected.map(|c| c.cor_dph).unwrap_or_default();
            AccelAxisView {
                raw_t: columns(&hours, &about),
                cor_t: columns(&hours, &cor),
                raw_temp: cloud(&log.temp_c, &about),
                model_temp: curve(&f.calibrated.model),
                held_out: held_out.next().flatten(),
                fitted: f,
            }
        })
        .collect();
    Ok(AccelFit {
        gravity: accel::gravity(&fitted.unit),
        unit: fitted.unit,
        axes,
        warnings: fitted.warnings,
        merit,
    })
}

/// Each axis of `unit` judged on the validation log `v`, in the unit's order, as `driftlab
/// evaluate` judges a calibration's axes on a log: the log's axis each corrects
/// ([`verify::find_axes`]), taken about the mean the axis keeps ([`AxisModel::as_fitted`]),
/// judged with `merit` ([`verify::judge`]), in-sample or held out settled over the axes
/// together ([`verify::settle_axes`]). Empty without a validation log.
///
/// [`AxisModel::as_fitted`]: crate::models::AxisModel::as_fitted
fn held_out(
    unit: &UnitCalibration,
    v: Option<&AccelValidation>,
    merit: MeritOptions,
) -> Vec<Option<Result<AccelHeldOut, String>>> {
    let Some(v) = v else {
        return Vec::new();
    };
    let log = match &v.log {
        Ok(log) => log,
        Err(e) => return unit.axes.iter().map(|_| Some(Err(e.clone()))).collect(),
    };
    let file = LogFile {
        name: &v.name,
        sha256: &v.sha256,
    };
    let found = verify::find_axes(unit, log);
    let mut judged: Vec<Result<(verify::Judged, Option<String>), String>> = unit
        .axes
        .iter()
        .zip(found)
        .map(|(ax, column)| {
            let column = column.ok_or_else(|| {
                format!(
                    "{}: no accelerometer axis {} (column {}) (its axes: {})",
                    log.source,
                    ax.name,
                    ax.rate_column,
                    log.axis_names().join(", ")
                )
            })?;
            let mut view = (**log).clone();
            view.select_axis(&column);
            view.other_axes.clear();
            let note = accel::orientation_note(&view, &ax.name, ax.kind, ax.kept_mean);
            let opts = verify::merit_options(&ax.model, Some(merit.filter_s), Some(merit.window_s));
            verify::judge(&ax.model, &ax.as_fitted(&view), file, opts, false)
                .map(|j| (j, note))
                .map_err(|e| e.to_string())
        })
        .collect();
    // The axes share the log's rows: one that saw too few of them takes what all tell, as
    // `evaluate` settles a unit's axes.
    let mut ok: Vec<&mut verify::Judged> = judged
        .iter_mut()
        .filter_map(|j| j.as_mut().ok().map(|(j, _)| j))
        .collect();
    let mut in_sample: Vec<bool> = ok.iter().map(|j| j.in_sample).collect();
    let mut shares: Vec<_> = ok.iter().map(|j| j.share).collect();
    verify::settle_axes(&mut in_sample, &mut shares);
    for ((j, i), s) in ok.iter_mut().zip(in_sample).zip(shares) {
        (j.in_sample, j.share) = (i, s);
    }
    judged
        .into_iter()
        .map(|j| {
            Some(j.map(|(j, note)| AccelHeldOut {
                label: j.sample_label(),
                in_sample: j.in_sample,
                evaluation: j.evaluation,
                note,
            }))
        })
        .collect()
}

/// Each of [`COLUMNS`] columns of `y` against `x` as its least and greatest finite value, in
/// the order they come (a band drawn as one line).
fn columns(x: &[f64], y: &[f64]) -> Line {
    let n = x.len().min(y.len());
    let per = n.div_ceil(COLUMNS).max(1);
    let mut out = Vec::with_capacity(2 * COLUMNS);
    for start in (0..n).step_by(per) {
        let end = (start + per).min(n);
        let finite = (start..end).filter(|&i| y[i].is_finite() && x[i].is_finite());
        let lo = finite.clone().min_by(|&a, &b| y[a].total_cmp(&y[b]));
        let hi = finite.max_by(|&a, &b| y[a].total_cmp(&y[b]));
        if let (Some(lo), Some(hi)) = (lo, hi) {
            let (a, b) = if lo <= hi { (lo, hi) } else { (hi, lo) };
            out.push([x[a], y[a]]);
            if b != a {
                out.push([x[b], y[b]]);
            }
        }
    }
    out
}

/// Every n-th finite point of `y` against `x`, at most [`CLOUD`].
fn cloud(x: &[f64], y: &[f64]) -> Line {
    let n = x.len().min(y.len());
    let every = n.div_ceil(CLOUD).max(1);
    (0..n)
        .step_by(every)
        .filter(|&i| x[i].is_finite() && y[i].is_finite())
        .map(|i| [x[i], y[i]])
        .collect()
}

/// A static model's prediction over its fitted T range (empty for a model that reads more
/// than T, or has no range).
fn curve(model: &crate::models::DriftModel) -> Line {
    let crate::models::DriftModel::Regression(r) = model else {
        return Vec::new();
    };
    let Some([lo, hi]) = r.model.ranges.temp else {
        return Vec::new();
    };
    (0..=200)
        .map(|k| lo + (hi - lo) * k as f64 / 200.0)
        .filter_map(|t| accel::static_at(model, t).map(|p| [t, p]))
        .collect()
}
