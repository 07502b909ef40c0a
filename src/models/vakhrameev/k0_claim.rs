//! K0 is fitted through the plateaus a calibration stores, and the file states how closely
//! (`k0.stats`): a curve edited by hand (a knot's value or place, a polynomial's coefficient)
//! that no longer passes where those statistics say is refused on load.
//!
//! The C header and the report print K0's statistics as the fit's quality, and the firmware
//! takes the curve: a constant raised by 5 °/h under an unchanged "rmse 0.0035" is a bias error
//! handed to the gyro's processor with a claim that it is not there. The plateaus (their
//! temperature and mean rate) are in the file, so the statistics can be made again from them
//! as every fit makes them ([`crate::models::approx::stats_on`], on the same points in the same
//! order, also for knots placed or set by hand: their statistics are judged on the points the
//! fit saw). Made again, they equal the stated ones to their last digits; a difference beyond
//! rounding is an edit, of the curve or of its statistics, and which of the two cannot be told.

use crate::error::Invalid;
use crate::models::approx::{Approx, stats_on};
use crate::number::readable;
use crate::signal::plateau::PlateauStats;

/// How far the statistics made again may stand from the stated ones, in the unit of K0
/// (rmse) or absolute (R²): rounding of sums over a handful of points, far below any edit a
/// person makes (°/h in the thousandths at the least).
fn tolerance(scale: f64) -> f64 {
    1e-9 * (1.0 + scale)
}

/// Refuses a `k0` whose statistics on `plateaus` (the points it was fitted through) are not
/// the ones it states, naming `k0` with the plateau it misses most, or `k0.stats.r2` when the
/// residuals agree and R² alone was edited. A calibration with no plateau, or a K0 that
/// states no residual (fitted to no point), is left to the checks of its statistics.
///
/// # Errors
/// The field, `k0` or `k0.stats.r2`, with the stated and the recomputed figure.
pub(super) fn check_k0_claim(k0: &Approx, plateaus: &[PlateauStats]) -> Result<(), Invalid> {
    let stated = k0.stats();
    if plateaus.is_empty() || stated.computed_rmse().is_none() {
        return Ok(());
    }
    let t: Vec<f64> = plateaus.iter().map(|p| p.temp_c).collect();
    let w: Vec<f64> = plateaus.iter().map(|p| p.omega_dph).collect();
    let made = stats_on(k0, &t, &w, None);
    let scale = w.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let tol = tolerance(scale);
    if held_constant_before_its_spread_was_stated(k0, &w, tol) {
        return Ok(());
    }
    let advice = "the curve or its statistics were edited: calibrate the log again rather than \
                  edit the file";
    if made.n != stated.n || (made.rmse - stated.rmse).abs() > tol {
        let ev = k0.evaluator();
        let miss = |k: usize| (w[k] - ev.eval(t[k])).abs();
        let worst = (0..t.len())
            .max_by(|a, b| miss(*a).total_cmp(&miss(*b)))
            .unwrap_or(0);
        return Err(Invalid::new(
            "k0",
            format!(
                "misses the plateaus it was fitted through by up to {} °/h (plateaus[{worst}]: \
                 Ω {} °/h at {} °C, where K0 is {} °/h): an rms of {} °/h over {} plateaus, \
                 where the file states {} over {} (k0.stats); {advice}",
                readable(miss(worst)),
                readable(w[worst]),
                readable(t[worst]),
                readable(ev.eval(t[worst])),
                readable(made.rmse),
                made.n,
                readable(stated.rmse),
                stated.n,
            ),
        ));
    }
    if let (Some(made_r2), Some(stated_r2)) = (made.computed_r2(), stated.computed_r2())
        && (made_r2 - stated_r2).abs() > tolerance(1.0)
    {
        return Err(Invalid::new(
            "k0.stats.r2",
            format!(
                "is {}, but K0's curve through the plateaus it was fitted through gives {}; \
                 {advice}",
                readable(stated_r2),
                readable(made_r2)
            ),
        ));
    }
    Ok(())
}

/// A K0 held constant at the plateaus' mean (their temperatures one set point), as files
/// written before such a K0 stated its residuals' spread hold it: rmse and R² both 0. Its
/// constant is checked instead: the mean of the plateaus, to rounding.
fn held_constant_before_its_spread_was_stated(k0: &Approx, omegas: &[f64], tol: f64) -> bool {
    let stated = k0.stats();
    let crate::models::approx::Curve::Polynomial { coeffs } = k0.curve() else {
        return false;
    };
    let [constant] = coeffs[..] else {
        return false;
    };
    let mean = omegas.iter().sum::<f64>() / omegas.len() as f64;
    stated.rmse == 0.0
        && stated.r2 == 0.0
        && stated.n == omegas.len()
        && (constant - mean).abs() <= tol
}
