//! Approximations of a coefficient as a function of one variable: linear, parabolic,
//! piecewise-linear and cubic spline, fitted by least squares.
//!
//! Every kind is linear in its parameters (polynomial coefficients, or the values at fixed
//! knots), so one solver serves all four: accumulate the normal equations over the points'
//! basis values, then solve the small system by SVD (nalgebra). Piecewise-linear and spline
//! curves are evaluated by the `splines` crate; the basis used to fit them is the same curve
//! written as weights on the knot values, and a test holds the two equal.
//!
//! A fitted approximation remembers the x-range it saw. Outside it, it holds the edge value
//! unless told to extrapolate: a calibration must not invent coefficients for rates the test
//! never reached.

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use splines::{Interpolation, Key, Spline};
use std::fmt;
use std::str::FromStr;

/// The family of curve an engineer picks for a coefficient.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ApproxKind {
    /// `c0 + c1·x`.
    Linear,
    /// `c0 + c1·x + c2·x²` (the paper's choice for K0).
    Parabolic,
    /// Straight segments between equally spaced knots.
    Pwl,
    /// Catmull-Rom cubic spline through values at equally spaced knots.
    Spline,
}

impl ApproxKind {
    /// All kinds, in the order a user interface lists them.
    pub const ALL: [ApproxKind; 4] = [
        ApproxKind::Linear,
        ApproxKind::Parabolic,
        ApproxKind::Pwl,
        ApproxKind::Spline,
    ];

    /// Whether the kind is defined by knots (and so takes a knot count).
    pub fn has_knots(self) -> bool {
        matches!(self, ApproxKind::Pwl | ApproxKind::Spline)
    }
}

impl fmt::Display for ApproxKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ApproxKind::Linear => "linear",
            ApproxKind::Parabolic => "parabolic",
            ApproxKind::Pwl => "pwl",
            ApproxKind::Spline => "spline",
        })
    }
}

impl FromStr for ApproxKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "linear" | "line" => Ok(ApproxKind::Linear),
            "parabolic" | "parabola" | "quadratic" => Ok(ApproxKind::Parabolic),
            "pwl" | "piecewise-linear" | "piecewise_linear" => Ok(ApproxKind::Pwl),
            "spline" | "cubic-spline" | "cubic_spline" => Ok(ApproxKind::Spline),
            other => Err(format!(
                "unknown approximation \"{other}\": use linear, parabolic, pwl or spline"
            )),
        }
    }
}

/// What the engineer chose for one coefficient.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ApproxSpec {
    /// The curve family.
    pub kind: ApproxKind,
    /// Number of knots for `pwl` and `spline` (at least 2); ignored otherwise.
    pub knots: usize,
    /// Evaluate the curve beyond the fitted x-range instead of holding the edge value.
    pub extrapolate: bool,
}

impl Default for ApproxSpec {
    fn default() -> Self {
        ApproxSpec {
            kind: ApproxKind::Linear,
            knots: 5,
            extrapolate: false,
        }
    }
}

impl ApproxSpec {
    /// A spec of `kind` with default knots and no extrapolation.
    pub fn of(kind: ApproxKind) -> ApproxSpec {
        ApproxSpec {
            kind,
            ..ApproxSpec::default()
        }
    }

    /// Number of free parameters the fit will have.
    pub fn params(&self) -> usize {
        match self.kind {
            ApproxKind::Linear => 2,
            ApproxKind::Parabolic => 3,
            ApproxKind::Pwl | ApproxKind::Spline => self.knots,
        }
    }
}

/// How well a fit matches its points.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct FitStats {
    /// Points used.
    pub n: usize,
    /// Root-mean-square residual, in the coefficient's unit.
    pub rmse: f64,
    /// Coefficient of determination (1 − SSres/SStot); 0 when the points have no spread.
    pub r2: f64,
}

/// The fitted curve, as stored in calibration files.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "form", rename_all = "snake_case", deny_unknown_fields)]
pub enum Curve {
    /// `Σ coeffs[k]·x^k`, lowest power first.
    Polynomial {
        /// Coefficients, lowest power first.
        coeffs: Vec<f64>,
    },
    /// Straight segments through `(knots_x[j], knots_y[j])`.
    Pwl {
        /// Knot positions, strictly increasing.
        knots_x: Vec<f64>,
        /// Values at the knots.
        knots_y: Vec<f64>,
    },
    /// Catmull-Rom spline through the knots; the tangent at an end knot uses a phantom knot
    /// continuing the first (last) segment in a straight line.
    CatmullRom {
        /// Knot positions, strictly increasing.
        knots_x: Vec<f64>,
        /// Values at the knots.
        knots_y: Vec<f64>,
    },
}

