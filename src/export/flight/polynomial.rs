//! The static part of a fitted model as a polynomial in T, which is all a flight controller
//! evaluates: from a regression over `1, T, T², T³` (`poly-t`, a custom model) or from
//! Vakhrameev's K0 when it is a line or a parabola. Rate terms are left out with a warning;
//! anything else a firmware cannot evaluate is refused by name.

use super::FlightError;
use crate::models::approx::Curve;
use crate::models::fitted::DriftModel;
use crate::models::regression::Term;

/// Highest power of T the flight controllers read (PX4 `X3`, ArduPilot `GYR3`).
pub const MAX_ORDER: usize = 3;

/// `Σ coeffs[k]·T^k` for T held to `[t_min, t_max]`, in the unit the model predicts in.
#[derive(Debug, Clone, PartialEq)]
pub struct TempPolynomial {
    /// Coefficients of T⁰ … T³, lowest first.
    pub coeffs: [f64; MAX_ORDER + 1],
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
        ((c[3] * t + c[2]) * t + c[1]) * t + c[0]
    }

    /// The coefficients of the same polynomial in powers of `(T − t_ref)`, lowest first:
    /// `b_k = Σ_{j≥k} C(j, k)·a_j·t_ref^(j−k)`.
    pub fn around(&self, t_ref: f64) -> [f64; MAX_ORDER + 1] {
        let a = &self.coeffs;
        let binom = |n: usize, k: usize| -> f64 {
            (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
        };
        let mut b = [0.0; MAX_ORDER + 1];
        for (k, bk) in b.iter_mut().enumerate() {
            *bk = (k..=MAX_ORDER)
                .map(|j| binom(j, k) * a[j] * t_ref.powi((j - k) as i32))
                .sum();
        }
        b
    }

    /// The same polynomial with every coefficient multiplied by `factor` (a unit change).
    pub fn scaled(mut self, factor: f64) -> TempPolynomial {
        for c in &mut self.coeffs {
            *c *= factor;
        }
        self
    }
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
            let mut c = [0.0; MAX_ORDER + 1];
            let mut left_out = Vec::new();
            for (term, coef) in m.spec.terms.iter().zip(&m.coefficients) {
                match term {
                    Term::One => c[0] += coef,
                    Term::T => c[1] += coef,
                    Term::T2 => c[2] += coef,
                    Term::T3 => c[3] += coef,
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
            Ok(TempPolynomial {
                coeffs: c,
                t_min,
                t_max,
                extrapolates: false,
                warnings,
            })
        }
    }
}
