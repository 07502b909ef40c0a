//! Raw against corrected: the figures of both records and the improvement ratios, with the
//! figures a correction made worse than raw. Apart from the computation because every face
//! reads these and none needs the walks.

use super::{Figures, MeritOptions, Unavailable, figures_over};
use serde::{Deserialize, Serialize};

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
    /// The figures the correction made worse than raw (ratio below 1), which every face marks.
    pub worse_than_raw: WorseThanRaw,
    /// Why a ratio of two figures that were computed is not taken (it is then NaN, `null` in
    /// JSON); a ratio of a figure that could not be computed has that figure's reason.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ratios_unavailable: Option<Unavailable>,
}

/// Which figures a correction made worse than the raw record (raw ÷ corrected below 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct WorseThanRaw {
    /// Peak-to-peak of the filtered drift.
    pub p2p: bool,
    /// Standard deviation of the filtered drift.
    pub std: bool,
    /// Largest |window mean|.
    pub win_mean: bool,
    /// Mean window RMS.
    pub win_rms: bool,
}

impl WorseThanRaw {
    /// Whether any figure is worse than raw.
    pub fn any(&self) -> bool {
        self.p2p || self.std || self.win_mean || self.win_rms
    }

    /// The names of the figures worse than raw, for messages.
    pub fn names(&self) -> Vec<&'static str> {
        [
            (self.p2p, "peak-to-peak"),
            (self.std, "std"),
            (self.win_mean, "largest |window mean|"),
            (self.win_rms, "mean window RMS"),
        ]
        .into_iter()
        .filter_map(|(w, n)| w.then_some(n))
        .collect()
    }
}

/// The smallest corrected figure, as a fraction of the raw one, that a ratio is taken over:
/// no correction of a gyro removes all but a billionth of its drift, so a smaller one is the
/// rounding of a correction that predicted the raw record itself (a stuck rate column).
pub const RATIO_FLOOR: f64 = 1e-9;

impl Comparison {
    /// Compares a raw and a corrected record of the same log.
    pub fn of(
        raw_dph: &[f64],
        cor_dph: &[f64],
        dt_s: f64,
        ready: &[std::ops::Range<usize>],
        opts: &MeritOptions,
    ) -> Comparison {
        // Samples read as missing (an accelerometer's glitch kept as NaN, a blank cell of a
        // second axis) are left out of both series' figures, which a NaN would otherwise cut
        // short or make n/a.
        let split = finite_ranges(raw_dph, cor_dph, ready);
        let ready = split.as_deref().unwrap_or(ready);
        let (raw, corrected) = rayon::join(
            || figures_over(raw_dph, dt_s, ready, opts),
            || figures_over(cor_dph, dt_s, ready, opts),
        );
        Comparison::from_figures(raw, corrected)
    }

    /// [`Comparison::of`] over each run of the campaign `log` on its own (its samples among
    /// `ready`, the correction's ready ranges), in run order; empty for a log of one run.
    /// Each run's figures are its own: no filter window reaches another run's samples.
    pub fn of_runs(
        log: &crate::log::Log,
        cor_dph: &[f64],
        ready: &[std::ops::Range<usize>],
        opts: &MeritOptions,
    ) -> Vec<Comparison> {
        if log.runs().len() < 2 {
            return Vec::new();
        }
        let dt = log.nominal_dt_s();
        log.run_ranges()
            .into_iter()
            .map(|run| {
                let within: Vec<std::ops::Range<usize>> = ready
                    .iter()
                    .map(|r| r.start.max(run.start)..r.end.min(run.end))
                    .filter(|r| r.start < r.end)
                    .collect();
                // A run with no ready sample is judged on nothing: its figures say so
                // (unavailable), never the whole log's.
                match within.is_empty() {
                    true => Comparison::of(&[], &[], dt, &[], opts),
                    false => Comparison::of(&log.omega_dph, cor_dph, dt, &within, opts),
                }
            })
            .collect()
    }

