//! What `driftlab calibrate` prints about a fit, for each kind of model: one axis as it
//! always was, or each axis of a unit and a summary of them.

use super::common::{self, CliError, fixed, num};
use driftlab::log::AxisKind;
use driftlab::models::accel::{self, Gravity};
use driftlab::models::regression::RegressionCalibration;
use driftlab::models::vakhrameev::Calibration;
use driftlab::models::{CalibratedAxis, DriftModel, UnitCalibration};
use std::path::Path;

/// What a Vakhrameev fit found: sampling, windows, plateaus and the five approximations.
pub fn vakhrameev_summary(cal: &Calibration, warnings: &[String]) -> Result<(), CliError> {
    let r = &cal.resolved;
    // A campaign lasted its runs' durations; the hour put between runs on the joined time
    // axis is no part of any.
    let (hours, runs) = match cal.source.runs.as_slice() {
        [] => (cal.source.duration_s / 3600.0, String::new()),
        runs => (
            runs.iter().map(|r| r.duration_s).sum::<f64>() / 3600.0,
            format!(" ({} runs)", runs.len()),
        ),
    };
    out!(
        "Log {}{runs}: {} samples, {} h, step {} s",
        cal.source.name,
        cal.source.samples,
        fixed(hours, 2),
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
            driftlab::number::fixed_stamp(p.range.start_s),
            driftlab::number::fixed_stamp(p.range.end_s),
            fixed(p.temp_c, 3),
            fixed(p.omega_dph, 4),
            p.omega_std_dph.map_or("n/a".to_string(), |s| fixed(s, 4)),
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
        // Through no point or one, a curve has no residual to measure and no spread to
        // explain: its rmse and R² are n/a, not the zeros the file holds for them.
        let (rmse, r2) = if s.n < 2 {
            ("n/a".to_string(), "n/a".to_string())
        } else {
            (format!("{:.4e}", s.rmse), format!("{:.3}", s.r2))
        };
        out!(
            "  {:<11} {:<10} {:>12.4e} {:>12.4e} {:>8} {:>11} {:>7}",
            name,
            ap.kind().to_string(),
            ap.x_min(),
            ap.x_max(),
            s.n,
            rmse,
            r2
        )?;
    }
    // Knots placed or set by hand, in the engine's words (none: nothing more is printed).
    for c in driftlab::models::vakhrameev::knots::Coefficient::ALL {
        let spec = c.spec(&cal.recipe);
        if spec.hand_knots() {
            out!("  {} {}", c.label(), c.knots_text(spec))?;
        }
    }
    for w in warnings {
        note!("warning: {w}");
    }
    Ok(())
}

