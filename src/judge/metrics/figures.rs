//! Computing the figures of one record: the filtered drift's peak-to-peak and std and the
//! window means and RMS, walked in parallel over fixed segments so that the result does not
//! depend on the number of threads. Apart from the types because this is where the time goes.

use super::running::{
    fold_segment_pairs, mean, min_max, moving_average_segments, over_segment_pairs, valid_len,
};
use super::{Figures, MeritOptions, Unavailable};
use crate::signal;

/// The fewest filter windows that share no sample the filtered drift must hold for its
/// peak-to-peak and std to be computed: two.
///
/// Consecutive filtered values average windows that overlap in all but one sample, so a
/// stretch of `n` filtered values of a `w`-sample filter holds only `1 + (n - 1) / w` averages
/// of samples apart. With one, every value shares most of its samples with every other: one
/// value has no spread at all (printed 0.0000, and read as a correction that reproduced the
/// record to its rounding), and a handful differ by the few samples their windows do not share
/// (a 40000-s filter over 40022 s gave 23 values and a ratio of 1.00x). Two windows apart are
/// the least that can differ by the drift itself, and a pair is what a peak-to-peak is; the
/// stretch must then be at least twice the filter. A log of several stretches counts the
/// windows apart in each.
pub const MIN_DISJOINT_FILTER_WINDOWS: usize = 2;

/// Why the peak-to-peak and std of a filtered drift cannot be computed, if they cannot: the
/// filter of `window` samples over stretches that hold `lens` filtered values each. None holds
/// one ([`Unavailable::ShorterThanFilter`]), or together they hold fewer than
/// [`MIN_DISJOINT_FILTER_WINDOWS`] windows apart ([`Unavailable::FilterOverlapsItself`]).
fn filtered_unavailable_of(
    lens: impl IntoIterator<Item = usize>,
    window: usize,
) -> Option<Unavailable> {
    let window = window.max(1);
    let (values, apart) = lens
        .into_iter()
        .filter(|&n| n > 0)
        .fold((0, 0), |(v, a), n| (v + n, a + 1 + (n - 1) / window));
    if values == 0 {
        Some(Unavailable::ShorterThanFilter)
    } else if apart < MIN_DISJOINT_FILTER_WINDOWS {
        Some(Unavailable::FilterOverlapsItself)
    } else {
        None
    }
}

/// Moving-average values per segment of a parallel walk: each segment starts its running sum
/// afresh (the first segment's values are those of one sequential walk).
pub(super) const SEGMENT: usize = 1 << 15;

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
        _ => {
            let parts: Vec<&[f64]> = ready
                .iter()
                .map(|r| &omega_dph[r.start.min(n)..r.end.min(n)])
                .filter(|x| !x.is_empty())
                .collect();
            figures_of_parts(&parts, dt_s, opts)
        }
    }
}

/// [`figures_over`] for several ranges (`parts`, each a range's samples), written plainly: the
/// filtered values of every range, then the whole windows of every range, pooled.
fn figures_of_parts(parts: &[&[f64]], dt_s: f64, opts: &MeritOptions) -> Figures {
    let samples: usize = parts.iter().map(|x| x.len()).sum();
    let window = signal::seconds_to_samples(opts.filter_s, dt_s);
    let filtered: Vec<f64> = parts
        .iter()
        .flat_map(|x| signal::moving_average_valid(x, window))
        .collect();
    let (mut p2p, mut std) = (0.0, 0.0);
    let filtered_unavailable =
        filtered_unavailable_of(parts.iter().map(|x| valid_len(x.len(), window)), window);
    if filtered_unavailable.is_none() {
        let (lo, hi) = min_max(&filtered);
        let m = mean(&filtered);
        let var = filtered.iter().map(|v| (v - m).powi(2)).sum::<f64>() / filtered.len() as f64;
        (p2p, std) = (hi - lo, var.sqrt());
    }
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
        windows_unavailable: window_shorter_than_a_sample(opts, dt_s),
        win_mean_p2p_unavailable: None,
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
            None => fold_segment_pairs(x, window, segments, seg, acc0, step),
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
                in_segment_order(pairs)
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
            None => {
                fold_segment_pairs(x, window, segments, seg, zero, |a, v| *a += (v - m).powi(2))
            }
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
                in_segment_order(pairs)
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
        filtered_unavailable: filtered_unavailable_of([len], window),
        windows_unavailable: window_shorter_than_a_sample(opts, dt_s),
        win_mean_p2p_unavailable: None,
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
pub(super) fn kept_extremes(filtered: &[f64]) -> (f64, f64) {
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

/// The per-segment results of walks done two segments side by side, back in segment order
/// (the second of the last pair is absent when the segments are odd in number).
fn in_segment_order<T>(pairs: Vec<(T, Option<T>)>) -> Vec<T> {
    pairs
        .into_iter()
        .flat_map(|(a, b)| [Some(a), b])
        .flatten()
        .collect()
}

/// A window of one sample (shorter than a sample, or under one and a half) is that sample,
/// and would be labelled with a length it does not have (`max |10-min mean|` over samples
/// 1000 s apart): its figures are n/a, by the rule that refuses such a window where it is asked
/// for ([`crate::judge::options::window_of_one_sample`]).
fn window_shorter_than_a_sample(opts: &MeritOptions, dt_s: f64) -> Option<Unavailable> {
    crate::judge::options::window_of_one_sample(opts.window_s, dt_s)
        .then_some(Unavailable::WindowShorterThanSample)
}
