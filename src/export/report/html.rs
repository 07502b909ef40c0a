//! The pieces every report page is made of: numbers and text as the page prints them, the
//! styles, the heading levels, tables of the identity and of the figures of merit, figures
//! inline. The page (`page.rs`) is one HTML file with everything inline (figures as inline SVG,
//! styles in the page), so it can be mailed, archived or printed on its own. No scripts, no
//! links out.
//!
//! Every piece is a maud template: a value put into one is text, escaped by the template,
//! whatever a log's file name, an axis, a gyro id or a recipe holds. Markup enters only as
//! `PreEscaped`, and only for what driftlab itself wrote: the styles and the figures' SVG.

pub use super::regression_section::{fmt_coef, fmt_se};

use super::{Figure, LogReport, ReportSummary};
use crate::error::{Error, Result};
use maud::{DOCTYPE, Markup, PreEscaped, html};

/// A figure of merit in °/h as the page prints it (4 decimals, as `driftlab evaluate`).
pub fn fmt_dph(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.4}")
    } else {
        "n/a".into()
    }
}

/// A figure in `unit` as the page prints it: °/h to 0.0001, m/s² to 10⁻⁶ (a tenth of a µg:
/// an accelerometer's corrected figures are thousandths of its raw ones).
pub fn fmt_in(v: f64, unit: &str) -> String {
    match unit {
        "m/s²" if v.is_finite() => format!("{v:.6}"),
        _ => fmt_dph(v),
    }
}

/// An improvement ratio as the page prints it.
pub fn fmt_ratio(r: f64) -> String {
    if r.is_finite() {
        format!("{r:.2}×")
    } else {
        "n/a".into()
    }
}

