//! Whether an axis's readings can be fitted or judged at all: the one up-front check every fit,
//! `evaluate`, `compare`, `report` and `allan` make of an axis before any figure is taken of
//! it. Three things make an axis's readings unusable whatever the model: a rate held at one
//! value (a wire, not a sensor), more readings beyond what any sensor gives than the readers
//! take for glitches ([`crate::log::impossible`]), and a gyro axis most of whose samples are
//! missing. A figure taken through any of them is rounding or 10³⁸, so it is refused here,
//! naming the axis and where, rather than printed.
//!
//! A campaign's joined log is checked run by run: a share over the joined log dilutes one
//! run's stretch of garbage among the other runs' samples (600 readings are 1.49 % of their
//! run and 0.5 % of three), and the joined time axis is in no file. Each run is judged as it
//! would be alone, and the refusal names it with its own share and its own times.

use super::FitError;
use crate::error::Result;
use crate::log::{AxisKind, Log};

/// One axis's readings to check: what [`check_readings`] needs of a log, so that a face
/// holding a series without a [`Log`] (a column of rate samples, an accelerometer's column)
/// checks it by the same rule.
#[derive(Debug, Clone, Copy)]
pub struct AxisReadings<'a> {
    /// The log (or the run) the readings are of, as messages name it.
    pub source: &'a str,
    /// The axis's name, empty for a log of one.
    pub axis: &'a str,
    /// What the axis measures: its bound, and its words.
    pub kind: AxisKind,
    /// The readings, in the kind's unit (°/h, m/s²).
    pub values: &'a [f64],
    /// The time of each reading, s, as the file has it (a reading without one is told at NaN).
    pub time_s: &'a [f64],
    /// What was added to the file's times to give `time_s` (a run placed on a campaign's
    /// joined time axis): taken off again in messages.
    pub time_shift_s: f64,
}

/// Refuses a log's selected axis whose readings no fit or figure can take: checked over each
/// run of a campaign's joined log in turn (`LogInfo::runs`), else over the whole log.
///
/// Every fit asks it ([`super::check_span`]), and so do `evaluate`, `compare`, `report` (which
/// leaves the log out of that axis's tables with this reason) and `allan`.
///
/// # Errors
/// As [`check_readings`], naming the run for a campaign.
pub fn check_axis_readings(log: &Log) -> Result<()> {
    let whole = AxisReadings {
        source: &log.source,
        axis: &log.axis,
        kind: log.axis_kind,
        values: &log.omega_dph,
        time_s: &log.time_s,
        time_shift_s: 0.0,
    };
    let spans = &log.info.runs;
    let fits = spans
        .iter()
        .all(|r| r.samples.end <= log.omega_dph.len() && r.samples.end <= log.time_s.len());
    if spans.len() < 2 || !fits {
        return check_readings(&whole);
    }
    for r in spans {
        check_readings(&AxisReadings {
            source: &r.name,
            values: &log.omega_dph[r.samples.clone()],
            time_s: &log.time_s[r.samples.clone()],
            time_shift_s: r.time_shift_s,
            ..whole
        })?;
    }
    Ok(())
}

/// Refuses an axis whose readings hold one value throughout (of the finite ones), more
/// readings beyond [`crate::log::impossible`]'s bound (10⁴ °/s, 1000 g) than the readers
/// drop as glitches, or, for a gyro axis, more than 1 % of its samples missing.
///
/// Any real sensor's output moves by its noise from one sample to the next; one value is a
/// wire, and every figure fitted to it, or judged on it, is rounding. A reading beyond the
/// bound is garbage the readers drop while it is a glitch; more of them are kept and told,
/// and a fit or a figure through them reads 10³⁸.
///
/// # Errors
/// [`FitError::FrozenRate`], naming the axis and the value; [`FitError::Impossible`], naming
/// the axis, how many readings, their share and when; [`FitError::MissingSamples`], a gyro
/// axis with more than 1 % of its samples missing.
pub fn check_readings(r: &AxisReadings<'_>) -> Result<()> {
    use crate::log::impossible::{MAX_PLAUSIBLE_ACCEL_M_S2, MOST_GLITCH_SHARE, beyond};
    let bound = match r.kind {
        AxisKind::Gyro => crate::log::mapping_check::MAX_PLAUSIBLE_RATE_DPH,
        AxisKind::Accel => MAX_PLAUSIBLE_ACCEL_M_S2,
    };
    let mut first: Option<f64> = None;
    let mut frozen = true;
    let mut beyond_any = false;
    let mut missing = 0usize;
    for &v in r.values {
        if !v.is_finite() {
            beyond_any |= v.is_infinite();
            missing += usize::from(v.is_nan());
            continue;
        }
        beyond_any |= v.abs() > bound;
        match first {
            None => first = Some(v),
            Some(f) => frozen &= v.to_bits() == f.to_bits(),
        }
    }
    // The readers drop the readings beyond while they are glitches: any left are the axis's.
    if beyond_any && let Some(b) = beyond(r.values.iter().copied(), bound) {
        let at = |k: usize| r.time_s.get(k).map_or(f64::NAN, |t| t - r.time_shift_s);
        return Err(FitError::Impossible {
            log: r.source.to_string(),
            axis: r.axis.to_string(),
            kind: r.kind,
            count: b.samples.len(),
            readings: b.readings,
            worst: b.worst,
            first_s: at(b.samples[0]),
            last_s: at(b.samples[b.samples.len() - 1]),
        }
        .into());
    }
    // A gyro axis whose column is mostly not read (the readers drop the rows of a few missing
    // cells): an accelerometer may be logged at a lower rate than its gyro, and its missing
    // samples are none of the fit's, but a gyro axis's Ω is the fit's every sample.
    let total = r.values.len();
    if r.kind == AxisKind::Gyro && missing as f64 > MOST_GLITCH_SHARE * total as f64 {
        return Err(FitError::MissingSamples {
            log: r.source.to_string(),
            axis: r.axis.to_string(),
            count: missing,
            total,
        }
        .into());
    }
    // One sample is no stretch at all: it takes two to hold a value.
    let finite = r.values.iter().filter(|v| v.is_finite()).take(2).count();
    if frozen
        && finite == 2
        && let Some(value_dph) = first
    {
        return Err(FitError::FrozenRate {
            log: r.source.to_string(),
            axis: r.axis.to_string(),
            kind: r.kind,
            value_dph,
        }
        .into());
    }
    Ok(())
}
