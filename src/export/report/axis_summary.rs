//! The summary of every axis at the top of a unit's page: for each log, one row per axis with
//! the raw and corrected figures of merit and their ratios, a figure the correction made worse
//! than raw marked. Apart from the page because it is the one table that reads every axis at
//! once (a lot's table of units would be its sibling).

use super::LogReport;
use super::html::{fmt_in, fmt_ratio, tag};
use super::page::PageAxis;
use crate::judge::metrics::Comparison;
use maud::{Markup, html};

/// A figure in °/h, `n/a` when it could not be computed.
fn dph(v: f64, unit: &str) -> String {
    if v.is_finite() {
        fmt_in(v, unit)
    } else {
        "n/a".into()
    }
}

/// A ratio cell: `n/a` when it cannot be computed, marked worse below 1.
fn ratio_cell(r: f64) -> Markup {
    html! {
        @if !r.is_finite() {
            td class="num" { "n/a" }
        } @else if r < 1.0 {
            td class="num worse" { (fmt_ratio(r)) " worse" }
        } @else {
            td class="num" { (fmt_ratio(r)) }
        }
    }
}

/// The summary of every axis: for each log, a line per axis with the four figures raw,
/// corrected and their ratio.
pub(super) fn summary(axes: &[PageAxis<'_>]) -> Markup {
    let Some(first) = axes.first() else {
        return html! {};
    };
    // The figures are in each axis's unit: °/h, and m/s² where the unit has accelerometers.
    let units = if axes.iter().any(|a| a.kind == crate::log::AxisKind::Accel) {
        "°/h (m/s² on accelerometer axes)"
    } else {
        "°/h"
    };
    let filters = axes
        .iter()
        .map(|a| format!("{} {:.0} s", a.name, a.summary.merit.filter_s))
        .collect::<Vec<_>>()
        .join(", ");
    // Every log given, judged or left out, by its place among the logs.
    let count = axes
        .iter()
        .flat_map(|a| {
            let judged = a.summary.logs.iter().map(|l| l.index);
            judged.chain(a.summary.left_out.iter().map(|l| l.index))
        })
        .max()
        .map_or(0, |m| m + 1);
    html! {
        h2 { "Summary of every axis" } "\n"
        p {
            "Each axis judged as a single-axis calibration of it would be (its section below has \
             the details): filtered drift over the axis's filter (" (filters) "), mean and RMS \
             over consecutive windows of " (format!("{:.0}", first.summary.merit.window_s))
            " s. Ratio = raw ÷ corrected (above 1: better; below 1 the correction made the \
             figure worse than raw, marked " b { "worse" } ")."
        }
        "\n"
        @if count == 0 {
            p { "No log was given: the calibration alone is reported." } "\n"
        }
        @for k in 0..count {
            @let judged = axes.iter().find_map(|a| a.summary.logs.iter().find(|l| l.index == k));
            @let left = axes.iter().find_map(|a| a.summary.left_out.iter().find(|l| l.index == k));
            @match (judged, left) {
                (Some(l), _) => { h3 { (l.name) " " (tag(l)) } "\n" }
                (None, Some(o)) => { h3 { (o.name) " (left out)" } "\n" }
                (None, None) => {}
            }
            table class="unit-summary" data-log=[judged.map(|l| &l.name).or(left.map(|o| &o.name))] {
                "\n"
                tr {
                    th rowspan="2" { "axis" }
                    th rowspan="2" { "model" }
                    th colspan="3" { "peak-to-peak of filtered drift, " (units) }
                    th colspan="3" { "std of filtered drift, " (units) }
                    th colspan="3" { "max |window mean|, " (units) }
                    th colspan="3" { "mean window RMS, " (units) }
                    th rowspan="2" { "outside the calibrated ranges" }
                }
                "\n"
                tr {
                    @for _ in 0..4 {
                        th { "raw" } th { "corrected" } th { "ratio" }
                    }
                }
                "\n"
                @for a in axes {
                    @if let Some(l) = a.summary.logs.iter().find(|l| l.index == k) {
                        (axis_row(a, l))
                    } @else if let Some(o) = a.summary.left_out.iter().find(|l| l.index == k) {
                        tr data-axis=(a.name) class="left-out" {
                            td { (a.name) }
                            td { (a.model.name()) }
                            td colspan="13" { "left out: " (o.reason) }
                        }
                        "\n"
                    }
                }
            }
            "\n"
        }
    }
}

/// The row of axis `a` in the table of its log `l`.
fn axis_row(a: &PageAxis<'_>, l: &LogReport) -> Markup {
    let c: &Comparison = &l.evaluation.comparison;
    let cells = [
        (c.raw.p2p_dph, c.corrected.p2p_dph, c.p2p_ratio),
        (c.raw.std_dph, c.corrected.std_dph, c.std_ratio),
        (
            c.raw.win_mean_max_abs_dph,
            c.corrected.win_mean_max_abs_dph,
            c.win_mean_ratio,
        ),
        (
            c.raw.win_rms_mean_dph,
            c.corrected.win_rms_mean_dph,
            c.win_rms_ratio,
        ),
    ];
    html! {
        tr data-axis=(a.name) {
            td { (a.name) }
            td { (a.model.name()) }
            @for (raw, cor, ratio) in cells {
                td class="num" { (dph(raw, l.unit)) }
                td class="num" { (dph(cor, l.unit)) }
                (ratio_cell(ratio))
            }
            td class="num" {
                (crate::number::percent(l.evaluation.outside_fraction)) " %"
                @if !l.evaluation.left_out.is_none() { br; small { (l.evaluation.left_out.to_string()) } }
            }
        }
        "\n"
    }
}
