//! An approximation taken apart for a loop over many samples: the same value as
//! `Approx::eval`, bit for bit, with the per-sample lookups done once. Apart from the curve
//! because it is a speed measure with its own invariant, held by its own test.

use super::knots::{Segments, Uniform};
use super::{Approx, Curve};

impl Approx {
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

/// The line through the end knot `(x0, y0)` and its neighbour, evaluated at `x` (equal to
/// `y0` at the knot itself, which is what clamped evaluation asks for).
#[inline]
pub(super) fn edge_line(x0: f64, y0: f64, x1: f64, y1: f64, x: f64) -> f64 {
    if x == x0 {
        y0
    } else {
        y0 + (y1 - y0) / (x1 - x0) * (x - x0)
    }
}
