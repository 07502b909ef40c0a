//! The input ranges a fitted regression model saw and its statistics, computed from the
//! residuals over the fitted samples. Apart from the fit because it runs once on the result.

use crate::models::regression::signals::Signals;

/// An R² this close to zero is zero: what is left of `1 - ss_res / ss_tot` when the two sums
/// are equal to their rounding.
const R2_ROUNDING: f64 = 1e-9;
use crate::models::regression::{InputRanges, Range, RegressionModel, RegressionStats, Term};

/// The input ranges over the fitted samples and the fit's statistics (from the residuals, not
/// the normal equations, for accuracy).
pub(super) fn ranges_and_stats(
    m: &RegressionModel,
    s: &Signals,
    used: &[bool],
) -> (InputRanges, RegressionStats) {
    let t = &m.spec.terms;
    let uses = |f: fn(&Term) -> bool| t.iter().any(f);
    let mut r = [[f64::INFINITY, f64::NEG_INFINITY]; 4];
    let mut rc = vec![[f64::INFINITY, f64::NEG_INFINITY]; s.channels.len()];
    let mut ch = vec![0.0; s.channels.len()];
    let mut row = Vec::new();
    let (mut n, mut sum, mut sum2, mut ss_res) = (0usize, 0.0, 0.0, 0.0);
    let grow = |r: &mut Range, v: f64| {
        if v.is_finite() {
            r[0] = r[0].min(v);
            r[1] = r[1].max(v);
        }
    };
    for i in s.ready_samples().filter(|&i| used[i]) {
        let x = s.inputs(i, &m.delay, &mut ch);
        let y = s.omega[i];
        let pred = m.predict(&x, &ch, &mut row);
        if !y.is_finite() || !pred.is_finite() {
            continue;
        }
        for (k, v) in [x.temp, x.tdot, x.tddot, x.dt].into_iter().enumerate() {
            grow(&mut r[k], v);
        }
        for (rk, &v) in rc.iter_mut().zip(&ch) {
            grow(rk, v);
        }
        n += 1;
        sum += y;
        sum2 += y * y;
        ss_res += (y - pred) * (y - pred);
    }
    let some = |used: bool, r: Range| (used && r[0] <= r[1]).then_some(r);
    let ranges = InputRanges {
        temp: some(
            uses(|t| {
                matches!(
                    t,
                    Term::T
                        | Term::T2
                        | Term::T3
                        | Term::TTdot
                        | Term::TTddot
                        | Term::PwlT { .. }
                        | Term::Tc { .. }
                )
            }),
            r[0],
        ),
        tdot: some(
            uses(|t| {
                matches!(
                    t,
                    Term::Tdot | Term::TTdot | Term::AbsTdot | Term::SgnTdotTddot
                )
            }),
            r[1],
        ),
        tddot: some(
            uses(|t| matches!(t, Term::Tddot | Term::TTddot | Term::SgnTdotTddot)),
            r[2],
        ),
        dt: some(uses(Term::needs_temp2), r[3]),
        channels: rc
            .into_iter()
            .map(|r| if r[0] <= r[1] { r } else { [0.0, 0.0] })
            .collect(),
    };
    let ss_tot = sum2 - sum * sum / n.max(1) as f64;
    let stats = RegressionStats {
        n,
        rmse: (ss_res / n.max(1) as f64).sqrt(),
        // Within a billionth of zero, R² is zero: the residual and the total sums equal to
        // their rounding (a model of the mean alone, a bias), never a fit "worse than the
        // mean" by 2e-15.
        r2: match 1.0 - ss_res / ss_tot {
            r2 if ss_tot > 0.0 && r2.abs() > R2_ROUNDING => r2,
            _ => 0.0,
        },
    };
    (ranges, stats)
}
