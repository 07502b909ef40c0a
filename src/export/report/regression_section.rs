//! What a regression model's part of a report page holds: its terms with coefficients ±
//! standard errors, λ, τd(T), lag, input ranges, fit statistics and searches, in place of a
//! Vakhrameev calibration's recipe, plateaus and K curves. Apart from the page because the page
//! holds it once for a single-axis model and once per regression axis of a unit.

use super::ReportSummary;
use super::html::{Depth, escape, fmt_num, merit_section, row};
use crate::models::regression::{FitSamples, RegressionCalibration};
use std::fmt::Write as _;

/// A coefficient of a regression model as the page prints it: seven significant digits in
/// mantissa-exponent form (coefficients of T³ and of T̈ differ by many orders of magnitude).
pub fn fmt_coef(v: f64) -> String {
    format!("{v:.6e}")
}

/// A standard error as the page prints it: three significant digits.
pub fn fmt_se(v: f64) -> String {
    format!("{v:.2e}")
}

/// The description of a model named `name`: the preset's sentence, or "custom model".
pub(super) fn describe(name: &str) -> String {
    match crate::models::presets::Preset::from_name(name) {
        Ok(p) => p.describe().to_string(),
        Err(_) => "custom model, composed term by term".into(),
    }
}

/// The terms written as a sum.
pub(super) fn formula(cal: &RegressionCalibration) -> String {
    cal.model
        .spec
        .terms
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(" + ")
}

/// The model as its introduction on the page writes it: the sum over its terms.
pub(super) fn formula_html(cal: &RegressionCalibration) -> String {
    format!(
        "Ω<sub>pred</sub> = Σ coefficient · term over the terms <code>{}</code>",
        escape(&formula(cal))
    )
}

