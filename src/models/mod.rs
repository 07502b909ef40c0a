//! The models: a fitted model's shared face (`fitted`), the named presets and model choices
//! (`presets`), the recipe of signal settings every model reads (`recipe`), Vakhrameev's
//! K0/K1±/K2± model (`vakhrameev`), the regression models of the other papers (`regression`),
//! the curve approximations they are built from (`approx`), and a fitted model in a few
//! lines a person reads (`summary`).
//!
//! Every model is fitted the same way, [`fit`] (or [`calibrate`], which also judges the model
//! on the log it was fitted on), from a [`ModelChoice`] and a [`Recipe`]. The recipe's signal
//! settings (T smoothing, derivative step H, plateaus) reach every model; the settings only
//! Vakhrameev's model reads (the K approximations, dead-bands, weighting and refinements) are
//! listed by [`settings_unused_by`] so that a face can refuse or flag them instead of dropping
//! them silently.

pub mod accel;
pub mod approx;
pub mod campaign;
mod error;
pub mod fitted;
pub mod presets;
mod readings;
pub mod recipe;
pub mod regression;
pub mod scripts;
pub mod summary;
pub mod unit;
pub mod vakhrameev;

pub use error::{FitError, HandKnotsNotKept, ParseError};
pub use fitted::{DriftModel, ModelCorrector, Predictor, stream_inputs};
pub use presets::{ModelChoice, Preset};
pub use readings::{AxisReadings, check_axis_readings, check_readings};
pub use recipe::{CheckedRecipe, Recipe};
pub use unit::{
    AxisModel, AxisPlan, CalibratedAxis, Keep, UnitCalibration, calibrate, calibrate_keeping,
};

use crate::error::{Error, Result};
use crate::judge::metrics::Evaluation;
use crate::log::Log;
use regression::RegressionCalibration;

/// The fewest samples a log must have to be calibrated (or its pointwise coefficients
/// gathered): fewer cannot hold a derivative's history and a plateau, and would be a file cut
/// short rather than a chamber run.
pub const MIN_SAMPLES: usize = 16;

/// The largest drift a calibration may predict anywhere over the ranges it was fitted on, °/h.
/// 10⁸ °/h is 28,000 °/s, beyond the measuring range of any gyro: a model that predicts more
/// (a hand-edited coefficient of 1e308, a range of ±1e308) is a broken file, not a gyro, and
/// its corrected rates would be noise of its own making or not numbers at all.
pub const MAX_DRIFT_DPH: f64 = 1e8;

/// Refuses a predicted drift `bound` (an upper bound of |prediction| over the fitted ranges)
/// that is not finite or beyond [`MAX_DRIFT_DPH`], naming `field`.
pub(crate) fn check_drift_bound(
    field: impl Into<String>,
    bound: f64,
) -> std::result::Result<(), crate::error::Invalid> {
    if bound.is_finite() && bound <= MAX_DRIFT_DPH {
        return Ok(());
    }
    Err(crate::error::Invalid::new(
        field,
        format!(
            "predicts a drift of up to {} deg/h over its own range, more than the {} deg/h \
             any gyro could show: the coefficients or ranges are not a calibration's",
            drift_past_limit(bound),
            crate::number::readable(MAX_DRIFT_DPH)
        ),
    ))
}

/// A drift beyond [`MAX_DRIFT_DPH`] as a message gives it: with the digits that tell it from
/// the limit (a drift just past it read "up to 1e8, more than the 1e8").
pub(crate) fn drift_past_limit(drift: f64) -> String {
    let text = crate::number::readable(drift);
    if text == crate::number::readable(MAX_DRIFT_DPH) {
        format!("{drift:.9e}")
    } else {
        text
    }
}

/// Fits `choice` on `log` with the recipe's settings.
///
/// # Errors
/// What the fit reports (too few samples, a missing channel, no plateaus, ...).
pub fn fit(log: &Log, choice: &ModelChoice, recipe: &CheckedRecipe) -> Result<DriftModel> {
    fit_with_progress(log, choice, recipe, &|_| true)
}

