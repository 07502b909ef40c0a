//! The stages between the plateaus (`crate::signal::plateau`) and the + and − sets: K0 through
//! the plateau points and the dead-bands; and the fallback every approximation of the model
//! goes through when its points cannot carry the curve asked for.

use super::Prepared;
use super::k0_plateaus::{distinct_temperatures, knots_at_temperatures, simpler_for};
use crate::error::Result;
use crate::models::FitError;
use crate::models::approx::{self, Approx, ApproxKind, ApproxSpec};
use crate::models::recipe::Recipe;
use crate::signal::plateau::PlateauStats;

/// K0(T) through the plateau points, lowering the order when there are too few plateaus.
///
/// A pwl or spline K0 whose knots were not placed by hand has them at the plateaus'
/// distinct temperatures ([`knots_at_temperatures`]: the recipe's knot count is a maximum),
/// so the curve passes through what was measured instead of bending where no plateau was.
/// No K0 is warned of for passing through every plateau point: each point is already the
/// mean of a plateau's samples, and a curve through the set points' means is what K0 is (the
/// papers' parabola through three plateaus; the knots at the plateaus' temperatures).
pub fn fit_k0(
    plateaus: &[PlateauStats],
    spec: &ApproxSpec,
    warnings: &mut Vec<String>,
) -> Result<Approx> {
    if plateaus.is_empty() {
        return Err(FitError::NoK0Plateaus.into());
    }
    let t: Vec<f64> = plateaus.iter().map(|p| p.temp_c).collect();
    let w: Vec<f64> = plateaus.iter().map(|p| p.omega_dph).collect();
    let temps = distinct_temperatures(&t);
    let placed = knots_at_temperatures(spec, &temps);
    if temps.len() < placed.params() && temps.len() < plateaus.len() {
        // Two plateaus at one set point are one temperature twice: a parabola through them
        // and a third takes its curvature from their hundredths of a degree, and bulges where
        // no plateau was (7.5 °/h between plateaus of 0.03 and 0.15).
        let simpler = simpler_for(spec, temps.len());
        let (kind, params) = match &simpler {
            Some(s) => (s.kind.to_string(), s.params()),
            None => ("a constant".to_string(), 1),
        };
        warnings.push(format!(
            "K0: {} with {} parameters asked for through {} plateaus at only {} temperatures \
             ({} °C): between them the curve is not known; fitted as {} with {} parameters \
             instead. Hold a plateau at another temperature to fit it",
            spec.kind,
            spec.params(),
            plateaus.len(),
            temps.len(),
            temps
                .iter()
                .map(|t| crate::number::significant(*t, 3))
                .collect::<Vec<_>>()
                .join(", "),
            kind,
            params
        ));
        return Ok(match simpler {
            Some(simpler) => {
                fit_k0_points(&knots_at_temperatures(&simpler, &temps), &t, &w, warnings)
            }
            None => constant(spec, &t, &w),
        });
    }
    Ok(fit_k0_points(&placed, &t, &w, warnings))
}

/// [`fit_or_fallback`] of K0 through its plateau points, without the warning of a curve
/// through every point (see [`fit_k0`]).
fn fit_k0_points(spec: &ApproxSpec, t: &[f64], w: &[f64], warnings: &mut Vec<String>) -> Approx {
    fit_or_fallback_as("K0", spec, t, w, None, false, warnings)
}

/// Fits `spec`, and when the points cannot support it, the richest simpler curve they can:
/// fewer knots, then a line, then a constant, then zero (no points: the term is left out).
pub fn fit_or_fallback(
    name: &str,
    spec: &ApproxSpec,
    x: &[f64],
    y: &[f64],
    warnings: &mut Vec<String>,
) -> Approx {
    fit_or_fallback_weighted(name, spec, x, y, None, warnings)
}

/// [`fit_or_fallback`] with point weights.
pub fn fit_or_fallback_weighted(
    name: &str,
    spec: &ApproxSpec,
    x: &[f64],
    y: &[f64],
    weights: Option<&[f64]>,
    warnings: &mut Vec<String>,
) -> Approx {
    fit_or_fallback_as(name, spec, x, y, weights, true, warnings)
}

