//! What a regression model's part of a report page holds: its terms with coefficients ±
//! standard errors, λ, τd(T), lag, input ranges, fit statistics and searches, in place of a
//! Vakhrameev calibration's recipe, plateaus and K curves. Apart from the page because the page
//! holds it once for a single-axis model and once per regression axis of a unit.

use super::ReportSummary;
use super::html::{Depth, fmt_num, heading, merit_section, row};
use crate::models::regression::{FitSamples, RegressionCalibration, TRefSpec};
use maud::{Markup, html};

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
pub(super) fn formula_html(cal: &RegressionCalibration) -> Markup {
    html! {
        "Ω" sub { "pred" } " = Σ coefficient · term over the terms " code { (formula(cal)) }
    }
}

/// What a regression model's page holds after its identity: the figures of merit, the model,
/// its coefficients, input ranges and searches, its sections at depth `d`.
pub(super) fn body(cal: &RegressionCalibration, s: &ReportSummary, d: Depth) -> Markup {
    let spec_json = serde_json::to_string_pretty(&cal.model.spec).unwrap_or_default();
    html! {
        (merit_section(s, d, &cal.source.runs))
        (heading(d.section, html! { "Model" }))
        table { "\n" (model_rows(cal, s.unit)) }
        "\n"
        (heading(d.section, html! { "Coefficients" }))
        p {
            "Least-squares coefficients, " (s.unit) " per unit of their term, ± standard error \
             (white-noise assumption: correlated noise makes the real uncertainty larger)."
        }
        "\n"
        table class="coefficients" {
            "\n"
            tr { th { "term" } th { "coefficient" } th { "± standard error" } th { "what it is" } }
            "\n"
            (coefficient_rows(cal))
        }
        "\n"
        (heading(d.section, html! { "Input ranges" }))
        p {
            "The ranges the inputs were fitted on. Outside them T, ΔT and the extra channels \
             are held at the edge value (the curves of them are not extrapolated); Ṫ and T̈ are \
             only flagged (terms are linear in them)."
        }
        "\n"
        table {
            "\n"
            tr { th { "input" } th { "min" } th { "max" } th { "beyond it" } }
            "\n"
            (range_rows(cal))
        }
        "\n"
        @if !cal.model.searches.is_empty() {
            (heading(d.section, html! { "Searches" }))
            table {
                "\n"
                tr {
                    th { "parameter" } th { "values tried" } th { "chosen" }
                    th { "RMS residual there, " (s.unit) } th { "note" }
                }
                "\n"
                (search_rows(cal))
            }
            "\n"
        }
        p { "The model's specification as stored in the calibration file:" } "\n"
        pre { (spec_json) } "\n"
    }
}

