//! A unit: every axis of one IMU (a three-axis FOG unit, a MEMS IMU's gyros and
//! accelerometers), calibrated from one log as one calibration. An accelerometer axis is an
//! axis of kind [`AxisKind::Accel`] beside the gyro axes, through the same fit, correction and
//! writers; what its kind changes is in [`super::accel`].
//!
//! The axes share the housing and its temperature, so they share everything a calibration
//! takes from T: one smoothing, one pair of derivatives, one set of plateaus
//! ([`vakhrameev::Pipeline`]). What an axis answers to that field is its own: its
//! model, its approximations and knots, its dead-bands, its K0 points (its own Ω averaged over
//! the shared plateaus). [`calibrate`] reads the log once and differentiates T once for
//! every Vakhrameev axis; a regression axis is fitted on its own, its signals being the model's.
//!
//! A log of one axis is a unit of one: the same [`calibrate`], with one plan that names no
//! axis ([`AxisPlan::unnamed`]). Such a calibration is what driftlab has always written (a
//! version-1 file, [`UnitCalibration::is_unit`] false); a unit of named axes is written as a
//! version-2 file (`crate::files::calibration`): a choice of serialization at the edge.

use super::FitError;
use super::{
    Calibrated, CheckedRecipe, DriftModel, ModelChoice, Recipe, check_span, fit, judge_on_own_log,
};
use crate::error::{Error, Invalid, Result};
use crate::judge::metrics::{Comparison, Evaluation, MeritOptions};
use crate::log::{AxisKind, Log};
use crate::models::vakhrameev;
use crate::models::vakhrameev::correct::CorrectedRate;

/// The most axes a unit may have: four IMUs of three gyro and three accelerometer axes each
/// are 24, and a hand-edited file of 1,000 axes would hold a thousand corrected columns in
/// memory on `apply`.
pub const MAX_UNIT_AXES: usize = 64;

/// One axis of a unit's calibration.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisModel {
    /// The axis's name (`gx`): the rate column's name without its unit, by default. Empty for
    /// the one axis of a single-axis calibration.
    pub name: String,
    /// The column the axis was read from on the calibration log (`gx_dps`, `acc_x_m_s2`), to
    /// find it in another log of the same stand; empty when not known.
    pub rate_column: String,
    /// The axis's fitted model, predicting in the kind's unit (°/h, m/s²).
    pub model: DriftModel,
    /// What the axis measures: the unit of its model and columns, the models it may take, its
    /// place in a flight controller's file.
    pub kind: AxisKind,
    /// An accelerometer axis's mean on its calibration log, m/s², which its correction keeps
    /// (it was fitted on its samples less this: [`super::accel`]); `None` for a gyro axis.
    pub kept_mean: Option<f64>,
}

impl AxisModel {
    /// A gyro axis of a unit.
    pub fn gyro(
        name: impl Into<String>,
        rate_column: impl Into<String>,
        model: DriftModel,
    ) -> AxisModel {
        AxisModel {
            name: name.into(),
            rate_column: rate_column.into(),
            model,
            kind: AxisKind::Gyro,
            kept_mean: None,
        }
    }

    /// `log` (holding the axis this one corrects) as this axis's model was fitted on it: an
    /// accelerometer's samples less the mean it keeps ([`super::accel::as_fitted`]), what
    /// every judgement of the axis reads.
    pub fn as_fitted<'a>(&self, log: &'a Log) -> std::borrow::Cow<'a, Log> {
        super::accel::as_fitted(log, self.kind, self.kept_mean)
    }
}

/// The calibration of a whole unit: one model per gyro axis, in the order they were fitted.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitCalibration {
    /// The axes, at least one.
    pub axes: Vec<AxisModel>,
}

impl UnitCalibration {
    /// The single-axis calibration of `model`, as driftlab has always made it.
    pub fn single(model: DriftModel) -> UnitCalibration {
        UnitCalibration {
            axes: vec![AxisModel::gyro("", "", model)],
        }
    }

    /// Whether this is a unit of named axes (written as a version-2 file) rather than the
    /// single-axis calibration of one unnamed axis (version 1).
    pub fn is_unit(&self) -> bool {
        self.axes.len() > 1 || self.axes.iter().any(|a| !a.name.is_empty())
    }

