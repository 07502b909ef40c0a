//! The one pipeline that runs the stages, in order: prepare (T smoothed and differentiated, Ω
//! filtered), plateaus (ranges, mask, statistics), dead-bands, K0, the + and − sets, K1 then
//! K2 per set.
//!
//! [`Pipeline`] holds what the T stages made (nothing in them depends on Ω), so the axes of a
//! unit share them; each axis runs the Ω stages (`staged.rs`) with the pipeline's batch
//! memory, which keeps the sets' samples while the dead-band settings stay. [`fit`] (every
//! intermediate kept, for the workbench and the tests) and [`fit_lean`] (only the calibration,
//! for the command line) run it once on one axis. The workbench's refit (`crate::refit`) runs
//! the same Ω stages with a memory kept between edits.

use super::staged::{StageInputs, StageMemory, Staged};
use super::stages::deadbands;
use super::{Calibration, PointSet, Prepared, SetSamples, set_samples};
use crate::error::{Invalid, Result};
use crate::log::Log;
use crate::models::recipe::{CheckedRecipe, Recipe};
use crate::models::{FitError, MIN_SAMPLES};
use crate::number::readable;
use crate::signal::plateau::{self, PlateauRange};
use crate::signal::timing::Timing;
use crate::signal::{self, DerivativeSteps, Derivatives};
use std::borrow::Cow;
use std::sync::Arc;

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

/// Calibrates the Vakhrameev model on `log` with `recipe`, keeping every intermediate.
///
/// # Errors
/// What [`Pipeline::new`] refuses, and no plateaus.
pub fn fit(log: &Log, recipe: &CheckedRecipe) -> Result<Fit> {
    let (mut pipeline, omega_filtered_dph) = Pipeline::with_omega(log, recipe)?;
    let staged = pipeline.stages(log, recipe, Cow::Borrowed(&omega_filtered_dph), true)?;
    let mut prepared = pipeline.prepared;
    prepared.omega_filtered_dph = omega_filtered_dph;
    let [
        k1_plus_points,
        k1_minus_points,
        k2_plus_points,
        k2_minus_points,
    ] = staged.points.map(Arc::unwrap_or_clone);
    Ok(Fit {
        calibration: staged.calibration,
        prepared,
        k1_plus_points,
        k1_minus_points,
        k2_plus_points,
        k2_minus_points,
        warnings: staged.warnings,
    })
}

/// [`fit`] for a caller that wants only the calibration (the command line): the same result,
/// made holding no more than the log, the filtered Ω (turned into `Ω_f − K0(T)` in place), Ṫ,
/// T̈ and the sets' sample indices; no points are gathered.
///
/// # Errors
/// As [`fit`].
pub fn fit_lean(log: &Log, recipe: &CheckedRecipe) -> Result<Calibrated> {
    let (mut pipeline, omega_filtered_dph) = Pipeline::with_omega(log, recipe)?;
    let staged = pipeline.stages(log, recipe, Cow::Owned(omega_filtered_dph), false)?;
    Ok(Calibrated {
        calibration: staged.calibration,
        deriv: pipeline.prepared.deriv,
        warnings: staged.warnings,
    })
}

/// Refuses what no fit can be made from: an invalid recipe, windows longer than the log, too
/// few or too many samples.
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

/// The samples of the + and − sets with the dead-bands that chose them: they depend on T's
/// derivatives, the plateaus and the dead-band settings only, so the axes of a unit that ask
/// for the same dead-bands share them, and the workbench keeps them while those stay.
#[derive(Debug, Clone)]
pub(crate) struct SetsOfSamples {
    /// The dead-bands, resolved.
    pub(crate) deadbands: (f64, f64),
    /// The samples of each set, `[+, −]`.
    pub(crate) samples: [SetSamples; 2],
}

/// The dead-bands stage and the sets' samples: the plateau mask of `ranges` over `time_s`,
/// the dead-bands `recipe` resolves to outside it, and the samples of each set beyond them.
pub(crate) fn sets_of_samples(
    time_s: &[f64],
    prepared: &Prepared,
    ranges: &[PlateauRange],
    recipe: &Recipe,
) -> SetsOfSamples {
    let mask = plateau::mask(time_s, ranges);
    let deadbands = deadbands(prepared, &mask, recipe);
    let samples = set_samples(&prepared.deriv, &mask, deadbands);
    SetsOfSamples { deadbands, samples }
}

/// The Vakhrameev pipeline over one log, holding what its T stages made: T smoothed and
/// differentiated within each segment, and the plateau ranges found from Ṫ (or given). The
/// axes of a unit share it; each axis runs its Ω stages through [`Pipeline::fit_axis`].
#[derive(Debug, Clone)]
pub struct Pipeline {
    /// The derivatives and segments; its filtered Ω is empty (each axis filters its own).
    prepared: Prepared,
    /// The plateau ranges every axis's K0 points are taken over.
    ranges: Vec<PlateauRange>,
    /// The recipe whose T settings made it, for [`Pipeline::fit_axis`] to check that an
    /// axis's recipe asks for the same.
    recipe: Recipe,
    /// The log's span, s, which every axis's windows must fit in.
    span_s: f64,
    /// The Ω stages' memory: the sets' samples of the last dead-band settings asked for.
    memory: StageMemory<()>,
}

