//! What `driftlab calibrate` prints about a fit, for each kind of model.

use super::common::{CliError, fixed, num};
use driftlab::models::DriftModel;
use driftlab::models::regression::RegressionCalibration;
use driftlab::models::vakhrameev::Calibration;

/// What a Vakhrameev fit found: sampling, windows, plateaus and the five approximations.
pub fn vakhrameev_summary(cal: &Calibration, warnings: &[String]) -> Result<(), CliError> {
    let r = &cal.resolved;
    out!(
        "Log {}: {} samples, {} h, step {} s",
        cal.source.name,
        cal.source.samples,
        fixed(cal.source.duration_s / 3600.0, 2),
        num(r.dt_s)
    )?;
    out!(
        "Filter {} samples, T smoothing {} samples, H = {} samples; dead-bands |Tdot| {:.3e} degC/s, |Tddot| {:.3e} degC/s^2",
        r.filter_samples,
        r.smooth_samples,
        r.step_samples,
        r.deadband_tdot,
        r.deadband_tddot
    )?;
    out!()?;
    out!("Plateaus (K0 points):")?;
    out!(
        "  {:>10} {:>10} {:>9} {:>11} {:>9} {:>8}",
        "start_s",
        "end_s",
        "T_degC",
        "Omega_dph",
        "std_dph",
        "samples"
    )?;
    for p in &cal.plateaus {
        out!(
            "  {:>10} {:>10} {:>9} {:>11} {:>9} {:>8}",
            fixed(p.range.start_s, 0),
            fixed(p.range.end_s, 0),
            fixed(p.temp_c, 3),
            fixed(p.omega_dph, 4),
            fixed(p.omega_std_dph, 4),
            p.samples
        )?;
    }
    out!()?;
    out!("Approximations:")?;
    out!(
        "  {:<11} {:<10} {:>12} {:>12} {:>8} {:>11} {:>7}",
        "",
        "kind",
        "x_min",
        "x_max",
        "n",
        "rmse",
        "R2"
    )?;
    for (name, ap) in cal.approximations() {
        let s = ap.stats();
        out!(
            "  {:<11} {:<10} {:>12.4e} {:>12.4e} {:>8} {:>11.4e} {:>7.3}",
            name,
            ap.kind().to_string(),
            ap.x_min(),
            ap.x_max(),
            s.n,
            s.rmse,
            s.r2
        )?;
    }
    for w in warnings {
        note!("warning: {w}");
    }
    Ok(())
}

/// What a regression fit found: terms with coefficients and standard errors, λ, lag, delays,
/// and searches that ended at the edge of their range.
pub fn regression_summary(r: &RegressionCalibration) -> Result<(), CliError> {
    let m = &r.model;
    out!(
        "Model {} on {}: {} samples, RMS residual {:.4} deg/h, R² {:.3}",
        m.spec.name,
        r.source.name,
        m.stats.n,
        m.stats.rmse,
        m.stats.r2
    )?;
    out!("  {:<22} {:>14} {:>12}", "term", "coefficient", "std error")?;
    for ((n, c), e) in m.names.iter().zip(&m.coefficients).zip(&m.std_errors) {
        out!("  {n:<22} {c:>14.6e} {e:>12.2e}")?;
    }
    if let Some(l) = m.lambda_s {
        out!("  self-heating λ = {l:.0} s")?;
    }
    if let Some(l) = m.lag_s {
        if m.lag_per_c == 0.0 {
            out!("  lag of T τ = {l:.0} s")?;
        } else {
            out!(
                "  lag of T τ = {l:.0} s at 20 degC, τ20/(1 + {:.4}·(T − 20)) elsewhere",
                m.lag_per_c
            )?;
        }
    }
    for p in &m.delay.points {
        out!("  delay τd = {:.0} s at {:.1} degC", p[1], p[0])?;
    }
    for c in m.searches.iter().filter(|c| c.at_edge) {
        out!(
            "  note: the best {} ({:.0}) is at the end of the searched range",
            c.parameter,
            c.best
        )?;
    }
    Ok(())
}

/// What `--json` gives of a fitted model beside its figures: a Vakhrameev fit's plateaus,
/// approximations and resolved settings, or a regression model.
pub fn model_json(model: &DriftModel) -> serde_json::Value {
    match model {
        DriftModel::Vakhrameev(cal) => serde_json::json!({
            "plateaus": cal.plateaus,
            "approximations": cal.approximations().iter().map(|(n, ap)| serde_json::json!({
                "name": n, "kind": ap.kind(), "x_min": ap.x_min(), "x_max": ap.x_max(), "stats": ap.stats()
            })).collect::<Vec<_>>(),
            "resolved": cal.resolved,
        }),
        DriftModel::Regression(r) => serde_json::json!({ "model": r.model }),
    }
}
