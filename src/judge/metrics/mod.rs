//! Figures of merit of a drift record, before and after correction (docs/method.md §4, "How results
//! are judged"): peak-to-peak and standard deviation of the filtered drift, and the mean and
//! RMS over consecutive 10-minute windows (Sukhanov 2011).
//!
//! The filtered drift is the centred moving average over full windows only, so every value
//! averages the same number of samples; the first samples of a log, where the corrector has no
//! rate history yet, are left out of every figure for both the raw and the corrected record.
//!
//! This module holds the options, the figures and a calibration judged on a log; computing the
//! figures (`figures`), the moving-average walks they are made of (`running`) and raw against
//! corrected (`comparison`) are in modules of their own.

mod comparison;
mod figures;
mod running;

pub use comparison::{Comparison, RATIO_FLOOR, WorseThanRaw};
pub use figures::{MIN_DISJOINT_FILTER_WINDOWS, figures, figures_buffered, figures_over};

use crate::models::vakhrameev::LeftOut;
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
    /// Why peak-to-peak and std could not be computed (they are then NaN, `null` in JSON).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filtered_unavailable: Option<Unavailable>,
    /// Why the window figures could not be computed (they are then NaN, `null` in JSON).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub windows_unavailable: Option<Unavailable>,
    /// Why the peak-to-peak of the window means alone could not be computed, when the other
    /// window figures could ([`Unavailable::OneWindow`]; it is then NaN, `null` in JSON).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub win_mean_p2p_unavailable: Option<Unavailable>,
}

/// Why a figure of merit could not be computed. A figure that cannot be computed is NaN
/// (printed `n/a` with this reason, `null` in JSON), never a zero that would read as perfect.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Unavailable {
    /// No sample is left once the warm-up of every segment is taken out.
    NothingAfterWarmup,
    /// No segment is as long as the filter window.
    ShorterThanFilter,
    /// The filter is longer than half of every judged stretch: its filtered values all
    /// average overlapping windows ([`figures::MIN_DISJOINT_FILTER_WINDOWS`]), so their spread
    /// is the filter's own overlap, not the drift's.
    FilterOverlapsItself,
    /// No segment holds a whole window.
    NoWholeWindow,
    /// The window holds one sample at the log's sampling interval (shorter than it, or
    /// under one and a half): each would be that sample. (Named as it was when only a window
    /// shorter than a sample counted, which the JSON keeps: `window_shorter_than_sample`.)
    WindowShorterThanSample,
    /// One whole window: its mean has no other to stand apart from, so the peak-to-peak of
    /// the window means is not a spread (it would read 0, a perfectly flat drift).
    OneWindow,
    /// A ratio over a corrected figure of zero, or of the rounding of the raw one
    /// (`RATIO_FLOOR`, a billionth).
    CorrectedAtRounding,
}

impl Unavailable {
    /// The reason in words, for a person.
    pub fn describe(self) -> &'static str {
        match self {
            Unavailable::NothingAfterWarmup => "no sample left after the warm-up",
            Unavailable::ShorterThanFilter => "no stretch of the log is as long as the filter",
            Unavailable::FilterOverlapsItself => {
                "the filter is longer than half of the judged stretch (after the warm-up): no two \
                 of its windows are apart, so the filtered drift is one average seen through \
                 overlapping windows and has no spread to measure; shorten the filter or judge \
                 a longer log"
            }
            Unavailable::NoWholeWindow => "no stretch of the log holds a whole window",
            Unavailable::WindowShorterThanSample => {
                "the window holds one sample at the sampling interval: each would be that \
                 sample, labelled with a length it does not have"
            }
            Unavailable::OneWindow => {
                "the log holds one whole window: a peak-to-peak of the window means needs two; \
                 shorten the window or judge a longer log"
            }
            Unavailable::CorrectedAtRounding => {
                "the corrected figure is zero, or below a billionth of the raw one: what is left \
                 of a correction that reproduces the record to its rounding, over which a ratio \
                 would be any number"
            }
        }
    }
}

impl std::fmt::Display for Unavailable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.describe())
    }
}

