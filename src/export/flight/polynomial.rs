//! The static part of a fitted model as a polynomial in T, which is all a flight controller
//! evaluates: from a regression over `1, T, T², T³` (`poly-t`, a custom model), over powers of
//! `T − Tref` up to the third (`px4`, `ardupilot`, `poly-t1` to `poly-t3`), or from
//! Vakhrameev's K0 when it is a line or a parabola. Rate terms are left out with a warning;
//! anything else a firmware cannot evaluate is refused by name.

use super::FlightError;
use crate::models::approx::Curve;
use crate::models::fitted::DriftModel;
use crate::models::regression::Term;

/// Highest power of T the flight controllers read (PX4 `X3`, ArduPilot `GYR3`).
pub const MAX_ORDER: usize = 3;

/// `Σ coeffs[k]·(T − centre)^k` for T held to `[t_min, t_max]`, in the unit the model
/// predicts in.
#[derive(Debug, Clone, PartialEq)]
pub struct TempPolynomial {
    /// Coefficients of (T − centre)⁰ … (T − centre)³, lowest first.
    pub coeffs: [f64; MAX_ORDER + 1],
    /// The temperature the powers are taken about, °C: 0 for a polynomial in T itself, the
    /// model's Tref for one in `T − Tref` (kept, so that re-centring on the firmware's
    /// reference moves the coefficients by the difference of two nearby temperatures).
    pub centre: f64,
    /// Lowest temperature of the fit, °C: below it the model holds its value there.
    pub t_min: f64,
    /// Highest temperature of the fit, °C.
    pub t_max: f64,
    /// Whether driftlab evaluates the curve beyond the range instead of holding it (a K0
    /// fitted with `extrapolate`): a firmware always holds it.
    pub extrapolates: bool,
    /// What was left out, for the user.
    pub warnings: Vec<String>,
}

impl TempPolynomial {
    /// The value at `t` as driftlab computes it (held at the range's ends unless the model
    /// extrapolates).
    pub fn eval(&self, t: f64) -> f64 {
        let t = if self.extrapolates {
            t
        } else {
            t.clamp(self.t_min, self.t_max)
        };
        let c = &self.coeffs;
        let x = t - self.centre;
        ((c[3] * x + c[2]) * x + c[1]) * x + c[0]
    }

    /// The coefficients of the same polynomial in powers of `(T − t_ref)`, lowest first:
    /// `b_k = Σ_{j≥k} C(j, k)·a_j·(t_ref − centre)^(j−k)`.
    pub fn around(&self, t_ref: f64) -> [f64; MAX_ORDER + 1] {
        shift(&self.coeffs, t_ref - self.centre)
    }

    /// The same polynomial with every coefficient multiplied by `factor` (a unit change).
    pub fn scaled(mut self, factor: f64) -> TempPolynomial {
        for c in &mut self.coeffs {
            *c *= factor;
        }
        self
    }
}