/// What a regression fit found: terms with coefficients and standard errors, λ, lag, delays,
/// and searches that ended at the edge of their range; its residual in the unit of the axis's
/// kind.
fn regression_summary(r: &RegressionCalibration, kind: AxisKind) -> Result<(), CliError> {
    let m = &r.model;
    out!(
        "Model {} on {}: {} samples, RMS residual {:.4} {}, R² {:.3}",
        m.spec.name,
        r.source.name,
        m.stats.n,
        m.stats.rmse,
        kind.unit_ascii(),
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

/// What a model's fit found, and the warnings about it.
fn model_summary(model: &DriftModel, warnings: &[String], kind: AxisKind) -> Result<(), CliError> {
    match model {
        DriftModel::Vakhrameev(cal) => vakhrameev_summary(cal, warnings),
        DriftModel::Regression(r) => {
            regression_summary(r, kind)?;
            for w in warnings {
                note!("warning: {w}");
            }
            Ok(())
        }
    }
}

/// A calibration made and saved: what is printed about it.
pub struct Printed<'a> {
    /// The calibration file written.
    pub out: &'a Path,
    /// Every axis fitted, with its in-sample figures and warnings.
    pub fitted: &'a [CalibratedAxis],
    /// The calibration as saved (stamped with its log).
    pub unit: &'a UnitCalibration,
    /// The command's warnings (settings not used), beside each fit's own.
    pub warnings: &'a [String],
    /// The length of the consecutive mean/RMS windows, s.
    pub window_s: f64,
    /// Plateaus of a campaign's runs share a temperature within this, °C.
    pub tolerance_c: f64,
}

impl Printed<'_> {
    /// A single-axis calibration as JSON: the file, the in-sample figures, the warnings and
    /// the model.
    pub fn single_json(&self) -> Result<(), CliError> {
        let (f, model) = (&self.fitted[0], &self.unit.axes[0].model);
        let mut warnings = self.warnings.to_vec();
        warnings.extend(f.calibrated.warnings.iter().cloned());
        let mut out = serde_json::json!({
            "calibration": self.out,
            "in_sample": f.calibrated.in_sample,
            "warnings": warnings,
        });
        if let (Some(out), serde_json::Value::Object(body)) =
            (out.as_object_mut(), model_json(model))
        {
            out.extend(body);
        }
        if let (Some(out), Some(c)) = (
            out.as_object_mut(),
            super::campaign_print::json(model, self.tolerance_c),
        ) {
            out.insert("campaign".into(), c);
        }
        common::print_json(&out)
    }

    /// A single-axis calibration as text: the fit, the in-sample figures, the file.
    pub fn single_text(&self) -> Result<(), CliError> {
        let (f, model) = (&self.fitted[0], &self.unit.axes[0].model);
        let mut warnings = self.warnings.to_vec();
        warnings.extend(f.calibrated.warnings.iter().cloned());
        model_summary(model, &warnings, AxisKind::Gyro)?;
        super::campaign_print::text(model, self.tolerance_c)?;
        out!()?;
        out!(
            "In-sample (calibrated and evaluated on {}):",
            model.source().name
        )?;
        common::print_evaluation(&f.calibrated.in_sample, self.window_s)?;
        out!()?;
        out!("Calibration written to {}", self.out.display())?;
        Ok(())
    }

    /// A unit as JSON: the file, the warnings, and each axis with its model and figures.
    pub fn unit_json(&self) -> Result<(), CliError> {
        let axes: Vec<serde_json::Value> = self
            .fitted
            .iter()
            .zip(&self.unit.axes)
            .map(|(f, ax)| {
                let mut v = serde_json::json!({
                    "name": f.name,
                    "rate_column": f.rate_column,
                    "model_name": ax.model.name(),
                    "in_sample": f.calibrated.in_sample,
                    "warnings": f.calibrated.warnings,
                });
                // An accelerometer says so: its figures are in m/s², about the mean it keeps.
                if let (Some(o), AxisKind::Accel) = (v.as_object_mut(), ax.kind) {
                    o.insert("kind".into(), serde_json::json!(ax.kind));
                    o.insert("unit".into(), serde_json::json!(ax.kind.unit_ascii()));
                    o.insert("kept_mean_m_s2".into(), serde_json::json!(ax.kept_mean));
                }
                if let (Some(o), serde_json::Value::Object(body)) =
                    (v.as_object_mut(), model_json(&ax.model))
                {
                    o.extend(body);
                }
                if let (Some(o), Some(c)) = (
                    v.as_object_mut(),
                    super::campaign_print::json(&ax.model, self.tolerance_c),
                ) {
                    o.insert("campaign".into(), c);
                }
                // An accelerometer's readings named in m/s² (`rmse_m_s2`), not °/h.
                ax.kind.name_fields_in_unit(&mut v);
                v
            })
            .collect();
        let mut out = serde_json::json!({
            "calibration": self.out,
            "warnings": self.warnings,
            "axes": axes,
        });
        if let (Some(o), Some(g)) = (out.as_object_mut(), accel::gravity(self.unit)) {
            o.insert("gravity".into(), gravity_json(&g));
        }
        common::print_json(&out)
    }

    /// A unit as text: each axis's fit and in-sample figures, a summary, the file.
    pub fn unit_text(&self) -> Result<(), CliError> {
        for w in self.warnings {
            note!("warning: {w}");
        }
        let name = self
            .unit
            .axes
            .first()
            .map(|a| a.model.source().name.clone())
            .unwrap_or_default();
        for (f, ax) in self.fitted.iter().zip(&self.unit.axes) {
            out!(
                "=== Axis {}{} — model {} ===",
                f.name,
                if f.rate_column.is_empty() || f.rate_column == f.name {
                    String::new()
                } else {
                    format!(" (column {})", f.rate_column)
                },
                ax.model.name()
            )?;
            let axis_warnings: Vec<String> = f
                .calibrated
                .warnings
                .iter()
                .map(|w| format!("axis {}: {w}", f.name))
                .collect();
            model_summary(&ax.model, &axis_warnings, ax.kind)?;
            super::campaign_print::text(&ax.model, self.tolerance_c)?;
            out!()?;
            match ax.kept_mean {
                Some(mean) => out!(
                    "In-sample, axis {} (calibrated and evaluated on {name}, about its mean {} \
                     {}, which its correction keeps):",
                    f.name,
                    num(mean),
                    ax.kind.unit_ascii()
                )?,
                None => out!(
                    "In-sample, axis {} (calibrated and evaluated on {name}):",
                    f.name
                )?,
            }
            common::print_evaluation_in(&f.calibrated.in_sample, self.window_s, ax.kind)?;
            out!()?;
        }
        self.unit_summary(&name)?;
        if let Some(g) = accel::gravity(self.unit) {
            out!()?;
            out!("{}", gravity_text(&g))?;
        }
        out!()?;
        out!(
            "Calibration of {} ({}) written to {}",
            match self.unit.axes.len() {
                1 => "1 axis".to_string(),
                n => format!("{n} axes"),
            },
            self.unit.axis_names().join(", "),
            self.out.display()
        )?;
        Ok(())
    }

    /// One line per axis: the in-sample figures, raw against corrected.
    fn unit_summary(&self, log_name: &str) -> Result<(), CliError> {
        let w = driftlab::judge::options::window_label(self.window_s);
        let units = if self.unit.has_accelerometers() {
            "deg/h, m/s^2 for the accelerometer axes"
        } else {
            "deg/h"
        };
        out!("Unit summary, in-sample on {log_name} ({units}; raw -> corrected, raw/cor):")?;
        out!(
            "  {:<8} {:<12} {:>30} {:>30} {:>30}",
            "axis",
            "model",
            "peak-to-peak",
            "std",
            format!("max |{w} mean|")
        )?;
        for (f, ax) in self.fitted.iter().zip(&self.unit.axes) {
            let c = &f.calibrated.in_sample.comparison;
            let [p2p, std, win_mean] = common::comparison_cells_in(c, ax.kind);
            out!(
                "  {:<8} {:<12} {:>30} {:>30} {:>30}",
                f.name,
                ax.model.name(),
                p2p,
                std,
                win_mean
            )?;
        }
        Ok(())
    }
}

/// Which axis carries gravity and how its reading changes with T, in one line.
pub fn gravity_text(g: &Gravity) -> String {
    let change = match g.scale_change_per_c {
        Some(c) => format!(
            "; its reading changes by {} ppm/degC of its mean over {} .. {} degC: its scale \
             factor's change with T, its bias's change included (one orientation cannot part \
             them)",
            num(c * 1e6),
            num(g.range_c.0),
            num(g.range_c.1)
        ),
        None => String::new(),
    };
    format!(
        "Gravity: axis {} carries it (mean {} m/s^2 on the calibration log, kept by its \
         correction){change}",
        g.axis,
        num(g.mean_m_s2)
    )
}

/// [`gravity_text`]'s numbers for `--json`.
pub fn gravity_json(g: &Gravity) -> serde_json::Value {
    serde_json::json!({
        "axis": g.axis,
        "mean_m_s2": g.mean_m_s2,
        "range_c": [g.range_c.0, g.range_c.1],
        "scale_change_ppm_per_c": g.scale_change_per_c.map(|c| c * 1e6),
    })
}
