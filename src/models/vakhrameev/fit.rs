//! The pipelines that run the stages: [`fit`] (every intermediate kept, for the workbench and
//! the tests), [`fit_lean`] (only the calibration, for the command line), [`fit_prepared`]
//! (the workbench's refit from signals it keeps) and [`fit_axes`] (every gyro axis of a unit
//! with one temperature processing).

use super::sets::{SetFit, fit_set, into_rest};
use super::stages::{deadbands, fit_k0};
use super::{
    Calibration, PointSet, Prepared, Regime, SetInputs, SetSamples, rest_dph, set_samples,
};
use crate::error::Result;
use crate::log::Log;
use crate::models::approx::Approx;
use crate::models::recipe::{CheckedRecipe, Recipe};
use crate::models::{FitError, MIN_SAMPLES};
use crate::signal::Derivatives;
use crate::signal::plateau::{self, PlateauRange, PlateauStats};

/// A calibration with every intermediate the stages produced.
#[derive(Debug, Clone)]
pub struct Fit {
    /// The result.
    pub calibration: Calibration,
    /// Filtered Ω and the derivatives.
    pub prepared: Prepared,
    /// Pointwise K1+ points.
    pub k1_plus_points: PointSet,
    /// Pointwise K1− points.
    pub k1_minus_points: PointSet,
    /// Pointwise K2+ points.
    pub k2_plus_points: PointSet,
    /// Pointwise K2− points.
    pub k2_minus_points: PointSet,
    /// What the fit had to work around (too few points, fewer plateaus than the K0 kind needs).
    pub warnings: Vec<String>,
}

/// Calibrates the Vakhrameev model on `log` with `recipe`.
pub fn fit(log: &Log, recipe: &CheckedRecipe) -> Result<Fit> {
    check_fittable(log, recipe)?;
    let prepared = Prepared::new(log, recipe);
    let ranges = plateau_ranges(log, &prepared, recipe);
    fit_prepared(log, prepared, &ranges, recipe)
}

fn check_fittable(log: &Log, recipe: &Recipe) -> Result<()> {
    recipe.check_against(log)?;
    check_sample_count(log)
}

/// Refuses a log with fewer than [`MIN_SAMPLES`] samples, or more than a calibration's `u32`
/// sample indices can count.
pub(crate) fn check_sample_count(log: &Log) -> Result<()> {
    if log.len() < MIN_SAMPLES {
        return Err(FitError::TooFewSamples {
            log: log.source.clone(),
            count: log.len(),
            minimum: MIN_SAMPLES,
        }
        .into());
    }
    if log.len() > u32::MAX as usize {
        return Err(FitError::TooManySamples {
            log: log.source.clone(),
            count: log.len(),
            maximum: u32::MAX as usize,
        }
        .into());
    }
    Ok(())
}

/// The stages before the K1/K2 fits: plateau statistics, K0, dead-bands and the sets' samples.
struct Staged {
    plateaus: Vec<PlateauStats>,
    k0: Approx,
    deadbands: (f64, f64),
    samples: [SetSamples; 2],
    warnings: Vec<String>,
}

fn stage(
    log: &Log,
    prepared: &Prepared,
    ranges: &[PlateauRange],
    recipe: &Recipe,
) -> Result<Staged> {
    let mut warnings = Vec::new();
    let plateaus = plateau_stats(log, ranges);
    let k0 = fit_k0(&plateaus, &recipe.k0, &mut warnings)?;
    let mask = plateau::mask(&log.time_s, ranges);
    let deadbands = deadbands(prepared, &mask, recipe);
    let samples = set_samples(&prepared.deriv, &mask, deadbands);
    Ok(Staged {
        plateaus,
        k0,
        deadbands,
        samples,
        warnings,
    })
}

/// Both sets fitted, side by side.
fn fit_sets(
    samples: &[SetSamples; 2],
    inputs: SetInputs,
    recipe: &Recipe,
    points: bool,
) -> (SetFit, SetFit) {
    rayon::join(
        || fit_set(&samples[0], inputs, Regime::Plus, recipe, points),
        || fit_set(&samples[1], inputs, Regime::Minus, recipe, points),
    )
}

/// Calibrates from already prepared signals and given plateau ranges (the workbench's path: it
/// keeps `Prepared` while only plateaus or approximations change).
pub fn fit_prepared(
    log: &Log,
    prepared: Prepared,
    ranges: &[PlateauRange],
    recipe: &Recipe,
) -> Result<Fit> {
    let Staged {
        plateaus,
        k0,
        deadbands,
        samples,
        mut warnings,
    } = stage(log, &prepared, ranges, recipe)?;
    let rest = rest_dph(&prepared.omega_filtered_dph, &log.temp_c, &k0);
    let inputs = SetInputs {
        tdot: &prepared.deriv.tdot,
        tddot: &prepared.deriv.tddot,
        rest: &rest,
    };
    let (plus, minus) = fit_sets(&samples, inputs, recipe, true);
    drop(rest);
    warnings.extend(plus.warnings);
    warnings.extend(minus.warnings);
    let calibration = Calibration::assemble(
        log,
        &prepared,
        recipe,
        deadbands,
        plateaus,
        [k0, plus.k1, minus.k1, plus.k2, minus.k2],
    );
    Ok(Fit {
        calibration,
        prepared,
        k1_plus_points: plus.k1_points,
        k1_minus_points: minus.k1_points,
        k2_plus_points: plus.k2_points,
        k2_minus_points: minus.k2_points,
        warnings,
    })
}

