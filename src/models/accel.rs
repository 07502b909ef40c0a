//! Accelerometer axes in the fit: the models they take, the mean they keep, and the axis that
//! carries gravity. Everything else of an accelerometer axis is a gyro axis's: the same T, the
//! same plateaus, the same fit, correction and writers ([`super::unit`]).
//!
//! **Models.** An accelerometer's bias follows its die's temperature, not how fast it moves:
//! it takes the static models (a polynomial in T, `poly-t`, `poly-tN`, the flight controllers'
//! `px4` and `ardupilot` forms and their scripts' fits, `pwl-t`, a custom model of T's terms),
//! and a model with rate terms or another channel is refused by name ([`check_static`]).
//!
//! **The mean it keeps.** A chamber run holds the unit in one orientation, in which gravity's
//! share on an axis and its bias at rest are one constant: no single run tells them apart. An
//! accelerometer axis is therefore fitted on its samples less their mean on the calibration
//! log ([`about_mean`]); its model predicts the change with T about that mean, and its
//! correction keeps the mean: the axis along g still reads g. The constant is the ordinary
//! accelerometer calibration's, as PX4's and ArduPilot's thermal calibrations leave it. The
//! mean is recorded in the unit ([`super::AxisModel::kept_mean`]); every judgement of the axis
//! takes its samples less it ([`as_fitted`]), so its figures are of the change with T and the
//! log it was fitted on is told as its own.
//!
//! **Gravity.** The axis whose mean is at least half of g carries gravity ([`gravity`]); the
//! change of its reading with T, over its mean, is its scale factor's change with T (with its
//! bias's change, which one orientation cannot part from it).

use crate::log::{AxisKind, Log, STANDARD_GRAVITY_M_S2};
use crate::models::presets::{ModelChoice, Preset};
use crate::models::regression::{DelaySpec, LagSpec, Term};
use crate::models::unit::UnitCalibration;
use crate::models::{DriftModel, FitError};
use std::borrow::Cow;

/// The model an accelerometer axis takes when none is named: a cubic in T − Tref, Tref the
/// middle of the range, the form both flight controllers evaluate.
pub const DEFAULT_MODEL: Preset = Preset::PolyOrder(3);

/// The static models, in words, for a refusal.
pub const STATIC_MODELS: &str = "poly-t, poly-tN, px4, ardupilot, pwl-t, px4-script, \
     ardupilot-script, or a custom model of 1, T, T^2, T^3, (T-Tref)^k and pwlT:N";

/// Whether `choice` is a static model: a curve in T alone, with no rate term, no other
/// channel, no delay and no lag.
pub fn is_static(choice: &ModelChoice) -> bool {
    match choice {
        ModelChoice::Preset(p) => matches!(
            p,
            Preset::PolyT
                | Preset::PwlT
                | Preset::Px4
                | Preset::ArduPilot
                | Preset::PolyOrder(_)
                | Preset::Px4Script
                | Preset::ArduPilotScript
        ),
        ModelChoice::Custom(s) => {
            s.terms.iter().all(|t| {
                matches!(
                    t,
                    Term::One | Term::T | Term::T2 | Term::T3 | Term::PwlT { .. } | Term::Tc { .. }
                )
            }) && s.delay == DelaySpec::None
                && s.lag == LagSpec::None
                && s.temp2.is_none()
        }
    }
}

/// Refuses `choice` for the accelerometer axis `axis` of `log` unless it is static.
///
/// # Errors
/// [`FitError::NotStatic`], naming the axis and the model.
pub fn check_static(log: &Log, axis: &str, choice: &ModelChoice) -> Result<(), FitError> {
    if is_static(choice) {
        return Ok(());
    }
    Err(FitError::NotStatic {
        log: log.source.clone(),
        axis: axis.to_string(),
        model: choice.name().to_string(),
    })
}

/// The mean of an accelerometer axis's samples, the constant its correction keeps (a cell the
/// reader could not read is no sample; the fit skips it as it skips a gyro's), over the
/// readings an accelerometer gives: a stretch of 10³⁸ (refused by every fit and judgement,
/// [`crate::models::check_axis_readings`]) would make every other sample read as beyond, and the
/// log's orientation seem turned.
pub fn mean_of(samples: &[f64]) -> f64 {
    crate::log::accel_axes::mean_within(samples, crate::log::impossible::MAX_PLAUSIBLE_ACCEL_M_S2)
}

