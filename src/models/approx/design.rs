//! A fit's design taken apart from its points: the basis a spec is fitted in over a known
//! x-range, the weights of its parameters in the fitted curve's value at any x, and the solve
//! of normal equations accumulated elsewhere.
//!
//! [`fit_with`](super::fit_with) accumulates the normal equations of one set of points and
//! solves them at once. A fit whose points' y is itself linear in another curve's parameters
//! (the Vakhrameev model's K1 points carry the fitted K2 term, its K2 points the K1 term) can
//! instead accumulate the cross-products of the two bases once, and then solve each of the
//! paper's refinement passes from them in O(parameters²) rather than a pass over the samples.
//! This module gives such a fit the same design (knots, scaling, penalty, solver, stored
//! curve) as the streaming fit, so the two differ by rounding only.

use super::fit::{fitted_approx, knot_values, powers_of_x, solve};
use super::knots::{knot_positions, knot_weights};
use super::{Approx, ApproxKind, ApproxSpec, Curve, FitError, XRange};
use nalgebra::{DMatrix, DVector};

/// Up to four basis weights and where they start: the value is
/// `Σ weights[k] · params[first + k]` for `k < width`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weights {
    /// Index of the parameter of `weights[0]`.
    pub first: usize,
    /// How many of `weights` count.
    pub width: usize,
    /// The weights.
    pub weights: [f64; 4],
}

impl Weights {
    const NONE: Weights = Weights {
        first: 0,
        width: 0,
        weights: [0.0; 4],
    };
}

/// The basis of a spec fitted over a known x-range.
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    spec: ApproxSpec,
    form: Form,
    /// The fitted range the curve records (the points' for a polynomial, the knots' span for
    /// a knot curve).
    lo: f64,
    hi: f64,
    /// Parameters, and the points the range counted.
    params: usize,
    points: usize,
}

#[derive(Debug, Clone, PartialEq)]
enum Form {
    /// Powers of `u = (x − centre)/scale`, as [`super::fit`] fits a polynomial.
    Poly { centre: f64, scale: f64 },
    /// Values at the knots.
    Knots { knots_x: Vec<f64> },
}

impl Design {
    /// The design the streaming fit would use for `spec` over points of `range`: the same
    /// refusals (too few knots or points, knots placed out of order).
    ///
    /// # Errors
    /// As [`super::fit_with`] refuses the spec before reading a point.
    pub fn new(spec: &ApproxSpec, range: XRange) -> Result<Design, FitError> {
        let params = match spec.kind {
            ApproxKind::Pwl | ApproxKind::Spline if spec.knots < 2 => {
                return Err(FitError::TooFewKnots(spec.kind));
            }
            _ => spec.params(),
        };
        spec.fitted_part().check_knots()?;
        if range.n < params {
            return Err(FitError::TooFewPoints {
                kind: spec.kind,
                needed: params,
                got: range.n,
            });
        }
        let (lo, hi) = (range.lo, range.hi);
        let (form, lo, hi) = match spec.kind {
            ApproxKind::Linear | ApproxKind::Parabolic => {
                let centre = 0.5 * (lo + hi);
                let scale = if hi > lo { 0.5 * (hi - lo) } else { 1.0 };
                (Form::Poly { centre, scale }, lo, hi)
            }
            ApproxKind::Pwl | ApproxKind::Spline => {
                let knots_x = match &spec.at {
                    Some(at) => at.clone(),
                    None => knot_positions(lo, hi, spec.knots),
                };
                let (a, b) = (knots_x[0], knots_x[knots_x.len() - 1]);
                (Form::Knots { knots_x }, a, b)
            }
        };
        Ok(Design {
            spec: spec.fitted_part(),
            form,
            lo,
            hi,
            params,
            points: range.n,
        })
    }

    /// Number of parameters.
    pub fn params(&self) -> usize {
        self.params
    }

    /// Points the range counted (the fit must use as many).
    pub fn points(&self) -> usize {
        self.points
    }

