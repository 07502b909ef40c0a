//! The centred moving average of the display series, into reused buffers.

/// The centred moving average of `x` within each of `ranges` alone (a window is truncated at a
/// range's ends, as [`signal::moving_average_centered`](crate::signal::moving_average_centered)
/// of the range's samples gives it); samples outside every range are `x`'s. What the workbench
/// draws of a corrected rate: its ready stretches, no window reaching into the warm-up.
pub(super) fn moving_average_within_into(
    x: &[f64],
    window: usize,
    ranges: &[std::ops::Range<usize>],
    prefix: &mut Vec<f64>,
    out: &mut Vec<f64>,
) {
    out.clear();
    out.extend_from_slice(x);
    for r in ranges
        .iter()
        .filter(|r| r.start <= r.end && r.end <= x.len())
    {
        average_into(&x[r.clone()], window, prefix, &mut out[r.clone()]);
    }
}

/// The centred moving average of `x` into `out` (of `x`'s length), with the arithmetic of
/// [`signal::moving_average_centered`](crate::signal::moving_average_centered) (so the same
/// bits), reusing the scratch `prefix`.
///
/// The prefix sums are one chain of additions, each waiting on the one before; the processor
/// takes each full window's division while it waits, so the averages come with the sums in one
/// walk rather than in a second pass (the workbench runs this beside the figures of merit, on
/// the other core).
fn average_into(x: &[f64], window: usize, prefix: &mut Vec<f64>, out: &mut [f64]) {
    let n = x.len();
    if window <= 1 || n == 0 {
        out.copy_from_slice(x);
        return;
    }
    let back = (window - 1) / 2;
    let ahead = window / 2;
    let origin = x[0];
    if prefix.len() != n + 1 {
        prefix.clear();
        prefix.resize(n + 1, 0.0);
    }
    prefix[0] = 0.0;
    let w = window as f64;
    // Sample i's whole window, i − back ..= i + ahead, lies inside the log for
    // back ≤ i < n − ahead; its sum is known once sample i + ahead is added.
    let lead = (back + ahead).min(n);
    let mut s = 0.0;
    for k in 0..lead {
        s += x[k] - origin;
        prefix[k + 1] = s;
    }
    for k in lead..n {
        s += x[k] - origin;
        prefix[k + 1] = s;
        let i = k - ahead;
        out[i] = origin + (s - prefix[i - back]) / w;
    }
    // The rest: shrunk windows at both ends of the log.
    let (full_lo, full_hi) = (back, n.saturating_sub(ahead));
    let (a, b) = if full_lo < full_hi {
        (full_lo, full_hi)
    } else {
        (n, n)
    };
    for i in (0..a).chain(b..n) {
        let lo = i.saturating_sub(back);
        let hi = (i + ahead).min(n - 1);
        out[i] = origin + (prefix[hi + 1] - prefix[lo]) / (hi + 1 - lo) as f64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_average_within_ranges_is_each_ranges_own() {
        let x: Vec<f64> = (0..300)
            .map(|i| (i as f64 * 0.21).cos() * 2.0 + 5.0)
            .collect();
        let ranges = [10..90, 90..91, 120..300];
        let (mut prefix, mut out) = (Vec::new(), Vec::new());
        for window in [1, 2, 7, 60, 500] {
            moving_average_within_into(&x, window, &ranges, &mut prefix, &mut out);
            let mut want = x.clone();
            for r in &ranges {
                let part = crate::signal::moving_average_centered(&x[r.clone()], window);
                want[r.clone()].copy_from_slice(&part);
            }
            assert_eq!(
                out.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                want.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                "window {window}"
            );
        }
    }

    #[test]
    fn the_display_average_is_the_signal_one() {
        let x: Vec<f64> = (0..700)
            .map(|i| (i as f64 * 0.37).sin() * 3.0 + 1e3 + (i % 7) as f64 * 1e-3)
            .collect();
        let (mut prefix, mut out) = (Vec::new(), vec![f64::NAN; 5]);
        for n in [0, 1, 2, 5, 17, 99, 100, 101, 700] {
            for window in [0, 1, 2, 3, 5, 17, 18, 100, 101, 699, 700, 701, 2000] {
                let want = crate::signal::moving_average_centered(&x[..n], window);
                let whole = vec![std::ops::Range { start: 0, end: n }];
                moving_average_within_into(&x[..n], window, &whole, &mut prefix, &mut out);
                assert_eq!(
                    out.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                    want.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
                    "n {n} window {window}"
                );
            }
        }
    }
}
