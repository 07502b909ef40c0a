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
    /// The largest |Ṫ| of the smoothed temperature over the samples with full history (those
    /// a fit reads), °C/min; `None` when no sample has the
    /// history the T smoothing and the derivative step need (a log shorter than they are:
    /// every rate would be the 0 that stands for "not known yet"), and `problems` says so.
    pub max_abs_rate_c_per_min: Option<f64>,
    /// The sampling step the rates were taken at, s; `None` for a log of fewer than two
    /// samples, which has no step.
    pub step_s: Option<f64>,
    /// The plateaus found, with their statistics (ranges without samples left out).
    pub plateaus: Vec<PlateauStats>,
    /// What the summary could not find, and why: one sentence each.
    pub problems: Vec<String>,
}

/// The sampling step of a log of `samples` samples whose nominal step is `dt_s`, as a person
/// reads it: "step 1 s (1 Hz)", or "no step (one sample)" where no two samples make one.
pub fn describe_step(samples: usize, dt_s: f64) -> String {
    match samples {
        0 => "no step (no sample)".to_string(),
        1 => "no step (one sample)".to_string(),
        _ => format!(
            "step {} s ({} Hz)",
            crate::number::readable(dt_s),
            crate::number::readable(1.0 / dt_s)
        ),
    }
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
    let mut problems = Vec::new();
    let step_s = (log.len() >= 2).then_some(dt_s);
    if log.len() < 2 {
        problems.push(format!(
            "{}: no step, no temperature rate and no plateau; a log needs at least two samples",
            if log.is_empty() {
                "no sample"
            } else {
                "one sample"
            }
        ));
    }
    let max_abs_rate_c_per_min = if deriv.ready.is_empty() {
        if log.len() >= 2 {
            problems.push(no_rate(&timing, steps, dt_s, opts));
        }
        None
    } else {
        // Over the samples with full history only: before the causal mean of T holds its
        // whole window, its lag is shorter and the rate jumps (a ramp read 25 % fast).
        Some(
            deriv
                .ready_samples()
                .fold(0.0f64, |a, i| a.max(deriv.tdot[i].abs()))
                * 60.0,
        )
    };
    LogSummary {
        temp_min_c,
        temp_max_c,
        max_abs_rate_c_per_min,
        step_s,
        plateaus,
        problems,
    }
}

/// Why no sample of a log of two samples or more has a rate: its longest segment is shorter
/// than the history the T smoothing and the derivative step need before the first rate.
fn no_rate(
    timing: &super::timing::Timing,
    steps: DerivativeSteps,
    dt_s: f64,
    opts: &SummaryOptions,
) -> String {
    // Counted in samples, which is what the history is made of: in seconds a sparse log's
    // span and the history can round to the same number (4 samples an hour apart, 5 needed).
    let longest = timing.segments.iter().map(|r| r.len()).max().unwrap_or(0);
    let needed = steps.ready_from() + 1;
    let n = crate::number::readable;
    format!(
        "no temperature rate: the log's {} holds {longest} samples, fewer than the {needed} \
         samples ({} s at {} s a sample) of history the T smoothing ({} s) and the derivative \
         step (H = {} s) need before the first rate",
        if timing.segments.len() > 1 {
            "longest segment"
        } else {
            "whole length"
        },
        n(needed as f64 * dt_s),
        n(dt_s),
        n(opts.temp_smoothing_s),
        n(opts.step_h_s)
    )
}
