//! K0's range is the span of the plateaus it was fitted through: a hand-edited `k0.x_min` or
//! `k0.x_max`, or a plateau's `temp_c`, that contradicts the other is refused on load.
//!
//! A calibration claims K0 over its range: the share of a log "outside the calibrated ranges",
//! the C header's `fitted on T in [..]` and its table's temperatures all read it. A range edited
//! wider than the plateaus claims a K0 where nothing was measured (a parabola exported 40 °C
//! past its last plateau); edited narrower, it holds K0 flat over plateaus it was fitted through;
//! a plateau's temperature edited outside it is a point the curve never saw.
//!
//! What a fit makes ([`super::k0_of`]): a polynomial K0 (a parabola, a line, a constant, also
//! the line a knot curve falls back to) spans exactly the lowest and highest plateau
//! temperature; a knot curve whose knots the fit placed has its end knots at the lowest and
//! highest of the plateaus' distinct temperatures (the mean of each set point's plateaus,
//! [`super::k0_plateaus`]), or, when it fell back to fewer knots spread evenly, at the lowest
//! and highest plateau, so each end lies between the two. Knots placed by hand stand where the
//! engineer put them, anywhere a log may hold ([`super::reach::check_k0_temperatures`]), and
//! are not checked here.

use crate::error::Invalid;
use crate::models::approx::{Approx, ApproxSpec, Curve};
use crate::number::readable;
use crate::signal::plateau::PlateauStats;

/// Refuses a `k0` (fitted for `spec`) whose range is not what a fit through `plateaus` makes,
/// naming the field that stands out and both values: a plateau alone outside the range (one
/// `temp_c` edited), else the range's end. A calibration with no
/// plateau is left to the checks of its statistics.
///
/// # Errors
/// The field, `k0.x_min`, `k0.x_max` or `plateaus[k].temp_c`, with both values.
pub(super) fn check_k0_range(
    k0: &Approx,
    spec: &ApproxSpec,
    plateaus: &[PlateauStats],
) -> Result<(), Invalid> {
    let knots = !matches!(k0.curve(), Curve::Polynomial { .. });
    if plateaus.is_empty() || (knots && spec.at.is_some()) {
        return Ok(());
    }
    let (x_min, x_max) = (k0.x_min(), k0.x_max());
    let Some(wrong) = wrong_end(plateaus, knots, x_min, x_max) else {
        return Ok(());
    };
    let temps: Vec<f64> = plateaus.iter().map(|p| p.temp_c).collect();
    let range = format!("{} … {} °C", readable(x_min), readable(x_max));
    let how = if knots {
        "a fit places K0's end knots at its lowest and highest plateau temperatures"
    } else {
        "a fit's K0 spans exactly its lowest and highest plateau temperature"
    };
    let advice = "one of them was edited: calibrate the log again rather than edit the file";
    // One plateau alone outside the range: its temperature moved (or the range's end moved
    // past it alone: the message says both). A knot curve's end knot is its set point's mean,
    // so its plateaus may lie a little outside the range.
    let slack = |x: f64| {
        if knots {
            super::k0_plateaus::DISTINCT_PLATEAU_C
        } else {
            tol(x)
        }
    };
    let out: Vec<usize> = (0..temps.len())
        .filter(|&k| temps[k] < x_min - slack(x_min) || temps[k] > x_max + slack(x_max))
        .collect();
    if let [k] = out[..] {
        return Err(Invalid::new(
            format!("plateaus[{k}].temp_c"),
            format!(
                "is {} °C, outside k0's range {range}, which the other plateaus lie within: \
                 {how}; {advice}",
                readable(temps[k])
            ),
        ));
    }
    let (lo_j, hi_j) = lowest_and_highest(&temps);
    let span = format!(
        "the plateaus K0 was fitted through span {} … {} °C (plateaus[{lo_j}].temp_c … \
         plateaus[{hi_j}].temp_c)",
        readable(temps[lo_j]),
        readable(temps[hi_j])
    );
    let (field, end) = match wrong {
        End::Low => ("k0.x_min", x_min),
        End::High => ("k0.x_max", x_max),
    };
    let outside = match out.len() {
        0 => String::new(),
        n => format!(", {n} of them outside k0's range {range}"),
    };
    Err(Invalid::new(
        field,
        format!(
            "is {} °C, but {span}{outside}: {how}; {advice}",
            readable(end)
        ),
    ))
}

/// An end of K0's range.
enum End {
    Low,
    High,
}

/// How far apart two temperatures may be and still be one, °C: a relative rounding.
fn tol(x: f64) -> f64 {
    1e-9 * (1.0 + x.abs())
}

/// The indices of the lowest and highest of `temps` (not empty).
fn lowest_and_highest(temps: &[f64]) -> (usize, usize) {
    let by = |a: &usize, b: &usize| temps[*a].total_cmp(&temps[*b]);
    let lo = (0..temps.len()).min_by(by).unwrap_or(0);
    let hi = (0..temps.len()).max_by(by).unwrap_or(0);
    (lo, hi)
}

/// The end of the range `x_min … x_max` that a fit through `plateaus` (not empty) could not
/// have made, if either: a polynomial's ends are the lowest and highest plateau temperature; a
/// knot curve's lie between those and the lowest and highest of the plateaus' distinct
/// temperatures.
fn wrong_end(plateaus: &[PlateauStats], knots: bool, x_min: f64, x_max: f64) -> Option<End> {
    let temps: Vec<f64> = plateaus.iter().map(|p| p.temp_c).collect();
    let (lo_j, hi_j) = lowest_and_highest(&temps);
    let (lo, hi) = (temps[lo_j], temps[hi_j]);
    let (inner_lo, inner_hi) = if knots {
        let distinct = super::k0_plateaus::plateau_temperatures(plateaus);
        match (distinct.first(), distinct.last()) {
            (Some(&a), Some(&b)) => (a, b),
            _ => (lo, hi),
        }
    } else {
        (lo, hi)
    };
    if x_min < lo - tol(lo) || x_min > inner_lo + tol(inner_lo) {
        Some(End::Low)
    } else if x_max > hi + tol(hi) || x_max < inner_hi - tol(inner_hi) {
        Some(End::High)
    } else {
        None
    }
}