/// A fitted approximation: its curve, the x-range it was fitted on and its statistics.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(try_from = "ApproxRepr", into = "ApproxRepr")]
pub struct Approx {
    kind: ApproxKind,
    curve: Curve,
    x_min: f64,
    x_max: f64,
    extrapolate: bool,
    stats: FitStats,
    /// The `splines` evaluator for knot curves, built once.
    spline: Option<Spline<f64, f64>>,
}

impl PartialEq for Approx {
    fn eq(&self, other: &Self) -> bool {
        self.kind == other.kind
            && self.curve == other.curve
            && self.x_min == other.x_min
            && self.x_max == other.x_max
            && self.extrapolate == other.extrapolate
            && self.stats == other.stats
    }
}

/// The serialised form of [`Approx`]; loading validates it.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ApproxRepr {
    kind: ApproxKind,
    x_min: f64,
    x_max: f64,
    extrapolate: bool,
    stats: FitStats,
    curve: Curve,
}

impl From<Approx> for ApproxRepr {
    fn from(a: Approx) -> Self {
        ApproxRepr {
            kind: a.kind,
            x_min: a.x_min,
            x_max: a.x_max,
            extrapolate: a.extrapolate,
            stats: a.stats,
            curve: a.curve,
        }
    }
}

impl TryFrom<ApproxRepr> for Approx {
    type Error = String;
    fn try_from(r: ApproxRepr) -> Result<Self, String> {
        Approx::new(r.kind, r.curve, r.x_min, r.x_max, r.extrapolate, r.stats)
    }
}

/// Why a fit could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// Fewer usable points than parameters.
    #[error("{kind} needs at least {needed} points, {got} usable")]
    TooFewPoints {
        /// The kind asked for.
        kind: ApproxKind,
        /// Parameters of the fit.
        needed: usize,
        /// Finite points given.
        got: usize,
    },
    /// A knot curve with fewer than two knots.
    #[error("{0} needs at least 2 knots")]
    TooFewKnots(ApproxKind),
}

impl Approx {
    /// Builds an approximation from stored parts, checking that every number is finite and the
    /// knots are ordered.
    pub fn new(
        kind: ApproxKind,
        curve: Curve,
        x_min: f64,
        x_max: f64,
        extrapolate: bool,
        stats: FitStats,
    ) -> Result<Approx, String> {
        if !x_min.is_finite() || !x_max.is_finite() || x_min > x_max {
            return Err(format!("invalid x-range [{x_min}, {x_max}]"));
        }
        let spline = match &curve {
            Curve::Polynomial { coeffs } => {
                if coeffs.is_empty() || coeffs.iter().any(|c| !c.is_finite()) {
                    return Err("polynomial coefficients must be finite and non-empty".into());
                }
                None
            }
            Curve::Pwl { knots_x, knots_y } | Curve::CatmullRom { knots_x, knots_y } => {
                check_knots(knots_x, knots_y)?;
                Some(build_spline(&curve))
            }
        };
        Ok(Approx {
            kind,
            curve,
            x_min,
            x_max,
            extrapolate,
            stats,
            spline,
        })
    }

    /// The zero function, for a coefficient with no data to fit (its term then contributes
    /// nothing, which is what an uncalibrated term should do).
    pub fn zero(kind: ApproxKind) -> Approx {
        Approx {
            kind,
            curve: Curve::Polynomial { coeffs: vec![0.0] },
            x_min: 0.0,
            x_max: 0.0,
            extrapolate: false,
            stats: FitStats::default(),
            spline: None,
        }
    }