/// A calibration with the derivatives it computed on its log (what an in-sample evaluation
/// needs) and no more.
#[derive(Debug, Clone)]
pub struct Calibrated {
    /// The result.
    pub calibration: Calibration,
    /// Ṫ and T̈ of the log, as the calibration computes them.
    pub deriv: Derivatives,
    /// What the fit had to work around.
    pub warnings: Vec<String>,
}

/// [`fit`] for a caller that wants only the calibration (the command line): the same result,
/// made holding no more than the log, the filtered Ω (turned into `Ω_f − K0(T)` in place), Ṫ,
/// T̈ and the sets' sample indices; no points are gathered.
pub fn fit_lean(log: &Log, recipe: &CheckedRecipe) -> Result<Calibrated> {
    check_fittable(log, recipe)?;
    let mut prepared = Prepared::new(log, recipe);
    let ranges = plateau_ranges(log, &prepared, recipe);
    let (calibration, warnings) = fit_lean_prepared(log, &mut prepared, &ranges, recipe)?;
    Ok(Calibrated {
        calibration,
        deriv: prepared.deriv,
        warnings,
    })
}

/// The lean fit of the axis in `log.omega_dph` from `prepared`, whose filtered Ω is that
/// axis's and is used up (turned into `Ω_f − K0(T)` in place, then dropped).
fn fit_lean_prepared(
    log: &Log,
    prepared: &mut Prepared,
    ranges: &[PlateauRange],
    recipe: &Recipe,
) -> Result<(Calibration, Vec<String>)> {
    let Staged {
        plateaus,
        k0,
        deadbands,
        samples,
        warnings,
    } = stage(log, prepared, ranges, recipe)?;
    let sets = SetsOfSamples {
        deadbands,
        samples,
        key: (recipe.deadband_tdot, recipe.deadband_tddot),
    };
    Ok(finish_lean(
        log,
        prepared,
        recipe,
        (plateaus, k0),
        &sets,
        warnings,
    ))
}

/// The samples of the + and − sets with the dead-bands that chose them: they depend on T's
/// derivatives, the plateaus and the dead-band settings only, so the axes of a unit that ask
/// for the same dead-bands share them.
#[derive(Debug, Clone)]
struct SetsOfSamples {
    /// The dead-bands, resolved.
    deadbands: (f64, f64),
    /// The samples of each set.
    samples: [SetSamples; 2],
    /// The recipe's dead-band settings they were resolved from.
    key: (Option<f64>, Option<f64>),
}

/// The lean fit's end: K1 and K2 of both sets from `Ω_f − K0(T)`, made in place of the filtered
/// Ω in `prepared`, and the calibration put together.
fn finish_lean(
    log: &Log,
    prepared: &mut Prepared,
    recipe: &Recipe,
    (plateaus, k0): (Vec<PlateauStats>, Approx),
    sets: &SetsOfSamples,
    mut warnings: Vec<String>,
) -> (Calibration, Vec<String>) {
    let mut rest = std::mem::take(&mut prepared.omega_filtered_dph);
    into_rest(&mut rest, &log.temp_c, &k0);
    let inputs = SetInputs {
        tdot: &prepared.deriv.tdot,
        tddot: &prepared.deriv.tddot,
        rest: &rest,
    };
    let (plus, minus) = fit_sets(&sets.samples, inputs, recipe, false);
    drop(rest);
    warnings.extend(plus.warnings);
    warnings.extend(minus.warnings);
    let calibration = Calibration::assemble(
        log,
        prepared,
        recipe,
        sets.deadbands,
        plateaus,
        [k0, plus.k1, minus.k1, plus.k2, minus.k2],
    );
    (calibration, warnings)
}

/// The temperature's part of a calibration, done once for every gyro axis of a unit: T
/// smoothed and differentiated within each segment, and the plateaus found from Ṫ (or given).
/// Nothing in it depends on Ω, so the axes of one log share it and only their own stages
/// (Ω filtered, plateau means, K0, the sets and their fits) run per axis.
#[derive(Debug, Clone)]
pub struct SharedTemperature {
    /// The derivatives and segments; its filtered Ω is the axis being fitted, or empty.
    prepared: Prepared,
    /// The plateau ranges every axis's K0 points are taken over.
    ranges: Vec<PlateauRange>,
    /// The recipe whose T settings made it, for [`SharedTemperature::fit_axis`] to check that
    /// an axis's recipe asks for the same.
    recipe: Recipe,
    /// The log's span, s, which every axis's windows must fit in.
    span_s: f64,
    /// The sets' samples of the last dead-band settings asked for.
    sets: Option<SetsOfSamples>,
}

