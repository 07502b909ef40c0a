//! Least-squares fitting of every approximation kind over packed points.

use super::knots::{knot_positions, knot_weights};
use super::{Approx, ApproxKind, ApproxSpec, Curve, FitError, FitStats};
use nalgebra::{DMatrix, DVector};

/// Fits `spec` to the points `(xs[k], ys[k])` by least squares. Non-finite points are skipped.
pub fn fit(spec: &ApproxSpec, xs: &[f64], ys: &[f64]) -> Result<Approx, FitError> {
    fit_weighted(spec, xs, ys, None)
}

/// Fits `spec` by weighted least squares: point `k` counts `weights[k]` times (points with a
/// non-finite or non-positive weight are skipped). `None` weighs every point alike.
pub fn fit_weighted(
    spec: &ApproxSpec,
    xs: &[f64],
    ys: &[f64],
    weights: Option<&[f64]>,
) -> Result<Approx, FitError> {
    let pts = Points::gather(xs, ys, weights);
    let needed = match spec.kind {
        ApproxKind::Pwl | ApproxKind::Spline if spec.knots < 2 => {
            return Err(FitError::TooFewKnots(spec.kind));
        }
        _ => spec.params(),
    };
    let got = pts.x.len();
    if got < needed {
        return Err(FitError::TooFewPoints {
            kind: spec.kind,
            needed,
            got,
        });
    }
    let (lo, hi) = pts
        .x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    let curve = match spec.kind {
        ApproxKind::Linear | ApproxKind::Parabolic => fit_polynomial(spec.params(), &pts, lo, hi),
        ApproxKind::Pwl | ApproxKind::Spline => {
            let knots_x = knot_positions(lo, hi, spec.knots);
            let knots_y = fit_knots(spec.kind, &knots_x, &pts);
            if spec.kind == ApproxKind::Pwl {
                Curve::Pwl { knots_x, knots_y }
            } else {
                Curve::CatmullRom { knots_x, knots_y }
            }
        }
    };
    let (lo, hi) = match &curve {
        Curve::Pwl { knots_x, .. } | Curve::CatmullRom { knots_x, .. } => {
            (knots_x[0], knots_x[knots_x.len() - 1])
        }
        Curve::Polynomial { .. } => (lo, hi),
    };
    let mut approx = Approx::new(
        spec.kind,
        curve,
        lo,
        hi,
        spec.extrapolate,
        FitStats::default(),
    )
    .map_err(|_| FitError::TooFewPoints {
        kind: spec.kind,
        needed,
        got,
    })?;
    approx.stats = stats_of(&approx, &pts);
    Ok(approx)
}

/// The usable points of a fit, packed so that every pass over them is a plain loop over
/// contiguous arrays (fits run on hundreds of thousands of points per workbench edit).
struct Points {
    x: Vec<f64>,
    y: Vec<f64>,
    w: Vec<f64>,
}

impl Points {
    fn gather(xs: &[f64], ys: &[f64], weights: Option<&[f64]>) -> Points {
        let n = xs.len().min(ys.len());
        let mut p = Points {
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
            w: Vec::with_capacity(n),
        };
        for k in 0..n {
            let w = weights.map_or(1.0, |w| w.get(k).copied().unwrap_or(0.0));
            if xs[k].is_finite() && ys[k].is_finite() && w.is_finite() && w > 0.0 {
                p.x.push(xs[k]);
                p.y.push(ys[k]);
                p.w.push(w);
            }
        }
        p
    }
}

/// Weighted statistics (plain ones when every weight is 1).
fn stats_of(a: &Approx, p: &Points) -> FitStats {
    let sw: f64 = p.w.iter().sum();
    let mean = p.y.iter().zip(&p.w).map(|(y, w)| w * y).sum::<f64>() / sw;
    let (mut ss_res, mut ss_tot) = (0.0, 0.0);
    for ((&x, &y), &w) in p.x.iter().zip(&p.y).zip(&p.w) {
        let r = y - a.eval(x);
        ss_res += w * r * r;
        ss_tot += w * (y - mean) * (y - mean);
    }
    FitStats {
        n: p.x.len(),
        rmse: (ss_res / sw).sqrt(),
        r2: if ss_tot > 0.0 {
            1.0 - ss_res / ss_tot
        } else {
            0.0
        },
    }
}

