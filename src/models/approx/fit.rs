//! Least-squares fitting of every approximation kind, streaming over the points.
//!
//! Every fit here is a normal-equation accumulation (polynomials: power sums; knot curves: the
//! banded AᵀA over [`knot_weights`]) preceded by a pass for the x-range and followed, when the
//! statistics are wanted, by a pass for the residuals. None of these passes needs the points
//! held in memory: a fit takes a [`PointSource`] that produces them on demand, so a calibration
//! of a long log fits straight from its columns. Each pass runs over fixed chunks of
//! [`CHUNK`] candidate points in parallel and adds the chunks' sums in order, so the result does
//! not depend on the number of threads; a set of at most `CHUNK` points is summed exactly as one
//! sequential loop would.

use super::knots::{knot_positions, knot_weights};
use super::{Approx, ApproxKind, ApproxSpec, Curve, FitError, FitStats};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// Candidate points per chunk of a pass.
pub const CHUNK: usize = 1 << 16;

/// Points a fit streams over: candidates `0..candidates()`, each an `(x, y, w)`. A candidate
/// with a non-finite x or y, or a weight that is not finite and positive, is skipped.
pub trait PointSource: Sync {
    /// Number of candidates.
    fn candidates(&self) -> usize;
    /// Calls `f(x, y, w)` for candidates `from..to`, in order.
    fn visit<F: FnMut(f64, f64, f64)>(&self, from: usize, to: usize, f: F);
}

/// What a source may know of its points before a fit: how many have a usable x and weight, and
/// their x-range. A fit that is given it checks it (it counts the points it used) and makes its
/// own pass when it did not hold, e.g. because some y was not finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct XRange {
    /// Points with a usable x and weight.
    pub n: usize,
    /// Smallest such x.
    pub lo: f64,
    /// Largest such x.
    pub hi: f64,
}

/// How [`fit_with`] runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// The points' x-range when known (saves a pass).
    pub known: Option<XRange>,
    /// Compute [`FitStats`] (a pass more); without them the stats hold only `n`.
    pub stats: bool,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            known: None,
            stats: true,
        }
    }
}

#[inline]
pub(crate) fn usable(x: f64, y: f64, w: f64) -> bool {
    x.is_finite() && y.is_finite() && w.is_finite() && w > 0.0
}

/// Sums `chunk(from, to)` over the fixed chunks of `n` candidates, in parallel, folding the
/// chunks' results in order with `add`.
pub(crate) fn over_chunks<T: Send>(
    n: usize,
    chunk: impl Fn(usize, usize) -> T + Sync,
    add: impl Fn(T, T) -> T,
) -> Option<T> {
    let parts: Vec<T> = if n <= CHUNK {
        vec![chunk(0, n)]
    } else {
        (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| chunk(c * CHUNK, ((c + 1) * CHUNK).min(n)))
            .collect()
    };
    parts.into_iter().reduce(add)
}

/// The usable points' count and x-range, by a pass over the source.
pub fn x_range<S: PointSource>(src: &S) -> XRange {
    let part = |from, to| {
        let mut r = XRange {
            n: 0,
            lo: f64::INFINITY,
            hi: f64::NEG_INFINITY,
        };
        src.visit(from, to, |x, y, w| {
            if usable(x, y, w) {
                r.n += 1;
                r.lo = r.lo.min(x);
                r.hi = r.hi.max(x);
            }
        });
        r
    };
    over_chunks(src.candidates(), part, |a, b| XRange {
        n: a.n + b.n,
        lo: a.lo.min(b.lo),
        hi: a.hi.max(b.hi),
    })
    .unwrap_or(XRange {
        n: 0,
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    })
}

/// Points given as slices (`weights`: `None` weighs every point 1; a missing weight is 0).
struct Slices<'a> {
    xs: &'a [f64],
    ys: &'a [f64],
    weights: Option<&'a [f64]>,
}

impl PointSource for Slices<'_> {
    fn candidates(&self) -> usize {
        self.xs.len().min(self.ys.len())
    }
    fn visit<F: FnMut(f64, f64, f64)>(&self, from: usize, to: usize, mut f: F) {
        for k in from..to {
            let w = self
                .weights
                .map_or(1.0, |w| w.get(k).copied().unwrap_or(0.0));
            f(self.xs[k], self.ys[k], w);
        }
    }
}

/// Fits `spec` to the points `(xs[k], ys[k])` by least squares. Non-finite points are skipped.
/// A knot curve has its knots at `spec.at` when placed by hand, else equally spaced over the
/// points' x-range; its fitted range is the knots' span either way. Hand-set values
/// (`spec.values`) are not read: the caller puts them in (see [`ApproxSpec::values`]).
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
    fit_with(spec, &Slices { xs, ys, weights }, FitOptions::default())
}

