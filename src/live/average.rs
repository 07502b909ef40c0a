//! The centred moving average of the display series, into reused buffers.

use rayon::prelude::*;

/// [`signal::moving_average_centered`] into `out`, with the same arithmetic (so the same
/// bits), reusing `out` and the scratch `prefix`; the averages are taken in parallel.
pub(super) fn moving_average_centered_into(
    x: &[f64],
    window: usize,
    prefix: &mut Vec<f64>,
    out: &mut Vec<f64>,
) {
    let n = x.len();
    if window <= 1 || n == 0 {
        out.clear();
        out.extend_from_slice(x);
        return;
    }
    let back = (window - 1) / 2;
    let ahead = window / 2;
    let origin = x[0];
    prefix.clear();
    prefix.reserve(n + 1);
    prefix.push(0.0);
    let mut s = 0.0;
    for &v in x {
        s += v - origin;
        prefix.push(s);
    }
    if out.len() != n {
        out.clear();
        out.resize(n, 0.0);
    }
    const CHUNK: usize = 1 << 15;
    let prefix = &prefix[..];
    // Samples whose whole window lies inside the log: the divisor is the window itself.
    let (full_lo, full_hi) = (back, n.saturating_sub(ahead));
    let w = window as f64;
    out.par_chunks_mut(CHUNK).enumerate().for_each(|(c, o)| {
        let base = c * CHUNK;
        let (a, b) = (
            full_lo.clamp(base, base + o.len()),
            full_hi.clamp(base, base + o.len()),
        );
        if a < b {
            let (lo_p, hi_p) = (
                &prefix[a - back..b - back],
                &prefix[a + ahead + 1..b + ahead + 1],
            );
            for ((v, &h), &l) in o[a - base..b - base].iter_mut().zip(hi_p).zip(lo_p) {
                *v = origin + (h - l) / w;
            }
        }
        // The rest (none unless the chunk reaches an end of the log): shrunk windows.
        let end = base + o.len();
        let (a, b) = if a < b { (a, b) } else { (end, end) };
        for i in (base..a).chain(b..end) {
            let v = &mut o[i - base];
            let lo = i.saturating_sub(back);
            let hi = (i + ahead).min(n - 1);
            *v = origin + (prefix[hi + 1] - prefix[lo]) / (hi + 1 - lo) as f64;
        }
    });
}