    /// The gyro of a drone log the unit was fitted on (`source.instance`), which every
    /// command that reads a drone log for it reads unless told otherwise: its axes come from
    /// one gyro, and a unit's file holds one source for them all. `None` for a calibration
    /// of a CSV, or one written before the record.
    pub fn fitted_on(&self) -> Option<crate::log::DroneGyro> {
        self.axes
            .iter()
            .find_map(|a| a.model.source().instance.clone())
    }

    /// The tolerance within which the plateaus of the campaign the unit was fitted on share a
    /// temperature, °C: the one recorded (`source.temp_tolerance_c`), or
    /// [`DEFAULT_TOLERANCE_C`](crate::models::campaign::DEFAULT_TOLERANCE_C) for a file
    /// written before it was. `None` for a calibration of one run.
    /// Any axis that records the runs tells it (a unit read from a file records them on every
    /// axis alike, [`UnitCalibration::validate`]).
    pub fn campaign_tolerance_c(&self) -> Option<f64> {
        let s = self
            .axes
            .iter()
            .map(|a| a.model.source())
            .find(|s| !s.runs.is_empty())?;
        Some(
            s.temp_tolerance_c
                .unwrap_or(crate::models::campaign::DEFAULT_TOLERANCE_C),
        )
    }

    /// The axes' names, in order.
    pub fn axis_names(&self) -> Vec<&str> {
        self.axes.iter().map(|a| a.name.as_str()).collect()
    }

    /// Whether any axis is an accelerometer's.
    pub fn has_accelerometers(&self) -> bool {
        self.axes.iter().any(|a| a.kind == AxisKind::Accel)
    }

    /// The axis named `name`.
    pub fn axis(&self, name: &str) -> Option<&AxisModel> {
        self.axes.iter().find(|a| a.name == name)
    }

    /// The first axis's model: the model of a single-axis calibration.
    ///
    /// # Errors
    /// [`Error::Internal`] for a unit without axes (never made by driftlab, refused by
    /// [`UnitCalibration::validate`]).
    pub fn first(&self) -> Result<&DriftModel> {
        self.axes
            .first()
            .map(|a| &a.model)
            .ok_or(Error::Internal("a unit calibration without axes"))
    }

