//! Approximations of a coefficient as a function of one variable: linear, parabolic,
//! piecewise-linear and cubic spline, fitted by least squares.
//!
//! Every kind is linear in its parameters (polynomial coefficients, or the values at fixed
//! knots), so one solver serves all four: accumulate the normal equations over the points'
//! basis values, then solve the small system by SVD (nalgebra). Piecewise-linear and spline
//! curves are defined by the `splines` crate: the basis used to fit them is that curve written
//! as weights on the knot values, and evaluation reads one cubic per segment off it
//! (`knots.rs`); tests hold all three equal.
//!
//! A fitted approximation remembers the x-range it saw. Outside it, it holds the edge value
//! unless told to extrapolate: a calibration must not invent coefficients for rates the test
//! never reached.

mod fit;
mod knots;

pub use fit::{
    CHUNK, FitOptions, PointSource, XRange, fit, fit_weighted, fit_with, fit_with_then, x_range,
};
pub use knots::{knot_positions, knot_weights};

use knots::{Segments, Uniform};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Most knots a knot curve may have: the most a recipe asks for.
pub const MAX_KNOTS: usize = 64;

/// Most coefficients a stored polynomial may have (degree 15). Fits make at most three; a
/// hand-edited file may hold a higher degree (the C export evaluates any), but a polynomial of
/// a million coefficients is no calibration curve, and evaluating it on every sample took
/// seconds per thousand samples.
pub const MAX_POLY_COEFFS: usize = 16;

/// The smallest gap between two knots, as a share of the span of all knots. Knots closer than
/// this (a hand-edited spacing of 1e-300) give slopes that overflow.
const MIN_KNOT_GAP: f64 = 1e-9;

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