    /// The family this approximation was fitted as.
    pub fn kind(&self) -> ApproxKind {
        self.kind
    }
    /// The fitted curve.
    pub fn curve(&self) -> &Curve {
        &self.curve
    }
    /// Smallest x seen by the fit.
    pub fn x_min(&self) -> f64 {
        self.x_min
    }
    /// Largest x seen by the fit.
    pub fn x_max(&self) -> f64 {
        self.x_max
    }
    /// Whether evaluation goes beyond the fitted range.
    pub fn extrapolates(&self) -> bool {
        self.extrapolate
    }
    /// Fit statistics.
    pub fn stats(&self) -> FitStats {
        self.stats
    }
    /// Knots of a knot curve (empty for polynomials).
    pub fn knots(&self) -> (&[f64], &[f64]) {
        match &self.curve {
            Curve::Polynomial { .. } => (&[], &[]),
            Curve::Pwl { knots_x, knots_y } | Curve::CatmullRom { knots_x, knots_y } => {
                (knots_x, knots_y)
            }
        }
    }

    /// Returns a copy with knot `j` moved to value `y` (the workbench's dragged knot).
    pub fn with_knot_value(&self, j: usize, y: f64) -> Approx {
        let mut curve = self.curve.clone();
        if let Curve::Pwl { knots_y, .. } | Curve::CatmullRom { knots_y, .. } = &mut curve
            && j < knots_y.len()
            && y.is_finite()
        {
            knots_y[j] = y;
        }
        let spline = self.spline.as_ref().map(|_| build_spline(&curve));
        Approx {
            curve,
            spline,
            ..self.clone()
        }
    }

    /// Value at `x`, holding the edge value outside the fitted range unless extrapolating.
    /// A non-finite `x` gives 0: no correction from a sample that has no derivative.
    #[inline]
    pub fn eval(&self, x: f64) -> f64 {
        if !x.is_finite() {
            return 0.0;
        }
        let x = if self.extrapolate {
            x
        } else {
            x.clamp(self.x_min, self.x_max)
        };
        match &self.curve {
            Curve::Polynomial { coeffs } => coeffs.iter().rev().fold(0.0, |acc, c| acc * x + c),
            Curve::Pwl { knots_x, knots_y } | Curve::CatmullRom { knots_x, knots_y } => {
                let n = knots_x.len();
                if x <= knots_x[0] {
                    edge_line(knots_x[0], knots_y[0], knots_x[1], knots_y[1], x)
                } else if x >= knots_x[n - 1] {
                    edge_line(
                        knots_x[n - 1],
                        knots_y[n - 1],
                        knots_x[n - 2],
                        knots_y[n - 2],
                        x,
                    )
                } else {
                    // Inside the knots the crate always has a segment; the fallback only guards
                    // against a bug, never against data.
                    self.spline
                        .as_ref()
                        .and_then(|s| s.sample(x))
                        .unwrap_or(0.0)
                }
            }
        }
    }
}

/// The line through the end knot `(x0, y0)` and its neighbour, evaluated at `x` (equal to
/// `y0` at the knot itself, which is what clamped evaluation asks for).
#[inline]
fn edge_line(x0: f64, y0: f64, x1: f64, y1: f64, x: f64) -> f64 {
    if x == x0 {
        y0
    } else {
        y0 + (y1 - y0) / (x1 - x0) * (x - x0)
    }
}

fn check_knots(xs: &[f64], ys: &[f64]) -> Result<(), String> {
    if xs.len() < 2 || xs.len() != ys.len() {
        return Err("a knot curve needs at least 2 knots with one value each".into());
    }
    if xs.iter().chain(ys).any(|v| !v.is_finite()) {
        return Err("knot positions and values must be finite".into());
    }
    if xs.windows(2).any(|w| w[1] <= w[0]) {
        return Err("knot positions must be strictly increasing".into());
    }
    Ok(())
}

/// The `splines` evaluator of a knot curve. Catmull-Rom needs a key beyond each end: a phantom
/// knot continuing the end segment straight, so that the curve's end tangents follow the data.
fn build_spline(curve: &Curve) -> Spline<f64, f64> {
    match curve {
        Curve::Polynomial { .. } => Spline::from_vec(Vec::new()),
        Curve::Pwl { knots_x, knots_y } => Spline::from_vec(
            knots_x
                .iter()
                .zip(knots_y)
                .map(|(&x, &y)| Key::new(x, y, Interpolation::Linear))
                .collect(),
        ),
        Curve::CatmullRom { knots_x, knots_y } => {
            let n = knots_x.len();
            let mut keys = Vec::with_capacity(n + 2);
            keys.push(Key::new(
                2.0 * knots_x[0] - knots_x[1],
                2.0 * knots_y[0] - knots_y[1],
                Interpolation::CatmullRom,
            ));
            keys.extend(
                knots_x
                    .iter()
                    .zip(knots_y)
                    .map(|(&x, &y)| Key::new(x, y, Interpolation::CatmullRom)),
            );
            keys.push(Key::new(
                2.0 * knots_x[n - 1] - knots_x[n - 2],
                2.0 * knots_y[n - 1] - knots_y[n - 2],
                Interpolation::CatmullRom,
            ));
            Spline::from_vec(keys)
        }
    }
}