/// What a regression model's page holds after its identity: the figures of merit, the model,
/// its coefficients, input ranges and searches, its sections at depth `d`.
pub(super) fn body(o: &mut String, cal: &RegressionCalibration, s: &ReportSummary, d: Depth) {
    let h = d.section;
    let m = &cal.model;
    let spec = &m.spec;
    let formula = formula(cal);
    merit_section(o, s, d);

    // The model.
    let _ = write!(o, "<{h}>Model</{h}>\n<table>\n");
    row(o, "terms", &formula);
    row(
        o,
        "fitted on",
        match spec.samples {
            FitSamples::All => "every sample with a full rate history",
            FitSamples::Plateaus => "the temperature plateaus only",
            FitSamples::Staged => "static terms on the plateaus, then rate terms on every sample",
        },
    );
    row(
        o,
        "fit statistics",
        &format!(
            "{} samples, RMS residual {} °/h, R² {:.4}",
            m.stats.n,
            fmt_num(m.stats.rmse),
            m.stats.r2
        ),
    );
    row(
        o,
        "self-heating constant λ",
        &match m.lambda_s {
            Some(l) => format!("{} s", fmt_num(l)),
            None => "— (no selfheat term)".into(),
        },
    );
    row(
        o,
        "delay τd(T)",
        &if m.delay.points.is_empty() {
            "none".to_string()
        } else {
            m.delay
                .points
                .iter()
                .map(|p| format!("{} s at {} °C", fmt_num(p[1]), fmt_num(p[0])))
                .collect::<Vec<_>>()
                .join("; ")
                + " (piecewise-linear in T, held at the end values)"
        },
    );
    row(
        o,
        "lag of T",
        &match m.lag_s {
            Some(l) if m.lag_per_c != 0.0 => format!(
                "first-order, τ = {} s at 20 °C, τ/(1 + {}·(T − 20 °C)) elsewhere",
                fmt_num(l),
                fmt_num(m.lag_per_c)
            ),
            Some(l) => format!("first-order, τ = {} s", fmt_num(l)),
            None => "none (T as measured)".into(),
        },
    );
    if !m.t_knots.is_empty() {
        row(
            o,
            "pwlT knots",
            &(m.t_knots
                .iter()
                .map(|&k| fmt_num(k))
                .collect::<Vec<_>>()
                .join(", ")
                + " °C"),
        );
    }
    if let Some(t2) = &m.temp2 {
        row(o, "second temperature sensor (dT = T − T2)", t2);
    }
    row(
        o,
        "T smoothing, derivative step H",
        &format!(
            "{} s causal moving average, H = {} s, at {} s sampling",
            spec.smoothing_s, spec.step_h_s, m.dt_s
        ),
    );
    o.push_str("</table>\n");

    // Coefficients.
    let _ = write!(
        o,
        "<{h}>Coefficients</{h}>\n<p>Least-squares coefficients, °/h per unit of their term, \
         ± standard error (white-noise assumption: correlated noise makes the real uncertainty \
         larger).</p>\n<table class=\"coefficients\">\n<tr><th>term</th><th>coefficient</th>\
         <th>± standard error</th><th>what it is</th></tr>\n",
    );
    let mut col = 0;
    for t in &spec.terms {
        for k in 0..t.width() {
            let (Some(name), Some(c), Some(se)) = (
                m.names.get(col),
                m.coefficients.get(col),
                m.std_errors.get(col),
            ) else {
                break;
            };
            let what = match t {
                crate::models::regression::Term::PwlT { .. } => format!(
                    "value at knot {} ({} °C)",
                    k,
                    m.t_knots.get(k).map(|&x| fmt_num(x)).unwrap_or_default()
                ),
                _ => t.describe(),
            };
            let _ = writeln!(
                o,
                "<tr><td><code>{}</code></td><td class=\"num\">{}</td><td class=\"num\">± {}</td><td>{}</td></tr>",
                escape(name),
                fmt_coef(*c),
                fmt_se(*se),
                escape(&what)
            );
            col += 1;
        }
    }
    o.push_str("</table>\n");

    // Input ranges.
    let _ = write!(
        o,
        "<{h}>Input ranges</{h}>\n<p>The ranges the inputs were fitted on. Outside them T, ΔT and \
         the extra channels are held at the edge value (the curves of them are not \
         extrapolated); Ṫ and T̈ are only flagged (terms are linear in them).</p>\n<table>\n\
         <tr><th>input</th><th>min</th><th>max</th><th>beyond it</th></tr>\n",
    );
    let r = &m.ranges;
    let mut range_row = |name: &str, range: Option<[f64; 2]>, hold: bool| {
        if let Some([lo, hi]) = range {
            let _ = writeln!(
                o,
                "<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td>{}</td></tr>",
                escape(name),
                fmt_num(lo),
                fmt_num(hi),
                if hold { "edge value held" } else { "flagged" }
            );
        }
    };
    range_row("T, °C", r.temp, true);
    range_row("Ṫ, °C/s", r.tdot, false);
    range_row("T̈, °C/s²", r.tddot, false);
    range_row("ΔT = T − T2, °C", r.dt, true);
    for (name, c) in m.channel_names().iter().zip(&r.channels) {
        range_row(name, Some(*c), true);
    }
    o.push_str("</table>\n");

    // Searches.
    if !m.searches.is_empty() {
        let _ = write!(
            o,
            "<{h}>Searches</{h}>\n<table>\n<tr><th>parameter</th><th>values tried</th>\
             <th>chosen</th><th>RMS residual there, °/h</th><th>note</th></tr>\n",
        );
        for c in &m.searches {
            let at =
                c.x.iter()
                    .position(|&x| x == c.best)
                    .and_then(|k| c.rmse.get(k))
                    .map(|&v| fmt_num(v))
                    .unwrap_or_default();
            let _ = writeln!(
                o,
                "<tr><td>{}</td><td class=\"num\">{} ({} … {} s)</td><td class=\"num\">{} s</td>\
                 <td class=\"num\">{}</td><td>{}</td></tr>",
                escape(&c.parameter),
                c.x.len(),
                c.x.first().map(|&v| fmt_num(v)).unwrap_or_default(),
                c.x.last().map(|&v| fmt_num(v)).unwrap_or_default(),
                fmt_num(c.best),
                at,
                if c.at_edge {
                    "at the edge of the searched range"
                } else {
                    ""
                }
            );
        }
        o.push_str("</table>\n");
    }
    let spec_json = serde_json::to_string_pretty(spec).unwrap_or_default();
    let _ = writeln!(
        o,
        "<p>The model's specification as stored in the calibration file:</p>\n<pre>{}</pre>",
        escape(&spec_json)
    );
}
