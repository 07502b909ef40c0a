//! A unit's accelerometer axes calibrated on a worker, through the engine's one path of a
//! unit's calibration ([`crate::models::campaign::calibrate_runs`], the call `calibrate
//! --accel` makes), each with the static model the engine gives an accelerometer when none is
//! named ([`crate::models::accel::default_plans`]); then what the window draws of each, in
//! m/s², thinned here so that a frame draws a few thousand points whatever the log's length.

use super::*;
use crate::models::accel::{self, Gravity};
use crate::models::campaign::{CampaignOptions, JoinedRuns, UnitPlan, calibrate_runs};
use crate::models::{CalibratedAxis, Keep, UnitCalibration};

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
}

/// What an accelerometer calibration answers: the same log (by identity) and recipe need
/// none again.
#[derive(Debug, Clone, PartialEq)]
pub struct AccelKey {
    log: Same<Log>,
    recipe: Recipe,
}

impl AccelKey {
    /// The key of `r`.
    pub fn of(r: &AccelRequest) -> AccelKey {
        AccelKey {
            log: Same::of(&r.log),
            recipe: r.recipe.clone(),
        }
    }
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
    let mut runs = JoinedRuns {
        log: (*req.log).clone(),
        name: req.name.clone(),
        sha256: req.sha256.clone(),
    };
    let fitted = calibrate_runs(&mut runs, &plan).map_err(|e| e.to_string())?;
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
                fitted: f,
            }
        })
        .collect();
    Ok(AccelFit {
        gravity: accel::gravity(&fitted.unit),
        unit: fitted.unit,
        axes,
        warnings: fitted.warnings,
    })
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
