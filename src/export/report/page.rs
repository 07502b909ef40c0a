//! The report page of a unit: the one writer of `report.html`, for every calibration.
//!
//! A single-axis calibration is a unit of one unnamed axis. Its page is laid out as it has
//! always been: the model's introduction under the title, then its sections at the top level.
//! A unit of several (or named) axes adds a summary of every axis after its identity, then a
//! section per axis, each holding what the single-axis page holds for its model one heading
//! level deeper.
//!
//! The page walks the unit's axes and nothing else, so each dimension is an addition: an
//! accelerometer axis is one more axis, its kind wording its heading and its figures' unit
//! ([`axis_heading`]), the axis that carries gravity said under the summary ([`gravity`]);
//! the runs of a campaign are more rows of the identity
//! ([`identity`]), more logs in each axis's figures of merit, and a campaign section per axis
//! (`campaign_section.rs`: nothing for one run); a lot is a page above this one
//! with one row per unit, as [`super::axis_summary`] has one row per axis.

use super::ReportSummary;
use super::axis_summary::summary;
use super::html::{AXIS, Depth, PAGE, corrected, document, figures_and_notes, row};
use super::{campaign_section, regression_section, vakhrameev_section};
use crate::error::{Error, Result};
use crate::log::AxisKind;
use crate::models::DriftModel;
use crate::models::accel::Gravity;
use maud::{Markup, html};
use std::path::Path;

/// One axis of a page: as the unit's calibration names it, its model, and what its report drew
/// and computed.
pub(super) struct PageAxis<'a> {
    /// The axis's name (`gx`); empty for the one axis of a single-axis calibration.
    pub(super) name: &'a str,
    /// The rate column it was calibrated from (`gx_dps`), empty when not known.
    pub(super) rate_column: &'a str,
    /// Its model.
    pub(super) model: &'a DriftModel,
    /// Its figures and figures of merit.
    pub(super) summary: &'a ReportSummary,
    /// What it measures.
    pub(super) kind: crate::log::AxisKind,
    /// The mean an accelerometer axis keeps, m/s².
    pub(super) kept_mean: Option<f64>,
}