/// Fits `spec` by weighted least squares to the points of `src`, without holding them.
pub fn fit_with<S: PointSource>(
    spec: &ApproxSpec,
    src: &S,
    opts: FitOptions,
) -> Result<Approx, FitError> {
    let (mut approx, sums) = fit_curve(spec, src, opts)?;
    if opts.stats {
        approx.stats = stats_of(&approx, src, sums);
    }
    Ok(approx)
}

/// [`fit_with`], and `then` of the fitted curve, run beside the pass that computes the
/// statistics when they are asked for (they change nothing `then` may read of the curve): a
/// caller whose next step needs the curve alone, as the K2 fit needs K1, overlaps the two.
///
/// # Errors
/// As [`fit_with`] (`then` is not called).
pub fn fit_with_then<S: PointSource, T: Send>(
    spec: &ApproxSpec,
    src: &S,
    opts: FitOptions,
    then: impl FnOnce(&Approx) -> T + Send,
) -> Result<(Approx, T), FitError> {
    let (mut approx, sums) = fit_curve(spec, src, opts)?;
    if !opts.stats {
        let t = then(&approx);
        return Ok((approx, t));
    }
    let (stats, t) = rayon::join(|| stats_of(&approx, src, sums), || then(&approx));
    approx.stats = stats;
    Ok((approx, t))
}

/// The curve of [`fit_with`], with the sums its statistics start from (its stats hold `n`
/// only).
fn fit_curve<S: PointSource>(
    spec: &ApproxSpec,
    src: &S,
    opts: FitOptions,
) -> Result<(Approx, Sums), FitError> {
    let needed = match spec.kind {
        ApproxKind::Pwl | ApproxKind::Spline if spec.knots < 2 => {
            return Err(FitError::TooFewKnots(spec.kind));
        }
        _ => spec.params(),
    };
    // Hand-placed positions are checked here too: a spec may reach a fit without a recipe's
    // checks (a library caller), and the segment search needs them strictly increasing.
    spec.fitted_part().check_knots()?;
    let range = match opts.known {
        Some(r) if r.n >= needed => r,
        _ => x_range(src),
    };
    let got = range.n;
    if got < needed {
        return Err(FitError::TooFewPoints {
            kind: spec.kind,
            needed,
            got,
        });
    }
    let (lo, hi) = (range.lo, range.hi);
    let (curve, sums) = match spec.kind {
        ApproxKind::Linear | ApproxKind::Parabolic => fit_polynomial(spec.params(), src, lo, hi),
        ApproxKind::Pwl | ApproxKind::Spline => {
            // Placed by hand, or spread evenly over the points.
            let knots_x = match &spec.at {
                Some(at) => at.clone(),
                None => knot_positions(lo, hi, spec.knots),
            };
            let (knots_y, sums) = fit_knots(spec.kind, &knots_x, src);
            let curve = if spec.kind == ApproxKind::Pwl {
                Curve::Pwl { knots_x, knots_y }
            } else {
                Curve::CatmullRom { knots_x, knots_y }
            };
            (curve, sums)
        }
    };
    if sums.n != got {
        // The range given was not that of the usable points: find it.
        return fit_curve(
            spec,
            src,
            FitOptions {
                known: None,
                ..opts
            },
        );
    }
    let (lo, hi) = match &curve {
        Curve::Pwl { knots_x, .. } | Curve::CatmullRom { knots_x, .. } => {
            (knots_x[0], knots_x[knots_x.len() - 1])
        }
        Curve::Polynomial { .. } => (lo, hi),
    };
    let approx = fitted_approx(spec, curve, (lo, hi), needed, got)?;
    Ok((approx, sums))
}

/// The approximation of a fitted curve over `(lo, hi)`, its stats holding the `got` points
/// only; a curve that is not one (a coefficient that overflowed) is reported as too few
/// points for the `needed` parameters, the only way a least-squares fit makes one.
pub(super) fn fitted_approx(
    spec: &ApproxSpec,
    curve: Curve,
    (lo, hi): (f64, f64),
    needed: usize,
    got: usize,
) -> Result<Approx, FitError> {
    Approx::new(
        spec.kind,
        curve,
        lo,
        hi,
        spec.extrapolate,
        FitStats {
            n: got,
            ..FitStats::default()
        },
    )
    .map_err(|_| FitError::TooFewPoints {
        kind: spec.kind,
        needed,
        got,
    })
}

/// Count, Σw and Σw·y of the points a fit used, gathered while accumulating.
#[derive(Debug, Clone, Copy)]
struct Sums {
    n: usize,
    sw: f64,
    swy: f64,
}

