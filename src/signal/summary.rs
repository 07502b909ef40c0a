//! A log at a glance, before anything is fitted: the temperature range it covers, the fastest
//! temperature rate it holds and the plateaus the detector finds in it. `driftlab inspect`
//! prints it, so an engineer sees whether a log can calibrate anything before calibrating.
//!
//! The rates and plateaus are those a fit with the same settings sees: T is smoothed and
//! differentiated within each segment of the log ([`derivatives_in`]), and the detector runs
//! on each segment's samples with full history, so a plateau never spans a gap.

use super::plateau::{self, DetectOptions, PlateauRange, PlateauStats};
use super::{DerivativeSteps, derivatives_in, seconds_to_samples};
use crate::log::Log;

/// How the summary differentiates T and finds its plateaus: a recipe's `temp_smoothing_s`,
/// `step_h_s` and plateau detector (the faces pass the default recipe's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SummaryOptions {
    /// T is smoothed over this long before it is differentiated, s.
    pub temp_smoothing_s: f64,
    /// The step of the backward difference, s.
    pub step_h_s: f64,
    /// The plateau detector's settings.
    pub plateaus: DetectOptions,
}

/// What a log covers: temperatures, rates and plateaus.
#[derive(Debug, Clone, PartialEq)]
pub struct LogSummary {
    /// The lowest temperature, °C (NaN samples skipped; +∞ for a log without one).
    pub temp_min_c: f64,
    /// The highest temperature, °C (NaN samples skipped; −∞ for a log without one).
    pub temp_max_c: f64,
    /// The largest |Ṫ| of the smoothed temperature, °C/min.
    pub max_abs_rate_c_per_min: f64,
    /// The plateaus found, with their statistics (ranges without samples left out).
    pub plateaus: Vec<PlateauStats>,
}

/// The summary of `log` with the given derivative and detector settings.
pub fn summarise(log: &Log, opts: &SummaryOptions) -> LogSummary {
    let timing = log.timing();
    let dt_s = timing.nominal_dt_s;
    let steps = DerivativeSteps {
        smooth: seconds_to_samples(opts.temp_smoothing_s, dt_s),
        step: seconds_to_samples(opts.step_h_s, dt_s),
    };
    let deriv = derivatives_in(&log.temp_c, steps, dt_s, &timing.segments);
    // Found within each segment's samples with full history, as a fit finds them.
    let ranges: Vec<PlateauRange> = deriv
        .ready
        .iter()
        .flat_map(|r| {
            plateau::detect(
                &log.time_s[r.clone()],
                &deriv.tdot[r.clone()],
                0,
                &opts.plateaus,
            )
        })
        .collect();
    let plateaus = ranges
        .iter()
        .filter_map(|r| plateau::stats(&log.time_s, &log.temp_c, &log.omega_dph, *r))
        .collect();
    let (temp_min_c, temp_max_c) = log
        .temp_c
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let max_abs_rate_c_per_min = deriv.tdot.iter().fold(0.0f64, |a, v| a.max(v.abs())) * 60.0;
    LogSummary {
        temp_min_c,
        temp_max_c,
        max_abs_rate_c_per_min,
        plateaus,
    }
}