impl Pipeline {
    /// Runs the T stages as `recipe` says, once for every axis of `log`.
    ///
    /// # Errors
    /// What no fit can be made from: an invalid recipe, windows longer than the log, too few
    /// or too many samples.
    pub fn new(log: &Log, recipe: &CheckedRecipe) -> Result<Pipeline> {
        check_fittable(log, recipe)?;
        Ok(Pipeline::of_temperature(log, recipe, &log.timing()))
    }

    /// [`Pipeline::new`] with the axis in `log.omega_dph` filtered beside the T stages, as
    /// `recipe` filters it: for that axis's [`Pipeline::fit_axis`], or a fit of it alone.
    pub(crate) fn with_omega(log: &Log, recipe: &CheckedRecipe) -> Result<(Pipeline, Vec<f64>)> {
        check_fittable(log, recipe)?;
        let timing = log.timing();
        let filter_samples = signal::seconds_to_samples(recipe.filter_s, timing.nominal_dt_s);
        let (mut pipeline, omega_filtered_dph) = rayon::join(
            || Pipeline::of_temperature(log, recipe, &timing),
            || signal::moving_average_centered_in(&log.omega_dph, filter_samples, &timing.segments),
        );
        pipeline.prepared.filter_samples = filter_samples;
        Ok((pipeline, omega_filtered_dph))
    }

    /// The T stages: prepare's T (smoothed, differentiated) and the plateau ranges.
    fn of_temperature(log: &Log, recipe: &Recipe, timing: &Timing) -> Pipeline {
        let dt_s = timing.nominal_dt_s;
        let steps = DerivativeSteps {
            smooth: signal::seconds_to_samples(recipe.temp_smoothing_s, dt_s),
            step: signal::seconds_to_samples(recipe.step_h_s, dt_s),
        };
        let deriv = signal::derivatives_in(&log.temp_c, steps, dt_s, &timing.segments);
        let ranges = plateau::ranges(&recipe.plateaus, &log.time_s, &deriv.tdot, &deriv.ready);
        Pipeline {
            prepared: Prepared {
                dt_s,
                filter_samples: 0,
                steps: Some(steps),
                omega_filtered_dph: Vec::new(),
                deriv,
                segments: timing.segments.clone(),
            },
            ranges,
            recipe: recipe.clone(),
            span_s: log.duration_s() + dt_s,
            memory: StageMemory::batch(),
        }
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
    /// `omega_filtered_dph` is the axis's Ω already filtered as `recipe` says (by
    /// [`Pipeline::with_omega`]), or none to filter it here.
    ///
    /// # Errors
    /// [`Invalid`] naming a T setting of `recipe` (`temp_smoothing_s`, `step_h_s`,
    /// `plateaus`) that differs from the shared one: the axes of one log share T, so they share
    /// how it is processed; or `filter_s` longer than the log. Otherwise what [`fit`] reports.
    pub fn fit_axis(
        &mut self,
        log: &Log,
        recipe: &CheckedRecipe,
        omega_filtered_dph: Option<Vec<f64>>,
    ) -> Result<(Calibration, Vec<String>)> {
        if let Some(name) = crate::models::unit::differing_temperature_setting(&self.recipe, recipe)
        {
            return Err(Invalid::new(
                name,
                "differs between the axes of one unit: T is shared, and so is how it is \
                 smoothed, differentiated and split into plateaus",
            )
            .into());
        }
        // What `fit` checks, on the log `new` has checked: the recipe's filter against the
        // log's span (its T windows are the shared ones).
        if recipe.filter_s > self.span_s {
            return Err(Invalid::new(
                "filter_s",
                format!(
                    "{} s is longer than the log {} ({} s)",
                    readable(recipe.filter_s),
                    log.source,
                    readable(self.span_s)
                ),
            )
            .into());
        }
        let p = &mut self.prepared;
        p.filter_samples = signal::seconds_to_samples(recipe.filter_s, p.dt_s);
        let omega_filtered_dph = omega_filtered_dph.unwrap_or_else(|| {
            signal::moving_average_centered_in(&log.omega_dph, p.filter_samples, &p.segments)
        });
        let staged = self.stages(log, recipe, Cow::Owned(omega_filtered_dph), false)?;
        Ok((staged.calibration, staged.warnings))
    }

    /// The Ω stages of the axis in `log.omega_dph`, filtered into `omega_filtered_dph`, run
    /// with the pipeline's batch memory; the points gathered when `points` is true.
    fn stages(
        &mut self,
        log: &Log,
        recipe: &Recipe,
        omega_filtered_dph: Cow<'_, [f64]>,
        points: bool,
    ) -> Result<Staged> {
        self.memory.run(StageInputs {
            log,
            signals: (),
            prepared: &self.prepared,
            omega_filtered_dph,
            ranges: &self.ranges,
            recipe,
            points,
            source: None,
        })
    }
}