/// `log` with the samples of the axis it holds less `mean`: what an accelerometer axis is
/// fitted and judged on. The time, temperature and what the reader noticed are the log's;
/// the other axes and channels, which a static model does not read, are left out.
pub fn about_mean(log: &Log, mean: f64) -> Log {
    let mut out = Log::from_columns(
        &log.source,
        log.time_s.clone(),
        log.omega_dph.iter().map(|v| v - mean).collect(),
        log.temp_c.clone(),
    );
    out.axis = log.axis.clone();
    out.axis_kind = log.axis_kind;
    out.info = log.info.clone();
    out
}

/// `log` (holding the axis a unit's axis of kind `kind` corrects) as that axis's model was
/// fitted: an accelerometer's samples less the mean it keeps, a gyro's as they are. A log
/// whose mean on the axis is more than [`ORIENTATION_SHIFT_G`] from the kept one was run in
/// another orientation (z down after z up) or on another unit: gravity's share differs, and
/// taken about the kept mean it would be judged as drift (2 g of it); its samples are then
/// taken less their own mean ([`orientation_note`] says so).
pub fn as_fitted(log: &Log, kind: AxisKind, kept_mean: Option<f64>) -> Cow<'_, Log> {
    match (kind, kept_mean) {
        (AxisKind::Accel, Some(kept)) => {
            let own = mean_of(&log.omega_dph);
            let mean = if moved(own, kept) { own } else { kept };
            Cow::Owned(about_mean(log, mean))
        }
        _ => Cow::Borrowed(log),
    }
}

/// How far, in g, a log's mean on an accelerometer axis may lie from the mean its calibration
/// keeps and still be taken as the same orientation: a turn-on bias and a unit set down again
/// move it by milli-g, a quarter turn or a flip by 1 or 2 g.
pub const ORIENTATION_SHIFT_G: f64 = 0.05;

fn moved(own: f64, kept: f64) -> bool {
    (own - kept).abs() > ORIENTATION_SHIFT_G * STANDARD_GRAVITY_M_S2
}

/// What to tell of an accelerometer axis `axis` judged on `log` (holding its samples) when the
/// log's mean is not the kept one ([`as_fitted`]); `None` when it is, or for a gyro axis.
pub fn orientation_note(
    log: &Log,
    axis: &str,
    kind: AxisKind,
    kept_mean: Option<f64>,
) -> Option<String> {
    let (AxisKind::Accel, Some(kept)) = (kind, kept_mean) else {
        return None;
    };
    let own = mean_of(&log.omega_dph);
    moved(own, kept).then(|| {
        let r = crate::number::readable;
        format!(
            "{}: accelerometer axis {axis} reads a mean of {} m/s² here, {} m/s² ({} g) from \
             the {} m/s² its calibration keeps: another orientation or another unit; its \
             figures are of its change about this log's own mean",
            log.source,
            r(own),
            r(own - kept),
            r((own - kept) / STANDARD_GRAVITY_M_S2),
            r(kept)
        )
    })
}

/// The axis of a unit that carries gravity, and how its reading changes with T.
#[derive(Debug, Clone, PartialEq)]
pub struct Gravity {
    /// The axis's name.
    pub axis: String,
    /// Its mean on the calibration log, m/s²: gravity's share on it, with its bias at rest.
    pub mean_m_s2: f64,
    /// The temperatures its model was fitted over, °C.
    pub range_c: (f64, f64),
    /// The change of its reading over that range, per °C, as a share of its mean: its scale
    /// factor's change with T, its bias's change included (one orientation cannot part them);
    /// `None` where the model cannot be read at the ends of its range.
    pub scale_change_per_c: Option<f64>,
}