impl SharedTemperature {
    /// Differentiates T and finds the plateaus as `recipe` says, once for every axis of `log`.
    ///
    /// # Errors
    /// What [`fit`] refuses before any work: an invalid recipe, windows longer than the log,
    /// too few or too many samples.
    pub fn new(log: &Log, recipe: &CheckedRecipe) -> Result<SharedTemperature> {
        check_fittable(log, recipe)?;
        let timing = log.timing();
        let dt_s = timing.nominal_dt_s;
        let steps = crate::signal::DerivativeSteps {
            smooth: crate::signal::seconds_to_samples(recipe.temp_smoothing_s, dt_s),
            step: crate::signal::seconds_to_samples(recipe.step_h_s, dt_s),
        };
        let deriv = crate::signal::derivatives_in(&log.temp_c, steps, dt_s, &timing.segments);
        let prepared = Prepared {
            dt_s,
            filter_samples: 0,
            steps: Some(steps),
            omega_filtered_dph: Vec::new(),
            deriv,
            segments: timing.segments,
        };
        let ranges = plateau_ranges(log, &prepared, recipe);
        let span_s = log.duration_s() + dt_s;
        Ok(SharedTemperature {
            prepared,
            ranges,
            recipe: recipe.recipe().clone(),
            span_s,
            sets: None,
        })
    }

    /// Ṫ and T̈ of the log, as every axis's calibration computes them.
    pub fn derivatives(&self) -> &Derivatives {
        &self.prepared.deriv
    }

    /// The plateau ranges the axes share.
    pub fn ranges(&self) -> &[PlateauRange] {
        &self.ranges
    }

    /// Fits the axis in `log.omega_dph` with `recipe`, the same calibration [`fit_lean`] makes
    /// of that axis alone (the same bits: `tests/` check it), returned with its warnings.
    ///
    /// # Errors
    /// [`Error::Invalid`] naming a T setting of `recipe` (`temp_smoothing_s`, `step_h_s`,
    /// `plateaus`) that differs from the shared one: the axes of one log share T, so they share
    /// how it is processed. Otherwise what [`fit`] reports.
    pub fn fit_axis(
        &mut self,
        log: &Log,
        recipe: &CheckedRecipe,
    ) -> Result<(Calibration, Vec<String>)> {
        let shared = &self.recipe;
        for (name, same) in [
            (
                "temp_smoothing_s",
                recipe.temp_smoothing_s == shared.temp_smoothing_s,
            ),
            ("step_h_s", recipe.step_h_s == shared.step_h_s),
            ("plateaus", recipe.plateaus == shared.plateaus),
        ] {
            if !same {
                return Err(crate::error::Invalid::new(
                    name,
                    "differs between the axes of one unit: T is shared, and so is how it is \
                     smoothed, differentiated and split into plateaus",
                )
                .into());
            }
        }
        // What `fit` checks, on the log `new` has checked: the recipe's filter against the
        // log's span (its T windows are the shared ones).
        if recipe.filter_s > self.span_s {
            return Err(crate::error::Invalid::new(
                "filter_s",
                format!(
                    "{} s is longer than the log {} ({} s)",
                    crate::number::readable(recipe.filter_s),
                    log.source,
                    crate::number::readable(self.span_s)
                ),
            )
            .into());
        }
        let p = &mut self.prepared;
        p.filter_samples = crate::signal::seconds_to_samples(recipe.filter_s, p.dt_s);
        p.omega_filtered_dph = crate::signal::moving_average_centered_in(
            &log.omega_dph,
            p.filter_samples,
            &p.segments,
        );
        let mut warnings = Vec::new();
        let plateaus = plateau_stats(log, &self.ranges);
        let k0 = fit_k0(&plateaus, &recipe.k0, &mut warnings)?;
        let key = (recipe.deadband_tdot, recipe.deadband_tddot);
        let sets = match self.sets.take() {
            Some(sets) if sets.key == key => sets,
            _ => {
                let mask = plateau::mask(&log.time_s, &self.ranges);
                let deadbands = deadbands(p, &mask, recipe);
                let samples = set_samples(&p.deriv, &mask, deadbands);
                SetsOfSamples {
                    deadbands,
                    samples,
                    key,
                }
            }
        };
        let fitted = finish_lean(log, p, recipe, (plateaus, k0), &sets, warnings);
        self.sets = Some(sets);
        Ok(fitted)
    }
}

/// The plateau ranges the recipe asks for on `log`, found from the prepared Ṫ.
fn plateau_ranges(log: &Log, prepared: &Prepared, recipe: &Recipe) -> Vec<PlateauRange> {
    let d = &prepared.deriv;
    plateau::ranges(&recipe.plateaus, &log.time_s, &d.tdot, &d.ready)
}

/// The K0 points: each plateau's statistics over `log`.
fn plateau_stats(log: &Log, ranges: &[PlateauRange]) -> Vec<PlateauStats> {
    plateau::stats_of(&log.time_s, &log.temp_c, &log.omega_dph, ranges)
}