    /// Checks a unit read from a file or about to be written: at least one axis, names unique
    /// and not empty in a unit of several, each model as [`DriftModel::validate`] checks it
    /// (its field named with the axis, `axes[gy].k0...`), every axis's record of a campaign's
    /// runs the first axis's but for the biases and offsets
    /// ([`check_same_runs`](crate::models::campaign::check_same_runs)), and the T settings of
    /// its Vakhrameev axes alike (they were made from one T).
    ///
    /// # Errors
    /// An [`Invalid`] naming the axis and the field.
    pub fn validate(&self) -> std::result::Result<(), Invalid> {
        if self.axes.is_empty() {
            return Err(Invalid::new("axes", "a unit needs at least one axis"));
        }
        if self.axes.len() > MAX_UNIT_AXES {
            return Err(Invalid::new(
                "axes",
                format!(
                    "{} axes: a unit has at most {MAX_UNIT_AXES} (each corrected axis holds \
                     columns the length of the log)",
                    self.axes.len()
                ),
            ));
        }
        for (k, a) in self.axes.iter().enumerate() {
            let field = |f: &str| format!("axes[{}].{f}", label(k, &a.name));
            if self.axes.len() > 1 && a.name.trim().is_empty() {
                return Err(Invalid::new(
                    field("name"),
                    "every axis of a unit of several needs a name",
                ));
            }
            if let Some(c) = a.name.chars().find(|&c| crate::text::is_unprintable(c)) {
                return Err(Invalid::new(
                    "axes.name",
                    format!(
                        "axis {k}'s name holds {}: a name is printable text",
                        crate::text::unprintable_named(c)
                    ),
                ));
            }
            if self.axes[..k].iter().any(|b| b.name == a.name) {
                return Err(Invalid::new(
                    field("name"),
                    format!("\"{}\" names two axes", a.name),
                ));
            }
            a.model
                .validate()
                .map_err(|e| Invalid::new(field(&e.field), e.reason))?;
            check_kind(self, k).map_err(|(name, reason)| Invalid::new(field(name), reason))?;
            if k > 0 {
                let first = &self.axes[0];
                crate::models::campaign::check_same_runs(
                    &a.model.source().runs,
                    &first.model.source().runs,
                    &label(0, &first.name),
                )
                .map_err(|e| Invalid::new(field(&e.field), e.reason))?;
            }
        }
        let recipes: Vec<(&str, &Recipe)> = self
            .axes
            .iter()
            .filter_map(|a| match &a.model {
                DriftModel::Vakhrameev(c) => Some((a.name.as_str(), &c.recipe)),
                DriftModel::Regression(_) => None,
            })
            .collect();
        if let Some((first_name, first)) = recipes.first() {
            for (name, r) in &recipes[1..] {
                if let Some(setting) = differing_temperature_setting(first, r) {
                    return Err(Invalid::new(
                        format!("axes[{name}].recipe.{setting}"),
                        format!(
                            "differs from axis {first_name}'s: the axes of a unit share T, and \
                             so how it is smoothed, differentiated and split into plateaus"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

impl UnitCalibration {
    /// Checks that no axis's rate column is another axis's: the column an axis was read from
    /// names an axis (as the log reader names it: `gy` for `gy_dps`),
    /// and when that is another axis of the unit, the names or the columns were swapped, and
    /// `apply`, which finds an axis by its name first, would correct one axis's column with
    /// another's coefficients.
    ///
    /// Run on every unit file read (a unit made in memory, as by a test of names, may pair
    /// them as it likes until it is written).
    ///
    /// # Errors
    /// An [`Invalid`] naming the axis's `rate_column` and the other axis's name.
    pub fn check_rate_columns(&self) -> std::result::Result<(), Invalid> {
        for (k, a) in self.axes.iter().enumerate() {
            if a.rate_column.is_empty() {
                continue;
            }
            let of_column = crate::log::ingest::names::axis_name(&a.rate_column);
            if of_column == a.name {
                continue;
            }
            if let Some(other) = self.axes.iter().find(|b| b.name == of_column) {
                return Err(Invalid::new(
                    format!("axes[{}].rate_column", label(k, &a.name)),
                    format!(
                        "\"{col}\" is the column of axis {other} (another axis of the unit), \
                         not of axis {name}: the names or the columns were swapped, and \
                         apply, which finds an axis by its name, would correct axis {name} \
                         with the coefficients fitted on \"{col}\"",
                        col = a.rate_column.escape_debug(),
                        other = other.name,
                        name = a.name,
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Checks what the kind of axis `k` of `unit` says of it: an accelerometer axis is named,
/// listed after every gyro axis (the order every writer keeps), holds a static model and the
/// finite mean it keeps; a gyro axis keeps none.
/// The field at fault is named with the reason.
fn check_kind(unit: &UnitCalibration, k: usize) -> std::result::Result<(), (&'static str, String)> {
    let a = &unit.axes[k];
    match a.kind {
        AxisKind::Gyro => {
            if a.kept_mean.is_some() {
                return Err((
                    "kept_mean_m_s2",
                    "a gyro axis keeps no mean: kept_mean_m_s2 is an accelerometer's".into(),
                ));
            }
            if unit.axes[..k].iter().any(|b| b.kind == AxisKind::Accel) {
                return Err((
                    "kind",
                    "a gyro axis after an accelerometer axis: a unit lists its gyro axes first"
                        .into(),
                ));
            }
        }
        AxisKind::Accel => {
            if a.name.trim().is_empty() {
                return Err(("name", "an accelerometer axis needs a name".into()));
            }
            match a.kept_mean {
                Some(m)
                    if m.is_finite() && m.abs() <= 100.0 * crate::log::STANDARD_GRAVITY_M_S2 => {}
                Some(m) => {
                    return Err((
                        "kept_mean_m_s2",
                        format!(
                            "{} m/s² is no mean an accelerometer at rest reads (at most 100 g)",
                            crate::number::readable(m)
                        ),
                    ));
                }
                None => {
                    return Err((
                        "kept_mean_m_s2",
                        "an accelerometer axis records the mean it keeps (kept_mean_m_s2)".into(),
                    ));
                }
            }
            let static_model = match &a.model {
                DriftModel::Regression(r) => {
                    super::accel::is_static(&ModelChoice::Custom(r.model.spec.clone()))
                }
                DriftModel::Vakhrameev(_) => false,
            };
            if !static_model {
                return Err((
                    "model",
                    format!(
                        "model {} reads more than T: an accelerometer axis takes a static curve in T \
                     ({})",
                        a.model.name(),
                        super::accel::STATIC_MODELS
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// An axis in a message: its name, or its position when it has none.
fn label(k: usize, name: &str) -> String {
    if name.is_empty() {
        k.to_string()
    } else {
        name.to_string()
    }
}

/// The first T setting (by its name in a recipe file) that differs between two recipes.
pub fn differing_temperature_setting(a: &Recipe, b: &Recipe) -> Option<&'static str> {
    if a.temp_smoothing_s != b.temp_smoothing_s {
        Some("temp_smoothing_s")
    } else if a.step_h_s != b.step_h_s {
        Some("step_h_s")
    } else if a.plateaus != b.plateaus {
        Some("plateaus")
    } else {
        None
    }
}

/// What to fit on one axis of a unit.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisPlan {
    /// The axis, as [`Log::axis_names`] names it; empty for the one axis of a calibration
    /// that names none ([`AxisPlan::unnamed`]).
    pub name: String,
    /// The model to fit.
    pub choice: ModelChoice,
    /// The settings, checked; its T settings are those of every Vakhrameev axis of the unit.
    pub recipe: CheckedRecipe,
}

impl AxisPlan {
    /// The plan of a calibration of one unnamed axis: the axis `omega_dph` holds, written as
    /// a single-axis (version-1) calibration.
    pub fn unnamed(choice: ModelChoice, recipe: CheckedRecipe) -> AxisPlan {
        AxisPlan {
            name: String::new(),
            choice,
            recipe,
        }
    }
}

/// One axis fitted and judged on the log it was fitted on.
#[derive(Debug, Clone)]
pub struct CalibratedAxis {
    /// The axis's name (empty for an [`AxisPlan::unnamed`] one).
    pub name: String,
    /// The rate column it was read from (empty when the log does not say, or the axis is
    /// unnamed).
    pub rate_column: String,
    /// The model, its in-sample figures (an accelerometer's about the mean it keeps) and its
    /// warnings.
    pub calibrated: Calibrated,
    /// What the axis measures.
    pub kind: AxisKind,
    /// The mean an accelerometer axis keeps ([`AxisModel::kept_mean`]).
    pub kept_mean: Option<f64>,
    /// The corrected rate its in-sample figures were read from, when the caller asked to keep
    /// it ([`Keep::Corrected`]): a caller that reads more of it (the lot's Allan figures)
    /// takes it here rather than correcting the log a second time. `None` otherwise, so that
    /// a unit of many axes on a long log holds one axis's corrected rate at a time.
    pub corrected: Option<CorrectedRate>,
}

/// Whether [`calibrate`] keeps each axis's corrected rate beside its fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Keep {
    /// The figures alone: each corrected rate dropped once judged.
    #[default]
    Figures,
    /// Each axis's corrected rate too ([`CalibratedAxis::corrected`]).
    Corrected,
}

impl CalibratedAxis {
    /// The axis of a unit's calibration this fit makes, with `model` (the fitted one, stamped
    /// by the caller with its log's name and runs).
    pub fn axis_model(&self, model: DriftModel) -> AxisModel {
        AxisModel {
            name: self.name.clone(),
            rate_column: self.rate_column.clone(),
            model,
            kind: self.kind,
            kept_mean: self.kept_mean,
        }
    }
}

/// Fits and judges every axis of `plans` on `log`, in their order, reading T once for all the
/// Vakhrameev axes: each gets the calibration a unit of that axis alone makes, bit for bit.
/// A log of one axis is calibrated as a unit of one ([`AxisPlan::unnamed`]). `log` ends as it
/// started: the same axis in `omega_dph`, the others in the same order.
///
/// For Vakhrameev's model the figures on the log reuse the fit's derivatives and hold only the
/// corrected rate, which on a 10⁷-sample log saves hundreds of MB over a whole correction.
///
/// # Errors
/// A [`FitError`] naming an axis the log does not have, two plans for one axis, or no plan;
/// an [`Invalid`] naming the axis and the setting when the Vakhrameev axes' T settings differ;
/// what a fit reports, with the axis named.
pub fn calibrate(
    log: &mut Log,
    plans: &[AxisPlan],
    merit: &MeritOptions,
) -> Result<Vec<CalibratedAxis>> {
    calibrate_keeping(log, plans, merit, Keep::Figures)
}

/// [`calibrate`], keeping each axis's corrected rate when `keep` says so.
///
/// # Errors
/// What [`calibrate`] refuses.
pub fn calibrate_keeping(
    log: &mut Log,
    plans: &[AxisPlan],
    merit: &MeritOptions,
    keep: Keep,
) -> Result<Vec<CalibratedAxis>> {
    check_plans(log, plans)?;
    let order = log.axis_names();
    let result = calibrate_axes(log, plans, merit, keep);
    log.select_axis(&order[0]);
    log.order_axes_as(&order);
    result
}

fn check_plans(log: &Log, plans: &[AxisPlan]) -> Result<()> {
    if plans.is_empty() {
        return Err(FitError::NoAxes {
            log: log.source.clone(),
        }
        .into());
    }
    if plans.len() > MAX_UNIT_AXES {
        return Err(Invalid::new(
            "axes",
            format!(
                "{} axes asked of {}: a unit has at most {MAX_UNIT_AXES}",
                plans.len(),
                log.source
            ),
        )
        .into());
    }
    if let [only] = plans
        && only.name.is_empty()
    {
        // A unit of one unnamed axis: the one `omega_dph` holds.
        return Ok(());
    }
    if plans.iter().any(|p| p.name.is_empty()) {
        return Err(Invalid::new(
            "axes",
            format!(
                "an axis without a name among {} axes of {}: only a calibration of one axis \
                 may leave it unnamed",
                plans.len(),
                log.source
            ),
        )
        .into());
    }
    let names = log.axis_names();
    for (k, p) in plans.iter().enumerate() {
        if log.kind_of(&p.name) == Some(AxisKind::Accel) {
            super::accel::check_static(log, &p.name, &p.choice)?;
            if log.runs().len() > 1 {
                return Err(Invalid::new(
                    "axes",
                    format!(
                        "accelerometer axis {}: a campaign of {} runs calibrates its gyro axes; \
                         an accelerometer's mean is kept from one run, so calibrate its \
                         accelerometers on one run",
                        p.name,
                        log.runs().len()
                    ),
                )
                .into());
            }
        }
        if log.kind_of(&p.name) == Some(AxisKind::Gyro)
            && let Some(a) = plans[..k]
                .iter()
                .find(|q| log.kind_of(&q.name) == Some(AxisKind::Accel))
        {
            return Err(Invalid::new(
                "axes",
                format!(
                    "gyro axis {} after accelerometer axis {}: a unit lists its gyro axes first",
                    p.name, a.name
                ),
            )
            .into());
        }
        if !names.contains(&p.name) {
            return Err(FitError::MissingAxis {
                log: log.source.clone(),
                axis: p.name.clone(),
                available: names,
            }
            .into());
        }
        if plans[..k].iter().any(|q| q.name == p.name) {
            return Err(FitError::AxisTwice {
                log: log.source.clone(),
                axis: p.name.clone(),
            }
            .into());
        }
    }
    let vakhrameev: Vec<&AxisPlan> = plans.iter().filter(|p| p.choice.is_vakhrameev()).collect();
    if let Some(first) = vakhrameev.first() {
        for p in &vakhrameev[1..] {
            if let Some(setting) = differing_temperature_setting(&first.recipe, &p.recipe) {
                return Err(Invalid::new(
                    format!("axis {}: {setting}", p.name),
                    format!(
                        "differs from axis {}'s: the axes of a unit share T, and so how it is \
                         smoothed, differentiated and split into plateaus",
                        first.name
                    ),
                )
                .into());
            }
        }
    }
    Ok(())
}

fn calibrate_axes(
    log: &mut Log,
    plans: &[AxisPlan],
    merit: &MeritOptions,
    keep: Keep,
) -> Result<Vec<CalibratedAxis>> {
    let kept = |c: CorrectedRate| (keep == Keep::Corrected).then_some(c);
    let about = |name: &str, e: Error| match e {
        _ if name.is_empty() => e,
        Error::Fit(e) => Error::Fit(e.on_axis(name)),
        Error::Invalid(i) => {
            Error::Invalid(Invalid::new(format!("axis {name}: {}", i.field), i.reason))
        }
        other => other,
    };
    // Each axis's own rate, before any is fitted: a stuck axis, or one holding readings no
    // sensor gives, is refused as `evaluate` refuses it, not written into the unit, and not
    // after the other axes' fits.
    for plan in plans {
        select(log, &plan.name);
        crate::models::check_axis_readings(log)?;
    }
    if let Some(first) = plans.first() {
        select(log, &first.name);
    }
    // T's part, once, from the first Vakhrameev axis's recipe (they all agree), with that
    // axis's Ω filtered beside it.
    let mut shared = match plans.iter().position(|p| p.choice.is_vakhrameev()) {
        Some(k) => {
            let p = &plans[k];
            check_span(log, &p.choice)?;
            select(log, &p.name);
            let (pipeline, filtered) =
                vakhrameev::Pipeline::with_omega(log, &p.recipe).map_err(|e| about(&p.name, e))?;
            Some((pipeline, Some((k, filtered))))
        }
        None => None,
    };
    let mut out = Vec::with_capacity(plans.len());
    for (k, plan) in plans.iter().enumerate() {
        select(log, &plan.name);
        // The figures are filtered as the axis's recipe filters Ω.
        let merit = &MeritOptions {
            filter_s: plan.recipe.filter_s,
            ..*merit
        };
        // An accelerometer axis: fitted and judged about the mean it keeps.
        if log.axis_kind == AxisKind::Accel {
            let mean = super::accel::mean_of(&log.omega_dph);
            let centred = super::accel::about_mean(log, mean);
            let (calibrated, corrected) =
                regression_axis(&centred, &plan.choice, &plan.recipe, merit)
                    .map_err(|e| about(&plan.name, e))?;
            out.push(CalibratedAxis {
                name: plan.name.clone(),
                rate_column: log.rate_column().unwrap_or_default(),
                calibrated,
                kind: AxisKind::Accel,
                kept_mean: Some(mean),
                corrected: kept(corrected),
            });
            continue;
        }
        let (calibrated, corrected) = match shared.as_mut().filter(|_| plan.choice.is_vakhrameev())
        {
            Some((shared, first)) => {
                let filtered = first.take_if(|(axis, _)| *axis == k).map(|(_, f)| f);
                let (calibration, mut warnings) = shared
                    .fit_axis(log, &plan.recipe, filtered)
                    .map_err(|e| about(&plan.name, e))?;
                let c = calibration.corrected_rate_with(log, shared.derivatives());
                // `Evaluation::of_rate`, with the step the shared part found (not found again
                // from the time stamps for each axis).
                let used: usize = c.ready.iter().map(|r| r.len()).sum();
                let dt_s = calibration.resolved.dt_s;
                let in_sample = Evaluation {
                    comparison: Comparison::of(&log.omega_dph, &c.cor_dph, dt_s, &c.ready, merit),
                    outside_fraction: c.outside_fraction,
                    warmup_samples: log.len().saturating_sub(used),
                    left_out: calibration.left_out(),
                };
                let model = DriftModel::Vakhrameev(Box::new(calibration));
                warnings.extend(judge_on_own_log(&model, &in_sample));
                let calibrated = Calibrated {
                    model,
                    in_sample,
                    warnings,
                };
                (calibrated, c)
            }
            None => regression_axis(log, &plan.choice, &plan.recipe, merit)
                .map_err(|e| about(&plan.name, e))?,
        };
        out.push(CalibratedAxis {
            name: plan.name.clone(),
            rate_column: match plan.name.is_empty() {
                true => String::new(),
                false => log.rate_column().unwrap_or_default(),
            },
            calibrated,
            kind: AxisKind::Gyro,
            kept_mean: None,
            corrected: kept(corrected),
        });
    }
    Ok(out)
}

/// Puts the axis named `name` in `omega_dph`; an unnamed plan's axis is already there.
fn select(log: &mut Log, name: &str) {
    if !name.is_empty() {
        log.select_axis(name);
    }
}

/// An axis of a model fitted over every sample (not Vakhrameev's): fitted, corrected and
/// judged on its own log; with the corrected rate it was judged on.
fn regression_axis(
    log: &Log,
    choice: &ModelChoice,
    recipe: &CheckedRecipe,
    merit: &MeritOptions,
) -> Result<(Calibrated, CorrectedRate)> {
    let model = fit(log, choice, recipe)?;
    let correction = model.correct(log)?;
    let in_sample = Evaluation::of_correction(log, &correction, merit);
    let calibrated = Calibrated {
        warnings: judge_on_own_log(&model, &in_sample),
        in_sample,
        model,
    };
    let corrected = CorrectedRate {
        cor_dph: correction.cor_dph,
        outside_fraction: correction.outside_fraction,
        ready_from: correction.ready_from,
        ready: correction.ready,
    };
    Ok((calibrated, corrected))
}
