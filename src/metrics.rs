//! Figures of merit of a drift record, before and after correction (METHOD.md, "How results
//! are judged"): peak-to-peak and standard deviation of the filtered drift, and the mean and
//! RMS over consecutive 10-minute windows (Sukhanov 2011).
//!
//! The filtered drift is the centred moving average over full windows only, so every value
//! averages the same number of samples; the first samples of a log, where the corrector has no
//! rate history yet, are left out of every figure for both the raw and the corrected record.

use crate::signal;
use serde::{Deserialize, Serialize};

/// How the figures are computed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MeritOptions {
    /// Moving-average window of the filtered drift, s.
    pub filter_s: f64,
    /// Length of the consecutive windows for mean and RMS, s.
    pub window_s: f64,
}

impl Default for MeritOptions {
    fn default() -> Self {
        MeritOptions {
            filter_s: 100.0,
            window_s: 600.0,
        }
    }
}

/// Figures of merit of one drift record, °/h.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Figures {
    /// Peak-to-peak of the filtered drift.
    pub p2p_dph: f64,
    /// Standard deviation of the filtered drift.
    pub std_dph: f64,
    /// Mean of the record.
    pub mean_dph: f64,
    /// Largest |mean| over the consecutive windows.
    pub win_mean_max_abs_dph: f64,
    /// Peak-to-peak of the window means.
    pub win_mean_p2p_dph: f64,
    /// Mean over windows of the RMS within each window (about zero, so bias counts).
    pub win_rms_mean_dph: f64,
    /// Largest RMS of a window.
    pub win_rms_max_dph: f64,
    /// Number of whole windows.
    pub windows: usize,
    /// Samples the figures were computed on.
    pub samples: usize,
}

/// Figures of `omega_dph` sampled every `dt_s`, from sample `skip` on.
pub fn figures(omega_dph: &[f64], dt_s: f64, skip: usize, opts: &MeritOptions) -> Figures {
    let x = &omega_dph[skip.min(omega_dph.len())..];
    if x.is_empty() {
        return Figures::default();
    }
    let filtered = signal::moving_average_valid(x, signal::seconds_to_samples(opts.filter_s, dt_s));
    let (p2p, std) = if filtered.is_empty() {
        (0.0, 0.0)
    } else {
        let (lo, hi) = min_max(&filtered);
        let m = mean(&filtered);
        let var = filtered.iter().map(|v| (v - m).powi(2)).sum::<f64>() / filtered.len() as f64;
        (hi - lo, var.sqrt())
    };
    let w = signal::seconds_to_samples(opts.window_s, dt_s);
    let (means, rms): (Vec<f64>, Vec<f64>) = x
        .chunks_exact(w)
        .map(|c| {
            (
                mean(c),
                (c.iter().map(|v| v * v).sum::<f64>() / c.len() as f64).sqrt(),
            )
        })
        .unzip();
    let (mlo, mhi) = if means.is_empty() {
        (0.0, 0.0)
    } else {
        min_max(&means)
    };
    Figures {
        p2p_dph: p2p,
        std_dph: std,
        mean_dph: mean(x),
        win_mean_max_abs_dph: means.iter().fold(0.0, |a: f64, m| a.max(m.abs())),
        win_mean_p2p_dph: mhi - mlo,
        win_rms_mean_dph: if rms.is_empty() { 0.0 } else { mean(&rms) },
        win_rms_max_dph: rms.iter().fold(0.0, |a: f64, &r| a.max(r)),
        windows: means.len(),
        samples: x.len(),
    }
}

/// Raw against corrected, with the improvement ratios (raw ÷ corrected: above 1 is better).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Comparison {
    /// Figures of the raw record.
    pub raw: Figures,
    /// Figures of the corrected record.
    pub corrected: Figures,
    /// raw.p2p ÷ corrected.p2p.
    pub p2p_ratio: f64,
    /// raw.std ÷ corrected.std.
    pub std_ratio: f64,
    /// raw ÷ corrected largest |window mean|.
    pub win_mean_ratio: f64,
    /// raw ÷ corrected mean window RMS.
    pub win_rms_ratio: f64,
}

impl Comparison {
    /// Compares a raw and a corrected record of the same log.
    pub fn of(
        raw_dph: &[f64],
        cor_dph: &[f64],
        dt_s: f64,
        skip: usize,
        opts: &MeritOptions,
    ) -> Comparison {
        let (raw, corrected) = rayon::join(
            || figures(raw_dph, dt_s, skip, opts),
            || figures(cor_dph, dt_s, skip, opts),
        );
        Comparison::from_figures(raw, corrected)
    }

    /// The comparison of figures already computed (the workbench keeps the raw ones).
    pub fn from_figures(raw: Figures, corrected: Figures) -> Comparison {
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { f64::INFINITY };
        Comparison {
            raw,
            corrected,
            p2p_ratio: ratio(raw.p2p_dph, corrected.p2p_dph),
            std_ratio: ratio(raw.std_dph, corrected.std_dph),
            win_mean_ratio: ratio(raw.win_mean_max_abs_dph, corrected.win_mean_max_abs_dph),
            win_rms_ratio: ratio(raw.win_rms_mean_dph, corrected.win_rms_mean_dph),
        }
    }
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len().max(1) as f64
}

fn min_max(x: &[f64]) -> (f64, f64) {
    x.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        })
}

/// A calibration judged on one log: the comparison plus how much of the log lay beyond the
/// calibrated ranges.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Evaluation {
    /// Raw against corrected.
    pub comparison: Comparison,
    /// Share of samples outside the calibrated T, Ṫ or T̈ ranges (edge values held there).
    pub outside_fraction: f64,
    /// Leading samples left out (no rate history yet).
    pub warmup_samples: usize,
}

impl Evaluation {
    /// Corrects `log` with `cal` and compares the result with the raw record.
    pub fn of(
        cal: &crate::model::Calibration,
        log: &crate::log::Log,
        opts: &MeritOptions,
    ) -> Evaluation {
        let correction = cal.correct(log);
        Evaluation::of_correction(log, &correction, opts)
    }

    /// Compares an existing correction of `log` with the raw record.
    pub fn of_correction(
        log: &crate::log::Log,
        c: &crate::correct::Correction,
        opts: &MeritOptions,
    ) -> Evaluation {
        let skip = c.ready_from;
        Evaluation {
            comparison: Comparison::of(&log.omega_dph, &c.cor_dph, log.nominal_dt_s(), skip, opts),
            outside_fraction: c.outside_fraction,
            warmup_samples: skip,
        }
    }
}
