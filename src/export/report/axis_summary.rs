//! The summary of every axis at the top of a unit's page: for each log, one row per axis with
//! the raw and corrected figures of merit and their ratios, a figure the correction made worse
//! than raw marked. Apart from the page because it is the one table that reads every axis at
//! once (a lot's table of units would be its sibling).

use super::html::{escape, fmt_dph, fmt_ratio, tag};
use super::page::PageAxis;
use crate::judge::metrics::Comparison;
use std::fmt::Write as _;

/// A figure in °/h, `n/a` when it could not be computed.
fn dph(v: f64) -> String {
    if v.is_finite() {
        fmt_dph(v)
    } else {
        "n/a".into()
    }
}

/// A ratio cell: `n/a` when it cannot be computed, marked worse below 1.
fn ratio_cell(r: f64) -> String {
    if !r.is_finite() {
        "<td class=\"num\">n/a</td>".into()
    } else if r < 1.0 {
        format!("<td class=\"num worse\">{} worse</td>", fmt_ratio(r))
    } else {
        format!("<td class=\"num\">{}</td>", fmt_ratio(r))
    }
}

/// The summary of every axis: for each log, a line per axis with the four figures raw,
/// corrected and their ratio.
pub(super) fn summary(o: &mut String, axes: &[PageAxis<'_>]) {
    let Some(first) = axes.first() else {
        return;
    };
    let _ = writeln!(
        o,
        "<h2>Summary of every axis</h2>\n<p>Each axis judged as a single-axis calibration of it \
         would be (its section below has the details): filtered drift over the axis's filter \
         ({}), mean and RMS over consecutive windows of {:.0} s. Ratio = raw ÷ corrected \
         (above 1: better; below 1 the correction made the figure worse than raw, marked \
         <b>worse</b>).</p>",
        axes.iter()
            .map(|a| format!("{} {:.0} s", escape(a.name), a.summary.merit.filter_s))
            .collect::<Vec<_>>()
            .join(", "),
        first.summary.merit.window_s
    );
    if first.summary.logs.is_empty() {
        o.push_str("<p>No log was given: the calibration alone is reported.</p>\n");
    }
    for (k, l) in first.summary.logs.iter().enumerate() {
        let _ = writeln!(o, "<h3>{} {}</h3>", escape(&l.name), tag(l.in_sample));
        let _ = writeln!(
            o,
            "<table class=\"unit-summary\" data-log=\"{}\">\n<tr><th rowspan=\"2\">axis</th>\
             <th rowspan=\"2\">model</th><th colspan=\"3\">peak-to-peak of filtered drift, °/h</th>\
             <th colspan=\"3\">std of filtered drift, °/h</th><th colspan=\"3\">max |window mean|, °/h</th>\
             <th colspan=\"3\">mean window RMS, °/h</th><th rowspan=\"2\">outside the calibrated ranges</th></tr>\n<tr>{}</tr>",
            escape(&l.name),
            "<th>raw</th><th>corrected</th><th>ratio</th>".repeat(4)
        );
        for a in axes {
            let Some(l) = a.summary.logs.get(k) else {
                continue;
            };
            let c: &Comparison = &l.evaluation.comparison;
            let _ = write!(
                o,
                "<tr data-axis=\"{}\"><td>{}</td><td>{}</td>",
                escape(a.name),
                escape(a.name),
                escape(a.model.name())
            );
            for (raw, cor, ratio) in [
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
            ] {
                let _ = write!(
                    o,
                    "<td class=\"num\">{}</td><td class=\"num\">{}</td>{}",
                    dph(raw),
                    dph(cor),
                    ratio_cell(ratio)
                );
            }
            let _ = writeln!(
                o,
                "<td class=\"num\">{:.1} %</td></tr>",
                l.evaluation.outside_fraction * 100.0
            );
        }
        o.push_str("</table>\n");
    }
}
