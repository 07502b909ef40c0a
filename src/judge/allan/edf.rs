//! Equivalent degrees of freedom of the Allan and Hadamard variances after Greenhall & Riley
//! (2003), "Uncertainty of stability variances based on finite differences": the basic sum,
//! its generalised autocovariances and the paper's large-sample tables. Apart because it is
//! a paper's algorithm of its own, checked against its tables rather than against the curve.

/// Equivalent degrees of freedom of an unmodified variance (Greenhall & Riley 2003): d = 2
/// Allan, d = 3 Hadamard; `m` the averaging factor, `n_phase` the number of phase points,
/// `overlapping` the stride (m for the overlapping estimator, 1 for the non-overlapping one).
///
/// Follows the paper's cases for unmodified variances: the exact basic sum when it has at
/// most 100 terms, the large-sample approximation of its Tables 2 and 3 when the series is
/// long, and the truncated sum otherwise. `None` when the noise type is outside α + 2d > 1,
/// d is not 2 or 3, or the series is too short for one term.
pub fn edf_greenhall(
    alpha: i32,
    d: u32,
    m: usize,
    n_phase: usize,
    overlapping: bool,
) -> Option<f64> {
    if !(2..=3).contains(&d) || !(-4..=2).contains(&alpha) || alpha + 2 * d as i32 <= 1 || m == 0 {
        return None;
    }
    const J_MAX: f64 = 100.0;
    let df = d as f64;
    let mf = m as f64;
    let s = if overlapping { mf } else { 1.0 };
    let f = Filter::Finite(mf);
    let l = 1.0 + mf * df; // filter length m/F + m·d, with F = m for unmodified variances
    let nf = n_phase as f64;
    if nf < l {
        return None;
    }
    let big_m = 1.0 + (s * (nf - l) / mf).floor();
    let j = big_m.min((df + 1.0) * s);
    let r = big_m / s;
    let inv = match alpha {
        a if a <= 0 => {
            if j <= J_MAX {
                let fp = if mf * (df + 1.0) <= J_MAX {
                    f
                } else {
                    Filter::Infinite
                };
                basic_sum(j, big_m, s, fp, alpha, d) / (sz(0.0, fp, alpha, d).powi(2) * big_m)
            } else if r > df + 1.0 {
                let (a0, a1) = table2(alpha, d)?;
                (a0 - a1 / r) / r
            } else {
                let mp = J_MAX / r;
                basic_sum(J_MAX, J_MAX, mp, Filter::Infinite, alpha, d)
                    / (sz(0.0, Filter::Infinite, alpha, d).powi(2) * J_MAX)
            }
        }
        1 => {
            if j <= J_MAX {
                basic_sum(j, big_m, s, f, 1, d) / (sz(0.0, f, 1, d).powi(2) * big_m)
            } else {
                let (b0, b1) = table3(d);
                let b = b0 + b1 * mf.ln();
                if r > df + 1.0 {
                    let (a0, a1) = table2(1, d)?;
                    (a0 - a1 / r) / (b * b * r)
                } else {
                    let mp = J_MAX / r;
                    basic_sum(J_MAX, J_MAX, mp, Filter::Finite(mp), 1, d) / (b * b * J_MAX)
                }
            }
        }
        _ => {
            // α = 2, white phase (angle) noise.
            let k = r.ceil();
            if k <= df {
                // Few terms: the exact basic sum (the paper's closed form for this case is the
                // same sum written out).
                basic_sum(j, big_m, s, f, 2, d) / (sz(0.0, f, 2, d).powi(2) * big_m)
            } else {
                let a0 = binomial(4 * d, 2 * d) / binomial(2 * d, d).powi(2);
                let a1 = df / 2.0;
                (a0 - a1 / r) / big_m
            }
        }
    };
    let edf = 1.0 / inv;
    (edf.is_finite() && edf > 0.0).then_some(edf)
}

/// The filter factor F of Greenhall's sums; infinite stands for the limit m → ∞.
#[derive(Clone, Copy)]
enum Filter {
    Finite(f64),
    Infinite,
}

/// Eq. (10) of Greenhall & Riley: the basic sum.
fn basic_sum(j: f64, big_m: f64, s: f64, f: Filter, alpha: i32, d: u32) -> f64 {
    let mut sum = sz(0.0, f, alpha, d).powi(2);
    sum += (1.0 - j / big_m) * sz(j / s, f, alpha, d).powi(2);
    let ji = j as usize;
    for jj in 1..ji {
        let jf = jj as f64;
        sum += 2.0 * (1.0 - jf / big_m) * sz(jf / s, f, alpha, d).powi(2);
    }
    sum
}

/// Eq. (9): the d-th difference of sx.
fn sz(t: f64, f: Filter, alpha: i32, d: u32) -> f64 {
    let c: &[f64] = match d {
        2 => &[6.0, -4.0, 1.0],
        _ => &[20.0, -15.0, 6.0, -1.0],
    };
    let mut v = c[0] * sx(t, f, alpha);
    for (k, &ck) in c.iter().enumerate().skip(1) {
        let kf = k as f64;
        v += ck * (sx(t - kf, f, alpha) + sx(t + kf, f, alpha));
    }
    v
}

/// Eq. (8).
fn sx(t: f64, f: Filter, alpha: i32) -> f64 {
    match f {
        Filter::Infinite => sw(t, alpha + 2),
        Filter::Finite(ff) => {
            ff * ff * (2.0 * sw(t, alpha) - sw(t - 1.0 / ff, alpha) - sw(t + 1.0 / ff, alpha))
        }
    }
}

/// Eq. (7): the generalised autocovariance of the noise of type α.
fn sw(t: f64, alpha: i32) -> f64 {
    let at = t.abs();
    let tlog = |p: i32| {
        if t == 0.0 { 0.0 } else { t.powi(p) * at.ln() }
    };
    match alpha {
        2 => -at,
        1 => tlog(2),
        0 => at.powi(3),
        -1 => tlog(4),
        -2 => at.powi(5),
        -3 => tlog(6),
        _ => at.powi(7),
    }
}

/// Table 2 of Greenhall & Riley (unmodified variances): (a0, a1) by α and d.
fn table2(alpha: i32, d: u32) -> Option<(f64, f64)> {
    let v = match (alpha, d) {
        (2, 2) => (35.0 / 18.0, 1.0),
        (2, 3) => (231.0 / 100.0, 1.5),
        (1, 2) => (790.0, 410.0),
        (1, 3) => (9950.0, 6520.0),
        (0, 2) => (2.0 / 3.0, 1.0 / 3.0),
        (0, 3) => (7.0 / 9.0, 0.5),
        (-1, 2) => (0.852, 0.375),
        (-1, 3) => (0.997, 0.617),
        (-2, 2) => (1.079, 0.368),
        (-2, 3) => (1.033, 0.607),
        (-3, 3) => (1.053, 0.553),
        (-4, 3) => (1.302, 0.535),
        _ => return None,
    };
    Some(v)
}

/// Table 3 of Greenhall & Riley (α = 1): (b0, b1) by d.
fn table3(d: u32) -> (f64, f64) {
    if d == 2 { (15.23, 12.0) } else { (47.8, 40.0) }
}

fn binomial(n: u32, k: u32) -> f64 {
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}
