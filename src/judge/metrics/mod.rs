//! Figures of merit of a drift record, before and after correction (docs/method.md §4, "How results
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
    /// Why peak-to-peak and std could not be computed (they are then NaN, `null` in JSON).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filtered_unavailable: Option<Unavailable>,
    /// Why the window figures could not be computed (they are then NaN, `null` in JSON).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub windows_unavailable: Option<Unavailable>,
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
    /// No segment holds a whole window.
    NoWholeWindow,
}

impl Unavailable {
    /// The reason in words, for a person.
    pub fn describe(self) -> &'static str {
        match self {
            Unavailable::NothingAfterWarmup => "no sample left after the warm-up",
            Unavailable::ShorterThanFilter => "no stretch of the log is as long as the filter",
            Unavailable::NoWholeWindow => "no stretch of the log holds a whole window",
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
        if self.windows_unavailable.is_some() {
            self.win_mean_max_abs_dph = f64::NAN;
            self.win_mean_p2p_dph = f64::NAN;
            self.win_rms_mean_dph = f64::NAN;
            self.win_rms_max_dph = f64::NAN;
        }
        self
    }
}

/// Moving-average values per segment of a parallel walk: each segment starts its running sum
/// afresh (the first segment's values are those of one sequential walk).
const SEGMENT: usize = 1 << 15;

/// Samples (at least; whole windows) per group of a parallel walk over the windows.
const WINDOW_GROUP: usize = 1 << 16;

/// Figures of `omega_dph` sampled every `dt_s`, from sample `skip` on.
///
/// The walks run in parallel over fixed segments of the record (so the result does not depend
/// on the number of threads): each segment's running sums start from its own first window, and
/// the segments' sums are added in order. On a record of at most one segment the figures are
/// those of one sequential walk to the bit.
pub fn figures(omega_dph: &[f64], dt_s: f64, skip: usize, opts: &MeritOptions) -> Figures {
    figures_kept(omega_dph, dt_s, skip, opts, None)
}

/// Figures of `omega_dph` over the samples of `ready` (one range per segment of the log, as
/// [`crate::signal::Derivatives::ready`] gives them): the filter and the windows stay inside
/// each range, so none reaches across a gap. A log of one segment gives [`figures`]'s bits.
pub fn figures_over(
    omega_dph: &[f64],
    dt_s: f64,
    ready: &[std::ops::Range<usize>],
    opts: &MeritOptions,
) -> Figures {
    let n = omega_dph.len();
    match ready {
        [] => figures(omega_dph, dt_s, n, opts),
        [r] if r.end >= n => figures(omega_dph, dt_s, r.start, opts),
        _ => figures_of_ranges(omega_dph, dt_s, ready, opts),
    }
}

/// [`figures_over`] for several ranges, written plainly: the filtered values of every range,
/// then the whole windows of every range, pooled.
fn figures_of_ranges(
    omega_dph: &[f64],
    dt_s: f64,
    ready: &[std::ops::Range<usize>],
    opts: &MeritOptions,
) -> Figures {
    let n = omega_dph.len();
    let parts: Vec<&[f64]> = ready
        .iter()
        .map(|r| &omega_dph[r.start.min(n)..r.end.min(n)])
        .filter(|x| !x.is_empty())
        .collect();
    let samples: usize = parts.iter().map(|x| x.len()).sum();
    let window = signal::seconds_to_samples(opts.filter_s, dt_s);
    let filtered: Vec<f64> = parts
        .iter()
        .flat_map(|x| signal::moving_average_valid(x, window))
        .collect();
    let (mut p2p, mut std) = (0.0, 0.0);
    let filtered_unavailable = if filtered.is_empty() {
        Some(Unavailable::ShorterThanFilter)
    } else {
        let (lo, hi) = min_max(&filtered);
        let m = mean(&filtered);
        let var = filtered.iter().map(|v| (v - m).powi(2)).sum::<f64>() / filtered.len() as f64;
        (p2p, std) = (hi - lo, var.sqrt());
        None
    };
    let w = signal::seconds_to_samples(opts.window_s, dt_s).max(1);
    let (means, rms): (Vec<f64>, Vec<f64>) = parts
        .iter()
        .flat_map(|x| x.chunks_exact(w))
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
    let total: f64 = parts.iter().flat_map(|x| x.iter()).sum();
    Figures {
        p2p_dph: p2p,
        std_dph: std,
        mean_dph: total / samples.max(1) as f64,
        win_mean_max_abs_dph: means.iter().fold(0.0, |a: f64, m| a.max(m.abs())),
        win_mean_p2p_dph: mhi - mlo,
        win_rms_mean_dph: if rms.is_empty() { 0.0 } else { mean(&rms) },
        win_rms_max_dph: rms.iter().fold(0.0, |a: f64, &r| a.max(r)),
        windows: means.len(),
        samples,
        filtered_unavailable,
        windows_unavailable: None,
    }
    .mark_unavailable()
}

