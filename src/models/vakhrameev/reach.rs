//! How far beyond its fitted range an extrapolating curve is taken: out to where a chamber
//! takes its argument, and no further; a curve predicting more than a gyro could show out
//! there is refused, naming its `extrapolate` setting and the way out.

use crate::error::Invalid;
use crate::models::approx::Approx;

/// How far a chamber takes each argument of the five approximations (K0: T, °C; K1±: Ṫ, °C/s;
/// K2±: T̈, °C/s²): the temperatures a log may hold; 30 °C/min, the fastest stress-screening
/// chamber (as [`crate::log::temp_rate`] holds a log to); that rate reversed within a minute.
/// An extrapolating curve is evaluated out there, so its drift is bounded there. (T̈ reached
/// 0.1 °C/s² once: a parabolic K2 fitted over ±2e-4 °C/s² and extrapolated, as the fit
/// writes it, predicted 1.4e8 °/h there, and its own calibration could not be read back.)
pub const CHAMBER_REACH: [(f64, f64); 5] = [
    crate::log::mapping_check::PLAUSIBLE_TEMP_C,
    (-0.5, 0.5),
    (-0.5, 0.5),
    (-1.0 / 60.0, 1.0 / 60.0),
    (-1.0 / 60.0, 1.0 / 60.0),
];

/// The largest drift the `k`-th approximation (in [`Calibration::fields`]' order) predicts
/// beyond its fitted range, out to the chamber's reach, when it extrapolates (0 when it holds
/// its edge values, which [`Approx::bound`] covers). Sampled at 1025 points and the range's
/// ends: the curves past their ranges are straight or of degree two, so this is their bound to
/// well within the factor [`crate::models::MAX_DRIFT_DPH`] leaves; a hand-edited K1 of slope
/// 1e13 over ±1e-6 °C/s predicted 5e9 °/h at the first sample past it.
fn beyond_range_bound(k: usize, a: &Approx) -> f64 {
    if !a.extrapolates() {
        return 0.0;
    }
    let (lo, hi) = CHAMBER_REACH[k];
    let (lo, hi) = (lo.min(a.x_min()), hi.max(a.x_max()));
    let drift = |x: f64| {
        let v = a.eval(x);
        if k == 0 { v.abs() } else { (v * x).abs() }
    };
    (0..=1024)
        .map(|j| lo + (hi - lo) * j as f64 / 1024.0)
        .chain([a.x_min(), a.x_max()])
        .map(drift)
        .fold(
            0.0,
            |m: f64, d| if d.is_nan() { f64::INFINITY } else { m.max(d) },
        )
}

/// Refuses the `k`-th approximation (named `name`) when it extrapolates to a drift beyond
/// [`crate::models::MAX_DRIFT_DPH`] within the chamber's reach.
pub(super) fn check_extrapolation(k: usize, name: &str, a: &Approx) -> Result<(), Invalid> {
    let beyond = beyond_range_bound(k, a);
    if beyond.is_finite() && beyond <= crate::models::MAX_DRIFT_DPH {
        return Ok(());
    }
    let (lo, hi) = CHAMBER_REACH[k];
    Err(Invalid::new(
        format!("{name}.extrapolate"),
        format!(
            "the curve, extrapolated beyond its fitted {} .. {} {unit} out to the {} .. {} \
             {unit} a chamber may take it, predicts a drift of up to {} deg/h, more than the {} \
             deg/h any gyro could show: fit it without extrapolating (it then holds its edge \
             values)",
            crate::number::readable(a.x_min()),
            crate::number::readable(a.x_max()),
            crate::number::readable(lo.min(a.x_min())),
            crate::number::readable(hi.max(a.x_max())),
            crate::models::drift_past_limit(beyond),
            crate::number::readable(crate::models::MAX_DRIFT_DPH),
            unit = ["°C", "°C/s", "°C/s", "°C/s²", "°C/s²"][k],
        ),
    ))
}

/// Refuses a K0 whose range or knots lie beyond the temperatures a log may hold
/// ([`CHAMBER_REACH`]'s first, the range a log's temperature is held to): a fit never makes
/// one, and a hand-edited K0 over ±1e300 °C was applied and exported, and then made a report
/// whose temperature axis could not be drawn. (K1's and K2's ranges are the rates the fit saw,
/// noise and all, and are bounded by the drift they predict instead.)
///
/// # Errors
/// An [`Invalid`] naming `k0.x_min`, `k0.x_max` or `k0.knots_x[j]`.
pub fn check_k0_temperatures(k0: &Approx) -> Result<(), Invalid> {
    let (lo, hi) = CHAMBER_REACH[0];
    let beyond = |x: f64| !(lo..=hi).contains(&x);
    let found = [
        ("k0.x_min".to_string(), k0.x_min()),
        ("k0.x_max".to_string(), k0.x_max()),
    ]
    .into_iter()
    .chain(
        k0.knots()
            .0
            .iter()
            .enumerate()
            .map(|(j, &x)| (format!("k0.knots_x[{j}]"), x)),
    )
    .find(|(_, x)| beyond(*x));
    match found {
        None => Ok(()),
        Some((field, x)) => Err(Invalid::new(
            field,
            format!(
                "{} °C lies beyond the temperatures a log may hold ({} … {} °C): no fit makes \
                 such a K0",
                crate::number::readable(x),
                crate::number::readable(lo),
                crate::number::readable(hi)
            ),
        )),
    }
}
