//! The pieces every report page is made of: numbers and text as the page prints them, the
//! styles, the heading levels, tables of the identity and of the figures of merit, figures
//! inline. The page (`page.rs`) is one HTML file with everything inline (figures as inline SVG,
//! styles in the page), so it can be mailed, archived or printed on its own. No scripts, no
//! links out.

pub use super::regression_section::{fmt_coef, fmt_se};

use super::{Figure, LogReport, ReportSummary};
use crate::error::{Error, Result};
use std::fmt::Write as _;

/// A figure of merit in °/h as the page prints it (4 decimals, as `driftlab evaluate`).
pub fn fmt_dph(v: f64) -> String {
    format!("{v:.4}")
}

/// An improvement ratio as the page prints it.
pub fn fmt_ratio(r: f64) -> String {
    if r.is_finite() {
        format!("{r:.2}×")
    } else {
        "∞".into()
    }
}

/// A number with about five significant digits: fixed-point for everyday magnitudes,
/// mantissa-exponent for very small and very large ones.
pub fn fmt_num(v: f64) -> String {
    let a = v.abs();
    if !v.is_finite() {
        return format!("{v}");
    }
    if a == 0.0 {
        return "0".into();
    }
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.4e}");
    }
    let decimals = (4 - a.log10().floor() as i32).clamp(0, 7) as usize;
    format!("{v:.decimals$}")
}

/// Escapes text for HTML content and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

pub(super) const CSS: &str = "
body { font-family: 'DejaVu Sans', Verdana, sans-serif; font-size: 10.5pt; color: #111;
       max-width: 1100px; margin: 2em auto; padding: 0 1em; line-height: 1.4; }