/// [`figures`], the same bits, with the filtered drift kept in `filtered` between its two walks
/// (min/max/mean, then the variance) instead of computed twice. The workbench judges a
/// correction on every edit and keeps the buffer between edits; there the second walk, one
/// division per value, costs more than reading the buffer.
pub fn figures_buffered(
    omega_dph: &[f64],
    dt_s: f64,
    skip: usize,
    opts: &MeritOptions,
    filtered: &mut Vec<f64>,
) -> Figures {
    figures_kept(omega_dph, dt_s, skip, opts, Some(filtered))
}

/// [`figures`], keeping the filtered drift in `keep` when given.
fn figures_kept(
    omega_dph: &[f64],
    dt_s: f64,
    skip: usize,
    opts: &MeritOptions,
    keep: Option<&mut Vec<f64>>,
) -> Figures {
    use rayon::prelude::*;
    let x = &omega_dph[skip.min(omega_dph.len())..];
    if x.is_empty() {
        return Figures::default().mark_unavailable();
    }
    // Without a buffer to keep it in, the filtered drift is walked twice (min/max/mean, then
    // the variance): on a long log a fresh buffer would cost more than the second walk.
    let window = signal::seconds_to_samples(opts.filter_s, dt_s);
    let len = valid_len(x.len(), window);
    let segments = len.div_ceil(SEGMENT);
    let filtered = || {
        if len == 0 {
            return (0.0, 0.0);
        }
        // One walk for min, max and the sum, the sum folded as `Iterator::sum` folds (from its
        // own neutral element, in order) within each segment.
        let zero: f64 = std::iter::empty::<f64>().sum();
        let seg = |k: usize| (k * SEGMENT, ((k + 1) * SEGMENT).min(len));
        let acc0 = (f64::INFINITY, f64::NEG_INFINITY, zero);
        let step = |acc: &mut (f64, f64, f64), v: f64| {
            *acc = (acc.0.min(v), acc.1.max(v), acc.2 + v);
        };
        let mut keep = keep;
        let parts: Vec<(f64, f64, f64)> = match keep.as_deref_mut() {
            None => over_segment_pairs(segments, |ka, kb| {
                let (mut a, mut b) = (acc0, acc0);
                moving_average_segments(
                    x,
                    window,
                    seg(ka),
                    kb.map(seg),
                    |v| step(&mut a, v),
                    |v| step(&mut b, v),
                );
                (a, b)
            }),
            Some(buf) => {
                if buf.len() != len {
                    buf.clear();
                    buf.resize(len, 0.0);
                }
                // The same walks in the same pairs, each value also stored at its place; the
                // extremes are found afterwards from the stored values (`kept_extremes`).
                let pairs: Vec<_> = buf
                    .par_chunks_mut(2 * SEGMENT)
                    .enumerate()
                    .map(|(p, out)| {
                        let (ka, kb) = (2 * p, 2 * p + 1);
                        let kb = (kb < segments).then_some(kb);
                        let (oa, ob) = out.split_at_mut(SEGMENT.min(out.len()));
                        let (mut a, mut b) = (acc0, acc0);
                        let (mut ja, mut jb) = (0, 0);
                        moving_average_segments(
                            x,
                            window,
                            seg(ka),
                            kb.map(seg),
                            |v| {
                                oa[ja] = v;
                                ja += 1;
                                a.2 += v;
                            },
                            |v| {
                                ob[jb] = v;
                                jb += 1;
                                b.2 += v;
                            },
                        );
                        (a, kb.map(|_| b))
                    })
                    .collect();
                pairs
                    .into_iter()
                    .flat_map(|(a, b)| [Some(a), b])
                    .flatten()
                    .collect()
            }
        };
        let (mut lo, mut hi, sum) = parts
            .into_iter()
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1), a.2 + b.2))
            .unwrap_or((0.0, 0.0, 0.0));
        if let Some(buf) = keep.as_deref() {
            (lo, hi) = kept_extremes(buf);
        }
        let m = sum / len as f64;
        let squares: Vec<f64> = match keep {
            None => over_segment_pairs(segments, |ka, kb| {
                let (mut a, mut b) = (zero, zero);
                moving_average_segments(
                    x,
                    window,
                    seg(ka),
                    kb.map(seg),
                    |v| a += (v - m).powi(2),
                    |v| b += (v - m).powi(2),
                );
                (a, b)
            }),
            Some(buf) => {
                // The kept values, summed per segment in order as the walk above sums them,
                // two segments side by side.
                let pairs: Vec<_> = buf
                    .par_chunks(2 * SEGMENT)
                    .map(|out| {
                        let (oa, ob) = out.split_at(SEGMENT.min(out.len()));
                        let (mut a, mut b) = (zero, zero);
                        let n = oa.len().min(ob.len());
                        for (&u, &v) in oa[..n].iter().zip(&ob[..n]) {
                            a += (u - m).powi(2);
                            b += (v - m).powi(2);
                        }
                        for &u in &oa[n..] {
                            a += (u - m).powi(2);
                        }
                        for &v in &ob[n..] {
                            b += (v - m).powi(2);
                        }
                        (a, (!ob.is_empty()).then_some(b))
                    })
                    .collect();
                pairs
                    .into_iter()
                    .flat_map(|(a, b)| [Some(a), b])
                    .flatten()
                    .collect()
            }
        };
        let var = squares.into_iter().reduce(|a, b| a + b).unwrap_or(0.0) / len as f64;
        (hi - lo, var.sqrt())
    };
    let w = signal::seconds_to_samples(opts.window_s, dt_s).max(1);
    // One walk for the whole-record mean and the window means and RMS: each window's sums add
    // its values in order from the neutral element of `Iterator::sum`.
    let windows = || {
        let zero: f64 = std::iter::empty::<f64>().sum();
        let span = w * (WINDOW_GROUP / w).max(1);
        // One window's sums into its group's total and statistics.
        let one = |c: &[f64], total: &mut f64, stats: &mut Vec<(f64, f64)>| {
            let (mut s, mut q) = (zero, zero);
            for &v in c {
                *total += v;
                s += v;
                q += v * v;
            }
            if c.len() == w {
                stats.push((s / c.len() as f64, (q / c.len() as f64).sqrt()));
            }
        };
        let groups: Vec<&[f64]> = x.chunks(span).collect();
        // Two groups walked in lockstep (independent chains, as for the filtered drift), each
        // summed exactly as alone.
        let parts: Vec<(f64, Vec<(f64, f64)>)> = over_segment_pairs(groups.len(), |a, b| {
            let (ga, gb) = (groups[a], b.map_or(&[][..], |b| groups[b]));
            let (mut ta, mut tb) = (zero, zero);
            let mut sa = Vec::with_capacity(ga.len() / w);
            let mut sb = Vec::with_capacity(gb.len() / w);
            let (mut ca, mut cb) = (ga.chunks(w), gb.chunks(w));
            loop {
                match (ca.next(), cb.next()) {
                    (Some(a), Some(b)) if a.len() == w && b.len() == w => {
                        let (mut s1, mut q1, mut s2, mut q2) = (zero, zero, zero, zero);
                        for (&u, &v) in a.iter().zip(b) {
                            ta += u;
                            s1 += u;
                            q1 += u * u;
                            tb += v;
                            s2 += v;
                            q2 += v * v;
                        }
                        let n = w as f64;
                        sa.push((s1 / n, (q1 / n).sqrt()));
                        sb.push((s2 / n, (q2 / n).sqrt()));
                    }
                    (None, None) => break,
                    (a, b) => {
                        if let Some(a) = a {
                            one(a, &mut ta, &mut sa);
                        }
                        if let Some(b) = b {
                            one(b, &mut tb, &mut sb);
                        }
                    }
                }
            }
            ((ta, sa), (tb, sb))
        });
        let mut total = zero;
        let (mut means, mut rms) = (Vec::new(), Vec::new());
        for (t, stats) in parts {
            total += t;
            for (m, r) in stats {
                means.push(m);
                rms.push(r);
            }
        }
        (total, means, rms)
    };
    let ((p2p, std), (total, means, rms)) = rayon::join(filtered, windows);
    let mean_x = total / x.len().max(1) as f64;
    let (mlo, mhi) = if means.is_empty() {
        (0.0, 0.0)
    } else {
        min_max(&means)
    };
    Figures {
        p2p_dph: p2p,
        std_dph: std,
        mean_dph: mean_x,
        win_mean_max_abs_dph: means.iter().fold(0.0, |a: f64, m| a.max(m.abs())),
        win_mean_p2p_dph: mhi - mlo,
        win_rms_mean_dph: if rms.is_empty() { 0.0 } else { mean(&rms) },
        win_rms_max_dph: rms.iter().fold(0.0, |a: f64, &r| a.max(r)),
        windows: means.len(),
        samples: x.len(),
        filtered_unavailable: (len == 0).then_some(Unavailable::ShorterThanFilter),
        windows_unavailable: None,
    }
    .mark_unavailable()
}

