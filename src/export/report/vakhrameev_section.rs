//! What a Vakhrameev calibration's part of a report page holds: its figures of merit, its
//! recipe, its plateaus and its coefficients. Apart from the page because the page holds it
//! once for a single-axis calibration and once per Vakhrameev axis of a unit.

use super::ReportSummary;
use super::html::{Depth, escape, fmt_num, merit_section, row};
use crate::models::approx::{Approx, Curve};
use crate::models::recipe::PlateauChoice;
use crate::models::vakhrameev::Calibration;
use std::fmt::Write as _;

/// The model, as its introduction on the page writes it.
pub(super) const FORMULA: &str = "Ω<sub>pred</sub> = K0(T) + K1±(Ṫ)·Ṫ + K2±(T̈)·T̈";

fn curve_text(a: &Approx) -> String {
    let list = |v: &[f64]| v.iter().map(|&x| fmt_num(x)).collect::<Vec<_>>().join(", ");
    match a.curve() {
        Curve::Polynomial { coeffs } => {
            format!("coefficients (lowest power first): {}", list(coeffs))
        }
        Curve::Pwl { knots_x, knots_y } | Curve::CatmullRom { knots_x, knots_y } => {
            format!("knots x: {}; values: {}", list(knots_x), list(knots_y))
        }
    }
}

/// What a Vakhrameev calibration's page holds after its identity: the figures of merit, the
/// recipe, the plateaus and the coefficients, its sections at depth `d`.
pub(super) fn body(o: &mut String, cal: &Calibration, s: &ReportSummary, d: Depth) {
    let h = d.section;
    merit_section(o, s, d);

    // Recipe.
    let r = &cal.recipe;
    let res = &cal.resolved;
    let _ = write!(o, "<{h}>Recipe</{h}>\n<table>\n");
    row(
        o,
        "Ω filter",
        &format!(
            "{} s centred moving average ({} samples)",
            r.filter_s, res.filter_samples
        ),
    );
    row(
        o,
        "T smoothing",
        &format!(
            "{} s causal moving average ({} samples)",
            r.temp_smoothing_s, res.smooth_samples
        ),
    );
    row(
        o,
        "derivative step H",
        &format!(
            "{} s ({} samples at {} s)",
            r.step_h_s, res.step_samples, res.dt_s
        ),
    );
    row(
        o,
        "dead-band |Ṫ|",
        &format!(
            "{:.4e} °C/s ({})",
            res.deadband_tdot,
            if r.deadband_tdot.is_some() {
                "set"
            } else {
                "automatic"
            }
        ),
    );
    row(
        o,
        "dead-band |T̈|",
        &format!(
            "{:.4e} °C/s² ({})",
            res.deadband_tddot,
            if r.deadband_tddot.is_some() {
                "set"
            } else {
                "automatic"
            }
        ),
    );
    row(
        o,
        "plateaus",
        match &r.plateaus {
            PlateauChoice::Auto(_) => "detected automatically",
            PlateauChoice::Manual { .. } => "given by hand",
        },
    );
    row(o, "weighting", &format!("{:?}", r.weighting).to_lowercase());
    row(o, "refinement passes", &r.refinements.to_string());
    o.push_str("</table>\n");
    let recipe_json = serde_json::to_string_pretty(r).unwrap_or_default();
    let _ = writeln!(
        o,
        "<p>The recipe as stored in the calibration file:</p>\n<pre>{}</pre>",
        escape(&recipe_json)
    );

    // Plateaus.
    let _ = write!(
        o,
        "<{h}>Plateaus</{h}>\n<table>\n<tr><th>#</th><th>start, s</th><th>end, s</th>\
         <th>T, °C</th><th>T spread, °C</th><th>Ω mean, °/h</th><th>Ω std, °/h</th><th>samples</th></tr>\n",
    );
    for (k, p) in cal.plateaus.iter().enumerate() {
        let _ = writeln!(
            o,
            "<tr><td>{}</td><td class=\"num\">{:.0}</td><td class=\"num\">{:.0}</td>\
             <td class=\"num\">{:.3}</td><td class=\"num\">{:.3}</td><td class=\"num\">{:.4}</td>\
             <td class=\"num\">{:.4}</td><td class=\"num\">{}</td></tr>",
            k + 1,
            p.range.start_s,
            p.range.end_s,
            p.temp_c,
            p.temp_spread_c,
            p.omega_dph,
            p.omega_std_dph,
            p.samples
        );
    }
    o.push_str("</table>\n");

    // Coefficients.
    let u = &cal.units;
    let _ = write!(
        o,
        "<{h}>Coefficients</{h}>\n<table>\n<tr><th>coefficient</th><th>kind</th>\
         <th>fitted range</th><th>beyond it</th><th>n</th><th>RMSE</th><th>R²</th><th>curve</th></tr>\n",
    );
    for (name, a) in cal.approximations() {
        let (xu, yu) = match &name[..2] {
            "K0" => (&u.temperature, &u.rate),
            "K1" => (&u.tdot, &u.k1),
            _ => (&u.tddot, &u.k2),
        };
        let st = a.stats();
        let _ = writeln!(
            o,
            "<tr><td>{} [{}]</td><td>{}</td><td class=\"num\">{} … {} {}</td><td>{}</td>\
             <td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{:.4}</td><td><small>{}</small></td></tr>",
            escape(name),
            escape(yu),
            a.kind(),
            fmt_num(a.x_min()),
            fmt_num(a.x_max()),
            escape(xu),
            if a.extrapolates() {
                "extrapolated"
            } else {
                "edge value held"
            },
            st.n,
            fmt_num(st.rmse),
            st.r2,
            escape(&curve_text(a))
        );
    }
    o.push_str("</table>\n");
}
