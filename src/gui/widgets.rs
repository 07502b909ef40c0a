//! Widgets more than one view draws, so that views never call into each other: the time axis
//! the time plots and the result plot share, an approximation's controls (K0, K1±, K2±), a
//! plot's "save as PNG" menu entry and a file's short name.

use crate::models::approx::{ApproxKind, ApproxSpec};
use eframe::egui::{self, Ui, WidgetInfo};
use std::path::Path;

/// The id of the time axis shared by the time plots and the result plot (zoom and pan
/// together).
pub fn time_link() -> egui::Id {
    egui::Id::unique("driftlab-time-axis")
}

/// The name people read for an approximation kind.
pub fn kind_name(k: ApproxKind) -> &'static str {
    match k {
        ApproxKind::Linear => "linear",
        ApproxKind::Parabolic => "parabolic",
        ApproxKind::Pwl => "piecewise-linear",
        ApproxKind::Spline => "spline",
    }
}

fn kind_tip(k: ApproxKind) -> &'static str {
    match k {
        ApproxKind::Linear => "c0 + c1·x",
        ApproxKind::Parabolic => "c0 + c1·x + c2·x²",
        ApproxKind::Pwl => "straight segments between knots (equally spaced unless placed by hand)",
        ApproxKind::Spline => {
            "Catmull-Rom cubic spline through knots (equally spaced unless placed by hand)"
        }
    }
}

/// What the engineer asked of an approximation's controls beside changing the spec.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ApproxAsks {
    /// Forget the knots placed and set by hand ("reset knots").
    pub reset: bool,
    /// Open the knot table ("knots…").
    pub table: bool,
}

/// Kind, knot count, "knots…" and "reset knots" for one coefficient. A new kind or knot count
/// is made by the engine's rules ([`ApproxSpec::with_kind`], [`ApproxSpec::with_knot_count`]:
/// a new count spreads the knots evenly again). "reset knots" is always there (greyed while no
/// knot is placed or set by hand), so that the row keeps its width when a drag starts.
pub fn approx_controls(ui: &mut Ui, id: &str, label: &str, spec: &mut ApproxSpec) -> ApproxAsks {
    let before = spec.clone();
    let mut kind = spec.kind;
    let r = egui::ComboBox::from_id_salt(("approx_kind", id))
        .selected_text(kind_name(kind))
        .width(112.0)
        .show_ui(ui, |ui| {
            for k in ApproxKind::ALL {
                ui.selectable_value(&mut kind, k, kind_name(k))
                    .on_hover_text(kind_tip(k));
            }
        })
        .response;
    let text = format!("{label} approximation");
    let value = kind_name(kind).to_string();
    r.widget_info(|| {
        let mut info = WidgetInfo::labeled(egui::accesskit::Role::ComboBox, true, &text);
        info.current_text_value = Some(value.clone());
        info
    });
    r.on_hover_text(format!(
        "Approximation of {label}: linear, parabolic, piecewise-linear or spline"
    ));
    if kind != spec.kind {
        *spec = spec.with_kind(kind);
    }
    let mut asks = ApproxAsks::default();
    if spec.kind.has_knots() {
        let mut n = spec.knots;
        ui.add(
            egui::DragValue::new(&mut n)
                .range(2..=24)
                .suffix(" knots")
                .speed(0.05),
        )
        .on_hover_text(format!(
            "{} A new count forgets the knots placed by hand: to keep them, add a knot with \
             Ctrl+click on the plot, or remove one from its right-click menu",
            if id == "k0" {
                // The engine places K0's knots (`vakhrameev::knots_at_temperatures`).
                format!(
                    "Most knots of {label} (2 to 24): one at each plateau temperature, or as \
                     many as asked picked evenly among them."
                )
            } else {
                format!("Number of knots of {label} (2 to 24), equally spaced.")
            }
        ));
        if n != spec.knots {
            *spec = spec.with_knot_count(n);
        }
        asks.table = ui
            .small_button("knots…")
            .on_hover_text(format!("Type the positions and values of {label}'s knots"))
            .clicked();
    }
    ui.checkbox(&mut spec.extrapolate, "extrap.")
        .on_hover_text(format!(
            "Evaluate {label} beyond the range it was fitted on, instead of holding its edge value"
        ));
    asks.reset = ui
        .add_enabled(
            before.hand_knots(),
            egui::Button::new("reset knots").small(),
        )
        .on_hover_text(format!(
            "Forget the knots of {label} placed or set by hand: equally spaced, fitted knots again"
        ))
        .on_disabled_hover_text(format!("No knot of {label} is placed or set by hand"))
        .clicked();
    asks
}

/// The "Save this plot as PNG…" entry of a plot's context menu; true when chosen (the menu
/// is closed then).
pub fn save_plot_entry(ui: &mut Ui) -> bool {
    let chosen = ui
        .button("Save this plot as PNG…")
        .on_hover_text("Write this plot alone as a PNG picture")
        .clicked();
    if chosen {
        ui.close();
    }
    chosen
}

/// A file's name for short messages, headings and the title bar (the full path goes in
/// tooltips), with line breaks, controls and bidi overrides written as `\uXXXX` by the one
/// rule the terminal and the report use ([`crate::text::escaped`]): a name cannot split a
/// heading over lines or reorder the text around it.
pub fn file_name(p: &Path) -> String {
    let name = p
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string());
    crate::text::escaped(&name, false).into_owned()
}

/// The y-axis width, points, that the plots linked in time (the four time plots and the
/// drift plot on the calibration log) all take, so that one time sits at one x in each: the
/// widest any of them needed so far for `log`'s plots (tick labels such as `-2.5e-5`, a
/// label on two lines), at least the time axes' own minimum. It grows within a frame or two
/// to the widest and never shrinks while the same log is shown.
pub fn linked_y_axis_width(ctx: &egui::Context, log: &Path) -> f32 {
    ctx.data(|d| d.get_temp::<f32>(linked_y_axis_id(log)))
        .unwrap_or(0.0)
        .max(super::plot_axes::TIME_Y_AXIS_MIN_WIDTH)
}

/// Tells [`linked_y_axis_width`] the y-axis width a linked plot took this frame (its frame's
/// left edge less its rectangle's).
pub fn note_linked_y_axis_width(
    ctx: &egui::Context,
    log: &Path,
    plot: egui::Rect,
    frame: egui::Rect,
) {
    let w = (frame.left() - plot.left()).ceil();
    if w.is_finite() && w > 0.0 {
        ctx.data_mut(|d| {
            let slot = d.get_temp_mut_or_insert_with(linked_y_axis_id(log), || 0.0f32);
            *slot = slot.max(w);
        });
    }
}

fn linked_y_axis_id(log: &Path) -> egui::Id {
    egui::Id::unique(("linked_y_axis_width", log))
}