/// Polynomial of `n` coefficients (at most 3), fitted on x scaled to [−1, 1] (for
/// conditioning) and expanded back to powers of x.
fn fit_polynomial(n: usize, p: &Points, lo: f64, hi: f64) -> Curve {
    let c = 0.5 * (lo + hi);
    let s = if hi > lo { 0.5 * (hi - lo) } else { 1.0 };
    // Sums of w·u^k for k = 0..4 and of w·u^k·y for k = 0..2 fill the whole normal matrix.
    let (mut su, mut suy) = ([0.0f64; 5], [0.0f64; 3]);
    for ((&x, &y), &w) in p.x.iter().zip(&p.y).zip(&p.w) {
        let u = (x - c) / s;
        let u2 = u * u;
        su[0] += w;
        su[1] += w * u;
        su[2] += w * u2;
        su[3] += w * u2 * u;
        su[4] += w * u2 * u2;
        suy[0] += w * y;
        suy[1] += w * u * y;
        suy[2] += w * u2 * y;
    }
    let ata = DMatrix::from_fn(n, n, |a, b| su[a + b]);
    let aty = DVector::from_fn(n, |a, _| suy[a]);
    let q = solve(ata, aty);
    // Σ q_j ((x − c)/s)^j expanded into Σ coeffs_k x^k.
    let mut coeffs = vec![0.0; n];
    for (j, qj) in q.iter().enumerate() {
        let scale = qj / s.powi(j as i32);
        for (k, ck) in coeffs.iter_mut().enumerate().take(j + 1) {
            *ck += scale * binomial(j, k) as f64 * (-c).powi((j - k) as i32);
        }
    }
    Curve::Polynomial { coeffs }
}

fn binomial(n: usize, k: usize) -> u64 {
    (0..k).fold(1u64, |acc, i| acc * (n - i) as u64 / (i + 1) as u64)
}

/// Knot values by least squares over the knot-weight basis, with a vanishing second-difference
/// penalty so that a knot interval without points is bridged smoothly instead of left singular.
fn fit_knots(kind: ApproxKind, knots_x: &[f64], p: &Points) -> Vec<f64> {
    let m = knots_x.len();
    // Row-major upper triangle of AᵀA and Aᵀy, in plain arrays for the hot loop.
    let mut ata = vec![0.0f64; m * m];
    let mut aty = vec![0.0f64; m];
    for ((&x, &y), &pw) in p.x.iter().zip(&p.y).zip(&p.w) {
        let (first, w) = knot_weights(kind, knots_x, x);
        let width = (m - first).min(4);
        for a in 0..width {
            let wa = pw * w[a];
            aty[first + a] += wa * y;
            let row = (first + a) * m + first;
            for b in a..width {
                ata[row + b] += wa * w[b];
            }
        }
    }
    let mut ata = DMatrix::from_fn(m, m, |a, b| ata[a.min(b) * m + a.max(b)]);
    let aty = DVector::from_vec(aty);
    let lambda = 1e-9 * ata.trace() / m as f64;
    for j in 1..m.saturating_sub(1) {
        let d = [(j - 1, 1.0), (j, -2.0), (j + 1, 1.0)];
        for &(a, wa) in &d {
            for &(b, wb) in &d {
                ata[(a, b)] += lambda * wa * wb;
            }
        }
    }
    solve(ata, aty).iter().copied().collect()
}

/// Least-squares solution of the normal equations; SVD so that a rank-deficient system (all
/// points at one x) still gives the minimum-norm answer rather than an error.
fn solve(ata: DMatrix<f64>, aty: DVector<f64>) -> DVector<f64> {
    let scale = ata.amax().max(f64::MIN_POSITIVE);
    let svd = ata.svd(true, true);
    svd.solve(&aty, scale * 1e-13)
        .unwrap_or_else(|_| DVector::zeros(aty.len()))
}
