//! The report page of a unit: the one writer of `report.html`, for every calibration.
//!
//! A single-axis calibration is a unit of one unnamed axis. Its page is laid out as it has
//! always been: the model's introduction under the title, then its sections at the top level.
//! A unit of several (or named) axes adds a summary of every axis after its identity, then a
//! section per axis, each holding what the single-axis page holds for its model one heading
//! level deeper.
//!
//! The page walks the unit's axes and nothing else, so the dimensions still to come are
//! additions: an accelerometer axis is one more axis (its kind would word its heading and its
//! introduction, [`axis_heading`]); the runs of a campaign are more rows of the identity
//! ([`identity`]) and more logs in each axis's figures of merit; a lot is a page above this one
//! with one row per unit, as [`super::axis_summary`] has one row per axis.

use super::ReportSummary;
use super::axis_summary::summary;
use super::html::{AXIS, Depth, PAGE, escape, figures_and_notes, head, row};
use super::{regression_section, vakhrameev_section};
use crate::error::{Error, Result};
use crate::models::DriftModel;
use std::fmt::Write as _;
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
}

/// Styles a unit's page adds to the single-axis page's.
const UNIT_CSS: &str = "
td.worse { color: #a00000; font-weight: bold; }
h2.axis { border-bottom: 2px solid #333; }
";

/// The corrected rate, as every introduction writes it.
const CORRECTED: &str = "Ω<sub>cor</sub> = Ω<sub>raw</sub> − Ω<sub>pred</sub>";

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
/// page's folder.
///
/// # Errors
/// A figure's SVG that cannot be read back, the page that cannot be written;
/// [`Error::Internal`] for a page without axes.
pub(super) fn write(axes: &[PageAxis<'_>], html: &Path) -> Result<()> {
    let text = page(axes, html.parent().unwrap_or(Path::new("")))?;
    crate::files::atomic::write_bytes(html, text.as_bytes()).map_err(|e| Error::io(html, e))
}

/// The whole page of `axes`, the figures' files named from `page_dir`.
fn page(axes: &[PageAxis<'_>], page_dir: &Path) -> Result<String> {
    let first = axes
        .first()
        .ok_or(Error::Internal("a report page without axes"))?;
    let layout = Layout::of(axes);
    let gyro = if first.model.gyro_id().is_empty() {
        "(no gyro id)"
    } else {
        first.model.gyro_id()
    };
    let mut o = String::with_capacity(1 << 20);
    match layout {
        Layout::Single => {
            head(&mut o, gyro, "");
            single_intro(&mut o, first.model, gyro);
        }
        Layout::Unit => {
            head(&mut o, gyro, UNIT_CSS);
            unit_intro(&mut o, axes, gyro);
        }
    }
    identity(&mut o, axes, layout, gyro);
    if layout == Layout::Unit {
        summary(&mut o, axes);
    }
    let depth = layout.depth();
    for axis in axes {
        if layout == Layout::Unit {
            axis_heading(&mut o, axis);
        }
        match axis.model {
            DriftModel::Vakhrameev(cal) => {
                vakhrameev_section::body(&mut o, cal, axis.summary, depth)
            }
            DriftModel::Regression(reg) => {
                regression_section::body(&mut o, reg, axis.summary, depth)
            }
        }
        figures_and_notes(&mut o, axis.summary, depth, page_dir)?;
    }
    o.push_str("</body>\n</html>\n");
    Ok(o)
}

/// The title and the model of a single-axis calibration.
fn single_intro(o: &mut String, model: &DriftModel, gyro: &str) {
    let _ = write!(
        o,
        "<h1>Thermal drift calibration report</h1>\n<p>Gyro <b class=\"gyro-id\">{}</b>, ",
        escape(gyro)
    );
    let _ = match model {
        DriftModel::Vakhrameev(_) => writeln!(
            o,
            "Vakhrameev model {}, {CORRECTED} (+ where Ṫ·T̈ &gt; 0, − where Ṫ·T̈ &lt; 0).</p>",
            vakhrameev_section::FORMULA
        ),
        DriftModel::Regression(reg) => writeln!(
            o,
            "regression model <b class=\"model-name\">{}</b>: {}. {}, {CORRECTED}.</p>",
            escape(&reg.model.spec.name),
            escape(&regression_section::describe(&reg.model.spec.name)),
            regression_section::formula_html(reg)
        ),
    };
}

/// The title of a unit, naming every axis and its model.
fn unit_intro(o: &mut String, axes: &[PageAxis<'_>], gyro: &str) {
    let names: Vec<&str> = axes.iter().map(|a| a.name).collect();
    let models: Vec<String> = axes
        .iter()
        .map(|a| format!("{} {}", escape(a.name), escape(a.model.name())))
        .collect();
    let _ = writeln!(
        o,
        "<h1>Thermal drift calibration report</h1>\n<p>Unit <b class=\"gyro-id\">{}</b> of {} \
         gyro axes ({}), each calibrated with its own model ({}) from the unit's one \
         temperature; {CORRECTED} on each axis.</p>",
        escape(gyro),
        axes.len(),
        escape(&names.join(", ")),
        models.join(", ")
    );
}

/// The identity of the calibration: the gyro, its axes or its model, the log it was fitted
/// on, when it was made and when and by what the report was written.
fn identity(o: &mut String, axes: &[PageAxis<'_>], layout: Layout, gyro: &str) {
    let Some(first) = axes.first() else {
        return;
    };
    o.push_str("<h2>Identity</h2>\n<table>\n");
    row(o, "gyro id", gyro);
    match (layout, first.model) {
        (Layout::Unit, _) => {
            let names: Vec<&str> = axes.iter().map(|a| a.name).collect();
            row(o, "axes", &names.join(", "));
        }
        (Layout::Single, DriftModel::Regression(reg)) => row(o, "model", &reg.model.spec.name),
        (Layout::Single, DriftModel::Vakhrameev(_)) => {}
    }
    let source = first.model.source();
    row(o, "calibration log", &source.name);
    row(o, "its SHA-256", &source.sha256);
    row(
        o,
        "its samples, duration",
        &format!(
            "{} samples, {:.2} h",
            source.samples,
            source.duration_s / 3600.0
        ),
    );
    row(o, "calibration created", created(first.model));
    row(
        o,
        "report written",
        &humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string(),
    );
    row(
        o,
        "written by",
        &format!("driftlab {}", env!("CARGO_PKG_VERSION")),
    );
    o.push_str("</table>\n");
}

/// When the calibration of `model` was made.
fn created(model: &DriftModel) -> &str {
    match model {
        DriftModel::Vakhrameev(c) => &c.created,
        DriftModel::Regression(r) => &r.created,
    }
}

/// The heading of an axis's section in a unit's page and its model in one sentence.
fn axis_heading(o: &mut String, axis: &PageAxis<'_>) {
    let _ = writeln!(
        o,
        "<h2 class=\"axis\" id=\"axis-{}\">Axis {}</h2>",
        escape(axis.name),
        escape(axis.name)
    );
    let column = if axis.rate_column.is_empty() {
        String::new()
    } else {
        format!(
            ", calibrated from column <code>{}</code>",
            escape(axis.rate_column)
        )
    };
    let _ = match axis.model {
        DriftModel::Vakhrameev(_) => writeln!(
            o,
            "<p>Vakhrameev model {}{column}.</p>",
            vakhrameev_section::FORMULA
        ),
        DriftModel::Regression(reg) => writeln!(
            o,
            "<p>Regression model <b class=\"model-name\">{}</b>: {}{column}.</p>",
            escape(&reg.model.spec.name),
            regression_section::formula_html(reg)
        ),
    };
}