    /// The fit's basis at a point's `x` (finite, within the range the design was made for).
    #[inline(always)]
    pub fn basis(&self, x: f64) -> Weights {
        match &self.form {
            Form::Poly { centre, scale } => powers(self.params, (x - centre) / scale),
            Form::Knots { knots_x } => knot_basis(self.spec.kind, knots_x, x),
        }
    }

    /// The weights of the parameters in the fitted curve's value at `x`, as
    /// [`Approx::eval`] takes it: nothing for a non-finite x, x held within the fitted range
    /// unless the spec extrapolates, the end segments' lines beyond the knots.
    #[inline(always)]
    pub fn value_weights(&self, x: f64) -> Weights {
        if !x.is_finite() {
            return Weights::NONE;
        }
        let x = if self.spec.extrapolate {
            x
        } else {
            x.clamp(self.lo, self.hi)
        };
        match &self.form {
            Form::Poly { centre, scale } => powers(self.params, (x - centre) / scale),
            Form::Knots { knots_x } => {
                let n = knots_x.len();
                if x < knots_x[0] {
                    edge(0, knots_x[0], knots_x[1], x)
                } else if x > knots_x[n - 1] {
                    let w = edge(n - 2, knots_x[n - 1], knots_x[n - 2], x);
                    // `edge` weighs (end, neighbour); the neighbour comes first here.
                    Weights {
                        weights: [w.weights[1], w.weights[0], 0.0, 0.0],
                        ..w
                    }
                } else {
                    knot_basis(self.spec.kind, knots_x, x)
                }
            }
        }
    }

    /// The parameters solving the normal equations `ata · θ = aty` (`ata_upper`: the upper
    /// triangle, row-major over `params × params`), as the streaming fit solves its own.
    pub fn solve(&self, ata_upper: &[f64], aty: Vec<f64>) -> Vec<f64> {
        let p = self.params;
        match &self.form {
            Form::Poly { .. } => {
                let ata = DMatrix::from_fn(p, p, |a, b| ata_upper[a.min(b) * p + a.max(b)]);
                solve(ata, DVector::from_vec(aty)).iter().copied().collect()
            }
            Form::Knots { knots_x } => knot_values(knots_x, ata_upper, aty),
        }
    }

    /// The approximation with parameters `theta` (its stats hold `n` only).
    ///
    /// # Errors
    /// A parameter that is not finite.
    pub fn approx(&self, theta: &[f64]) -> Result<Approx, FitError> {
        let curve = match &self.form {
            Form::Poly { centre, scale } => Curve::Polynomial {
                coeffs: powers_of_x(theta, *centre, *scale),
            },
            Form::Knots { knots_x } => {
                let (knots_x, knots_y) = (knots_x.clone(), theta.to_vec());
                if self.spec.kind == ApproxKind::Pwl {
                    Curve::Pwl { knots_x, knots_y }
                } else {
                    Curve::CatmullRom { knots_x, knots_y }
                }
            }
        };
        fitted_approx(
            &self.spec,
            curve,
            (self.lo, self.hi),
            self.params,
            self.points,
        )
    }
}

/// `1, u, u², …` for `n ≤ 4` parameters.
#[inline(always)]
fn powers(n: usize, u: f64) -> Weights {
    let u2 = u * u;
    Weights {
        first: 0,
        width: n.min(4),
        weights: [1.0, u, u2, u2 * u],
    }
}

/// [`knot_weights`] with the count of weights that belong to knots.
#[inline(always)]
fn knot_basis(kind: ApproxKind, knots_x: &[f64], x: f64) -> Weights {
    let span = if kind == ApproxKind::Spline { 4 } else { 2 };
    let (first, weights) = knot_weights(kind, knots_x, x);
    Weights {
        first,
        width: (knots_x.len() - first).min(span),
        weights,
    }
}