/// A number with about five significant digits: fixed-point for everyday magnitudes,
/// mantissa-exponent for very small and very large ones.
pub fn fmt_num(v: f64) -> String {
    let a = v.abs();
    if !v.is_finite() {
        return "n/a".into();
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

/// The styles of every page driftlab writes (the report's, and a lot's `lot.html`), so they
/// read and print alike.
pub const CSS: &str = "
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
.cannot-tell { background: #e4e4e4; }
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

/// A heading level of the page. The page's sections sit one level deeper in a unit's page
/// than in a single-axis page, and the template names its tags statically: [`heading`] picks
/// the tag.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Level {
    H2,
    H3,
    H4,
}

/// `content` as a heading of `level`, its line ended.
pub(super) fn heading(level: Level, content: Markup) -> Markup {
    match level {
        Level::H2 => html! { h2 { (content) } "\n" },
        Level::H3 => html! { h3 { (content) } "\n" },
        Level::H4 => html! { h4 { (content) } "\n" },
    }
}

/// The heading levels of a page's sections: a single-axis page's sections are `h2` (a log's
/// figures of merit `h3`); in a unit's page each axis is an `h2` and its sections one deeper.
#[derive(Debug, Clone, Copy)]
pub(super) struct Depth {
    /// A section (Recipe, Figures, ...).
    pub(super) section: Level,
    /// A part of a section (one log's figures of merit).
    pub(super) part: Level,
}

/// The sections of a page of one calibration.
pub(super) const PAGE: Depth = Depth {
    section: Level::H2,
    part: Level::H3,
};

/// The sections of one axis in a unit's page.
pub(super) const AXIS: Depth = Depth {
    section: Level::H3,
    part: Level::H4,
};

/// A row of a two-column table: a name and its value, both text.
pub(super) fn row(key: &str, value: &str) -> Markup {
    html! { tr { th { (key) } td { (value) } } "\n" }
}

/// The label of a log judged in-sample, held out, or that the calibration's sketch cannot
/// tell apart from its own log (with why, on hover).
pub(super) fn tag(l: &super::LogReport) -> Markup {
    html! {
        @match (l.kind, &l.cannot_tell) {
            ("in-sample", _) => span class="tag in-sample" { "in-sample" },
            ("cannot tell", why) => span class="tag cannot-tell"
                title=(why.as_deref().unwrap_or_default()) { "cannot tell if held out" },
            _ => span class="tag held-out" { "held out" },
        }
    }
}

/// The corrected rate, as every introduction writes it.
pub(super) fn corrected() -> Markup {
    html! { "Ω" sub { "cor" } " = Ω" sub { "raw" } " − Ω" sub { "pred" } }
}

/// The SVG of a figure, ready to sit inside the page: the file as written (which has no XML
/// declaration and no external references; plotters escapes every text it draws), its root
/// given the figure's title as its label. The file is driftlab's own drawing, so it goes in
/// as markup; the title goes through the template's escaping.
fn inline_svg(f: &Figure) -> Result<Markup> {
    let text = std::fs::read_to_string(&f.svg).map_err(|e| Error::io(&f.svg, e))?;
    let start = text.find("<svg").unwrap_or(0);
    let label = html! { (f.title) }.into_string();
    Ok(PreEscaped(text[start..].replacen(
        "<svg ",
        &format!("<svg role=\"img\" aria-label=\"{label}\" preserveAspectRatio=\"xMidYMid meet\" "),
        1,
    )))
}

/// A figure inline, its caption naming its PNG by its path from `page_dir` (the folder of the
/// page: the file's name beside it, `gx/k0.png` for an axis of a unit).
fn figure_html(f: &Figure, page_dir: &std::path::Path) -> Result<Markup> {
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
    let svg = inline_svg(f)?;
    Ok(html! {
        figure {
            "\n" (svg)
            figcaption {
                b { (f.title) "." } " " (f.caption) " "
                i { "(also " (name) " and .svg beside this page)" }
            }
        }
        "\n"
    })
}

/// `run`: the number of the campaign's run this log is, when it is one
/// ([`super::campaign_section::run_of`]).
fn merit_table(l: &LogReport, d: Depth, window_s: f64, run: Option<usize>) -> Markup {
    let e = &l.evaluation;
    let c = &e.comparison;
    // The windowed figures named by the window they were computed over, as the CLI's tables.
    let w = crate::judge::options::window_label(window_s);
    let (mean_max, mean_p2p, rms_mean, rms_max) = (
        format!("max |{w} mean|"),
        format!("peak-to-peak of {w} means"),
        format!("mean {w} RMS"),
        format!("max {w} RMS"),
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
            mean_max.as_str(),
            c.raw.win_mean_max_abs_dph,
            c.corrected.win_mean_max_abs_dph,
            Some(c.win_mean_ratio),
        ),
        (
            mean_p2p.as_str(),
            c.raw.win_mean_p2p_dph,
            c.corrected.win_mean_p2p_dph,
            None,
        ),
        (
            rms_mean.as_str(),
            c.raw.win_rms_mean_dph,
            c.corrected.win_rms_mean_dph,
            Some(c.win_rms_ratio),
        ),
        (
            rms_max.as_str(),
            c.raw.win_rms_max_dph,
            c.corrected.win_rms_max_dph,
            None,
        ),
        ("mean", c.raw.mean_dph, c.corrected.mean_dph, None),
    ];
    html! {
        (heading(d.part, html! {
            (l.name) " " (tag(l))
            @if let Some(k) = run { " run " (k) " of the campaign" }
        }))
        p {
            (l.samples) " samples, " (crate::number::fixed(l.duration_s / 3600.0, 2)) " h, T "
            (format!("{:.1}", l.temp_range_c.0)) " … " (format!("{:.1}", l.temp_range_c.1))
            " °C; " (e.warmup_samples) " warm-up samples left out, " (c.raw.windows)
            " windows of " (w) "; " (crate::number::percent(e.outside_fraction))
            " % of samples outside the calibrated ranges"
            @if !e.left_out.is_none() { " (" (e.left_out.to_string()) ")" }
            ". SHA-256 " code { (l.sha256) }
        }
        @if let Some(why) = &l.cannot_tell {
            p {
                "The calibration's sketch of its own log cannot tell whether this is that log ("
                (why) "): these figures are no held-out evidence."
            }
        }
        "\n"
        table class="merit" data-log=(l.name)
            data-set=(l.kind.replace(' ', "-")) {
            "\n"
            tr { th { "figure, " (l.unit) } th { "raw" } th { "corrected" } th { "ratio" } }
            "\n"
            @for (name, raw, cor, ratio) in rows {
                tr {
                    td { (name) }
                    td class="num" { (fmt_in(raw, l.unit)) }
                    td class="num" { (fmt_in(cor, l.unit)) }
                    td class="num" { (ratio.map(fmt_ratio).unwrap_or_default()) }
                }
                "\n"
            }
        }
        "\n"
        @for (what, why) in c.unavailable() {
            p class="na" { (what) " n/a: " (why) }
            "\n"
        }
    }
}

/// The whole page: its head up to `<body>`, with the styles (and `extra_css` after them),
/// then `body`.
pub(super) fn document(gyro: &str, extra_css: &str, body: Markup) -> Markup {
    html! {
        (DOCTYPE) "\n"
        html lang="en" {
            "\n"
            head {
                "\n" meta charset="utf-8"; "\n"
                title { "Thermal drift calibration report: " (gyro) } "\n"
                style { (PreEscaped(CSS)) (PreEscaped(extra_css)) } "\n"
            }
            "\n"
            body { "\n" (body) }
            "\n"
        }
        "\n"
    }
}

/// The figures of merit of every log; a log that is a run of the campaign in `runs` (empty
/// for a calibration of one run) says which.
pub(super) fn merit_section(
    s: &ReportSummary,
    d: Depth,
    runs: &[crate::models::campaign::RunRecord],
) -> Markup {
    html! {
        (heading(d.section, html! { "Figures of merit" }))
        p {
            "Filtered drift: " (format!("{:.0}", s.merit.filter_s))
            "-s centred moving average; mean and RMS over consecutive "
            (format!("{:.0}", s.merit.window_s))
            "-s windows. Ratio = raw ÷ corrected (above 1: better). "
            b { "In-sample" } ": fitted and judged on the same log, as the papers do; "
            b { "held out" } ": judged on another log of the same gyro, what matters in service."
        }
        "\n"
        @if s.logs.is_empty() && s.left_out.is_empty() {
            p { "No log was given: the calibration alone is reported." } "\n"
        }
        @for l in &s.logs {
            (merit_table(l, d, s.merit.window_s, super::campaign_section::run_of(runs, &l.sha256)))
        }
        @for o in &s.left_out {
            p class="left-out" data-log=(o.name) { b { (o.name) } " is left out: " (o.reason) } "\n"
        }
    }
}

/// Every figure of `s` and its notes, at depth `d`, the figures' files named from `page_dir`.
pub(super) fn figures_and_notes(
    s: &ReportSummary,
    d: Depth,
    page_dir: &std::path::Path,
) -> Result<Markup> {
    let figures = s
        .figures
        .iter()
        .chain(s.logs.iter().flat_map(|l| &l.figures))
        .map(|f| figure_html(f, page_dir))
        .collect::<Result<Vec<Markup>>>()?;
    Ok(html! {
        (heading(d.section, html! { "Figures" }))
        @for f in &figures { (f) }
        @if !s.notes.is_empty() {
            (heading(d.section, html! { "Notes" }))
            ul class="notes" {
                "\n"
                @for n in &s.notes { li { (n) } "\n" }
            }
            "\n"
        }
    })
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
    fn a_row_escapes_both_cells() {
        assert_eq!(
            row("<a href=\"x\">", "&'").into_string(),
            "<tr><th>&lt;a href=&quot;x&quot;&gt;</th><td>&amp;'</td></tr>\n"
        );
    }
}
