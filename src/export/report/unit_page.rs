//! The page of a unit's report: the unit's identity, a summary table of every axis on every
//! log (raw and corrected figures with their ratios, a figure worse than raw marked), then a
//! section per axis holding what the single-axis page holds for its model.

use super::UnitReportSummary;
use super::html::{
    AXIS, escape, figures_and_notes, fmt_dph, fmt_ratio, head, row, vakhrameev_body,
};
use super::regression_page::{formula, regression_body};
use crate::error::Result;
use crate::judge::metrics::Comparison;
use crate::models::{DriftModel, UnitCalibration};
use std::fmt::Write as _;
use std::path::Path;

/// Styles the unit's page adds to the single-axis page's.
const UNIT_CSS: &str = "
td.worse { color: #a00000; font-weight: bold; }
h2.axis { border-bottom: 2px solid #333; }
";

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

/// The whole page of a unit.
pub(super) fn page(
    unit: &UnitCalibration,
    r: &UnitReportSummary,
    page_dir: &Path,
) -> Result<String> {
    let mut o = String::with_capacity(1 << 21);
    let first = unit.first()?;
    let gyro = if first.gyro_id().is_empty() {
        "(no gyro id)"
    } else {
        first.gyro_id()
    };
    let names = unit.axis_names().join(", ");
    head(&mut o, gyro, UNIT_CSS);
    let models: Vec<String> = unit
        .axes
        .iter()
        .map(|a| format!("{} {}", escape(&a.name), escape(a.model.name())))
        .collect();
    let _ = writeln!(
        o,
        "<h1>Thermal drift calibration report</h1>\n<p>Unit <b class=\"gyro-id\">{}</b> of {} \
         gyro axes ({}), each calibrated with its own model ({}) from the unit's one \
         temperature; Ω<sub>cor</sub> = Ω<sub>raw</sub> − Ω<sub>pred</sub> on each axis.</p>",
        escape(gyro),
        unit.axes.len(),
        escape(&names),
        models.join(", ")
    );

    // Identity.
    let source = first.source();
    o.push_str("<h2>Identity</h2>\n<table>\n");
    row(&mut o, "gyro id", gyro);
    row(&mut o, "axes", &names);
    row(&mut o, "calibration log", &source.name);
    row(&mut o, "its SHA-256", &source.sha256);
    row(
        &mut o,
        "its samples, duration",
        &format!(
            "{} samples, {:.2} h",
            source.samples,
            source.duration_s / 3600.0
        ),
    );
    row(&mut o, "calibration created", created(first));
    row(
        &mut o,
        "report written",
        &humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string(),
    );
    row(
        &mut o,
        "written by",
        &format!("driftlab {}", env!("CARGO_PKG_VERSION")),
    );
    o.push_str("</table>\n");

    summary(&mut o, r);

    // Every axis.
    for (ax, rep) in unit.axes.iter().zip(&r.axes) {
        let _ = writeln!(
            o,
            "<h2 class=\"axis\" id=\"axis-{}\">Axis {}</h2>",
            escape(&ax.name),
            escape(&ax.name)
        );
        let column = if ax.rate_column.is_empty() {
            String::new()
        } else {
            format!(
                ", calibrated from column <code>{}</code>",
                escape(&ax.rate_column)
            )
        };
        match &ax.model {
            DriftModel::Vakhrameev(cal) => {
                let _ = writeln!(
                    o,
                    "<p>Vakhrameev model Ω<sub>pred</sub> = K0(T) + K1±(Ṫ)·Ṫ + K2±(T̈)·T̈{column}.</p>"
                );
                vakhrameev_body(&mut o, cal, &rep.summary, AXIS);
            }
            DriftModel::Regression(reg) => {
                let _ = writeln!(
                    o,
                    "<p>Regression model <b class=\"model-name\">{}</b>: Ω<sub>pred</sub> = Σ \
                     coefficient · term over the terms <code>{}</code>{column}.</p>",
                    escape(&reg.model.spec.name),
                    escape(&formula(reg))
                );
                regression_body(&mut o, reg, &rep.summary, AXIS);
            }
        }
        figures_and_notes(&mut o, &rep.summary, AXIS, page_dir)?;
    }
    o.push_str("</body>\n</html>\n");
    Ok(o)
}

fn created(model: &DriftModel) -> &str {
    match model {
        DriftModel::Vakhrameev(c) => &c.created,
        DriftModel::Regression(r) => &r.created,
    }
}

/// The summary of every axis: for each log, a line per axis with the four figures raw,
/// corrected and their ratio.
fn summary(o: &mut String, r: &UnitReportSummary) {
    let Some(first) = r.axes.first() else {
        return;
    };
    let _ = writeln!(
        o,
        "<h2>Summary of every axis</h2>\n<p>Each axis judged as a single-axis calibration of it \
         would be (its section below has the details): filtered drift over the axis's filter \
         ({}), mean and RMS over consecutive windows of {:.0} s. Ratio = raw ÷ corrected \
         (above 1: better; below 1 the correction made the figure worse than raw, marked \
         <b>worse</b>).</p>",
        r.axes
            .iter()
            .map(|a| format!("{} {:.0} s", escape(&a.name), a.summary.merit.filter_s))
            .collect::<Vec<_>>()
            .join(", "),
        first.summary.merit.window_s
    );
    if first.summary.logs.is_empty() {
        o.push_str("<p>No log was given: the calibration alone is reported.</p>\n");
    }
    for (k, l) in first.summary.logs.iter().enumerate() {
        let _ = writeln!(
            o,
            "<h3>{} {}</h3>",
            escape(&l.name),
            if l.in_sample {
                "<span class=\"tag in-sample\">in-sample</span>"
            } else {
                "<span class=\"tag held-out\">held out</span>"
            }
        );
        let _ = writeln!(
            o,
            "<table class=\"unit-summary\" data-log=\"{}\">\n<tr><th rowspan=\"2\">axis</th>\
             <th rowspan=\"2\">model</th><th colspan=\"3\">peak-to-peak of filtered drift, °/h</th>\
             <th colspan=\"3\">std of filtered drift, °/h</th><th colspan=\"3\">max |window mean|, °/h</th>\
             <th colspan=\"3\">mean window RMS, °/h</th><th rowspan=\"2\">outside the calibrated ranges</th></tr>\n<tr>{}</tr>",
            escape(&l.name),
            "<th>raw</th><th>corrected</th><th>ratio</th>".repeat(4)
        );
        for a in &r.axes {
            let Some(l) = a.summary.logs.get(k) else {
                continue;
            };
            let c: &Comparison = &l.evaluation.comparison;
            let _ = write!(
                o,
                "<tr data-axis=\"{}\"><td>{}</td><td>{}</td>",
                escape(&a.name),
                escape(&a.name),
                escape(&a.model)
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
