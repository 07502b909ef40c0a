//! A fitted approximation: its stored curve, the x-range it saw, its statistics, the checks
//! a loaded one must pass, and its value at one point. Apart from the choices in the parent
//! module because this is what calibration files hold and every correction evaluates.

use super::evaluator::edge_line;
use super::knots::Segments;
use super::{ApproxKind, CurveError, FitStats, MAX_KNOTS, MAX_POLY_COEFFS, MIN_KNOT_GAP};
use serde::{Deserialize, Serialize};

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
    pub(super) kind: ApproxKind,
    pub(super) curve: Curve,
    pub(super) x_min: f64,
    pub(super) x_max: f64,
    pub(super) extrapolate: bool,
    pub(super) stats: FitStats,
    /// Knot curves as one cubic per segment, read off the `splines` evaluator once.
    pub(super) segments: Option<Segments>,
    /// Polynomials of up to 4 coefficients, unpacked for a branch-free Horner step.
    pub(super) poly: Option<[f64; 4]>,
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
    type Error = CurveError;
    fn try_from(r: ApproxRepr) -> Result<Self, CurveError> {
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
    ) -> Result<Approx, CurveError> {
        if !x_min.is_finite() || !x_max.is_finite() || x_min > x_max {
            return Err(CurveError::XRange { x_min, x_max });
        }
        let spline = match &curve {
            Curve::Polynomial { coeffs } => {
                if coeffs.is_empty() || coeffs.iter().any(|c| !c.is_finite()) {
                    return Err(CurveError::Coefficients);
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

    /// Whether this is a term left out for want of points: the zero polynomial over an empty
    /// range, as [`Approx::zero`] makes it and every calibration file has written it (`coeffs
    /// [0]`, `x_min` = `x_max` = 0). Such a term adds nothing wherever its input lies, so it has
    /// no range a sample could lie outside of ([`Approx::judged_range`]).
    pub fn is_left_out(&self) -> bool {
        self.x_min == self.x_max
            && matches!(&self.curve, Curve::Polynomial { coeffs } if coeffs.iter().all(|&c| c == 0.0))
    }

    /// The range a sample's input is judged against, `[lo, hi]`: beyond it (`x < lo || x > hi`)
    /// the calibration never saw the input, and the edge value was held or the curve
    /// extrapolated. The range the curve was fitted on; the whole line for a term left out
    /// ([`Approx::is_left_out`]), which no input lies outside of: with its range `[0, 0]`
    /// every sample with a nonzero Ṫ or T̈ counted as outside the calibrated ranges, 99 % of a
    /// log, for a term that is zero everywhere.
    pub fn judged_range(&self) -> [f64; 2] {
        if self.is_left_out() {
            [f64::NEG_INFINITY, f64::INFINITY]
        } else {
            [self.x_min, self.x_max]
        }
    }

    /// Whether `x` lies beyond [`Approx::judged_range`] (a NaN lies nowhere: never beyond).
    pub fn is_beyond(&self, x: f64) -> bool {
        let [lo, hi] = self.judged_range();
        x < lo || x > hi
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
    pub fn check(&self) -> Result<(), CurveError> {
        match (&self.curve, self.kind) {
            // Any kind may hold a polynomial of its degree or less: a knot kind holds a constant
            // (zero) when its points were too few for any curve. A higher degree than the
            // kind's would be corrected with while the report and the C header name the kind.
            (Curve::Polynomial { coeffs }, kind) => {
                if coeffs.len() > MAX_POLY_COEFFS {
                    return Err(CurveError::TooManyCoefficients { got: coeffs.len() });
                }
                let most = match kind {
                    ApproxKind::Linear => 2,
                    ApproxKind::Parabolic => 3,
                    ApproxKind::Pwl | ApproxKind::Spline => 1,
                };
                if coeffs.len() > most {
                    return Err(CurveError::DegreeOfKind {
                        got: coeffs.len(),
                        kind,
                        most,
                    });
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
                return Err(CurveError::FormOfKind { form, kind });
            }
        }
        let (kx, _) = self.knots();
        if kx.len() > MAX_KNOTS {
            return Err(CurveError::TooManyKnots { got: kx.len() });
        }
        if let (Some(first), Some(last)) = (kx.first(), kx.last()) {
            let span = last - first;
            let gap = kx
                .windows(2)
                .map(|w| w[1] - w[0])
                .fold(f64::INFINITY, f64::min);
            if !span.is_finite() {
                return Err(CurveError::KnotSpan {
                    first: *first,
                    last: *last,
                });
            }
            if gap < MIN_KNOT_GAP * span {
                return Err(CurveError::KnotsTooClose { gap, span });
            }
        }
        if !(self.x_max - self.x_min).is_finite() {
            return Err(CurveError::RangeWidth {
                x_min: self.x_min,
                x_max: self.x_max,
            });
        }
        // Only the zero of a term with no points stands on a range of no width.
        if self.x_max == self.x_min && self.stats.n > 1 {
            return Err(CurveError::ZeroWidthFit {
                x: self.x_min,
                n: self.stats.n,
            });
        }
        if !(self.stats.rmse.is_finite() && self.stats.r2.is_finite()) {
            return Err(CurveError::Stats {
                rmse: self.stats.rmse,
                r2: self.stats.r2,
            });
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

    /// This approximation with the statistics of its fit (a fit made from moments computes
    /// them after the curve, on the points it was fitted to).
    pub fn with_stats(self, stats: FitStats) -> Approx {
        Approx { stats, ..self }
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
    pub(super) fn eval_curve(&self, x: f64) -> f64 {
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

fn check_knots(xs: &[f64], ys: &[f64]) -> Result<(), CurveError> {
    if xs.len() < 2 || xs.len() != ys.len() {
        return Err(CurveError::KnotCount);
    }
    if xs.iter().chain(ys).any(|v| !v.is_finite()) {
        return Err(CurveError::KnotNotFinite);
    }
    if xs.windows(2).any(|w| w[1] <= w[0]) {
        return Err(CurveError::KnotOrder);
    }
    // Checked before the segments are made: the `splines` crate's evaluator, asked for the
    // segments of knots whose span overflows, panics.
    let (first, last) = (xs[0], xs[xs.len() - 1]);
    if !(last - first).is_finite() {
        return Err(CurveError::KnotSpan { first, last });
    }
    Ok(())
}
