//! The plots' axes and numbers: the time axis's unit by the log's length, tick marks and
//! their labels, axis labels that fit the plot's height, and numbers and durations written
//! for a plot or a table.

use eframe::egui;
use std::ops::RangeInclusive;

/// How time is shown on the x-axis: seconds, minutes or hours, by the log's length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeScale {
    /// Seconds per axis unit.
    pub div: f64,
    /// Axis unit.
    pub unit: &'static str,
}

impl TimeScale {
    /// The scale for a log lasting `duration_s`.
    pub fn for_duration(duration_s: f64) -> TimeScale {
        if duration_s >= 3.0 * 3600.0 {
            TimeScale {
                div: 3600.0,
                unit: "h",
            }
        } else if duration_s >= 600.0 {
            TimeScale {
                div: 60.0,
                unit: "min",
            }
        } else {
            TimeScale {
                div: 1.0,
                unit: "s",
            }
        }
    }
}

/// A number formatted to about four significant digits, in scientific notation when tiny or
/// huge.
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return if v.is_nan() {
            "—".into()
        } else {
            "∞".into()
        };
    }
    let a = v.abs();
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        format!("{v:.3e}")
    } else if a >= 100.0 {
        format!("{v:.1}")
    } else if a >= 1.0 {
        format!("{v:.3}")
    } else {
        format!("{v:.4}")
    }
}

/// A duration for a person: seconds, minutes or hours, about three digits.
pub fn duration(s: f64) -> String {
    if !s.is_finite() {
        "n/a".into()
    } else if s >= 3600.0 {
        format!("{:.2} h", s / 3600.0)
    } else if s >= 60.0 {
        format!("{:.1} min", s / 60.0)
    } else {
        format!("{} s", num(s))
    }
}

/// True when a tick at `v` sits far enough inside `range` for its label to be drawn whole: a
/// label centred on a tick at an end of the axis is half outside the plot and is clipped
/// ("10000" read as "100").
pub fn label_fits(v: f64, range: &RangeInclusive<f64>, margin: f64) -> bool {
    let (a, b) = (
        range.start().min(*range.end()),
        range.start().max(*range.end()),
    );
    let m = (b - a) * margin;
    v >= a + m && v <= b - m
}

/// The smallest font a y-axis label is shrunk to, points (below it, it no longer reads).
pub const MIN_AXIS_LABEL_SIZE: f32 = 9.0;

/// A y-axis label that fits a plot `height` points tall, always on one line: "name, unit" in
/// the body font when it fits, else in a font as much smaller as it needs (not under
/// [`MIN_AXIS_LABEL_SIZE`]). A label broken onto two lines takes the y-axis a second column
/// of text, so that one plot's axis is wider than its neighbours' and reads as two labels.
pub fn axis_label(ctx: &egui::Context, label: &str, height: f32) -> egui::RichText {
    egui::RichText::new(label).size(axis_label_size(ctx, label, height))
}

/// The font size of [`axis_label`], points.
pub fn axis_label_size(ctx: &egui::Context, label: &str, height: f32) -> f32 {
    let body = egui::TextStyle::Body.resolve(&ctx.global_style()).size;
    let long = label_width(ctx, label, body);
    let room = height * 0.95;
    if long <= room {
        body
    } else {
        (body * room / long).max(MIN_AXIS_LABEL_SIZE)
    }
}

/// The length of `label` laid out on one line in the body font at `size` points.
pub fn label_width(ctx: &egui::Context, label: &str, size: f32) -> f32 {
    let font = egui::FontId::new(
        size,
        egui::TextStyle::Body.resolve(&ctx.global_style()).family,
    );
    ctx.fonts_mut(|f| {
        f.layout_no_wrap(label.to_string(), font, egui::Color32::WHITE)
            .size()
            .x
    })
}

/// Share of an x-axis kept clear of labels at each end (half a label's width on a plot a few
/// hundred points wide).
pub const X_LABEL_MARGIN: f64 = 0.035;

/// Share of a y-axis kept clear of labels at each end (half a label's height).
pub const Y_LABEL_MARGIN: f64 = 0.04;

/// The narrowest y-axis of a time plot, points.
pub const TIME_Y_AXIS_MIN_WIDTH: f32 = 64.0;