/// The smallest and largest of the filtered drift kept by [`figures_buffered`], as the walk
/// of [`figures`] finds them (each segment folded in order with `f64::min` and `f64::max`
/// from ±∞, the segments' extremes folded in order), the same bits.
///
/// That walk's folds are chains, each step waiting on the one before; here each part of the
/// record is folded by four independent chains of comparisons instead. Both ignore NaN, so
/// both give the smallest (largest) number of the record, whatever the order, and a number
/// other than zero has one representation. Only a zero extreme, whose sign the order of the folds may decide,
/// is found again by the walk's own folds.
fn kept_extremes(filtered: &[f64]) -> (f64, f64) {
    use rayon::prelude::*;
    // A comparison that a NaN fails keeps the extreme, as `f64::min` and `f64::max` do; it is
    // one instruction where those take several to tell NaN apart.
    let lanes = |part: &[f64]| {
        let (mut lo, mut hi) = ([f64::INFINITY; 4], [f64::NEG_INFINITY; 4]);
        let quads = part.chunks_exact(4);
        for &v in quads.remainder() {
            lo[0] = if v < lo[0] { v } else { lo[0] };
            hi[0] = if v > hi[0] { v } else { hi[0] };
        }
        for q in quads {
            for k in 0..4 {
                lo[k] = if q[k] < lo[k] { q[k] } else { lo[k] };
                hi[k] = if q[k] > hi[k] { q[k] } else { hi[k] };
            }
        }
        let lo = lo.into_iter().fold(f64::INFINITY, f64::min);
        let hi = hi.into_iter().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let (lo, hi) = filtered.par_chunks(SEGMENT).map(lanes).reduce(
        || (f64::INFINITY, f64::NEG_INFINITY),
        |a, b| (a.0.min(b.0), a.1.max(b.1)),
    );
    if lo != 0.0 && hi != 0.0 {
        return (lo, hi);
    }
    filtered
        .chunks(SEGMENT)
        .map(|seg| {
            seg.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |a, &v| {
                    (a.0.min(v), a.1.max(v))
                })
        })
        .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
        .unwrap_or((0.0, 0.0))
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
    /// The figures the correction made worse than raw (ratio below 1), which every face marks.
    pub worse_than_raw: WorseThanRaw,
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

impl Comparison {
    /// Compares a raw and a corrected record of the same log.
    pub fn of(
        raw_dph: &[f64],
        cor_dph: &[f64],
        dt_s: f64,
        ready: &[std::ops::Range<usize>],
        opts: &MeritOptions,
    ) -> Comparison {
        let (raw, corrected) = rayon::join(
            || figures_over(raw_dph, dt_s, ready, opts),
            || figures_over(cor_dph, dt_s, ready, opts),
        );
        Comparison::from_figures(raw, corrected)
    }

    /// The comparison of figures already computed (the workbench keeps the raw ones).
    pub fn from_figures(raw: Figures, corrected: Figures) -> Comparison {
        // A ratio needs two finite figures and a corrected one above zero: otherwise it is
        // NaN (`n/a`), never an infinite improvement.
        let ratio = |a: f64, b: f64| {
            if a.is_finite() && b.is_finite() && b > 0.0 {
                a / b
            } else {
                f64::NAN
            }
        };
        let p2p_ratio = ratio(raw.p2p_dph, corrected.p2p_dph);
        let std_ratio = ratio(raw.std_dph, corrected.std_dph);
        let win_mean_ratio = ratio(raw.win_mean_max_abs_dph, corrected.win_mean_max_abs_dph);
        let win_rms_ratio = ratio(raw.win_rms_mean_dph, corrected.win_rms_mean_dph);
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

/// Length of [`signal::moving_average_valid`]'s output.
fn valid_len(n: usize, window: usize) -> usize {
    if window <= 1 {
        n
    } else if n < window {
        0
    } else {
        n - window + 1
    }
}

/// Values `from..to` of [`signal::moving_average_valid`], passed to `f` in order, with the
/// running sum started afresh at `from` (so values `0..` are those of one sequential walk, bit
/// for bit).
#[inline]
fn moving_average_segment(
    x: &[f64],
    window: usize,
    from: usize,
    to: usize,
    mut f: impl FnMut(f64),
) {
    if window <= 1 {
        x[from..to].iter().for_each(|&v| f(v));
        return;
    }
    if from >= to {
        return;
    }
    let origin = x[0];
    let w = window as f64;
    // Value j averages x[j .. j + window].
    let mut s: f64 = x[from..from + window].iter().map(|v| v - origin).sum();
    f(origin + s / w);
    let (add, sub) = (&x[from + window..to + window - 1], &x[from..to - 1]);
    for (&a, &b) in add.iter().zip(sub) {
        s += (a - origin) - (b - origin);
        f(origin + s / w);
    }
}

/// `walk(a, Some(a + 1))` for the segments of a walk taken in pairs (`walk(last, None)` for an
/// odd one out), in parallel; the segments' results in segment order.
fn over_segment_pairs<T: Send>(
    segments: usize,
    walk: impl Fn(usize, Option<usize>) -> (T, T) + Sync,
) -> Vec<T> {
    use rayon::prelude::*;
    let pairs: Vec<(T, Option<T>)> = (0..segments.div_ceil(2))
        .into_par_iter()
        .map(|p| {
            let (a, b) = (2 * p, 2 * p + 1);
            let kb = (b < segments).then_some(b);
            let (ra, rb) = walk(a, kb);
            (ra, kb.map(|_| rb))
        })
        .collect();
    let mut out = Vec::with_capacity(segments);
    for (a, b) in pairs {
        out.push(a);
        out.extend(b);
    }
    out
}

/// [`moving_average_segment`] over segment `a` and, when given, segment `b`, in lockstep: each
/// segment's values are computed and passed on exactly as a walk of its own would (so the same
/// bits), but the two running sums are independent chains that the processor overlaps. A walk
/// of one running sum waits on each addition; that wait, not the arithmetic, is its cost.
#[inline]
fn moving_average_segments(
    x: &[f64],
    window: usize,
    (a_from, a_to): (usize, usize),
    b: Option<(usize, usize)>,
    mut fa: impl FnMut(f64),
    mut fb: impl FnMut(f64),
) {
    let Some((b_from, b_to)) = b.filter(|&(f, t)| f < t && window > 1 && a_from < a_to) else {
        moving_average_segment(x, window, a_from, a_to, fa);
        if let Some((f, t)) = b {
            moving_average_segment(x, window, f, t, fb);
        }
        return;
    };
    let origin = x[0];
    let w = window as f64;
    let mut sa: f64 = x[a_from..a_from + window].iter().map(|v| v - origin).sum();
    let mut sb: f64 = x[b_from..b_from + window].iter().map(|v| v - origin).sum();
    fa(origin + sa / w);
    fb(origin + sb / w);
    let (add_a, sub_a) = (&x[a_from + window..a_to + window - 1], &x[a_from..a_to - 1]);
    let (add_b, sub_b) = (&x[b_from + window..b_to + window - 1], &x[b_from..b_to - 1]);
    let n = add_a.len().min(add_b.len());
    for ((&pa, &ma), (&pb, &mb)) in add_a[..n]
        .iter()
        .zip(&sub_a[..n])
        .zip(add_b[..n].iter().zip(&sub_b[..n]))
    {
        sa += (pa - origin) - (ma - origin);
        fa(origin + sa / w);
        sb += (pb - origin) - (mb - origin);
        fb(origin + sb / w);
    }
    for (&p, &m) in add_a[n..].iter().zip(&sub_a[n..]) {
        sa += (p - origin) - (m - origin);
        fa(origin + sa / w);
    }
    for (&p, &m) in add_b[n..].iter().zip(&sub_b[n..]) {
        sb += (p - origin) - (m - origin);
        fb(origin + sb / w);
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
        }
    }
}

#[cfg(test)]
mod tests;