/// The accelerometer axis of `unit` that carries gravity: the one whose kept mean is largest,
/// when it is at least half of g (a unit on its side shares g between two axes, each reading
/// 0.7 g; one lying level reads it on one). `None` when no axis reads that much.
pub fn gravity(unit: &UnitCalibration) -> Option<Gravity> {
    let (ax, mean) = unit
        .axes
        .iter()
        .filter(|a| a.kind == AxisKind::Accel)
        .filter_map(|a| a.kept_mean.map(|m| (a, m)))
        .filter(|(_, m)| m.abs() >= 0.5 * STANDARD_GRAVITY_M_S2)
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))?;
    let (range_c, change) = match static_ends(&ax.model) {
        Some(((lo, hi), (p_lo, p_hi))) => (
            (lo, hi),
            (hi > lo).then(|| (p_hi - p_lo) / (hi - lo) / mean),
        ),
        None => ((f64::NAN, f64::NAN), None),
    };
    Some(Gravity {
        axis: ax.name.clone(),
        mean_m_s2: mean,
        range_c,
        scale_change_per_c: change,
    })
}

/// A static model's fitted T range and its prediction at either end.
fn static_ends(model: &DriftModel) -> Option<((f64, f64), (f64, f64))> {
    let DriftModel::Regression(r) = model else {
        return None;
    };
    let [lo, hi] = r.model.ranges.temp?;
    Some(((lo, hi), (static_at(model, lo)?, static_at(model, hi)?)))
}

/// What a static model (an accelerometer axis's) predicts at temperature `temp_c`, T held to
/// its fitted range as its correction holds it; `None` for a model that reads more than T.
pub fn static_at(model: &DriftModel, temp_c: f64) -> Option<f64> {
    let DriftModel::Regression(r) = model else {
        return None;
    };
    let m = &r.model;
    if !is_static(&ModelChoice::Custom(m.spec.clone())) {
        return None;
    }
    let mut x = crate::models::regression::terms::Inputs {
        t_s: 0.0,
        temp: temp_c,
        tdot: 0.0,
        tddot: 0.0,
        dt: 0.0,
    };
    m.clamp(&mut x, &mut []);
    let mut row = Vec::new();
    Some(m.predict(&x, &[], &mut row))
}

/// A log of one gyro axis without a name beside accelerometer axes: a unit's axes are found
/// in a log (and its calibration's in the next) by their names, and the gyro's has none.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "{log}: its gyro axis has no name, and a unit's axes are found by theirs: name its rate \
     column, or calibrate the accelerometers alone (axes {})",
    accels.join(",")
)]
pub struct UnnamedGyro {
    /// The log.
    pub log: String,
    /// Its accelerometer axes.
    pub accels: Vec<String>,
}

/// The axes a unit is calibrated on when its accelerometer axes are asked for: `chosen`, the
/// gyro axes a face chose (`None`: the log's one axis, unnamed), then every accelerometer
/// axis of `log`; `by_hand`: the engineer named the axes to fit (`--axes`), and they are
/// taken as named, accelerometers among them or not. A log of one gyro axis becomes a unit
/// of that axis, by its name, and the accelerometers: the one rule `calibrate --accel` and
/// the workbench choose by, so that a log of one gyro and three accelerometers is the same
/// unit of four axes in both.
///
/// # Errors
/// [`UnnamedGyro`]: the log's one gyro axis has no name to find it by.
pub fn with_accelerometers(
    chosen: Option<Vec<String>>,
    by_hand: bool,
    log: &Log,
) -> Result<Option<Vec<String>>, UnnamedGyro> {
    let accels = log.axes_of(AxisKind::Accel);
    if accels.is_empty() {
        return Ok(chosen);
    }
    let mut axes = match chosen {
        Some(axes) if by_hand => return Ok(Some(axes)),
        Some(axes) => axes
            .into_iter()
            .filter(|n| log.kind_of(n) == Some(AxisKind::Gyro))
            .collect(),
        None if log.axis.is_empty() => {
            return Err(UnnamedGyro {
                log: log.source.clone(),
                accels,
            });
        }
        None => vec![log.axis.clone()],
    };
    axes.extend(accels);
    Ok(Some(axes))
}

/// Every accelerometer axis of `log` (in the log's order), each with [`DEFAULT_MODEL`] and
/// `recipe`: the plans `calibrate --accel` makes when no model is named, for a face that
/// offers the accelerometers without a model of their own (the workbench).
pub fn default_plans(
    log: &Log,
    recipe: &crate::models::recipe::CheckedRecipe,
) -> Vec<crate::models::AxisPlan> {
    log.axes_of(AxisKind::Accel)
        .into_iter()
        .map(|name| crate::models::AxisPlan {
            name,
            choice: ModelChoice::Preset(DEFAULT_MODEL),
            recipe: recipe.clone(),
        })
        .collect()
}