/// The line through the end knot at `x0` and its neighbour at `x1`, at `x`, as weights on
/// (end, neighbour), the end knot being parameter `at` or `at + 1` as the caller orders them.
#[inline(always)]
fn edge(at: usize, x0: f64, x1: f64, x: f64) -> Weights {
    let t = (x - x0) / (x1 - x0);
    Weights {
        first: at,
        width: 2,
        weights: [1.0 - t, t, 0.0, 0.0],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::approx::fit_weighted;

    fn range(xs: &[f64]) -> XRange {
        XRange {
            n: xs.len(),
            lo: xs.iter().copied().fold(f64::INFINITY, f64::min),
            hi: xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        }
    }

    fn specs() -> Vec<ApproxSpec> {
        let mut out: Vec<ApproxSpec> = [
            ApproxKind::Linear,
            ApproxKind::Parabolic,
            ApproxKind::Pwl,
            ApproxKind::Spline,
        ]
        .into_iter()
        .flat_map(|k| {
            [false, true].map(|extrapolate| ApproxSpec {
                extrapolate,
                ..ApproxSpec::of(k)
            })
        })
        .collect();
        out.push(ApproxSpec {
            at: Some(vec![-0.9, -0.2, 0.1, 0.5, 1.3]),
            ..ApproxSpec::of(ApproxKind::Spline)
        });
        out
    }

    /// The value weights, applied to the fitted parameters, give what the stored curve
    /// evaluates to, inside the range, at its ends and beyond them on both sides.
    #[test]
    fn value_weights_reproduce_the_curves_value_everywhere() {
        let xs: Vec<f64> = (0..400).map(|i| -0.8 + 1.9 * i as f64 / 399.0).collect();
        let ys: Vec<f64> = xs.iter().map(|x| (3.0 * x).sin() + 0.2 * x).collect();
        for spec in specs() {
            let d = Design::new(&spec, range(&xs)).expect("design");
            let fitted = fit_weighted(&spec, &xs, &ys, None).expect("fit");
            // The streaming fit's parameters in the design's own basis: solve again from the
            // fit's normal equations here.
            let p = d.params();
            let (mut ata, mut aty) = (vec![0.0; p * p], vec![0.0; p]);
            for (&x, &y) in xs.iter().zip(&ys) {
                let b = d.basis(x);
                for a in 0..b.width {
                    aty[b.first + a] += b.weights[a] * y;
                    for c in a..b.width {
                        ata[(b.first + a) * p + b.first + c] += b.weights[a] * b.weights[c];
                    }
                }
            }
            let theta = d.solve(&ata, aty);
            let ours = d.approx(&theta).expect("approx");
            for probe in [-5.0, -0.95, -0.8, -0.3, 0.0, 0.77, 1.1, 1.3, 1.31, 4.0] {
                let w = d.value_weights(probe);
                let v: f64 = (0..w.width)
                    .map(|k| w.weights[k] * theta[w.first + k])
                    .sum();
                let e = ours.eval(probe);
                assert!(
                    (v - e).abs() <= 1e-9 * (1.0 + e.abs()),
                    "{spec:?} at {probe}: weights give {v}, the curve {e}"
                );
                // And the curve is the streaming fit's.
                let f = fitted.eval(probe);
                assert!(
                    (f - e).abs() <= 1e-7 * (1.0 + f.abs()),
                    "{spec:?} at {probe}: streaming fit {f}, design {e}"
                );
            }
            assert_eq!(d.value_weights(f64::NAN), Weights::NONE);
        }
    }

    #[test]
    fn a_design_refuses_what_the_fit_refuses() {
        let r = XRange {
            n: 2,
            lo: 0.0,
            hi: 1.0,
        };
        assert!(matches!(
            Design::new(&ApproxSpec::of(ApproxKind::Parabolic), r),
            Err(FitError::TooFewPoints {
                needed: 3,
                got: 2,
                ..
            })
        ));
        let one_knot = ApproxSpec {
            knots: 1,
            ..ApproxSpec::of(ApproxKind::Pwl)
        };
        assert!(matches!(
            Design::new(&one_knot, r),
            Err(FitError::TooFewKnots(ApproxKind::Pwl))
        ));
    }
}
