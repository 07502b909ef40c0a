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

/// Where a point falls on a curve: all its value there needs but the curve's own values (the
/// clamped point, which end line or segment, the segment's argument). The curves of a unit's
/// axes fitted over the same samples have the same knots, so a sample's spot is found once for
/// them all ([`Evaluator::same_spots`]) and each axis's value read at it ([`Evaluator::at`]).
#[derive(Debug, Clone, Copy)]
pub enum Spot {
    /// A point that is not finite: the value 0.
    Zero,
    /// A polynomial's point, clamped.
    Poly(f64),
    /// At or before the first knot, on the line through it and its neighbour.
    First(f64),
    /// At or past the last knot, on the line through it and its neighbour.
    Last(f64),
    /// Inside segment `.0`, at its local parameter `.1 ∈ [0, 1]`.
    Segment(u32, f64),
    /// Any other curve's point, clamped.
    Curve(f64),
}

impl Evaluator<'_> {
    /// [`Approx::eval`].
    #[inline(always)]
    pub fn eval(&self, x: f64) -> f64 {
        self.at(self.spot(x))
    }

    /// Where `x` falls on this curve ([`Spot`]).
    #[inline(always)]
    pub fn spot(&self, x: f64) -> Spot {
        if !x.is_finite() {
            return Spot::Zero;
        }
        let x = x.clamp(self.lo, self.hi);
        let (ends, inner) = match &self.form {
            Form::Poly(_) => return Spot::Poly(x),
            Form::Uniform(e, u) => (e, Inner::Uniform(u)),
            Form::Knots(e, s) => (e, Inner::Knots(s)),
            Form::Curve => return Spot::Curve(x),
        };
        if x <= ends.first[0] {
            Spot::First(x)
        } else if x >= ends.last[0] {
            Spot::Last(x)
        } else {
            let (i, u) = match inner {
                Inner::Uniform(u) => u.locate(x),
                Inner::Knots(s) => s.locate(x),
            };
            Spot::Segment(i as u32, u)
        }
    }

    /// This curve's value at a spot found on it, or on a curve of the same spots
    /// ([`Evaluator::same_spots`]): `at(spot(x))` is [`Approx::eval`]`(x)`, bit for bit.
    #[inline(always)]
    pub fn at(&self, spot: Spot) -> f64 {
        match (spot, &self.form) {
            (Spot::Zero, _) => 0.0,
            (Spot::Poly(x), Form::Poly(c)) => ((c[3] * x + c[2]) * x + c[1]) * x + c[0],
            (Spot::First(x), Form::Uniform(e, _) | Form::Knots(e, _)) => {
                let [x0, y0, x1, y1] = e.first;
                edge_line(x0, y0, x1, y1, x)
            }
            (Spot::Last(x), Form::Uniform(e, _) | Form::Knots(e, _)) => {
                let [xn, yn, xm, ym] = e.last;
                edge_line(xn, yn, xm, ym, x)
            }
            (Spot::Segment(i, u), Form::Uniform(_, f)) => f.at(i as usize, u),
            (Spot::Segment(i, u), Form::Knots(_, s)) => s.at(i as usize, u),
            (Spot::Poly(x) | Spot::Curve(x) | Spot::First(x) | Spot::Last(x), _) => {
                self.approx.eval_curve(x)
            }
            (Spot::Segment(..), _) => f64::NAN,
        }
    }

    /// Whether every point falls on the same spot of `self` and of `other`: the same clamp,
    /// the same kind of curve, the same knots. Compared bit for bit; a curve of any other form
    /// than a polynomial or knots shares spots with none.
    pub fn same_spots(&self, other: &Evaluator<'_>) -> bool {
        let bits = |a: f64, b: f64| a.to_bits() == b.to_bits();
        let ends = |a: &Ends, b: &Ends| {
            [a.first[0], a.first[2], a.last[0], a.last[2]]
                .iter()
                .zip([b.first[0], b.first[2], b.last[0], b.last[2]])
                .all(|(&x, y)| bits(x, y))
        };
        bits(self.lo, other.lo)
            && bits(self.hi, other.hi)
            && match (&self.form, &other.form) {
                (Form::Poly(_), Form::Poly(_)) => true,
                (Form::Uniform(ea, a), Form::Uniform(eb, b)) => ends(ea, eb) && a.same_knots(b),
                (Form::Knots(ea, a), Form::Knots(eb, b)) => ends(ea, eb) && a.same_knots(b),
                _ => false,
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
