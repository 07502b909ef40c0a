//! A calibration taken apart for a loop over many samples: its five approximations as
//! [`Evaluator`]s and their ranges read once, so that a correction of a million samples does
//! not repeat per sample the lookups [`Calibration::predict`] makes through each
//! [`Approx::eval`](crate::models::approx::Approx::eval) (curve kind, knot vectors, segment
//! table, an out-of-line call). The same bits as [`Calibration::predict`] and
//! [`Calibration::is_outside`]: each evaluator is its approximation's `eval`, bit for bit (a
//! test holds them equal).

use super::{Calibration, Regime};
use crate::models::approx::{Approx, Evaluator, Spot};

/// [`Calibration::predict`] and [`Calibration::is_outside`] for many samples.
#[derive(Debug, Clone, Copy)]
pub struct Predictor<'a> {
    k0: Evaluator<'a>,
    /// K1 and K2 of the + set, then of the − set.
    k1: [Evaluator<'a>; 2],
    k2: [Evaluator<'a>; 2],
    /// The range each input is judged against ([`Approx::judged_range`]): of K0, then of K1
    /// and K2 of each set.
    k0_range: [f64; 2],
    k1_range: [[f64; 2]; 2],
    k2_range: [[f64; 2]; 2],
}

fn range(a: &Approx) -> [f64; 2] {
    a.judged_range()
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

/// Where one sample falls on a calibration's curves: its T on K0, its Ṫ and T̈ on K1 and K2 of
/// its regime's set ([`Predictor::spots`]). The same for every axis of a unit whose curves
/// share their spots ([`Predictor::shares_spots`]).
#[derive(Debug, Clone, Copy)]
pub struct Spots {
    /// The sample's regime.
    pub regime: Regime,
    k0: Spot,
    /// K1's and K2's spots (unused in the static regime).
    k1: Spot,
    k2: Spot,
    tdot: f64,
    tddot: f64,
}

impl Predictor<'_> {
    /// [`Calibration::predict`].
    #[inline(always)]
    pub fn predict(&self, temp_c: f64, tdot: f64, tddot: f64) -> (f64, Regime) {
        let s = self.spots(temp_c, tdot, tddot);
        (self.predict_at(&s), s.regime)
    }

    /// Where a sample falls on this calibration's curves.
    #[inline(always)]
    pub fn spots(&self, temp_c: f64, tdot: f64, tddot: f64) -> Spots {
        let regime = Regime::of(tdot, tddot);
        let (k1, k2) = match regime {
            Regime::Static => (Spot::Zero, Spot::Zero),
            Regime::Plus => (self.k1[0].spot(tdot), self.k2[0].spot(tddot)),
            Regime::Minus => (self.k1[1].spot(tdot), self.k2[1].spot(tddot)),
        };
        Spots {
            regime,
            k0: self.k0.spot(temp_c),
            k1,
            k2,
            tdot,
            tddot,
        }
    }

    /// The predicted drift of a sample at `s`, found on this calibration's curves or on those of
    /// one that shares their spots: [`Calibration::predict`], bit for bit.
    #[inline(always)]
    pub fn predict_at(&self, s: &Spots) -> f64 {
        let k0 = self.k0.at(s.k0);
        let set = match s.regime {
            Regime::Static => return k0,
            Regime::Plus => 0,
            Regime::Minus => 1,
        };
        k0 + self.k1[set].at(s.k1) * s.tdot + self.k2[set].at(s.k2) * s.tddot
    }

    /// Whether every sample falls on the same spots of `self`'s curves and `other`'s, and lies
    /// inside or outside the calibrated ranges alike: the axes of a unit fitted over the same
    /// plateaus and sets, with the same kinds of curve and knots.
    pub fn shares_spots(&self, other: &Predictor<'_>) -> bool {
        let same = |a: &[Evaluator<'_>], b: &[Evaluator<'_>]| {
            a.iter().zip(b).all(|(a, b)| a.same_spots(b))
        };
        let bits = |a: &[[f64; 2]], b: &[[f64; 2]]| {
            a.iter()
                .flatten()
                .zip(b.iter().flatten())
                .all(|(x, y)| x.to_bits() == y.to_bits())
        };
        self.k0.same_spots(&other.k0)
            && same(&self.k1, &other.k1)
            && same(&self.k2, &other.k2)
            && bits(&[self.k0_range], &[other.k0_range])
            && bits(&self.k1_range, &other.k1_range)
            && bits(&self.k2_range, &other.k2_range)
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

    /// The axes of the sample unit, each fitted alone with curves of every kind (the same
    /// kinds on every axis): corrected in one pass, each axis's correction is its own
    /// `correct_into`'s, bit for bit. Axes fitted with other knots share no spots, and the
    /// pass then corrects nothing.
    #[test]
    fn a_unit_corrected_in_one_pass_is_each_axis_corrected_alone() {
        use crate::models::vakhrameev::{Calibration, correct::Correction};
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("sample_logs/imu3-calibration.csv");
        let unit = crate::log::ingest::read_path(&path, &Default::default()).expect("sample unit");
        let logs: Vec<crate::log::Log> = unit
            .axis_names()
            .iter()
            .map(|n| {
                let mut v = unit.clone();
                assert!(v.select_axis(n));
                v
            })
            .collect();
        assert_eq!(logs.len(), 3);
        let kinds = [
            (ApproxKind::Parabolic, ApproxKind::Pwl, ApproxKind::Spline),
            (ApproxKind::Pwl, ApproxKind::Spline, ApproxKind::Linear),
            (ApproxKind::Spline, ApproxKind::Parabolic, ApproxKind::Pwl),
        ];
        for (k0, k1, k2) in kinds {
            let recipe = Recipe {
                k0: ApproxSpec::of(k0),
                k1_plus: ApproxSpec::of(k1),
                k1_minus: ApproxSpec {
                    extrapolate: true,
                    ..ApproxSpec::of(k2)
                },
                k2_plus: ApproxSpec::of(k2),
                k2_minus: ApproxSpec::of(k1),
                ..Recipe::default()
            }
            .checked()
            .expect("recipe");
            let cals: Vec<Calibration> = logs
                .iter()
                .map(|l| super::super::fit(l, &recipe).expect("fit").calibration)
                .collect();
            let deriv = cals[0].derivatives(&logs[0]);
            let alone: Vec<Correction> = cals
                .iter()
                .zip(&logs)
                .map(|(c, l)| c.correct_with(l, &deriv))
                .collect();
            let mut outs: Vec<Correction> = (0..3).map(|_| Correction::default()).collect();
            let mut bufs: Vec<&mut Correction> = outs.iter_mut().collect();
            let omegas: Vec<&[f64]> = logs.iter().map(|l| l.omega_dph.as_slice()).collect();
            let refs: Vec<&Calibration> = cals.iter().collect();
            assert!(
                Calibration::correct_unit_into(&refs, &logs[0].temp_c, &omegas, &deriv, &mut bufs),
                "{k0:?} {k1:?} {k2:?}: the axes share their spots"
            );
            for (a, (got, want)) in outs.iter().zip(&alone).enumerate() {
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&got.pred_dph), bits(&want.pred_dph), "axis {a}");
                assert_eq!(bits(&got.cor_dph), bits(&want.cor_dph), "axis {a}");
                assert_eq!(got.regime, want.regime, "axis {a}");
                assert_eq!(got.outside_by_regime, want.outside_by_regime, "axis {a}");
                assert_eq!(got.ready, want.ready, "axis {a}");
            }
            // Another axis fitted with more knots on K1+ shares no spots with the first.
            let more = Recipe {
                k1_plus: ApproxSpec {
                    knots: 9,
                    ..ApproxSpec::of(ApproxKind::Pwl)
                },
                ..(*recipe).clone()
            }
            .checked()
            .expect("recipe");
            let other = super::super::fit(&logs[1], &more).expect("fit").calibration;
            let mut spare = [Correction::default(), Correction::default()];
            let mut bufs: Vec<&mut Correction> = spare.iter_mut().collect();
            assert!(!Calibration::correct_unit_into(
                &[&cals[0], &other],
                &logs[0].temp_c,
                &omegas[..2],
                &deriv,
                &mut bufs
            ));
            assert!(spare.iter().all(|c| c.pred_dph.is_empty()));
        }
    }
}