/// Equally spaced knot positions over `[lo, hi]` (a degenerate range is widened a little so the
/// knots stay strictly increasing).
pub fn knot_positions(lo: f64, hi: f64, m: usize) -> Vec<f64> {
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        let pad = lo.abs().max(1.0) * 1e-9;
        (lo - pad, hi + pad)
    };
    (0..m)
        .map(|j| lo + (hi - lo) * j as f64 / (m - 1) as f64)
        .collect()
}

/// Weights of the knot values at `x` for a knot curve, as (first knot index, up to 4 weights).
///
/// The value of a piecewise-linear or Catmull-Rom curve is linear in its knot values; these are
/// the coefficients, written out from the same formulas the `splines` crate evaluates
/// (`cubic_hermite` with finite-difference tangents), with the phantom end knots folded back onto
/// the real ones. `x` must lie within the knots.
pub fn knot_weights(kind: ApproxKind, knots_x: &[f64], x: f64) -> (usize, [f64; 4]) {
    let n = knots_x.len();
    // Segment i: knots_x[i] <= x < knots_x[i+1] (the last segment includes its right end).
    let i = match knots_x.partition_point(|&k| k <= x) {
        0 => 0,
        p => (p - 1).min(n - 2),
    };
    let (xa, xb) = (knots_x[i], knots_x[i + 1]);
    let t = ((x - xa) / (xb - xa)).clamp(0.0, 1.0);
    if kind != ApproxKind::Spline {
        return (i, [1.0 - t, t, 0.0, 0.0]);
    }
    // Neighbouring knot positions, phantom ones by straight continuation.
    let xp = if i == 0 {
        2.0 * xa - xb
    } else {
        knots_x[i - 1]
    };
    let xn = if i + 2 >= n {
        2.0 * xb - xa
    } else {
        knots_x[i + 2]
    };
    let (t2, t3) = (t * t, t * t * t);
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + t;
    let h01 = 3.0 * t2 - 2.0 * t3;
    let h11 = t3 - t2;
    let s0 = (xb - xa) / (xb - xp);
    let s1 = (xb - xa) / (xn - xa);
    // value = h00·ya + h10·s0·(yb − yp) + h01·yb + h11·s1·(yn − ya)
    let mut w = [0.0; 4]; // weights on knots i-1, i, i+1, i+2
    w[0] -= h10 * s0;
    w[1] += h00 - h11 * s1;
    w[2] += h01 + h10 * s0;
    w[3] += h11 * s1;
    // Fold phantoms: yp = 2ya − yb at the left end, yn = 2yb − ya at the right end.
    if i == 0 {
        let wp = w[0];
        w[0] = 0.0;
        w[1] += 2.0 * wp;
        w[2] -= wp;
    }
    if i + 2 >= n {
        let wn = w[3];
        w[3] = 0.0;
        w[2] += 2.0 * wn;
        w[1] -= wn;
    }
    if i == 0 {
        // Shift so the first weight belongs to knot 0.
        (0, [w[1], w[2], w[3], 0.0])
    } else {
        (i - 1, w)
    }
}

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
    let wt = |k: usize| weights.map_or(1.0, |w| w.get(k).copied().unwrap_or(0.0));
    let finite =
        |k: usize| xs[k].is_finite() && ys[k].is_finite() && wt(k).is_finite() && wt(k) > 0.0;
    let idx: Vec<usize> = (0..xs.len().min(ys.len())).filter(|&k| finite(k)).collect();
    let needed = match spec.kind {
        ApproxKind::Pwl | ApproxKind::Spline if spec.knots < 2 => {
            return Err(FitError::TooFewKnots(spec.kind));
        }
        _ => spec.params(),
    };
    if idx.len() < needed {
        return Err(FitError::TooFewPoints {
            kind: spec.kind,
            needed,
            got: idx.len(),
        });
    }
    let (lo, hi) = idx
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &k| {
            (lo.min(xs[k]), hi.max(xs[k]))
        });
    let curve = match spec.kind {
        ApproxKind::Linear | ApproxKind::Parabolic => {
            fit_polynomial(spec.params(), &idx, xs, ys, &wt, lo, hi)
        }
        ApproxKind::Pwl | ApproxKind::Spline => {
            let knots_x = knot_positions(lo, hi, spec.knots);
            let knots_y = fit_knots(spec.kind, &knots_x, &idx, xs, ys, &wt);
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
        got: idx.len(),
    })?;
    approx.stats = stats_of(&approx, &idx, xs, ys, &wt);
    Ok(approx)
}