/// A knot curve as [`Approx::eval`] evaluates it inside its knots, for code generators that must
/// repeat that arithmetic exactly (the firmware export).
#[derive(Debug, Clone, Copy)]
pub struct SegmentCubics<'a> {
    /// Knot positions, strictly increasing.
    pub knots_x: &'a [f64],
    /// `1/h` when the knots are equally spaced (segment `⌊(x − knots_x[0])·inv_step⌋`, at most
    /// the last), else 0 (the segment is the last knot `≤ x`).
    pub inv_step: f64,
    /// Per segment `i`, `c0 + c1·u + c2·u² + c3·u³` in Horner order, with
    /// `u = (x − knots_x[i]) / (knots_x[i+1] − knots_x[i])` clamped to `[0, 1]`.
    pub coeffs: &'a [[f64; 4]],
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
            return Err(format!(
                "invalid x-range [{}, {}]",
                crate::number::readable(x_min),
                crate::number::readable(x_max)
            ));
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

    /// The per-segment cubics of a knot curve (`None` for polynomials).
    pub fn segment_cubics(&self) -> Option<SegmentCubics<'_>> {
        self.segments.as_ref().map(|s| {
            let (knots_x, inv_step, coeffs) = s.parts();
            SegmentCubics {
                knots_x,
                inv_step,
                coeffs,
            }
        })
    }

    /// Checks what a stored approximation can get wrong beyond what [`Approx::new`] checks: a
    /// knot curve of another form than its kind (a `pwl` drawn as a spline), more than
    /// [`MAX_POLY_COEFFS`] polynomial coefficients or [`MAX_KNOTS`] knots, knots too close to
    /// each other, an x-range whose width overflows, statistics that are not numbers.
    ///
    /// # Errors
    /// The reason, for the caller to put after the field's name.
    pub fn check(&self) -> Result<(), String> {
        match (&self.curve, self.kind) {
            // Any kind may hold a polynomial: a knot kind holds a constant when its points were
            // too few for any curve, and a file may be edited to a higher degree.
            (Curve::Polynomial { coeffs }, _) => {
                if coeffs.len() > MAX_POLY_COEFFS {
                    return Err(format!(
                        "a polynomial has at most {MAX_POLY_COEFFS} coefficients (degree {}), \
                         this one has {}",
                        MAX_POLY_COEFFS - 1,
                        coeffs.len()
                    ));
                }
            }
            (Curve::Pwl { .. }, ApproxKind::Pwl)
            | (Curve::CatmullRom { .. }, ApproxKind::Spline) => {}
            (curve, kind) => {
                let form = match curve {
                    Curve::Polynomial { .. } => "polynomial",
                    Curve::Pwl { .. } => "pwl",
                    Curve::CatmullRom { .. } => "catmull_rom",
                };
                return Err(format!(
                    "the curve is of form {form}, which is not how a {kind} approximation is stored"
                ));
            }
        }
        let (kx, _) = self.knots();
        if kx.len() > MAX_KNOTS {
            return Err(format!(
                "{} knots, more than the {MAX_KNOTS} a knot curve may have",
                kx.len()
            ));
        }
        if let (Some(first), Some(last)) = (kx.first(), kx.last()) {
            let span = last - first;
            let gap = kx
                .windows(2)
                .map(|w| w[1] - w[0])
                .fold(f64::INFINITY, f64::min);
            if !span.is_finite() {
                return Err(format!(
                    "knots from {} to {} span more than a number can hold",
                    crate::number::readable(*first),
                    crate::number::readable(*last)
                ));
            }
            if gap < MIN_KNOT_GAP * span {
                return Err(format!(
                    "two knots are {} apart, less than {MIN_KNOT_GAP:e} of the {} they span",
                    crate::number::readable(gap),
                    crate::number::readable(span)
                ));
            }
        }
        if !(self.x_max - self.x_min).is_finite() {
            return Err(format!(
                "the range {} .. {} is wider than a number can hold",
                crate::number::readable(self.x_min),
                crate::number::readable(self.x_max)
            ));
        }
        if !(self.stats.rmse.is_finite() && self.stats.r2.is_finite()) {
            return Err(format!(
                "the fit statistics are not numbers (rmse {}, R² {})",
                crate::number::readable(self.stats.rmse),
                crate::number::readable(self.stats.r2)
            ));
        }
        Ok(())
    }

    /// An upper bound of |value| over the fitted range `[x_min, x_max]` (infinite when the
    /// curve overflows there): `Σ|c_k|·M^k` for a polynomial, with `M` the largest |x|; twice
    /// the largest knot value (a Catmull-Rom segment overshoots its knots by less than that)
    /// and the values at the range's ends for a knot curve.
    pub fn bound(&self) -> f64 {
        match &self.curve {
            Curve::Polynomial { coeffs } => {
                let m = self.x_min.abs().max(self.x_max.abs());
                coeffs
                    .iter()
                    .rev()
                    .fold(0.0, |acc: f64, c| acc * m + c.abs())
            }
            Curve::Pwl { knots_y, .. } | Curve::CatmullRom { knots_y, .. } => {
                let top = knots_y.iter().fold(0.0f64, |a, y| a.max(y.abs()));
                (2.0 * top)
                    .max(self.eval(self.x_min).abs())
                    .max(self.eval(self.x_max).abs())
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

    /// This approximation prepared for evaluation at many points ([`Evaluator`]).
    pub fn evaluator(&self) -> Evaluator<'_> {
        let (lo, hi) = if self.extrapolate {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            (self.x_min, self.x_max)
        };
        let form = match (&self.curve, &self.segments, self.poly) {
            (_, _, Some(c)) => Form::Poly(c),
            (
                Curve::Pwl { knots_x, knots_y } | Curve::CatmullRom { knots_x, knots_y },
                Some(s),
                _,
            ) => {
                let n = knots_x.len();
                let ends = Ends {
                    first: [knots_x[0], knots_y[0], knots_x[1], knots_y[1]],
                    last: [
                        knots_x[n - 1],
                        knots_y[n - 1],
                        knots_x[n - 2],
                        knots_y[n - 2],
                    ],
                };
                match s.uniform() {
                    Some(u) => Form::Uniform(ends, u),
                    None => Form::Knots(ends, s),
                }
            }
            _ => Form::Curve,
        };
        Evaluator {
            approx: self,
            lo,
            hi,
            form,
        }
    }

    /// Value at `x`, holding the edge value outside the fitted range unless extrapolating.
    /// A non-finite `x` gives 0: no correction from a sample that has no derivative.
    #[inline(always)]
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
        self.eval_curve(x)
    }

    /// [`Approx::eval`] past the polynomial fast path, at an `x` already clamped (kept out of
    /// line so that the fast path inlines into the hot loops).
    #[inline(never)]
    fn eval_curve(&self, x: f64) -> f64 {
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

/// An [`Approx`] taken apart for a loop over many samples: the same value as [`Approx::eval`],
/// bit for bit, without its out-of-line call and the lookups that call repeats per sample
/// (curve kind, knot vectors, segment table). The workbench evaluates a knot curve on hundreds of
/// thousands of samples per edit; there this costs about half as many instructions.
#[derive(Debug, Clone, Copy)]
pub struct Evaluator<'a> {
    approx: &'a Approx,
    /// The clamp bounds (infinite when extrapolating: the same as not clamping a finite x).
    lo: f64,
    hi: f64,
    form: Form<'a>,
}

/// The end knots of a knot curve as [`edge_line`] takes them: `(x0, y0, x1, y1)` of the first
/// knot and its neighbour, and of the last knot and its neighbour.
#[derive(Debug, Clone, Copy)]
struct Ends {
    first: [f64; 4],
    last: [f64; 4],
}

/// What an [`Evaluator`] does per sample.
#[derive(Debug, Clone, Copy)]
enum Form<'a> {
    /// A polynomial of at most 4 coefficients.
    Poly([f64; 4]),
    /// A knot curve with equally spaced knots (every fitted one).
    Uniform(Ends, Uniform<'a>),
    /// A knot curve with knots set otherwise (a loaded file's).
    Knots(Ends, &'a Segments),
    /// Anything else, through [`Approx::eval_curve`].
    Curve,
}

impl Evaluator<'_> {
    /// [`Approx::eval`].
    #[inline(always)]
    pub fn eval(&self, x: f64) -> f64 {
        if !x.is_finite() {
            return 0.0;
        }
        let x = x.clamp(self.lo, self.hi);
        let (ends, inner) = match &self.form {
            Form::Poly(c) => return ((c[3] * x + c[2]) * x + c[1]) * x + c[0],
            Form::Uniform(e, u) => (e, Inner::Uniform(u)),
            Form::Knots(e, s) => (e, Inner::Knots(s)),
            Form::Curve => return self.approx.eval_curve(x),
        };
        let ([x0, y0, x1, y1], [xn, yn, xm, ym]) = (ends.first, ends.last);
        if x <= x0 {
            edge_line(x0, y0, x1, y1, x)
        } else if x >= xn {
            edge_line(xn, yn, xm, ym, x)
        } else {
            match inner {
                Inner::Uniform(u) => u.eval(x),
                Inner::Knots(s) => s.eval(x),
            }
        }
    }
}

/// The segment lookup of a knot curve's [`Form`].
enum Inner<'a, 'b> {
    Uniform(&'b Uniform<'a>),
    Knots(&'b Segments),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_evaluator_gives_evals_bits() {
        let kx = vec![-2.0, -0.5, 0.25, 1.0, 3.0];
        let ky = vec![1.0, -3.0, 0.5, 2.0, -1.0];
        let u = knot_positions(-1.0, 2.0, 6);
        let uy: Vec<f64> = u.iter().map(|x| (x * 1.3).sin()).collect();
        let mut curves = Vec::new();
        for extrapolate in [false, true] {
            for (kind, curve) in [
                (
                    ApproxKind::Pwl,
                    Curve::Pwl {
                        knots_x: kx.clone(),
                        knots_y: ky.clone(),
                    },
                ),
                (
                    ApproxKind::Spline,
                    Curve::CatmullRom {
                        knots_x: kx.clone(),
                        knots_y: ky.clone(),
                    },
                ),
                (
                    ApproxKind::Pwl,
                    Curve::Pwl {
                        knots_x: u.clone(),
                        knots_y: uy.clone(),
                    },
                ),
                (
                    ApproxKind::Spline,
                    Curve::CatmullRom {
                        knots_x: u.clone(),
                        knots_y: uy.clone(),
                    },
                ),
                (
                    ApproxKind::Parabolic,
                    Curve::Polynomial {
                        coeffs: vec![0.5, -1.5, 2.0],
                    },
                ),
                (
                    ApproxKind::Parabolic,
                    Curve::Polynomial {
                        coeffs: vec![0.5, -1.5, 2.0, 0.1, -0.01],
                    },
                ),
            ] {
                let (lo, hi) = match &curve {
                    Curve::Polynomial { .. } => (-1.5, 2.5),
                    Curve::Pwl { knots_x, .. } | Curve::CatmullRom { knots_x, .. } => {
                        (knots_x[0], knots_x[knots_x.len() - 1])
                    }
                };
                let a = Approx::new(kind, curve, lo, hi, extrapolate, FitStats::default())
                    .expect("valid curve");
                curves.push(a.with_knot_value(1, 0.75));
                curves.push(a);
            }
        }
        curves.push(Approx::zero(ApproxKind::Linear));
        let mut xs: Vec<f64> = (0..4001).map(|i| -5.0 + i as f64 * 2.5e-3).collect();
        xs.extend(kx.iter().chain(&u).copied());
        xs.extend([
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -0.0,
            1e300,
            -1e300,
        ]);
        for a in &curves {
            let e = a.evaluator();
            for &x in &xs {
                assert_eq!(e.eval(x).to_bits(), a.eval(x).to_bits(), "{a:?} at {x}");
            }
        }
    }
}
