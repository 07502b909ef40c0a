//! The figures of merit held to plain references: the fused walks against the obvious
//! two-pass formulas, bit for bit, and closed forms.

use super::figures::{SEGMENT, kept_extremes};
use super::running::{mean, min_max, moving_average_segment, valid_len};
use super::*;
use crate::signal;

/// The values of [`signal::moving_average_valid`], one at a time and with the same arithmetic
/// (so the same bits), without a buffer.
struct MovingAverageValid<'a> {
    x: &'a [f64],
    window: usize,
    origin: f64,
    w: f64,
    s: f64,
    /// Index of the next value to yield, counted as the index of its window's last sample + 1.
    next: usize,
}

impl<'a> MovingAverageValid<'a> {
    fn new(x: &'a [f64], window: usize) -> Self {
        let origin = x.first().copied().unwrap_or(0.0);
        MovingAverageValid {
            x,
            window,
            origin,
            w: window as f64,
            s: 0.0,
            next: if window <= 1 { 0 } else { window },
        }
    }
}

impl Iterator for MovingAverageValid<'_> {
    type Item = f64;

    fn next(&mut self) -> Option<f64> {
        let (x, window, origin) = (self.x, self.window, self.origin);
        if window <= 1 {
            let v = x.get(self.next).copied();
            self.next += 1;
            return v;
        }
        let i = self.next;
        if i > x.len() {
            return None;
        }
        if i == window {
            self.s = x[..window].iter().map(|v| v - origin).sum();
        } else {
            self.s += (x[i - 1] - origin) - (x[i - 1 - window] - origin);
        }
        self.next += 1;
        Some(origin + self.s / self.w)
    }
}

/// `figures` as it was written before its walks were fused.
fn reference(omega_dph: &[f64], dt_s: f64, skip: usize, opts: &MeritOptions) -> Figures {
    let x = &omega_dph[skip.min(omega_dph.len())..];
    if x.is_empty() {
        return Figures::default().mark_unavailable();
    }
    let filter = signal::seconds_to_samples(opts.filter_s, dt_s).max(1);
    let filtered = signal::moving_average_valid(x, filter);
    // The first filtered value averages samples 0 .. filter, the last n - 1 .. n - 1 + filter:
    // they share none from n - 1 = filter on.
    let apart = filtered.len() > filter;
    let (p2p, std) = if !apart {
        (0.0, 0.0)
    } else {
        let (lo, hi) = min_max(&filtered);
        let m = mean(&filtered);
        let var = filtered.iter().map(|v| (v - m).powi(2)).sum::<f64>() / filtered.len() as f64;
        (hi - lo, var.sqrt())
    };
    let w = signal::seconds_to_samples(opts.window_s, dt_s);
    // Whole windows one after the other, each summed by hand: a walk of its own, not the
    // chunked one under test.
    let (mut means, mut rms) = (Vec::new(), Vec::new());
    let mut start = 0;
    while w > 0 && start + w <= x.len() {
        let (mut sum, mut squares) = (0.0, 0.0);
        for &v in &x[start..start + w] {
            sum += v;
            squares += v * v;
        }
        means.push(sum / w as f64);
        rms.push((squares / w as f64).sqrt());
        start += w;
    }
    let mlo = means.iter().copied().fold(f64::INFINITY, f64::min);
    let mhi = means.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (mlo, mhi) = if means.is_empty() {
        (0.0, 0.0)
    } else {
        (mlo, mhi)
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
        filtered_unavailable: if filtered.is_empty() {
            Some(Unavailable::ShorterThanFilter)
        } else {
            (!apart).then_some(Unavailable::FilterOverlapsItself)
        },
        windows_unavailable: None,
        win_mean_p2p_unavailable: None,
    }
    .mark_unavailable()
}

#[test]
fn figures_are_the_unfused_ones() {
    let x: Vec<f64> = (0..5000)
        .map(|i| (i as f64 * 0.013).sin() * 30.0 - 4.0 + (i % 11) as f64 * 1e-2)
        .collect();
    for skip in [0, 3, 4990, 5000] {
        // A filter of one sample, and the shortest window (two samples: one of a single
        // sample is n/a, `window_of_one_sample`).
        for (filter_s, window_s) in [(100.0, 600.0), (0.0, 600.0), (1.0, 2.0), (5e4, 1e5)] {
            let opts = MeritOptions { filter_s, window_s };
            let want = reference(&x, 1.0, skip, &opts);
            let got = figures(&x, 1.0, skip, &opts);
            assert_eq!(format!("{got:?}"), format!("{want:?}"), "{skip} {opts:?}");
            let mut kept = vec![f64::NAN; 3];
            let got = figures_buffered(&x, 1.0, skip, &opts, &mut kept);
            assert_eq!(format!("{got:?}"), format!("{want:?}"), "{skip} {opts:?}");
        }
    }
}

#[test]
fn figures_of_a_long_record_are_the_sequential_ones_but_for_rounding() {
    // Several segments and window groups: the walks are split, so the sums are
    // reassociated, and nothing else.
    let x: Vec<f64> = (0..300_000)
        .map(|i| (i as f64 * 1.3e-4).sin() * 30.0 - 4.0 + (i % 11) as f64 * 1e-2)
        .collect();
    let opts = MeritOptions::default();
    let want = reference(&x, 1.0, 7, &opts);
    let got = figures(&x, 1.0, 7, &opts);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-11 * a.abs().max(b.abs());
    assert_eq!((got.windows, got.samples), (want.windows, want.samples));
    for (a, b) in [
        (got.p2p_dph, want.p2p_dph),
        (got.std_dph, want.std_dph),
        (got.mean_dph, want.mean_dph),
        (got.win_mean_max_abs_dph, want.win_mean_max_abs_dph),
        (got.win_mean_p2p_dph, want.win_mean_p2p_dph),
        (got.win_rms_mean_dph, want.win_rms_mean_dph),
        (got.win_rms_max_dph, want.win_rms_max_dph),
    ] {
        assert!(close(a, b), "{got:?}\n{want:?}");
    }
}