/// The rows of the model's table: its terms, what it was fitted on, its statistics, λ, τd(T),
/// the lag, the knots and the T settings.
fn model_rows(cal: &RegressionCalibration, unit: &str) -> Markup {
    let m = &cal.model;
    let spec = &m.spec;
    let delay = if m.delay.points.is_empty() {
        "none".to_string()
    } else {
        m.delay
            .points
            .iter()
            .map(|p| format!("{} s at {} °C", fmt_num(p[1]), fmt_num(p[0])))
            .collect::<Vec<_>>()
            .join("; ")
            + " (piecewise-linear in T, held at the end values)"
    };
    let lag = match m.lag_s {
        Some(l) if m.lag_per_c != 0.0 => format!(
            "first-order, τ = {} s at 20 °C, τ/(1 + {}·(T − 20 °C)) elsewhere",
            fmt_num(l),
            fmt_num(m.lag_per_c)
        ),
        Some(l) => format!("first-order, τ = {} s", fmt_num(l)),
        None => "none (T as measured)".into(),
    };
    html! {
        (row("terms", &formula(cal)))
        (row(
            "fitted on",
            match spec.samples {
                FitSamples::All => "every sample with a full rate history",
                FitSamples::Plateaus => "the temperature plateaus only",
                FitSamples::Staged => {
                    "static terms on the plateaus, then rate terms on every sample"
                }
            },
        ))
        (row(
            "fit statistics",
            &format!(
                "{} samples, RMS residual {} {unit}, R² {:.4}",
                m.stats.n,
                fmt_num(m.stats.rmse),
                m.stats.r2
            ),
        ))
        (row(
            "self-heating constant λ",
            &match m.lambda_s {
                Some(l) => format!("{} s", fmt_num(l)),
                None => "— (no selfheat term)".into(),
            },
        ))
        (row("delay τd(T)", &delay))
        (row("lag of T", &lag))
        @if !m.t_knots.is_empty() {
            (row(
                "pwlT knots",
                &(m.t_knots
                    .iter()
                    .map(|&k| fmt_num(k))
                    .collect::<Vec<_>>()
                    .join(", ")
                    + " °C"),
            ))
        }
        @if let Some(t_ref) = m.t_ref_c {
            (row(
                "reference temperature Tref",
                &format!(
                    "{} °C (the terms in T − Tref are powers of T less it; {})",
                    fmt_num(t_ref),
                    match spec.t_ref {
                        TRefSpec::Fixed { .. } => "fixed by the model",
                        TRefSpec::MidRange => "the middle of the fitted range",
                    }
                ),
            ))
        }
        @if let Some(t2) = &m.temp2 {
            (row("second temperature sensor (dT = T − T2)", t2))
        }
        (row(
            "T smoothing, derivative step H",
            &format!(
                "{} s causal moving average, H = {} s, at {} s sampling",
                spec.smoothing_s, spec.step_h_s, m.dt_s
            ),
        ))
    }
}

/// A row per coefficient: its column's name, value ± standard error, and what its term is.
fn coefficient_rows(cal: &RegressionCalibration) -> Markup {
    let m = &cal.model;
    let mut rows = Vec::new();
    let mut col = 0;
    for t in &m.spec.terms {
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
            rows.push((name, *c, *se, what));
            col += 1;
        }
    }
    html! {
        @for (name, c, se, what) in &rows {
            tr {
                td { code { (name) } }
                td class="num" { (fmt_coef(*c)) }
                td class="num" { "± " (fmt_se(*se)) }
                td { (what) }
            }
            "\n"
        }
    }
}

/// A row per input with a fitted range: T, Ṫ, T̈, ΔT and each extra channel.
fn range_rows(cal: &RegressionCalibration) -> Markup {
    let m = &cal.model;
    let r = &m.ranges;
    let channels = m.channel_names();
    let fixed = [
        ("T, °C", r.temp, true),
        ("Ṫ, °C/s", r.tdot, false),
        ("T̈, °C/s²", r.tddot, false),
        ("ΔT = T − T2, °C", r.dt, true),
    ];
    let rows = fixed.into_iter().chain(
        channels
            .iter()
            .zip(&r.channels)
            .map(|(name, c)| (name.as_str(), Some(*c), true)),
    );
    html! {
        @for (name, range, hold) in rows {
            @if let Some([lo, hi]) = range {
                tr {
                    td { (name) }
                    td class="num" { (fmt_num(lo)) }
                    td class="num" { (fmt_num(hi)) }
                    td { (if hold { "edge value held" } else { "flagged" }) }
                }
                "\n"
            }
        }
    }
}

/// A row per search: the parameter, the values tried, the one chosen and its residual.
fn search_rows(cal: &RegressionCalibration) -> Markup {
    html! {
        @for c in &cal.model.searches {
            tr {
                td { (c.parameter) }
                td class="num" {
                    (c.x.len()) " ("
                    (c.x.first().map(|&v| fmt_num(v)).unwrap_or_default()) " … "
                    (c.x.last().map(|&v| fmt_num(v)).unwrap_or_default()) " s)"
                }
                td class="num" { (fmt_num(c.best)) " s" }
                td class="num" {
                    (c.x.iter()
                        .position(|&x| x == c.best)
                        .and_then(|k| c.rmse.get(k))
                        .map(|&v| fmt_num(v))
                        .unwrap_or_default())
                }
                td { (if c.at_edge { "at the edge of the searched range" } else { "" }) }
            }
            "\n"
        }
    }
}