/// The statistics of `a` on the points of `src`, fitted to them or not (a curve whose knot
/// values were set by hand is judged on the points its fit saw): a pass for their mean, one
/// for the residuals. A source without a usable point leaves `a`'s own statistics.
pub fn stats_with<S: PointSource>(a: &Approx, src: &S) -> FitStats {
    let part = |from, to| {
        let mut s = Sums {
            n: 0,
            sw: 0.0,
            swy: 0.0,
        };
        src.visit(from, to, |x, y, w| {
            if usable(x, y, w) {
                s.n += 1;
                s.sw += w;
                s.swy += w * y;
            }
        });
        s
    };
    let add = |a: Sums, b: Sums| Sums {
        n: a.n + b.n,
        sw: a.sw + b.sw,
        swy: a.swy + b.swy,
    };
    match over_chunks(src.candidates(), part, add) {
        Some(sums) if sums.n > 0 && sums.sw > 0.0 => stats_of(a, src, sums),
        _ => a.stats(),
    }
}

/// [`stats_with`] of points given as slices (`weights`: `None` weighs every point 1).
pub fn stats_on(a: &Approx, xs: &[f64], ys: &[f64], weights: Option<&[f64]>) -> FitStats {
    stats_with(a, &Slices { xs, ys, weights })
}

/// Weighted statistics (plain ones when every weight is 1).
fn stats_of<S: PointSource>(a: &Approx, src: &S, sums: Sums) -> FitStats {
    let mean = sums.swy / sums.sw;
    let a = a.evaluator();
    let part = |from, to| {
        let (mut ss_res, mut ss_tot) = (0.0, 0.0);
        src.visit(from, to, |x, y, w| {
            if usable(x, y, w) {
                let r = y - a.eval(x);
                ss_res += w * r * r;
                ss_tot += w * (y - mean) * (y - mean);
            }
        });
        (ss_res, ss_tot)
    };
    let (ss_res, ss_tot) =
        over_chunks(src.candidates(), part, |a, b| (a.0 + b.0, a.1 + b.1)).unwrap_or((0.0, 0.0));
    FitStats {
        n: sums.n,
        rmse: (ss_res / sums.sw).sqrt(),
        r2: if ss_tot > 0.0 {
            1.0 - ss_res / ss_tot
        } else {
            0.0
        },
    }
}

/// Polynomial of `n` coefficients (at most 3), fitted on x scaled to [−1, 1] (for
/// conditioning) and expanded back to powers of x.
fn fit_polynomial<S: PointSource>(n: usize, src: &S, lo: f64, hi: f64) -> (Curve, Sums) {
    let c = 0.5 * (lo + hi);
    let s = if hi > lo { 0.5 * (hi - lo) } else { 1.0 };
    // Sums of w·u^k for k = 0..4 and of w·u^k·y for k = 0..2 fill the whole normal matrix.
    type Acc = (usize, [f64; 5], [f64; 3]);
    let part = |from, to| {
        let (mut used, mut su, mut suy) = (0usize, [0.0f64; 5], [0.0f64; 3]);
        if n <= 2 {
            // A line needs the sums up to u² and u·y only (the others would go unused).
            src.visit(from, to, |x, y, w| {
                if !usable(x, y, w) {
                    return;
                }
                used += 1;
                let u = (x - c) / s;
                su[0] += w;
                su[1] += w * u;
                su[2] += w * (u * u);
                suy[0] += w * y;
                suy[1] += w * u * y;
            });
            return (used, su, suy);
        }
        src.visit(from, to, |x, y, w| {
            if !usable(x, y, w) {
                return;
            }
            used += 1;
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
        });
        (used, su, suy)
    };
    let add = |a: Acc, b: Acc| {
        let mut r = a;
        r.0 += b.0;
        for k in 0..5 {
            r.1[k] += b.1[k];
        }
        for k in 0..3 {
            r.2[k] += b.2[k];
        }
        r
    };
    let (used, su, suy) = over_chunks(src.candidates(), part, add).unwrap_or_default();
    let ata = DMatrix::from_fn(n, n, |a, b| su[a + b]);
    let aty = DVector::from_fn(n, |a, _| suy[a]);
    let q = solve(ata, aty);
    (
        Curve::Polynomial {
            coeffs: powers_of_x(q.as_slice(), c, s),
        },
        Sums {
            n: used,
            sw: su[0],
            swy: suy[0],
        },
    )
}

