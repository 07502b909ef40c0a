//! What a Vakhrameev calibration's part of a report page holds: its figures of merit, its
//! recipe, its plateaus and its coefficients. Apart from the page because the page holds it
//! once for a single-axis calibration and once per Vakhrameev axis of a unit.

use super::ReportSummary;
use super::html::{Depth, fmt_num, heading, merit_section, row};
use crate::models::approx::{Approx, Curve};
use crate::models::recipe::PlateauChoice;
use crate::models::vakhrameev::Calibration;
use maud::{Markup, html};

/// The model, as its introduction on the page writes it.
pub(super) fn formula() -> Markup {
    html! { "Ω" sub { "pred" } " = K0(T) + K1±(Ṫ)·Ṫ + K2±(T̈)·T̈" }
}

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
pub(super) fn body(cal: &Calibration, s: &ReportSummary, d: Depth) -> Markup {
    let recipe_json = serde_json::to_string_pretty(&cal.recipe).unwrap_or_default();
    html! {
        (merit_section(s, d, &cal.source.runs))
        (heading(d.section, html! { "Recipe" }))
        table { "\n" (recipe_rows(cal)) }
        "\n"
        p { "The recipe as stored in the calibration file:" } "\n"
        pre { (recipe_json) } "\n"
        (heading(d.section, html! { "Plateaus" }))
        table {
            "\n"
            tr {
                th { "#" } th { "start, s" } th { "end, s" } th { "T, °C" } th { "T spread, °C" }
                th { "Ω mean, °/h" } th { "Ω std, °/h" } th { "samples" }
            }
            "\n"
            @for (k, p) in cal.plateaus.iter().enumerate() {
                tr {
                    td { (k + 1) }
                    td class="num" { (format!("{:.0}", p.range.start_s)) }
                    td class="num" { (format!("{:.0}", p.range.end_s)) }
                    td class="num" { (format!("{:.3}", p.temp_c)) }
                    td class="num" { (format!("{:.3}", p.temp_spread_c)) }
                    td class="num" { (format!("{:.4}", p.omega_dph)) }
                    td class="num" { (p.omega_std_dph.map_or("n/a".to_string(), |s| format!("{s:.4}"))) }
                    td class="num" { (p.samples) }
                }
                "\n"
            }
        }
        "\n"
        (heading(d.section, html! { "Coefficients" }))
        table {
            "\n"
            tr {
                th { "coefficient" } th { "kind" } th { "fitted range" } th { "beyond it" }
                th { "n" } th { "RMSE" } th { "R²" } th { "curve" }
            }
            "\n"
            @for (name, a) in cal.approximations() {
                (coefficient_row(cal, name, a))
            }
        }
        "\n"
    }
}

/// The rows of the recipe's table: each setting with what it resolved to on the log.
fn recipe_rows(cal: &Calibration) -> Markup {
    let r = &cal.recipe;
    let res = &cal.resolved;
    let set_or_auto = |set: bool| if set { "set" } else { "automatic" };
    html! {
        (row(
            "Ω filter",
            &format!(
                "{} s centred moving average ({} samples)",
                r.filter_s, res.filter_samples
            ),
        ))
        (row(
            "T smoothing",
            &format!(
                "{} s causal moving average ({} samples)",
                r.temp_smoothing_s, res.smooth_samples
            ),
        ))
        (row(
            "derivative step H",
            &format!(
                "{} s ({} samples at {} s)",
                r.step_h_s, res.step_samples, res.dt_s
            ),
        ))
        (row(
            "dead-band |Ṫ|",
            &format!(
                "{:.4e} °C/s ({})",
                res.deadband_tdot,
                set_or_auto(r.deadband_tdot.is_some())
            ),
        ))
        (row(
            "dead-band |T̈|",
            &format!(
                "{:.4e} °C/s² ({})",
                res.deadband_tddot,
                set_or_auto(r.deadband_tddot.is_some())
            ),
        ))
        (row(
            "plateaus",
            match &r.plateaus {
                PlateauChoice::Auto(_) => "detected automatically",
                PlateauChoice::Manual { .. } => "given by hand",
            },
        ))
        (row("weighting", &format!("{:?}", r.weighting).to_lowercase()))
        (row("refinement passes", &refinement_passes(cal)))
        @for (name, spec) in knot_rows(cal) {
            (row(&format!("knots of {name}"), &spec))
        }
    }
}

/// The refinement passes asked for, and the ones run when a set's passes diverged and were
/// stopped short (the fit's warning says why).
fn refinement_passes(cal: &Calibration) -> String {
    let asked = cal.recipe.refinements;
    match cal.resolved.refinements_run {
        Some([plus, minus]) => format!(
            "{asked} asked for; {plus} run on the + set, {minus} on the − set (the passes \
             diverged and were stopped)"
        ),
        None => asked.to_string(),
    }
}

/// The knots of each knot curve of the recipe, as the engine words them (`5 knots, equally
/// spaced`, or where they were placed by hand and the values set by hand): the page says
/// what the engineer chose, not only what the fit made of it.
fn knot_rows(cal: &Calibration) -> Vec<(&'static str, String)> {
    crate::models::vakhrameev::knots::Coefficient::ALL
        .iter()
        .map(|&c| (c, c.spec(&cal.recipe)))
        .filter(|(_, spec)| spec.kind.has_knots())
        .map(|(c, spec)| (c.label(), c.knots_text(spec)))
        .collect()
}

/// The row of coefficient `name` (`K0`, `K1+`, ...), fitted as `a`.
fn coefficient_row(cal: &Calibration, name: &str, a: &Approx) -> Markup {
    let u = &cal.units;
    let (xu, yu) = match name.get(..2) {
        Some("K0") => (&u.temperature, &u.rate),
        Some("K1") => (&u.tdot, &u.k1),
        _ => (&u.tddot, &u.k2),
    };
    let st = a.stats();
    html! {
        tr {
            td { (name) " [" (yu) "]" }
            td { (a.kind()) }
            td class="num" { (fmt_num(a.x_min())) " … " (fmt_num(a.x_max())) " " (xu) }
            td { (if a.extrapolates() { "extrapolated" } else { "edge value held" }) }
            td class="num" { (st.n) }
            td class="num" { (crate::number::or_na(st.computed_rmse(), fmt_num)) }
            td class="num" { (crate::number::or_na(st.computed_r2(), |v| format!("{v:.4}"))) }
            td { small { (curve_text(a)) } }
        }
        "\n"
    }
}
