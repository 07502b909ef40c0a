//! `lot.html`: the lot on one page. The counts and the spec; each figure's distribution over
//! the lot as a strip of dots, one per unit, the outliers marked and each dot a link to its
//! unit's calibration; and the table of units, each linked to its calibration.
//!
//! The page is a maud template, as the report's pages are ([`crate::export::report::html`]):
//! every name it shows (a unit's, from a file name; a reason quoting a column) is text escaped
//! by the template, and a link's target is the unit's folder, which [`super::folder_of`] made
//! of letters, digits, `.`, `-`, `_` and `%XX` alone (its `%` written `%25` in the link). It has the report's styles, no script and no link out
//! of the output folder.

use super::table::{column_name, columns};
use super::{LotOutcome, Status, UnitOutcome};
use crate::export::report::html::{CSS, fmt_num};
use maud::{DOCTYPE, Markup, PreEscaped, html};

/// The strip's drawing width and height, and the margin on each side, in SVG units.
const WIDTH: f64 = 720.0;
const HEIGHT: f64 = 46.0;
const MARGIN: f64 = 14.0;

/// The page's own styles, after the report's.
const LOT_CSS: &str = "
.pass { color: #1d6b2a; } .fail { color: #a33a00; font-weight: bold; }
.error { color: #b00020; font-weight: bold; }
svg.strip { width: 100%; height: auto; border: 1px solid #ddd; }
svg.strip circle { fill: #3b6ea5; fill-opacity: 0.75; }
svg.strip circle.failed { fill: #d08000; }
svg.strip circle.outlier { fill: #c00020; fill-opacity: 1; }
";

/// The text of `lot.html`.
pub fn page(lot: &LotOutcome) -> String {
    let [pass, fail, error] = lot.counts();
    let title = format!(
        "Lot of {} units: {pass} pass, {fail} fail, {error} error",
        lot.units.len()
    );
    let spec = serde_json::to_value(&lot.spec).unwrap_or_default();
    let body = html! {
        h1 { (title) } "\n"
        p {
            (lot.outliers.len()) " figures of units lie more than "
            (fmt_num(lot.spec.outlier_sigmas()))
            " robust standard deviations from the lot's median (marked red below). "
            "Each dot, and each unit's name, links to its calibration."
        } "\n"
        h2 { "Spec" } "\n"
        table {
            @if let Some(map) = spec.as_object() {
                @for (key, value) in map {
                    tr { th { (key) } td { (value.to_string()) } } "\n"
                }
            }
            @if spec.as_object().is_none_or(|m| m.is_empty()) {
                tr { td { "no limit: every unit that is calibrated passes" } }
            }
        } "\n"
        h2 { "Distributions" } "\n"
        @for (axis, figure) in columns(&lot.units) {
            (strip(lot, &axis, &figure))
        }
        h2 { "Units" } "\n"
        (units_table(lot))
    };
    html! {
        (DOCTYPE) "\n"
        html lang="en" {
            "\n"
            head {
                "\n" meta charset="utf-8"; "\n"
                title { (title) } "\n"
                style { (PreEscaped(CSS)) (PreEscaped(LOT_CSS)) } "\n"
            }
            "\n"
            body { "\n" (body) }
            "\n"
        }
        "\n"
    }
    .into_string()
}

/// One figure's distribution: a dot per unit that has it, on a line from the lowest value to
/// the highest, with the median and its band of outliers' bounds.
fn strip(lot: &LotOutcome, axis: &str, figure: &str) -> Markup {
    let values: Vec<(&UnitOutcome, f64)> = lot
        .units
        .iter()
        .filter_map(|u| {
            let v = u.axes.iter().find(|a| a.axis == axis)?.get(figure)?.value?;
            Some((u, v))
        })
        .collect();
    let name = column_name(axis, figure);
    if values.is_empty() {
        return html! {
            h3 { (name) } p { "No unit has this figure (see the units' reasons)." } "\n"
        };
    }
    let xs: Vec<f64> = values.iter().map(|(_, v)| *v).collect();
    let spread = super::outliers::robust_spread(&xs);
    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let at = |v: f64| {
        if hi > lo {
            MARGIN + (v - lo) / (hi - lo) * (WIDTH - 2.0 * MARGIN)
        } else {
            WIDTH / 2.0
        }
    };
    let outlier = |u: &UnitOutcome| {
        lot.outliers
            .iter()
            .any(|o| o.unit == u.unit && o.axis == axis && o.figure == figure)
    };
    html! {
        h3 { (name) } "\n"
        svg.strip xmlns="http://www.w3.org/2000/svg" viewBox=(format!("0 0 {WIDTH} {HEIGHT}")) {
            line x1=(MARGIN) x2=(WIDTH - MARGIN) y1=(HEIGHT / 2.0) y2=(HEIGHT / 2.0)
                stroke="#999" {}
            @if let Some((median, _, _)) = spread {
                line x1=(at(median)) x2=(at(median)) y1="4" y2=(HEIGHT - 4.0) stroke="#333"
                    stroke-dasharray="3 2" {}
            }
            @for (k, (u, v)) in values.iter().enumerate() {
                a href=(link(&format!("{}/calibration.json", u.folder))) {
                    circle class=(dot_class(u, outlier(u)))
                        cx=(at(*v)) cy=(HEIGHT / 2.0 + ((k % 5) as f64 - 2.0) * 4.0) r="4" {
                        title { (u.unit) ": " (fmt_num(*v)) }
                    }
                }
            }
        } "\n"
        p {
            (values.len()) " units, " (fmt_num(lo)) " … " (fmt_num(hi))
            @if let Some((median, sd, _)) = spread {
                "; median " (fmt_num(median)) " (dashed), robust sd " (fmt_num(sd))
            }
        } "\n"
    }
}

/// A link to `path` in the output folder: a unit's folder holds `%XX` for the bytes of its
/// name that [`super::folder_of`] wrote so, which a browser would decode, so `%` is itself
/// written `%25`.
fn link(path: &str) -> String {
    path.replace('%', "%25")
}

fn dot_class(u: &UnitOutcome, outlier: bool) -> &'static str {
    match (outlier, u.status) {
        (true, _) => "outlier",
        (false, Status::Fail) => "failed",
        _ => "",
    }
}

/// Every unit: its status, its reasons, its outlying figures, a link to its calibration.
fn units_table(lot: &LotOutcome) -> Markup {
    html! {
        table {
            tr { th { "unit" } th { "status" } th { "reasons" } th { "outliers" } } "\n"
            @for u in &lot.units {
                tr {
                    td {
                        @if let Some(c) = &u.calibration {
                            a href=(link(c)) { (u.unit) }
                        } @else {
                            (u.unit)
                        }
                    }
                    td class=(u.status.word()) { (u.status.word()) }
                    td { (u.reasons.join("; ")) }
                    td {
                        (lot.outliers
                            .iter()
                            .filter(|o| o.unit == u.unit)
                            .map(|o| format!(
                                "{} ({:+.1} sd)",
                                column_name(&o.axis, &o.figure),
                                o.sigmas
                            ))
                            .collect::<Vec<_>>()
                            .join("; "))
                    }
                } "\n"
            }
        }
    }
}