#[test]
fn buffered_figures_of_a_long_record_are_the_walked_ones() {
    // Odd and even numbers of segments, a buffer reused across lengths, a window of one.
    let x: Vec<f64> = (0..300_000)
        .map(|i| (i as f64 * 1.3e-4).sin() * 30.0 - 4.0 + (i % 11) as f64 * 1e-2)
        .collect();
    let mut kept = Vec::new();
    for (n, skip) in [
        (300_000, 7),
        (3 * SEGMENT + 99, 0),
        (2 * SEGMENT + 99, 0),
        (SEGMENT, 5),
    ] {
        for filter_s in [100.0, 1.0] {
            let opts = MeritOptions {
                filter_s,
                window_s: 600.0,
            };
            let want = figures(&x[..n], 1.0, skip, &opts);
            let got = figures_buffered(&x[..n], 1.0, skip, &opts, &mut kept);
            assert_eq!(
                format!("{got:?}"),
                format!("{want:?}"),
                "{n} {skip} {opts:?}"
            );
        }
    }
}

#[test]
fn kept_extremes_are_the_walks_even_at_signed_zeros_and_nan() {
    // Segment by segment, in order, written out as loops.
    let walk = |x: &[f64]| {
        let mut whole: Option<(f64, f64)> = None;
        let mut start = 0;
        while start < x.len() {
            let end = (start + SEGMENT).min(x.len());
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for &v in &x[start..end] {
                lo = lo.min(v);
                hi = hi.max(v);
            }
            whole = Some(match whole {
                None => (lo, hi),
                Some((a, b)) => (a.min(lo), b.max(hi)),
            });
            start = end;
        }
        whole.unwrap_or((0.0, 0.0))
    };
    let bits = |(a, b): (f64, f64)| (a.to_bits(), b.to_bits());
    let mut cases: Vec<Vec<f64>> = vec![
        vec![0.0, -0.0, 0.0, -0.0, -0.0],
        vec![-0.0, 0.0, 1.0],
        vec![0.0, -0.0, -1.0],
        vec![f64::NAN, -0.0, 0.0, f64::NAN, 0.0],
        vec![f64::NAN; 7],
        vec![f64::INFINITY, f64::NAN, -3.0],
    ];
    let long: Vec<f64> = (0..3 * SEGMENT + 5)
        .map(|i| match i % 9 {
            0 => -0.0,
            1 => 0.0,
            2 => f64::NAN,
            _ => (i as f64 * 0.1).sin(),
        })
        .collect();
    cases.push(long.clone());
    cases.push(long.iter().map(|v| v.abs()).collect());
    cases.push(long.iter().map(|v| -v.abs()).collect());
    for x in &cases {
        assert_eq!(
            bits(kept_extremes(x)),
            bits(walk(x)),
            "{:?}",
            &x[..x.len().min(8)]
        );
    }
}

#[test]
fn a_segment_from_the_start_is_the_sequential_walk() {
    let x: Vec<f64> = (0..700)
        .map(|i| (i as f64 * 0.37).sin() * 3.0 + 1e3)
        .collect();
    for window in [0, 1, 2, 17, 100] {
        let want = signal::moving_average_valid(&x, window);
        let mut got = Vec::new();
        moving_average_segment(&x, window, 0, want.len(), |v| got.push(v));
        assert_eq!(got, want, "window {window}");
    }
}

#[test]
fn unbuffered_moving_average_is_the_signal_one() {
    let x: Vec<f64> = (0..500)
        .map(|i| (i as f64 * 0.37).sin() * 3.0 + 1e3 + (i % 7) as f64 * 1e-3)
        .collect();
    for n in [0, 1, 5, 17, 500] {
        for window in [0, 1, 2, 5, 17, 18, 600] {
            let want = signal::moving_average_valid(&x[..n], window);
            let got: Vec<f64> = MovingAverageValid::new(&x[..n], window).collect();
            assert_eq!(got.len(), valid_len(n, window));
            assert_eq!(
                got.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                want.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                "n {n} window {window}"
            );
        }
    }
}

#[test]
fn a_ratio_over_a_corrected_figure_of_zero_is_na_with_its_reason() {
    // A correction that reproduces the record: the corrected figures are zero, and a ratio
    // over them would be any number.
    let raw: Vec<f64> = (0..4000).map(|i| (i as f64 * 0.01).sin()).collect();
    let opts = MeritOptions {
        filter_s: 10.0,
        window_s: 600.0,
    };
    let ready: Vec<std::ops::Range<usize>> = std::iter::once(0..raw.len()).collect();
    let c = Comparison::of(&raw, &vec![0.0; raw.len()], 1.0, &ready, &opts);
    assert!(c.raw.p2p_dph > 1.0 && c.corrected.p2p_dph == 0.0);
    assert!(c.p2p_ratio.is_nan() && c.std_ratio.is_nan());
    assert_eq!(c.ratios_unavailable, Some(Unavailable::CorrectedAtRounding));
    assert_eq!(
        c.unavailable(),
        vec![("ratios", Unavailable::CorrectedAtRounding)]
    );
    // A correction that leaves some drift has its ratios and no reason.
    let half: Vec<f64> = raw.iter().map(|v| 0.5 * v).collect();
    let c = Comparison::of(&raw, &half, 1.0, &ready, &opts);
    assert!((c.p2p_ratio - 2.0).abs() < 1e-12, "{}", c.p2p_ratio);
    assert!(c.unavailable().is_empty());
}