/// [`fit_or_fallback_weighted`], warning of a curve through every point (as many parameters
/// as points) when `through_every_point` says to.
fn fit_or_fallback_as(
    name: &str,
    spec: &ApproxSpec,
    x: &[f64],
    y: &[f64],
    weights: Option<&[f64]>,
    through_every_point: bool,
    warnings: &mut Vec<String>,
) -> Approx {
    if let Ok(a) = approx::fit_weighted(spec, x, y, weights) {
        let n = a.stats().n;
        if through_every_point && n == spec.params() && n > 1 {
            warnings.push(format!(
                "{name}: {} with {n} parameters through {n} points: the curve passes through \
                 every point and averages none of their noise",
                spec.kind
            ));
        }
        return a;
    }
    let wt = |k: usize| weights.map_or(1.0, |w| w.get(k).copied().unwrap_or(0.0));
    let (xs, ys): (Vec<f64>, Vec<f64>) = (0..x.len().min(y.len()))
        .filter(|&k| x[k].is_finite() && y[k].is_finite() && wt(k) > 0.0)
        .map(|k| (x[k], y[k]))
        .unzip();
    let got = xs.len();
    if got == 0 {
        warnings.push(format!(
            "{name}: no usable points, the term is left out (zero)"
        ));
        return Approx::zero(spec.kind);
    }
    let mut simpler = Vec::new();
    if spec.kind.has_knots() {
        // Fewer knots than placed by hand cannot stand where they were placed: spread evenly.
        let knots = got.min(spec.knots);
        simpler.push(ApproxSpec {
            knots,
            at: spec.at.clone().filter(|_| knots == spec.knots),
            values: None,
            ..spec.clone()
        });
    }
    simpler.push(ApproxSpec {
        kind: ApproxKind::Linear,
        at: None,
        values: None,
        ..spec.clone()
    });
    for fallback in simpler {
        if let Ok(a) = approx::fit(&fallback, &xs, &ys) {
            let same = fallback.kind == spec.kind && fallback.params() == spec.params();
            warnings.push(if same {
                // Not fewer points: the weights made the fit singular.
                format!(
                    "{name}: the weighted fit of {} could not be solved; fitted with every one \
                     of its {got} points weighed alike",
                    spec.kind
                )
            } else if got < spec.params() {
                format!(
                    "{name}: {} with {} parameters asked for through {got} usable points, more \
                     unknowns than points: fitted as {} with {} parameters instead",
                    spec.kind,
                    spec.params(),
                    fallback.kind,
                    fallback.params()
                )
            } else {
                format!(
                    "{name}: {} with {} parameters could not be fitted to its {got} usable \
                     points: fitted as {} with {} parameters instead",
                    spec.kind,
                    spec.params(),
                    fallback.kind,
                    fallback.params()
                )
            });
            if through_every_point && fallback.params() == got && got > 1 {
                warnings.push(format!(
                    "{name}: {} with {got} parameters through {got} points: the curve passes \
                     through every point and averages none of their noise",
                    fallback.kind
                ));
            }
            return a;
        }
    }
    let a = constant(spec, &xs, &ys);
    warnings.push(format!(
        "{name}: {got} usable point(s), held constant at {:.6}",
        a.eval(xs[0])
    ));
    a
}

/// The mean of the finite `ys` over the range of their `xs`, held constant, as `spec`'s kind
/// (zero when no point is finite).
fn constant(spec: &ApproxSpec, xs: &[f64], ys: &[f64]) -> Approx {
    let (xs, ys): (Vec<f64>, Vec<f64>) = xs
        .iter()
        .zip(ys)
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .map(|(x, y)| (*x, *y))
        .unzip();
    if xs.is_empty() {
        return Approx::zero(spec.kind);
    }
    let got = xs.len();
    let mean = ys.iter().sum::<f64>() / got as f64;
    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let stats = approx::FitStats {
        n: got,
        rmse: 0.0,
        r2: 0.0,
    };
    // Its statistics are those of the mean on its points, as any fit's are: the residuals'
    // rms is their spread (not 0, which a file would state as a curve through every point).
    Approx::new(
        spec.kind,
        approx::Curve::Polynomial { coeffs: vec![mean] },
        lo,
        hi,
        false,
        stats,
    )
    .map(|a| {
        let stats = approx::stats_on(&a, &xs, &ys, None);
        a.with_stats(stats)
    })
    .unwrap_or_else(|_| Approx::zero(spec.kind))
}