/// [`fit`], telling `progress` the share done (0 to 1) as it goes: a regression model's
/// searches report each cost evaluation, the Vakhrameev fit its start and end. When
/// `progress` returns false the fit stops as soon as it can with [`Error::Cancelled`].
///
/// # Errors
/// As [`fit`], and [`Error::Cancelled`].
pub fn fit_with_progress(
    log: &Log,
    choice: &ModelChoice,
    recipe: &CheckedRecipe,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<DriftModel> {
    if !progress(0.0) {
        return Err(Error::Cancelled);
    }
    recipe.check_against(log)?;
    check_span(log, choice)?;
    if let ModelChoice::Preset(p) = choice
        && let Some(script) = p.script()
    {
        let spec = p
            .spec(log)?
            .unwrap_or_else(|| scripts::spec(script, p.name()))
            .with_recipe(recipe);
        let m = scripts::fit(log, script, p.name(), spec)?;
        progress(1.0);
        return Ok(DriftModel::Regression(Box::new(
            RegressionCalibration::new(&recipe.gyro_id, log, m),
        )));
    }
    match choice.spec(log)? {
        None => {
            let cal = vakhrameev::fit_lean(log, recipe)?.calibration;
            progress(1.0);
            Ok(DriftModel::Vakhrameev(Box::new(cal)))
        }
        Some(spec) => {
            let m = regression::fit_with_progress(log, &spec.with_recipe(recipe), progress)?;
            Ok(DriftModel::Regression(Box::new(
                RegressionCalibration::new(&recipe.gyro_id, log, m),
            )))
        }
    }
}

/// The smallest temperature span a model of T is fitted over, °C: across less, a line or a
/// parabola in T is mostly the sensor's resolution and the noise.
pub const MIN_TEMP_SPAN_C: f64 = 2.0;

/// The smallest |Ṫ| a log must reach for rate terms, °C/min: a log that never ramps faster
/// carries no K1 or Ṫ coefficient.
pub const MIN_RAMP_C_PER_MIN: f64 = 0.05;

/// Refuses, before any fit, a log too narrow for `choice`: a rate that holds one value
/// throughout, a temperature span under [`MIN_TEMP_SPAN_C`], or rate terms on a log that
/// never ramps faster than [`MIN_RAMP_C_PER_MIN`].
///
/// # Errors
/// [`FitError::NarrowSpan`] or [`FitError::NoRamps`], saying what the log spans and what the
/// model needs.
pub fn check_span(log: &Log, choice: &ModelChoice) -> Result<()> {
    check_axis_readings(log)?;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &v in log.temp_c.iter().filter(|v| v.is_finite()) {
        if v < lo {
            lo = v;
        }
        if v > hi {
            hi = v;
        }
    }
    if (hi - lo).is_nan() || hi - lo < MIN_TEMP_SPAN_C {
        return Err(FitError::NarrowSpan {
            log: log.source.clone(),
            model: choice.name().to_string(),
            span_c: (hi >= lo).then_some((lo, hi)),
            minimum_c: MIN_TEMP_SPAN_C,
        }
        .into());
    }
    let rates = match choice {
        ModelChoice::Preset(p) if p.is_static_polynomial() => false,
        ModelChoice::Preset(Preset::PwlT | Preset::Sukhanov) => false,
        ModelChoice::Custom(s) => s.terms.iter().any(regression::Term::is_rate),
        _ => true,
    };
    if rates {
        // Ṫ over about a minute (or two samples of a slower log) from the raw temperature,
        // so the sensor's resolution does not count as a rate; within each stretch between
        // gaps (no rate is taken across one), over the whole stretch when it is shorter, so
        // that a 40-ns log or one of 3-s bursts is not said never to change (its windows
        // longer than a stretch are the reason it cannot be fitted, and the fit says so).
        let t = &log.time_s;
        let timing = log.timing();
        let dt_s = timing.nominal_dt_s;
        let mut fastest = 0.0f64;
        'segments: for r in &timing.segments {
            if r.len() < 2 {
                continue;
            }
            let span = 60.0f64.max(2.5 * dt_s).min(t[r.end - 1] - t[r.start]);
            let mut j = r.start;
            for i in r.clone() {
                while j < i && t[i] - t[j] > span {
                    j += 1;
                }
                let dt = t[i] - t[j];
                if dt > 0.0 && dt >= 0.5 * span {
                    fastest = fastest.max(((log.temp_c[i] - log.temp_c[j]) / dt).abs() * 60.0);
                    if fastest >= MIN_RAMP_C_PER_MIN {
                        break 'segments;
                    }
                }
            }
        }
        if fastest < MIN_RAMP_C_PER_MIN {
            return Err(FitError::NoRamps {
                log: log.source.clone(),
                model: choice.name().to_string(),
                fastest_c_per_min: fastest,
                minimum_c_per_min: MIN_RAMP_C_PER_MIN,
            }
            .into());
        }
    }
    Ok(())
}

/// A model fitted on a log and judged on that same log.
#[derive(Debug, Clone)]
pub struct Calibrated {
    /// The fitted model.
    pub model: DriftModel,
    /// Raw against corrected on the log it was fitted on.
    pub in_sample: Evaluation,
    /// What the fit had to work around, and what a face must show before the model is used:
    /// a fit with as many unknowns as points or more, a figure of its own log that the
    /// correction makes worse than raw ([`judge_on_own_log`]).
    pub warnings: Vec<String>,
}