impl Figures {
    /// Marks what could not be computed: NaN figures with their reason instead of zeros.
    fn mark_unavailable(mut self) -> Figures {
        if self.samples == 0 {
            self.mean_dph = f64::NAN;
            self.filtered_unavailable = Some(Unavailable::NothingAfterWarmup);
            self.windows_unavailable = Some(Unavailable::NothingAfterWarmup);
        }
        if self.filtered_unavailable.is_some() {
            self.p2p_dph = f64::NAN;
            self.std_dph = f64::NAN;
        }
        if self.windows == 0 {
            self.windows_unavailable
                .get_or_insert(Unavailable::NoWholeWindow);
        }
        if self.windows == 1 && self.windows_unavailable.is_none() {
            self.win_mean_p2p_dph = f64::NAN;
            self.win_mean_p2p_unavailable = Some(Unavailable::OneWindow);
        }
        if self.windows_unavailable.is_some() {
            self.windows = 0;
            self.win_mean_max_abs_dph = f64::NAN;
            self.win_mean_p2p_dph = f64::NAN;
            self.win_rms_mean_dph = f64::NAN;
            self.win_rms_max_dph = f64::NAN;
        }
        self
    }
}

/// A calibration judged on one log: the comparison plus how much of the log lay beyond the
/// calibrated ranges.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Evaluation {
    /// Raw against corrected.
    pub comparison: Comparison,
    /// Share of samples outside the calibrated T, Ṫ or T̈ ranges (edge values held there).
    pub outside_fraction: f64,
    /// Samples left out at the start of each segment (no rate history yet).
    pub warmup_samples: usize,
    /// The terms left out for want of points, which have no range `outside_fraction` counts
    /// ([`Approx::judged_range`](crate::models::approx::Approx::judged_range)): said beside it
    /// wherever it is shown. Written only when a term was left out.
    #[serde(default, skip_serializing_if = "LeftOut::is_none")]
    pub left_out: LeftOut,
}

impl Evaluation {
    /// Corrects `log` with `cal` and compares the result with the raw record.
    pub fn of(
        cal: &crate::models::vakhrameev::Calibration,
        log: &crate::log::Log,
        opts: &MeritOptions,
    ) -> Evaluation {
        let correction = cal.correct(log);
        Evaluation::of_correction(log, &correction, opts)
    }

    /// Compares an existing correction of `log` with the raw record.
    pub fn of_correction(
        log: &crate::log::Log,
        c: &crate::models::vakhrameev::correct::Correction,
        opts: &MeritOptions,
    ) -> Evaluation {
        Evaluation::of_rate(log, &c.cor_dph, &c.ready, c.outside_fraction, opts)
    }

    /// Compares a corrected rate of `log` (figures over the samples of `ready`, one range per
    /// segment) with the raw record: [`Evaluation::of_correction`] for a caller that holds the
    /// corrected rate alone.
    pub fn of_rate(
        log: &crate::log::Log,
        cor_dph: &[f64],
        ready: &[std::ops::Range<usize>],
        outside_fraction: f64,
        opts: &MeritOptions,
    ) -> Evaluation {
        let used: usize = ready.iter().map(|r| r.len()).sum();
        Evaluation {
            comparison: Comparison::of(&log.omega_dph, cor_dph, log.nominal_dt_s(), ready, opts),
            outside_fraction,
            warmup_samples: log.len().saturating_sub(used),
            left_out: LeftOut::default(),
        }
    }

    /// This evaluation of `model`, with the terms it left out named.
    pub fn of_model(self, model: &crate::models::DriftModel) -> Evaluation {
        Evaluation {
            left_out: model.left_out(),
            ..self
        }
    }

    /// The share of samples outside the calibrated ranges as a sentence's end: `7.7% outside
    /// the calibrated ranges`, and the terms left out of it (`99 %` of a log would otherwise
    /// read as if the calibration covered nothing).
    pub fn outside_text(&self) -> String {
        let share = crate::number::percent(self.outside_fraction);
        if self.left_out.is_none() {
            format!("{share}% outside the calibrated ranges")
        } else {
            format!("{share}% outside the calibrated ranges ({})", self.left_out)
        }
    }
}

#[cfg(test)]
mod tests;
