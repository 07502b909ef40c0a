//! The moving-average walks the figures are made of: a running sum over one segment, or two
//! segments in lockstep, the segments of a walk taken in pairs in parallel, and the small
//! folds (mean, extremes) beside them. Apart from the figures because their bits are what the
//! tests hold against one sequential walk.

pub(super) fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len().max(1) as f64
}

pub(super) fn min_max(x: &[f64]) -> (f64, f64) {
    x.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        })
}

/// Length of [`signal::moving_average_valid`](crate::signal::moving_average_valid)'s output.
pub(super) fn valid_len(n: usize, window: usize) -> usize {
    if window <= 1 {
        n
    } else if n < window {
        0
    } else {
        n - window + 1
    }
}

/// Values `from..to` of
/// [`signal::moving_average_valid`](crate::signal::moving_average_valid), passed to `f` in
/// order, with the running sum started afresh at `from` (so values `0..` are those of one
/// sequential walk, bit for bit).
#[inline]
pub(super) fn moving_average_segment(
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
pub(super) fn over_segment_pairs<T: Send>(
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

/// Folds the moving average of `x` (over `window` samples) segment by segment, two segments
/// side by side ([`over_segment_pairs`], [`moving_average_segments`]): each segment's values,
/// in order, into its own accumulator started at `init` by `step`. `seg(k)` is segment `k`'s
/// range of samples. Returns one accumulator per segment, in order.
pub(super) fn fold_segment_pairs<T: Copy + Send + Sync>(
    x: &[f64],
    window: usize,
    segments: usize,
    seg: impl Fn(usize) -> (usize, usize) + Sync,
    init: T,
    step: impl Fn(&mut T, f64) + Sync,
) -> Vec<T> {
    over_segment_pairs(segments, |ka, kb| {
        let (mut a, mut b) = (init, init);
        moving_average_segments(
            x,
            window,
            seg(ka),
            kb.map(&seg),
            |v| step(&mut a, v),
            |v| step(&mut b, v),
        );
        (a, b)
    })
}

/// [`moving_average_segment`] over segment `a` and, when given, segment `b`, in lockstep: each
/// segment's values are computed and passed on exactly as a walk of its own would (so the same
/// bits), but the two running sums are independent chains that the processor overlaps. A walk
/// of one running sum waits on each addition; that wait, not the arithmetic, is its cost.
#[inline]
pub(super) fn moving_average_segments(
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
