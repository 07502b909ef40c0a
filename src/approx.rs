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
    /// Knot curves as one cubic per segment, read off the `splines` evaluator once.
    segments: Option<Segments>,
    /// Polynomials of up to 4 coefficients, unpacked for a branch-free Horner step.
    poly: Option<[f64; 4]>,
}

/// A knot curve as cubic polynomials in the local parameter `u ∈ [0, 1]` of each segment.
///
/// The `splines` crate defines the curve; evaluating it costs a binary search and a Hermite
/// blend per call (about 16 ns), which a correction of millions of samples per edit cannot
/// afford. Each segment of a piecewise-linear or Catmull-Rom curve is a polynomial of degree
/// at most 3 in `u`, so four samples of the crate's curve per segment determine it exactly; the
/// hot loop then finds the segment (arithmetically, for the equally spaced knots fits produce)
/// and takes one Horner step. A test holds the two evaluations equal.
#[derive(Debug, Clone)]
struct Segments {
    knots_x: Vec<f64>,
    /// `1/h` when the knots are equally spaced, else 0 (binary search).
    inv_step: f64,
    /// Per segment, `c0 + c1·u + c2·u² + c3·u³`.
    coeffs: Vec<[f64; 4]>,
}

impl Segments {
    fn of(curve: &Curve) -> Option<Segments> {
        let (Curve::Pwl { knots_x, knots_y } | Curve::CatmullRom { knots_x, knots_y }) = curve
        else {
            return None;
        };
        let spline = build_spline(curve);
        let n = knots_x.len();
        let coeffs = (0..n - 1)
            .map(|i| {
                let (a, b) = (knots_x[i], knots_x[i + 1]);
                let at = |u: f64| {
                    if u >= 1.0 {
                        knots_y[i + 1]
                    } else {
                        spline.sample(a + (b - a) * u).unwrap_or(knots_y[i])
                    }
                };
                if matches!(curve, Curve::Pwl { .. }) {
                    // Linear segments: the two ends say it all, and exactly.
                    let (p0, p3) = (at(0.0), at(1.0));
                    return [p0, p3 - p0, 0.0, 0.0];
                }
                let (p0, p1, p2, p3) = (at(0.0), at(1.0 / 3.0), at(2.0 / 3.0), at(1.0));
                // The cubic through (0, p0), (1/3, p1), (2/3, p2), (1, p3) in powers of u.
                [
                    p0,
                    (-11.0 * p0 + 18.0 * p1 - 9.0 * p2 + 2.0 * p3) / 2.0,
                    (18.0 * p0 - 45.0 * p1 + 36.0 * p2 - 9.0 * p3) / 2.0,
                    (-9.0 * p0 + 27.0 * p1 - 27.0 * p2 + 9.0 * p3) / 2.0,
                ]
            })
            .collect();
        let h = (knots_x[n - 1] - knots_x[0]) / (n - 1) as f64;
        let uniform = knots_x
            .iter()
            .enumerate()
            .all(|(j, &x)| (x - (knots_x[0] + h * j as f64)).abs() <= 1e-12 * h.abs().max(1e-300));
        Some(Segments {
            knots_x: knots_x.clone(),
            inv_step: if uniform { 1.0 / h } else { 0.0 },
            coeffs,
        })
    }

    /// Value at `x` inside the knots.
    #[inline]
    fn eval(&self, x: f64) -> f64 {
        let k = &self.knots_x;
        let last = k.len() - 2;
        let i = if self.inv_step > 0.0 {
            (((x - k[0]) * self.inv_step) as usize).min(last)
        } else {
            k.partition_point(|&v| v <= x).saturating_sub(1).min(last)
        };
        let u = ((x - k[i]) / (k[i + 1] - k[i])).clamp(0.0, 1.0);
        let c = &self.coeffs[i];
        ((c[3] * u + c[2]) * u + c[1]) * u + c[0]
    }
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
                Segments::of(&curve)
            }
        };
        Ok(Approx {
            kind,
            poly: poly4(&curve),
            curve,
            x_min,
            x_max,
            extrapolate,
            stats,
            segments: spline,
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
            segments: None,
            poly: Some([0.0; 4]),
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
        let segments = Segments::of(&curve);
        Approx {
            curve,
            segments,
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
        if let Some(c) = &self.poly {
            return ((c[3] * x + c[2]) * x + c[1]) * x + c[0];
        }
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
                    self.segments.as_ref().map_or(0.0, |s| s.eval(x))
                }
            }
        }
    }
}

/// The coefficients of a polynomial of degree at most 3, padded with zeros (the padding adds
/// exact zeros, so the value is bit for bit the plain Horner sum).
fn poly4(curve: &Curve) -> Option<[f64; 4]> {
    match curve {
        Curve::Polynomial { coeffs } if coeffs.len() <= 4 => {
            let mut c = [0.0; 4];
            c[..coeffs.len()].copy_from_slice(coeffs);
            Some(c)
        }
        _ => None,
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