/// The coefficients `a` of a polynomial in powers of `x`, as coefficients in powers of
/// `x − by`.
fn shift(a: &[f64; MAX_ORDER + 1], by: f64) -> [f64; MAX_ORDER + 1] {
    let binom = |n: usize, k: usize| -> f64 {
        (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
    };
    let mut b = [0.0; MAX_ORDER + 1];
    for (k, bk) in b.iter_mut().enumerate() {
        *bk = (k..=MAX_ORDER)
            .map(|j| binom(j, k) * a[j] * by.powi((j - k) as i32))
            .sum();
    }
    b
}

/// The static part of `model` as a polynomial in T.
///
/// # Errors
/// A model whose static part is not a polynomial of degree at most 3 in T as measured: a
/// K0 of knots, a delayed or lagged T, a second sensor, an extra channel, self-heating.
pub fn static_polynomial(model: &DriftModel) -> Result<TempPolynomial, FlightError> {
    match model {
        DriftModel::Vakhrameev(cal) => {
            let k0 = &cal.k0;
            let Curve::Polynomial { coeffs } = k0.curve() else {
                return Err(FlightError::K0NotPolynomial {
                    model: model.name().to_string(),
                    kind: k0.kind().to_string(),
                });
            };
            if coeffs.len() > MAX_ORDER + 1 {
                return Err(FlightError::NotPolynomial(format!(
                    "model {}: K0 has degree {}, above the {MAX_ORDER} the firmware reads",
                    model.name(),
                    coeffs.len() - 1
                )));
            }
            let mut c = [0.0; MAX_ORDER + 1];
            c[..coeffs.len()].copy_from_slice(coeffs);
            Ok(TempPolynomial {
                coeffs: c,
                centre: 0.0,
                t_min: k0.x_min(),
                t_max: k0.x_max(),
                extrapolates: k0.extrapolates(),
                warnings: vec![
                    "the rate terms K1±(Tdot)·Tdot and K2±(Tddot)·Tddot are left out: the \
                     flight controller corrects with K0(T) alone, so on a ramp it leaves the \
                     drift those terms would have removed"
                        .into(),
                ],
            })
        }
        DriftModel::Regression(r) => {
            let m = &r.model;
            let name = &m.spec.name;
            if m.delay.max_s() > 0.0 {
                return Err(FlightError::NotPolynomial(format!(
                    "model {name} reads T delayed by up to {} s; the flight controller reads T \
                     as measured",
                    m.delay.max_s()
                )));
            }
            if m.lag_s.is_some_and(|l| l > 0.0) {
                return Err(FlightError::NotPolynomial(format!(
                    "model {name} reads T through a lag; the flight controller reads T as \
                     measured"
                )));
            }
            // Powers of T about 0 °C in `c`, powers of T − Tref in `d`.
            let mut c = [0.0; MAX_ORDER + 1];
            let mut d = [0.0; MAX_ORDER + 1];
            let mut left_out = Vec::new();
            for (term, coef) in m.spec.terms.iter().zip(&m.coefficients) {
                match term {
                    Term::One => c[0] += coef,
                    Term::T => c[1] += coef,
                    Term::T2 => c[2] += coef,
                    Term::T3 => c[3] += coef,
                    Term::Tc { power } if usize::from(*power) <= MAX_ORDER => {
                        d[usize::from(*power)] += coef;
                    }
                    Term::Tc { .. } => {
                        let order = m
                            .spec
                            .terms
                            .iter()
                            .filter_map(|t| match t {
                                Term::Tc { power } => Some(*power),
                                _ => None,
                            })
                            .max()
                            .unwrap_or(0);
                        return Err(FlightError::NotPolynomial(format!(
                            "model {name} is a polynomial of order {order} in T - Tref; PX4 \
                             and ArduPilot evaluate one of order {MAX_ORDER} at most: \
                             calibrate with px4, ardupilot or poly-t3"
                        )));
                    }
                    t if t.is_rate() => left_out.push(t.to_string()),
                    t => {
                        return Err(FlightError::NotPolynomial(format!(
                            "model {name} has the term {t} ({}); the flight controller \
                             evaluates a polynomial in T (terms 1, T, T^2, T^3)",
                            t.describe()
                        )));
                    }
                }
            }
            let Some([t_min, t_max]) = m.ranges.temp else {
                return Err(FlightError::NotPolynomial(format!(
                    "model {name} reads no temperature: there is nothing to correct against T"
                )));
            };
            let mut warnings = Vec::new();
            if !left_out.is_empty() {
                warnings.push(format!(
                    "the rate terms {} of model {name} are left out: the flight controller \
                     corrects with the polynomial in T alone, so on a ramp it leaves the drift \
                     those terms would have removed",
                    left_out.join(", ")
                ));
            }
            // A model of T − Tref terms is given about its Tref (the 0 °C terms, if any,
            // moved there), one of T alone about 0 °C.
            let (coeffs, centre) = match m.t_ref_c {
                Some(t_ref) => {
                    let mut b = shift(&c, t_ref);
                    for (bk, dk) in b.iter_mut().zip(d) {
                        *bk += dk;
                    }
                    (b, t_ref)
                }
                None => (c, 0.0),
            };
            Ok(TempPolynomial {
                coeffs,
                centre,
                t_min,
                t_max,
                extrapolates: false,
                warnings,
            })
        }
    }
}