/// Weighted statistics (plain ones when every weight is 1).
fn stats_of(
    a: &Approx,
    idx: &[usize],
    xs: &[f64],
    ys: &[f64],
    wt: &dyn Fn(usize) -> f64,
) -> FitStats {
    let n = idx.len();
    let sw: f64 = idx.iter().map(|&k| wt(k)).sum();
    let mean = idx.iter().map(|&k| wt(k) * ys[k]).sum::<f64>() / sw;
    let (mut ss_res, mut ss_tot) = (0.0, 0.0);
    for &k in idx {
        let r = ys[k] - a.eval(xs[k]);
        ss_res += wt(k) * r * r;
        ss_tot += wt(k) * (ys[k] - mean).powi(2);
    }
    FitStats {
        n,
        rmse: (ss_res / sw).sqrt(),
        r2: if ss_tot > 0.0 {
            1.0 - ss_res / ss_tot
        } else {
            0.0
        },
    }
}

/// Polynomial of `p` coefficients, fitted on x scaled to [−1, 1] (for conditioning) and
/// expanded back to powers of x.
fn fit_polynomial(
    p: usize,
    idx: &[usize],
    xs: &[f64],
    ys: &[f64],
    wt: &dyn Fn(usize) -> f64,
    lo: f64,
    hi: f64,
) -> Curve {
    let c = 0.5 * (lo + hi);
    let s = if hi > lo { 0.5 * (hi - lo) } else { 1.0 };
    let mut ata = DMatrix::<f64>::zeros(p, p);
    let mut aty = DVector::<f64>::zeros(p);
    let mut row = [0.0; 3];
    for &k in idx {
        let u = (xs[k] - c) / s;
        row[0] = 1.0;
        for j in 1..p {
            row[j] = row[j - 1] * u;
        }
        let w = wt(k);
        for a in 0..p {
            aty[a] += w * row[a] * ys[k];
            for b in a..p {
                ata[(a, b)] += w * row[a] * row[b];
            }
        }
    }
    symmetrize(&mut ata);
    let q = solve(ata, aty);
    // Σ q_j ((x − c)/s)^j expanded into Σ coeffs_k x^k.
    let mut coeffs = vec![0.0; p];
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
fn fit_knots(
    kind: ApproxKind,
    knots_x: &[f64],
    idx: &[usize],
    xs: &[f64],
    ys: &[f64],
    wt: &dyn Fn(usize) -> f64,
) -> Vec<f64> {
    let m = knots_x.len();
    let mut ata = DMatrix::<f64>::zeros(m, m);
    let mut aty = DVector::<f64>::zeros(m);
    for &k in idx {
        let (first, w) = knot_weights(kind, knots_x, xs[k]);
        let width = (m - first).min(4);
        let pw = wt(k);
        for a in 0..width {
            aty[first + a] += pw * w[a] * ys[k];
            for b in a..width {
                ata[(first + a, first + b)] += pw * w[a] * w[b];
            }
        }
    }
    symmetrize(&mut ata);
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

fn symmetrize(m: &mut DMatrix<f64>) {
    for a in 0..m.nrows() {
        for b in 0..a {
            m[(a, b)] = m[(b, a)];
        }
    }
}

/// Least-squares solution of the normal equations; SVD so that a rank-deficient system (all
/// points at one x) still gives the minimum-norm answer rather than an error.
fn solve(ata: DMatrix<f64>, aty: DVector<f64>) -> DVector<f64> {
    let scale = ata.amax().max(f64::MIN_POSITIVE);
    let svd = ata.svd(true, true);
    svd.solve(&aty, scale * 1e-13)
        .unwrap_or_else(|_| DVector::zeros(aty.len()))
}