/// `Σ q_j ((x − c)/s)^j` expanded into `Σ coeffs_k x^k`: the polynomial fitted on the scaled
/// x, as stored.
pub(super) fn powers_of_x(q: &[f64], c: f64, s: f64) -> Vec<f64> {
    let mut coeffs = vec![0.0; q.len()];
    for (j, qj) in q.iter().enumerate() {
        let scale = qj / s.powi(j as i32);
        for (k, ck) in coeffs.iter_mut().enumerate().take(j + 1) {
            *ck += scale * binomial(j, k) as f64 * (-c).powi((j - k) as i32);
        }
    }
    coeffs
}

fn binomial(n: usize, k: usize) -> u64 {
    (0..k).fold(1u64, |acc, i| acc * (n - i) as u64 / (i + 1) as u64)
}

/// Knot values by least squares over the knot-weight basis, with a vanishing second-difference
/// penalty so that a knot interval without points is bridged smoothly instead of left singular.
fn fit_knots<S: PointSource>(kind: ApproxKind, knots_x: &[f64], src: &S) -> (Vec<f64>, Sums) {
    let m = knots_x.len();
    // Row-major upper triangle of AᵀA and Aᵀy, in plain arrays for the hot loop.
    struct Acc {
        used: usize,
        sw: f64,
        swy: f64,
        ata: Vec<f64>,
        aty: Vec<f64>,
    }
    let span = if kind == ApproxKind::Spline { 4 } else { 2 };
    let part = |from, to| {
        let mut a = Acc {
            used: 0,
            sw: 0.0,
            swy: 0.0,
            ata: vec![0.0f64; m * m],
            aty: vec![0.0f64; m],
        };
        let (ata, aty) = (&mut a.ata, &mut a.aty);
        let (mut used, mut sw, mut swy) = (0usize, 0.0f64, 0.0f64);
        src.visit(from, to, |x, y, pw| {
            if !usable(x, y, pw) {
                return;
            }
            used += 1;
            sw += pw;
            swy += pw * y;
            let (first, w) = knot_weights(kind, knots_x, x);
            // A straight segment weighs its two ends alone: the other two weights are zero, and
            // adding their zero products would change no sum (a third of the work).
            let width = (m - first).min(span);
            for a in 0..width {
                let wa = pw * w[a];
                aty[first + a] += wa * y;
                let row = (first + a) * m + first;
                for b in a..width {
                    ata[row + b] += wa * w[b];
                }
            }
        });
        (a.used, a.sw, a.swy) = (used, sw, swy);
        a
    };
    let add = |mut a: Acc, b: Acc| {
        a.used += b.used;
        a.sw += b.sw;
        a.swy += b.swy;
        a.ata.iter_mut().zip(&b.ata).for_each(|(p, q)| *p += q);
        a.aty.iter_mut().zip(&b.aty).for_each(|(p, q)| *p += q);
        a
    };
    let Some(acc) = over_chunks(src.candidates(), part, add) else {
        return (
            vec![0.0; m],
            Sums {
                n: 0,
                sw: 0.0,
                swy: 0.0,
            },
        );
    };
    (
        knot_values(knots_x, &acc.ata, acc.aty),
        Sums {
            n: acc.used,
            sw: acc.sw,
            swy: acc.swy,
        },
    )
}

/// The knot values solving the normal equations of a knot fit (`ata_upper`: the upper
/// triangle of AᵀA, row-major over `m × m`), with the vanishing second-difference penalty
/// that bridges a knot interval without points.
pub(super) fn knot_values(knots_x: &[f64], ata_upper: &[f64], aty: Vec<f64>) -> Vec<f64> {
    let m = knots_x.len();
    let mut ata = DMatrix::from_fn(m, m, |a, b| ata_upper[a.min(b) * m + a.max(b)]);
    let aty = DVector::from_vec(aty);
    let lambda = 1e-9 * ata.trace() / m as f64;
    for j in 1..m.saturating_sub(1) {
        // The second difference over the knots' positions, scaled to (1, −2, 1) for equal
        // gaps (and exactly that for the equally spaced knots of a fit, whose gaps differ by
        // rounding only): a knot with no point near it continues its neighbours' straight
        // line in x, wherever it was placed.
        let (h1, h2) = (knots_x[j] - knots_x[j - 1], knots_x[j + 1] - knots_x[j]);
        let hbar = 0.5 * (h1 + h2);
        let (a, c) = if (h1 - h2).abs() <= 1e-9 * hbar {
            (1.0, 1.0)
        } else {
            (hbar / h1, hbar / h2)
        };
        let d = [(j - 1, a), (j, -(a + c)), (j + 1, c)];
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
pub(super) fn solve(ata: DMatrix<f64>, aty: DVector<f64>) -> DVector<f64> {
    let scale = ata.amax().max(f64::MIN_POSITIVE);
    let svd = ata.svd(true, true);
    svd.solve(&aty, scale * 1e-13)
        .unwrap_or_else(|_| DVector::zeros(aty.len()))
}