/// Styles a unit's page adds to the single-axis page's.
const UNIT_CSS: &str = "
td.worse { color: #a00000; font-weight: bold; }
h2.axis { border-bottom: 2px solid #333; }
";

/// How a page lays out its axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Layout {
    /// The one unnamed axis of a single-axis calibration: its sections at the top level.
    Single,
    /// A unit: a summary of every axis, then a section per axis.
    Unit,
}

impl Layout {
    /// The layout of a page of `axes` (a unit of one unnamed axis is a single-axis
    /// calibration, as [`crate::models::UnitCalibration::is_unit`] tells them apart).
    fn of(axes: &[PageAxis<'_>]) -> Layout {
        match axes {
            [one] if one.name.is_empty() => Layout::Single,
            _ => Layout::Unit,
        }
    }

    /// The heading levels of an axis's sections.
    fn depth(self) -> Depth {
        match self {
            Layout::Single => PAGE,
            Layout::Unit => AXIS,
        }
    }
}

/// Writes the page of `axes` to `html` (atomically); the figures' files are named from the
/// page's folder. `tolerance_c`: within what two plateaus of a campaign share a temperature
/// (its section's repeatability and hysteresis).
///
/// # Errors
/// A figure's SVG that cannot be read back, the page that cannot be written;
/// [`Error::Internal`] for a page without axes.
pub(super) fn write(
    axes: &[PageAxis<'_>],
    html: &Path,
    tolerance_c: f64,
    gravity: Option<&Gravity>,
) -> Result<()> {
    let text = page(
        axes,
        html.parent().unwrap_or(Path::new("")),
        tolerance_c,
        gravity,
    )?;
    crate::files::atomic::write_bytes(html, text.as_bytes()).map_err(|e| Error::io(html, e))
}

/// The whole page of `axes`, the figures' files named from `page_dir`.
fn page(
    axes: &[PageAxis<'_>],
    page_dir: &Path,
    tolerance_c: f64,
    gravity: Option<&Gravity>,
) -> Result<String> {
    let first = axes
        .first()
        .ok_or(Error::Internal("a report page without axes"))?;
    let layout = Layout::of(axes);
    let gyro = if first.model.gyro_id().is_empty() {
        "(no gyro id)"
    } else {
        first.model.gyro_id()
    };
    let depth = layout.depth();
    let figures = axes
        .iter()
        .map(|a| figures_and_notes(a.summary, depth, page_dir))
        .collect::<Result<Vec<Markup>>>()?;
    let body = html! {
        @match layout {
            Layout::Single => (single_intro(first.model, gyro)),
            Layout::Unit => (unit_intro(axes, gyro)),
        }
        (identity(axes, layout, gyro))
        @if layout == Layout::Unit {
            (summary(axes))
        }
        @if let Some(g) = gravity {
            (self::gravity(g))
        }
        @for (axis, figures) in axes.iter().zip(&figures) {
            @if layout == Layout::Unit {
                (axis_heading(axis))
            }
            @match axis.model {
                DriftModel::Vakhrameev(cal) => {
                    (vakhrameev_section::body(cal, axis.summary, depth))
                }
                DriftModel::Regression(reg) => {
                    (regression_section::body(reg, axis.summary, depth))
                }
            }
            (campaign_section::body(&axis.model.source().runs, axis.summary, tolerance_c, depth))
            (figures)
        }
    };
    let extra_css = match layout {
        Layout::Single => "",
        Layout::Unit => UNIT_CSS,
    };
    Ok(document(gyro, extra_css, body).into_string())
}

/// The title and the model of a single-axis calibration.
fn single_intro(model: &DriftModel, gyro: &str) -> Markup {
    html! {
        h1 { "Thermal drift calibration report" } "\n"
        p {
            "Gyro " b class="gyro-id" { (gyro) } ", "
            @match model {
                DriftModel::Vakhrameev(_) => {
                    "Vakhrameev model " (vakhrameev_section::formula()) ", " (corrected())
                    " (+ where Ṫ·T̈ > 0, − where Ṫ·T̈ < 0)."
                }
                DriftModel::Regression(reg) => {
                    "regression model " b class="model-name" { (reg.model.spec.name) } ": "
                    (regression_section::describe(&reg.model.spec.name)) ". "
                    (regression_section::formula_html(reg)) ", " (corrected()) "."
                }
            }
        }
        "\n"
    }
}

/// The title of a unit, naming every axis and its model.
fn unit_intro(axes: &[PageAxis<'_>], gyro: &str) -> Markup {
    let names: Vec<&str> = axes.iter().map(|a| a.name).collect();
    let models: Vec<String> = axes
        .iter()
        .map(|a| format!("{} {}", a.name, a.model.name()))
        .collect();
    let accels = axes.iter().filter(|a| a.kind == AxisKind::Accel).count();
    let what = match accels {
        0 => format!("{} gyro axes", axes.len()),
        n => format!(
            "{} axes, {} of a gyro and {n} of an accelerometer,",
            axes.len(),
            axes.len() - n
        ),
    };
    html! {
        h1 { "Thermal drift calibration report" } "\n"
        p {
            "Unit " b class="gyro-id" { (gyro) } " of " (what) " ("
            (names.join(", ")) "), each calibrated with its own model (" (models.join(", "))
            ") from the unit's one temperature; " (corrected()) " on each axis."
            @if accels > 0 {
                " Gyro axes in °/h; accelerometer axes in m/s², each fitted about its mean on \
                 the calibration log, which its correction keeps (gravity's share and the bias \
                 at rest are the ordinary accelerometer calibration's), and judged about it."
            }
        }
        "\n"
    }
}

/// The identity of the calibration: the gyro, its axes or its model, the log it was fitted
/// on, when it was made and when and by what the report was written.
fn identity(axes: &[PageAxis<'_>], layout: Layout, gyro: &str) -> Markup {
    let Some(first) = axes.first() else {
        return html! {};
    };
    let source = first.model.source();
    let names: Vec<&str> = axes.iter().map(|a| a.name).collect();
    html! {
        h2 { "Identity" } "\n"
        table {
            "\n"
            (row("gyro id", gyro))
            @match (layout, first.model) {
                (Layout::Unit, _) => (row("axes", &names.join(", "))),
                (Layout::Single, DriftModel::Regression(reg)) => {
                    (row("model", &reg.model.spec.name))
                }
                (Layout::Single, DriftModel::Vakhrameev(_)) => {}
            }
            (row("calibration log", &crate::text::escaped(&source.name, false)))
            (row("its SHA-256", &source.sha256))
            (row(
                "its samples, duration",
                &format!(
                    "{} samples, {} h",
                    source.samples,
                    crate::number::fixed(source.duration_s / 3600.0, 2)
                ),
            ))
            (row("calibration created", created(first.model)))
            (row(
                "report written",
                &humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string(),
            ))
            (row("written by", &format!("driftlab {}", env!("CARGO_PKG_VERSION"))))
        }
        "\n"
    }
}

/// When the calibration of `model` was made.
fn created(model: &DriftModel) -> &str {
    match model {
        DriftModel::Vakhrameev(c) => &c.created,
        DriftModel::Regression(r) => &r.created,
    }
}

/// The heading of an axis's section in a unit's page and its model in one sentence.
fn axis_heading(axis: &PageAxis<'_>) -> Markup {
    let column = html! {
        @if !axis.rate_column.is_empty() {
            ", calibrated from column " code { (axis.rate_column) }
        }
    };
    let kind = match axis.kind {
        AxisKind::Gyro => "Axis ",
        AxisKind::Accel => "Accelerometer axis ",
    };
    html! {
        h2 class="axis" id={ "axis-" (axis.name) } { (kind) (axis.name) } "\n"
        @if let Some(mean) = axis.kept_mean {
            p {
                "Readings in m/s², fitted about their mean on the calibration log, "
                (crate::number::readable(mean)) " m/s², which the correction keeps: every \
                 figure below is of the reading less that mean."
            }
            "\n"
        }
        p {
            @match axis.model {
                DriftModel::Vakhrameev(_) => {
                    "Vakhrameev model " (vakhrameev_section::formula()) (column) "."
                }
                DriftModel::Regression(reg) => {
                    "Regression model " b class="model-name" { (reg.model.spec.name) } ": "
                    (regression_section::formula_html(reg)) (column) "."
                }
            }
        }
        "\n"
    }
}

/// Which axis carries gravity, and its reading's change with T over its mean: what one
/// orientation tells of its scale factor.
fn gravity(g: &Gravity) -> Markup {
    html! {
        h2 { "Gravity" } "\n"
        p class="gravity" {
            "Axis " b { (g.axis) } " carries gravity: its mean on the calibration log is "
            (crate::number::readable(g.mean_m_s2)) " m/s², which its correction keeps."
            @if let Some(c) = g.scale_change_per_c {
                " Its reading changes by " (crate::number::readable(c * 1e6)) " ppm/°C of its \
                 mean over " (crate::number::readable(g.range_c.0)) " … "
                (crate::number::readable(g.range_c.1)) " °C: its scale factor's change with T, \
                 its bias's change included (one orientation cannot part them)."
            }
        }
        "\n"
    }
}