/// A time plot's axes as every page draws them: the value and time ticks, and grid lines at
/// round steps.
pub fn with_time_axes(plot: egui_plot::Plot<'_>) -> egui_plot::Plot<'_> {
    plot.y_axis_min_width(TIME_Y_AXIS_MIN_WIDTH)
        .y_axis_formatter(tick_y)
        .x_axis_formatter(tick_x)
        .x_grid_spacer(egui_plot::uniform_grid_spacer(nice_steps_x))
        .y_grid_spacer(egui_plot::uniform_grid_spacer(nice_steps))
}

/// The span of the log's time (s) a time plot shows, its x axis being in seconds over `div`:
/// `full` before the plot has bounds.
pub fn shown_span(pui: &egui_plot::PlotUi<'_>, div: f64, full: (f64, f64)) -> (f64, f64) {
    let b = pui.plot_bounds();
    if b.is_valid_x() && b.width() > 0.0 {
        (b.min()[0] * div, b.max()[0] * div)
    } else {
        full
    }
}

/// [`tick`] for an x-axis: no label where it would be cut at either end.
pub fn tick_x(mark: egui_plot::GridMark, range: &RangeInclusive<f64>) -> String {
    if label_fits(mark.value, range, X_LABEL_MARGIN) {
        tick(mark, range)
    } else {
        String::new()
    }
}

/// [`tick`] for a y-axis: no label where it would be cut at the top or the bottom.
pub fn tick_y(mark: egui_plot::GridMark, range: &RangeInclusive<f64>) -> String {
    if label_fits(mark.value, range, Y_LABEL_MARGIN) {
        tick(mark, range)
    } else {
        String::new()
    }
}

/// An axis tick label: as many decimals as the tick step needs, scientific notation for
/// tiny or huge steps (rates in °C/s² are of order 1e-5).
pub fn tick(mark: egui_plot::GridMark, _range: &RangeInclusive<f64>) -> String {
    let (v, step) = (mark.value, mark.step_size.abs());
    if v == 0.0 {
        return "0".into();
    }
    if step > 0.0 && !(1e-3..1e5).contains(&step) {
        let e = step.log10().floor();
        let mant_decimals = ((v.abs().log10().floor() - e).max(0.0) as usize).min(4);
        return format!("{v:.mant_decimals$e}");
    }
    let decimals = if step > 0.0 {
        (-step.log10().floor()).max(0.0) as usize
    } else {
        3
    };
    format!("{v:.decimals$}")
}

/// Grid steps of 1, 2 or 5 × 10^k giving about four labelled lines over the visible range
/// (egui_plot's default powers of ten leave a short plot with a single label).
pub fn nice_steps(input: egui_plot::GridInput) -> [f64; 3] {
    nice_steps_n(input, 4.0)
}

/// [`nice_steps`] for a wide x-axis: about eight labelled lines.
pub fn nice_steps_x(input: egui_plot::GridInput) -> [f64; 3] {
    nice_steps_n(input, 8.0)
}

fn nice_steps_n(input: egui_plot::GridInput, labels: f64) -> [f64; 3] {
    let span = (input.bounds.1 - input.bounds.0).abs();
    let target = (span / labels)
        .max(input.base_step_size)
        .max(f64::MIN_POSITIVE);
    let p = 10f64.powf(target.log10().floor());
    let major = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&s| s >= target)
        .unwrap_or(10.0 * p);
    [major / 5.0, major, major * 5.0]
}

/// A ratio as shown in the figures, to three significant digits ("4.72×", "14.4×", "0.990×"),
/// so that a ratio coloured as below 1 never reads "1.00×".
pub fn ratio(r: f64) -> String {
    if !r.is_finite() {
        return if r.is_nan() {
            "n/a".into()
        } else {
            "∞".into()
        };
    }
    let a = r.abs();
    if a >= 100.0 {
        format!("{}×", crate::number::fixed(r, 0))
    } else if a >= 10.0 {
        format!("{r:.1}×")
    } else if a >= 1.0 || a == 0.0 {
        format!("{r:.2}×")
    } else {
        // Three significant digits below 1: 0.990×, 0.0123×.
        let decimals = (2.0 - a.log10().floor()) as usize;
        format!("{r:.decimals$}×")
    }
}
