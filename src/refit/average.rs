//! The centred moving average of the display series, into reused buffers.

/// The centred moving average of `x` within each of `ranges` alone (a window is truncated at a
/// range's ends, as [`signal::moving_average_centered`](crate::signal::moving_average_centered)
/// of the range's samples gives it); samples outside every range are `x`'s. What the workbench
/// draws of a corrected rate: its ready stretches, no window reaching into the warm-up.
///
/// `out` is written once per sample (the samples outside the ranges copied, those inside
/// averaged): on a million samples a copy of the whole series first, then overwritten, cost
/// 16 MB of memory traffic more per axis and edit.
pub(super) fn moving_average_within_into(
    x: &[f64],
    window: usize,
    ranges: &[std::ops::Range<usize>],
    prefix: &mut Vec<f64>,
    out: &mut Vec<f64>,
) {
    let n = x.len();
    if out.len() != n {
        out.clear();
        out.resize(n, 0.0);
    }
    let mut valid: Vec<std::ops::Range<usize>> = ranges
        .iter()
        .filter(|r| r.start <= r.end && r.end <= n)
        .cloned()
        .collect();
    // The samples outside every range: x's.
    let mut by_start = valid.clone();
    by_start.sort_by_key(|r| r.start);
    let mut at = 0;
    for r in &by_start {
        if r.start > at {
            out[at..r.start].copy_from_slice(&x[at..r.start]);
        }
        at = at.max(r.end);
    }
    out[at..].copy_from_slice(&x[at..]);
    // Each range's average in the ranges' order (a later range overlapping an earlier one
    // writes over it, as it always has).
    for r in valid.drain(..) {
        average_into(&x[r.clone()], window, prefix, &mut out[r]);
    }
}

/// The centred moving average of `x` into `out` (of `x`'s length), with the arithmetic of
/// [`signal::moving_average_centered`](crate::signal::moving_average_centered) (so the same
/// bits), reusing the scratch `prefix`.
///
/// The prefix sums are one chain of additions, each waiting on the one before; the processor
/// takes each full window's division while it waits, so the averages come with the sums in one
/// walk rather than in a second pass (the workbench runs this beside the figures of merit, on
/// the other core). A full window reads the prefix sum a window behind the one it adds, and
/// the shrunk windows at the ends read the first and last window's sums: on a series longer
/// than twice the window the sums are kept in a ring of a little over one window (the same
/// values, so the same bits), not a second series of the log's length written and read back.
fn average_into(x: &[f64], window: usize, prefix: &mut Vec<f64>, out: &mut [f64]) {
    let n = x.len();
    if window <= 1 || n == 0 {
        out.copy_from_slice(x);
        return;
    }
    let back = (window - 1) / 2;
    let ahead = window / 2;
    let lead = (back + ahead).min(n);
    if n <= 2 * (lead + 1) {
        return average_whole_prefix(x, window, prefix, out);
    }
    let origin = x[0];
    let w = window as f64;
    // Prefix sum j (of the first j samples) is at `ring[j & mask]`; the first window's are
    // kept apart in `head` for the shrunk windows at the start.
    let size = (lead + 2).next_power_of_two();
    let mask = size - 1;
    if prefix.len() != size + lead + 1 {
        prefix.clear();
        prefix.resize(size + lead + 1, 0.0);
    }
    let (ring, head) = prefix.split_at_mut(size);
    ring[0] = 0.0;
    head[0] = 0.0;
    let mut s = 0.0;
    for k in 0..lead {
        s += x[k] - origin;
        ring[(k + 1) & mask] = s;
        head[k + 1] = s;
    }
    // Sample i's whole window, i − back ..= i + ahead, lies inside the series for
    // back ≤ i < n − ahead; its sum is known once sample i + ahead is added. The sum a window
    // behind is read before the new one is stored (the ring holds more than a window).
    for (k, &v) in x.iter().enumerate().skip(lead) {
        s += v - origin;
        let behind = ring[(k - lead) & mask];
        ring[(k + 1) & mask] = s;
        out[k - ahead] = origin + (s - behind) / w;
    }
    // The rest: shrunk windows at both ends of the series (lo = 0 at the start; hi + 1 = n at
    // the end, with lo ≥ n − lead, whose sums the ring still holds).
    for (i, o) in out[..back].iter_mut().enumerate() {
        let hi = (i + ahead).min(n - 1);
        *o = origin + (head[hi + 1] - head[0]) / (hi + 1) as f64;
    }
    for (i, o) in out.iter_mut().enumerate().skip(n - ahead) {
        let lo = i - back;
        *o = origin + (ring[n & mask] - ring[lo & mask]) / (n - lo) as f64;
    }
}

/// [`average_into`] with every prefix sum kept: for a series at most about twice the window,
/// whose shrunk windows may read any of them.
fn average_whole_prefix(x: &[f64], window: usize, prefix: &mut Vec<f64>, out: &mut [f64]) {
    let n = x.len();
    let back = (window - 1) / 2;
    let ahead = window / 2;
    let origin = x[0];
    if prefix.len() != n + 1 {
        prefix.clear();
        prefix.resize(n + 1, 0.0);
    }
    prefix[0] = 0.0;
    let w = window as f64;
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
    // The rest: shrunk windows at both ends of the series.
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