    /// The comparison of figures already computed (the workbench keeps the raw ones).
    pub fn from_figures(raw: Figures, corrected: Figures) -> Comparison {
        // A ratio needs two finite figures and a corrected one above zero and above the
        // rounding of the raw one (a corrected figure a billionth of the raw is what is left
        // of subtracting a number from itself): otherwise it is NaN (`n/a`), never an
        // infinite improvement.
        // Two figures a billionth apart are the same figure (a correction by a constant
        // leaves the peak-to-peak as it was, to rounding): their ratio is 1, neither better nor
        // worse than raw.
        let ratio = |a: f64, b: f64| {
            if a.is_finite() && b.is_finite() && b > 0.0 && b > a.abs() * RATIO_FLOOR {
                match (a - b).abs() <= a.abs() * RATIO_FLOOR {
                    true => 1.0,
                    false => a / b,
                }
            } else {
                f64::NAN
            }
        };
        let p2p_ratio = ratio(raw.p2p_dph, corrected.p2p_dph);
        let std_ratio = ratio(raw.std_dph, corrected.std_dph);
        let win_mean_ratio = ratio(raw.win_mean_max_abs_dph, corrected.win_mean_max_abs_dph);
        let win_rms_ratio = ratio(raw.win_rms_mean_dph, corrected.win_rms_mean_dph);
        let at_rounding = [
            (raw.p2p_dph, corrected.p2p_dph, p2p_ratio),
            (raw.std_dph, corrected.std_dph, std_ratio),
            (
                raw.win_mean_max_abs_dph,
                corrected.win_mean_max_abs_dph,
                win_mean_ratio,
            ),
            (
                raw.win_rms_mean_dph,
                corrected.win_rms_mean_dph,
                win_rms_ratio,
            ),
        ]
        .iter()
        .any(|(a, b, r)| a.is_finite() && b.is_finite() && r.is_nan());
        Comparison {
            raw,
            corrected,
            p2p_ratio,
            std_ratio,
            win_mean_ratio,
            win_rms_ratio,
            worse_than_raw: WorseThanRaw {
                p2p: p2p_ratio < 1.0,
                std: std_ratio < 1.0,
                win_mean: win_mean_ratio < 1.0,
                win_rms: win_rms_ratio < 1.0,
            },
            ratios_unavailable: at_rounding.then_some(Unavailable::CorrectedAtRounding),
        }
    }

    /// What is `n/a` and why, for every face to print under its table: the filtered figures,
    /// the window figures (the raw record's reason, or the corrected one's), and the ratios.
    pub fn unavailable(&self) -> Vec<(&'static str, Unavailable)> {
        [
            (
                "peak-to-peak and std",
                self.raw
                    .filtered_unavailable
                    .or(self.corrected.filtered_unavailable),
            ),
            (
                "window figures",
                self.raw
                    .windows_unavailable
                    .or(self.corrected.windows_unavailable),
            ),
            (
                "peak-to-peak of the window means",
                self.raw
                    .win_mean_p2p_unavailable
                    .or(self.corrected.win_mean_p2p_unavailable),
            ),
            ("ratios", self.ratios_unavailable),
        ]
        .into_iter()
        .filter_map(|(what, why)| Some((what, why?)))
        .collect()
    }
}

/// `ready` cut around the samples where `raw` or `cor` is not finite; `None` (nothing to cut,
/// nothing allocated) when every sample of `ready` is finite in both.
fn finite_ranges(
    raw: &[f64],
    cor: &[f64],
    ready: &[std::ops::Range<usize>],
) -> Option<Vec<std::ops::Range<usize>>> {
    let n = raw.len().min(cor.len());
    let finite = |i: usize| raw[i].is_finite() && cor[i].is_finite();
    let clipped = |r: &std::ops::Range<usize>| r.start.min(n)..r.end.min(n);
    if ready.iter().all(|r| clipped(r).all(finite)) {
        return None;
    }
    let mut out = Vec::new();
    for r in ready {
        let mut start = None;
        for i in clipped(r) {
            match (finite(i), start) {
                (true, None) => start = Some(i),
                (false, Some(a)) => {
                    out.push(a..i);
                    start = None;
                }
                _ => {}
            }
        }
        if let Some(a) = start {
            out.push(a..r.end.min(n));
        }
    }
    Some(out)
}