/// The warning of a correction (of model `model_name`) that makes a figure of merit of its own
/// calibration log worse than raw, naming each such figure with both values; `None` when none
/// is. The workbench's fit gives it as the command line's does.
pub fn worse_than_raw(model_name: &str, in_sample: &Evaluation) -> Option<String> {
    let c = &in_sample.comparison;
    let n = |v: f64| crate::number::significant(v, 4);
    let mut worse = Vec::new();
    for (figure, raw, cor) in [
        (
            "peak-to-peak of the filtered drift",
            c.raw.p2p_dph,
            c.corrected.p2p_dph,
        ),
        (
            "std of the filtered drift",
            c.raw.std_dph,
            c.corrected.std_dph,
        ),
        (
            "max |10-min mean|",
            c.raw.win_mean_max_abs_dph,
            c.corrected.win_mean_max_abs_dph,
        ),
        (
            "mean 10-min RMS",
            c.raw.win_rms_mean_dph,
            c.corrected.win_rms_mean_dph,
        ),
    ] {
        // (A figure a billionth above raw is raw's, to rounding: as the ratio takes it.)
        if raw.is_finite()
            && cor.is_finite()
            && cor - raw > raw.abs() * crate::judge::metrics::RATIO_FLOOR
        {
            worse.push(format!("{figure} {} -> {} deg/h", n(raw), n(cor)));
        }
    }
    (!worse.is_empty()).then(|| {
        format!(
            "on its own log the correction is worse than raw: {}; check the plateaus and \
             whether model {model_name} suits this test",
            worse.join(", ")
        )
    })
}

/// The warnings a model earns on the log it was fitted on: each figure of merit that the
/// correction makes worse than raw (a calibration that cannot even correct its own log is
/// wrong: a ramp taken for a plateau, a model that does not suit the test), and for a
/// regression model more coefficients than samples, an R² below zero (the fit is worse than
/// the samples' mean), and the column it reads as a second temperature sensor (a guess from
/// the names, said so that the engineer can tell the chamber's air from a sensor on the gyro);
/// for a Vakhrameev model on plateaus given by hand, each one over which the temperature
/// moves far faster than the detector allows ([`unsteady`](crate::signal::plateau::unsteady))
/// and each that holds no sample or one ([`too_few_samples`](crate::signal::plateau::too_few_samples)).
pub fn judge_on_own_log(model: &DriftModel, in_sample: &Evaluation) -> Vec<String> {
    let mut out: Vec<String> = worse_than_raw(model.name(), in_sample)
        .into_iter()
        .collect();
    let n = |v: f64| crate::number::significant(v, 4);
    if let DriftModel::Vakhrameev(c) = model
        && let recipe::PlateauChoice::Manual { ranges } = &c.recipe.plateaus
    {
        // Ranges given by hand are held to the tolerance of the detector they replace.
        let limit = crate::signal::plateau::DetectOptions::default().max_rate_c_per_min;
        let mut told: Vec<String> = c
            .plateaus
            .iter()
            .filter_map(|p| crate::signal::plateau::unsteady(p, limit))
            .collect();
        told.extend(crate::signal::plateau::too_few_samples(ranges, &c.plateaus));
        // A few name the plateaus; the rest are counted, not listed line by line.
        const LISTED: usize = 8;
        if told.len() > LISTED {
            let more = told.len() - LISTED;
            told.truncate(LISTED);
            told.push(format!(
                "and {more} more plateaus given by hand are told likewise (the first {LISTED} \
                 above)"
            ));
        }
        out.extend(told);
    }
    if let DriftModel::Regression(r) = model {
        let m = &r.model;
        if let Some(t2) = &m.temp2 {
            out.push(format!(
                "model {}: \"{t2}\" is read as the second temperature sensor (its dT terms are \
                 the temperature minus \"{t2}\"){}",
                m.spec.name,
                if regression::names_chamber_air(t2) {
                    "; the name says it measures the chamber's air, not a sensor on the gyro, \
                     so dT is the chamber's lag behind the gyro rather than a gradient inside it"
                } else {
                    ""
                }
            ));
        }
        let unknowns = m.coefficients.len();
        if unknowns >= m.stats.n {
            out.push(format!(
                "model {}: {unknowns} coefficients fitted on {} samples: as many unknowns as \
                 points or more, so the coefficients are not determined by the data",
                m.spec.name, m.stats.n
            ));
        }
        if m.stats.r2 < 0.0 {
            out.push(format!(
                "model {}: R² {} on the samples it was fitted on: it predicts them worse than \
                 their mean does",
                m.spec.name,
                n(m.stats.r2)
            ));
        }
    }
    out
}

/// The recipe's settings that `choice` does not read, by their names in a recipe file, among
/// those that differ from the defaults: the K approximations, dead-bands, weighting and
/// refinements for every model but Vakhrameev's, and the plateaus for a model fitted over
/// every sample. A face refuses them when the engineer gave them, or says they are ignored.
pub fn settings_unused_by(recipe: &Recipe, choice: &ModelChoice) -> Vec<&'static str> {
    let d = Recipe::default();
    let mut out = Vec::new();
    if !choice.is_vakhrameev() {
        for ((name, mine), (_, default)) in recipe.specs().into_iter().zip(d.specs()) {
            if mine != default {
                out.push(name);
            }
        }
        if recipe.deadband_tdot != d.deadband_tdot {
            out.push("deadband_tdot");
        }
        if recipe.deadband_tddot != d.deadband_tddot {
            out.push("deadband_tddot");
        }
        if recipe.weighting != d.weighting {
            out.push("weighting");
        }
        if recipe.refinements != d.refinements {
            out.push("refinements");
        }
    }
    if !choice.uses_plateaus() && recipe.plateaus != d.plateaus {
        out.push("plateaus");
    }
    out
}