/// Default dead-band: a fifth of the 95th percentile of |v| over the samples that count.
fn auto_deadband(v: &[f64], usable: impl Fn(usize) -> bool) -> f64 {
    let stride = (v.len() / 200_000).max(1);
    // The magnitudes as their bits: a finite `abs` is a non-negative number, whose bits order
    // as the numbers do, and integers select faster than floats compared by `total_cmp`.
    let mut a: Vec<u64> = (0..v.len())
        .step_by(stride)
        .filter(|&i| usable(i) && v[i].is_finite())
        .map(|i| v[i].abs().to_bits())
        .collect();
    if a.is_empty() {
        return 0.0;
    }
    let k = ((a.len() as f64 * 0.95) as usize).min(a.len() - 1);
    let (_, p95, _) = a.select_nth_unstable(k);
    f64::from_bits(*p95) / 5.0
}

/// Whether sample `i` lies in one of `ready` (ordered, disjoint ranges).
fn is_ready(ready: &[std::ops::Range<usize>], i: usize) -> bool {
    let k = ready.partition_point(|r| r.end <= i);
    ready.get(k).is_some_and(|r| r.contains(&i))
}

/// Resolves the dead-bands of the recipe on this log.
pub fn deadbands(prepared: &Prepared, mask: &[bool], recipe: &Recipe) -> (f64, f64) {
    let d = &prepared.deriv;
    let usable = |i: usize| !mask[i] && is_ready(&d.ready, i);
    // The two are independent, and each a pass and a selection over a fifth of the log:
    // made side by side (the first axis's plateau stage, which the others wait for, holds them).
    rayon::join(
        || {
            recipe
                .deadband_tdot
                .unwrap_or_else(|| auto_deadband(&d.tdot, usable))
        },
        || {
            recipe
                .deadband_tddot
                .unwrap_or_else(|| auto_deadband(&d.tddot, usable))
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fallback_says_what_it_fitted_instead_and_why() {
        // Weights that overflowed (Ṫ² of a wild temperature cell) leave the weighted fit one
        // point; the same line is fitted to every point weighed alike, and said so (this used
        // to read "fitted as linear with 2 parameters instead of linear with 2").
        let (x, y) = ([0.0, 1.0, 2.0, 3.0], [1.0, 3.0, 5.0, 7.0]);
        let weights = [f64::INFINITY, f64::INFINITY, f64::INFINITY, 1.0];
        let spec = ApproxSpec::of(ApproxKind::Linear);
        let mut warnings = Vec::new();
        let a = fit_or_fallback_weighted("K1+", &spec, &x, &y, Some(&weights), &mut warnings);
        assert_eq!(a.kind(), ApproxKind::Linear);
        assert_eq!(
            warnings,
            [
                "K1+: the weighted fit of linear could not be solved; fitted with every one of \
              its 4 points weighed alike"
            ]
        );
        // Too few points for the curve asked for: the count is named.
        let mut warnings = Vec::new();
        let spline = ApproxSpec {
            kind: ApproxKind::Spline,
            knots: 10,
            extrapolate: false,
            ..ApproxSpec::default()
        };
        fit_or_fallback("K0", &spline, &x, &y, &mut warnings);
        assert_eq!(
            warnings,
            [
                "K0: spline with 10 parameters asked for through 4 usable points, more \
                 unknowns than points: fitted as spline with 4 parameters instead",
                "K0: spline with 4 parameters through 4 points: the curve passes through \
                 every point and averages none of their noise"
            ]
        );
    }
}
