//! A calibration taken apart for a loop over many samples: its five approximations as
//! [`Evaluator`]s and their ranges read once, so that a correction of a million samples does
//! not repeat per sample the lookups [`Calibration::predict`] makes through each
//! [`Approx::eval`](crate::models::approx::Approx::eval) (curve kind, knot vectors, segment
//! table, an out-of-line call). The same bits as [`Calibration::predict`] and
//! [`Calibration::is_outside`]: each evaluator is its approximation's `eval`, bit for bit (a
//! test holds them equal).

use super::{Calibration, Regime};
use crate::models::approx::{Approx, Evaluator};

/// [`Calibration::predict`] and [`Calibration::is_outside`] for many samples.
#[derive(Debug, Clone, Copy)]
pub struct Predictor<'a> {
    k0: Evaluator<'a>,
    /// K1 and K2 of the + set, then of the − set.
    k1: [Evaluator<'a>; 2],
    k2: [Evaluator<'a>; 2],
    /// `[x_min, x_max]` of K0, then of K1 and K2 of each set.
    k0_range: [f64; 2],
    k1_range: [[f64; 2]; 2],
    k2_range: [[f64; 2]; 2],
}

fn range(a: &Approx) -> [f64; 2] {
    [a.x_min(), a.x_max()]
}

impl Calibration {
    /// This calibration prepared for many samples ([`Predictor`]).
    pub fn predictor(&self) -> Predictor<'_> {
        Predictor {
            k0: self.k0.evaluator(),
            k1: [self.k1_plus.evaluator(), self.k1_minus.evaluator()],
            k2: [self.k2_plus.evaluator(), self.k2_minus.evaluator()],
            k0_range: range(&self.k0),
            k1_range: [range(&self.k1_plus), range(&self.k1_minus)],
            k2_range: [range(&self.k2_plus), range(&self.k2_minus)],
        }
    }
}

impl Predictor<'_> {
    /// [`Calibration::predict`].
    #[inline(always)]
    pub fn predict(&self, temp_c: f64, tdot: f64, tddot: f64) -> (f64, Regime) {
        let regime = Regime::of(tdot, tddot);
        let k0 = self.k0.eval(temp_c);
        let pred = match regime {
            Regime::Static => k0,
            Regime::Plus => k0 + self.k1[0].eval(tdot) * tdot + self.k2[0].eval(tddot) * tddot,
            Regime::Minus => k0 + self.k1[1].eval(tdot) * tdot + self.k2[1].eval(tddot) * tddot,
        };
        (pred, regime)
    }

    /// [`Calibration::is_outside`].
    #[inline(always)]
    pub fn is_outside(&self, temp_c: f64, tdot: f64, tddot: f64, regime: Regime) -> bool {
        let beyond = |[lo, hi]: [f64; 2], x: f64| x < lo || x > hi;
        beyond(self.k0_range, temp_c)
            || match regime {
                Regime::Static => false,
                Regime::Plus => beyond(self.k1_range[0], tdot) || beyond(self.k2_range[0], tddot),
                Regime::Minus => beyond(self.k1_range[1], tdot) || beyond(self.k2_range[1], tddot),
            }
    }

    /// The predicted drift, its regime and whether the sample lies outside the calibrated
    /// ranges, of one sample.
    #[inline(always)]
    pub fn sample(&self, temp_c: f64, tdot: f64, tddot: f64) -> (f64, Regime, bool) {
        let (p, r) = self.predict(temp_c, tdot, tddot);
        (p, r, self.is_outside(temp_c, tdot, tddot, r))
    }
}

#[cfg(test)]
mod tests {
    use crate::models::approx::{ApproxKind, ApproxSpec};
    use crate::models::recipe::Recipe;

    /// Every kind of curve, held and extrapolated, at samples inside, at and beyond every
    /// range, in every regime and not finite: the predictor's values and verdicts are
    /// `predict`'s and `is_outside`'s, bit for bit.
    #[test]
    fn the_predictor_is_predict_bit_for_bit() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
        let log = crate::log::ingest::read_path(&path, &Default::default()).expect("sample log");
        let kinds = [
            ApproxKind::Linear,
            ApproxKind::Parabolic,
            ApproxKind::Pwl,
            ApproxKind::Spline,
        ];
        let mut checked = 0usize;
        for (n, &kind) in kinds.iter().enumerate() {
            let other = kinds[(n + 1) % 4];
            let recipe = Recipe {
                k0: ApproxSpec::of(if n % 2 == 0 {
                    ApproxKind::Linear
                } else {
                    ApproxKind::Parabolic
                }),
                k1_plus: ApproxSpec::of(kind),
                k1_minus: ApproxSpec {
                    extrapolate: true,
                    ..ApproxSpec::of(other)
                },
                k2_plus: ApproxSpec {
                    extrapolate: n % 2 == 1,
                    ..ApproxSpec::of(other)
                },
                k2_minus: ApproxSpec::of(kind),
                ..Recipe::default()
            };
            let fit = super::super::fit(&log, &recipe.checked().expect("recipe")).expect("fit");
            let cal = &fit.calibration;
            let p = cal.predictor();
            let span = |a: &crate::models::approx::Approx| {
                let (lo, hi) = (a.x_min(), a.x_max());
                let w = (hi - lo).abs().max(1e-9);
                [lo - w, lo, lo + 0.3 * w, (lo + hi) / 2.0, hi, hi + 0.7 * w]
            };
            let mut temps = span(&cal.k0).to_vec();
            temps.push(f64::NAN);
            let mut tdots: Vec<f64> = span(&cal.k1_plus)
                .into_iter()
                .chain(span(&cal.k1_minus))
                .collect();
            tdots.extend([0.0, -0.0, f64::INFINITY, f64::NAN]);
            let mut tddots: Vec<f64> = span(&cal.k2_plus)
                .into_iter()
                .chain(span(&cal.k2_minus))
                .flat_map(|x| [x, -x])
                .collect();
            tddots.extend([0.0, f64::NEG_INFINITY]);
            for &t in &temps {
                for &td in &tdots {
                    for &tdd in &tddots {
                        let (want, regime) = cal.predict(t, td, tdd);
                        let (got, r, outside) = p.sample(t, td, tdd);
                        assert_eq!(r, regime);
                        assert_eq!(got.to_bits(), want.to_bits(), "{t} {td} {tdd}");
                        assert_eq!(outside, cal.is_outside(t, td, tdd, regime));
                        checked += 1;
                    }
                }
            }
        }
        assert_eq!(checked, 4 * 7 * 16 * 26);
    }
}