h1 { font-size: 20pt; margin-bottom: 0.2em; }
h2 { font-size: 14pt; border-bottom: 1px solid #999; margin-top: 1.6em; }
h3 { font-size: 11.5pt; margin-bottom: 0.3em; }
table { border-collapse: collapse; margin: 0.5em 0 1em; }
th, td { border: 1px solid #bbb; padding: 0.2em 0.6em; vertical-align: top; }
th { background: #eee; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
code, pre { font-family: 'DejaVu Sans Mono', monospace; font-size: 9pt; }
pre { background: #f6f6f6; padding: 0.6em; overflow-x: auto; }
.tag { display: inline-block; padding: 0 0.5em; border-radius: 3px; font-size: 9pt;
       font-weight: bold; }
.in-sample { background: #fde2c8; }
.held-out { background: #cde8f6; }
figure { margin: 1em 0 2em; page-break-inside: avoid; break-inside: avoid; }
figure svg { width: 100%; height: auto; border: 1px solid #ddd; }
figcaption { font-size: 9.5pt; color: #333; margin-top: 0.3em; }
.notes li { color: #7a4b00; }
@media print {
  body { max-width: none; margin: 0; font-size: 9.5pt; }
  h2 { page-break-after: avoid; break-after: avoid; }
  table, figure { page-break-inside: avoid; break-inside: avoid; }
  pre { white-space: pre-wrap; }
}
";

/// The heading levels of a page's sections: a single-axis page's sections are `h2` (a log's
/// figures of merit `h3`); in a unit's page each axis is an `h2` and its sections one deeper.
#[derive(Debug, Clone, Copy)]
pub(super) struct Depth {
    /// A section (Recipe, Figures, ...).
    pub(super) section: &'static str,
    /// A part of a section (one log's figures of merit).
    pub(super) part: &'static str,
}

/// The sections of a page of one calibration.
pub(super) const PAGE: Depth = Depth {
    section: "h2",
    part: "h3",
};

/// The sections of one axis in a unit's page.
pub(super) const AXIS: Depth = Depth {
    section: "h3",
    part: "h4",
};

pub(super) fn row(out: &mut String, key: &str, value: &str) {
    let _ = writeln!(
        out,
        "<tr><th>{}</th><td>{}</td></tr>",
        escape(key),
        escape(value)
    );
}

pub(super) fn tag(in_sample: bool) -> &'static str {
    if in_sample {
        "<span class=\"tag in-sample\">in-sample</span>"
    } else {
        "<span class=\"tag held-out\">held out</span>"
    }
}

/// The SVG of a figure, ready to sit inside the page (the file as written, which has no XML
/// declaration and no external references).
fn inline_svg(f: &Figure) -> Result<String> {
    let text = std::fs::read_to_string(&f.svg).map_err(|e| Error::io(&f.svg, e))?;
    let start = text.find("<svg").unwrap_or(0);
    Ok(text[start..].replacen(
        "<svg ",
        &format!(
            "<svg role=\"img\" aria-label=\"{}\" preserveAspectRatio=\"xMidYMid meet\" ",
            escape(&f.title)
        ),
        1,
    ))
}

/// A figure inline, its caption naming its PNG by its path from `page_dir` (the folder of the
/// page: the file's name beside it, `gx/k0.png` for an axis of a unit).
fn figure_html(out: &mut String, f: &Figure, page_dir: &std::path::Path) -> Result<()> {
    let name = match f.png.strip_prefix(page_dir) {
        Ok(rel) if !page_dir.as_os_str().is_empty() => rel
            .components()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect::<Vec<_>>()
            .join("/"),
        _ => f
            .png
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
    };
    let _ = writeln!(out, "<figure>");
    out.push_str(&inline_svg(f)?);
    let _ = writeln!(
        out,
        "<figcaption><b>{}.</b> {} <i>(also {} and .svg beside this page)</i></figcaption></figure>",
        escape(&f.title),
        escape(&f.caption),
        escape(&name)
    );
    Ok(())
}

fn merit_table(out: &mut String, l: &LogReport, d: Depth) {
    let e = &l.evaluation;
    let c = &e.comparison;
    let _ = writeln!(
        out,
        "<{h}>{} {}</{h}>\n<p>{} samples, {:.2} h, T {:.1} … {:.1} °C; {} warm-up samples left out, \
         {} windows of 10 min; {:.1} % of samples outside the calibrated ranges. SHA-256 <code>{}</code></p>",
        escape(&l.name),
        tag(l.in_sample),
        l.samples,
        l.duration_s / 3600.0,
        l.temp_range_c.0,
        l.temp_range_c.1,
        e.warmup_samples,
        c.raw.windows,
        e.outside_fraction * 100.0,
        escape(&l.sha256),
        h = d.part
    );
    let _ = writeln!(
        out,
        "<table class=\"merit\" data-log=\"{}\" data-set=\"{}\">\n<tr><th>figure, °/h</th>\
         <th>raw</th><th>corrected</th><th>ratio</th></tr>",
        escape(&l.name),
        if l.in_sample { "in-sample" } else { "held-out" }
    );
    let rows = [
        (
            "peak-to-peak of filtered drift",
            c.raw.p2p_dph,
            c.corrected.p2p_dph,
            Some(c.p2p_ratio),
        ),
        (
            "std of filtered drift",
            c.raw.std_dph,
            c.corrected.std_dph,
            Some(c.std_ratio),
        ),
        (
            "max |10-min mean|",
            c.raw.win_mean_max_abs_dph,
            c.corrected.win_mean_max_abs_dph,
            Some(c.win_mean_ratio),
        ),
        (
            "peak-to-peak of 10-min means",
            c.raw.win_mean_p2p_dph,
            c.corrected.win_mean_p2p_dph,
            None,
        ),
        (
            "mean 10-min RMS",
            c.raw.win_rms_mean_dph,
            c.corrected.win_rms_mean_dph,
            Some(c.win_rms_ratio),
        ),
        (
            "max 10-min RMS",
            c.raw.win_rms_max_dph,
            c.corrected.win_rms_max_dph,
            None,
        ),
        ("mean", c.raw.mean_dph, c.corrected.mean_dph, None),
    ];
    for (name, raw, cor, ratio) in rows {
        let _ = writeln!(
            out,
            "<tr><td>{name}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td></tr>",
            fmt_dph(raw),
            fmt_dph(cor),
            ratio.map(fmt_ratio).unwrap_or_default()
        );
    }
    out.push_str("</table>\n");
}

/// The page's head up to `<body>`, with the styles (and `extra_css` after them).
pub(super) fn head(o: &mut String, gyro: &str, extra_css: &str) {
    let _ = writeln!(
        o,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>Thermal drift calibration report: {}</title>\n<style>{CSS}{extra_css}</style>\n</head>\n<body>",
        escape(gyro)
    );
}

/// The figures of merit of every log.
pub(super) fn merit_section(o: &mut String, s: &ReportSummary, d: Depth) {
    let _ = writeln!(
        o,
        "<{h}>Figures of merit</{h}>\n<p>Filtered drift: {:.0}-s centred moving average; mean and \
         RMS over consecutive {:.0}-s windows. Ratio = raw ÷ corrected (above 1: better). \
         <b>In-sample</b>: fitted and judged on the same log, as the papers do; <b>held out</b>: \
         judged on another log of the same gyro, what matters in service.</p>",
        s.merit.filter_s,
        s.merit.window_s,
        h = d.section
    );
    if s.logs.is_empty() {
        o.push_str("<p>No log was given: the calibration alone is reported.</p>\n");
    }
    for l in &s.logs {
        merit_table(o, l, d);
    }
}

/// Every figure of `s` and its notes, at depth `d`, the figures' files named from `page_dir`.
pub(super) fn figures_and_notes(
    o: &mut String,
    s: &ReportSummary,
    d: Depth,
    page_dir: &std::path::Path,
) -> Result<()> {
    let h = d.section;
    let _ = writeln!(o, "<{h}>Figures</{h}>");
    for f in &s.figures {
        figure_html(o, f, page_dir)?;
    }
    for l in &s.logs {
        for f in &l.figures {
            figure_html(o, f, page_dir)?;
        }
    }

    if !s.notes.is_empty() {
        let _ = write!(o, "<{h}>Notes</{h}>\n<ul class=\"notes\">\n");
        for n in &s.notes {
            let _ = writeln!(o, "<li>{}</li>", escape(n));
        }
        o.push_str("</ul>\n");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_five_significant_digits() {
        assert_eq!(fmt_num(-49.995), "-49.995");
        assert_eq!(fmt_num(0.016671), "0.016671");
        assert_eq!(fmt_num(39.71605), "39.716");
        assert_eq!(fmt_num(-7.594423e6), "-7.5944e6");
        assert_eq!(fmt_num(2.9648e-5), "2.9648e-5");
        assert_eq!(fmt_num(0.0), "0");
    }

    #[test]
    fn text_is_escaped() {
        assert_eq!(
            escape("<a href=\"x\">&'"),
            "&lt;a href=&quot;x&quot;&gt;&amp;&#39;"
        );
    }
}
