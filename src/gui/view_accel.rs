//! An accelerometer axis of a unit, on the Calibration page in place of the gyro axis's plots:
//! what the engine fitted (its static model, the mean its correction keeps, the axis that
//! carries gravity), its figures raw against corrected, in-sample and, with a validation log
//! open, held out (as `driftlab evaluate` judges the axis there), in the figures panel's
//! tables ([`super::view_figures::axis_table`]), and its change about the kept mean against
//! time and against T, every figure and plot in m/s², the unit of its kind
//! ([`AxisKind::unit`]). It has no choices of its own: the unit's T, smoothing and plateaus
//! are its, and its model is the one `calibrate --accel` gives it.

use super::action::Action;
use super::jobs::{AccelAxisView, AccelFit};
use super::plot_items::{Palette, num};
use super::state::AppState;
use super::view_figures::{Scale, axis_table};
use crate::log::AxisKind;
use crate::models::accel::Gravity;
use eframe::egui::{RichText, Ui};
use egui_plot::{Corner, Legend, Line, Plot, PlotPoints, Points};

/// The unit an accelerometer's figures are in.
const UNIT: &str = AxisKind::Accel.unit();

/// The accelerometer axis view (no state of its own).
#[derive(Debug, Default)]
pub struct AccelView;

impl AccelView {
    /// Accelerometer axis `k` of the unit.
    pub fn ui(&mut self, ui: &mut Ui, state: &AppState, k: usize) -> Vec<Action> {
        let out = Vec::new();
        let Some(accel) = &state.accel else {
            return out;
        };
        let name = accel.names.get(k).map(String::as_str).unwrap_or_default();
        let current = state.accel_current();
        let fit = accel.fit.as_ref().map(|f| &f.result);
        ui.horizontal_wrapped(|ui| {
            ui.heading(format!("Accelerometer axis {name}"));
            ui.label(RichText::new(format!("figures and plots in {UNIT}")).weak());
            if !current {
                ui.spinner();
            }
        });
        let fit = match fit {
            Some(Ok(f)) => f,
            Some(Err(e)) => {
                ui.colored_label(ui.visuals().error_fg_color, e);
                return out;
            }
            None => {
                ui.label("calibrating…");
                return out;
            }
        };
        let Some(axis) = fit.axes.iter().find(|a| a.fitted.name == name) else {
            ui.label(format!("axis {name} is not in the calibration"));
            return out;
        };
        summary(ui, axis, fit);
        figures(ui, state, axis, fit, current);
        ui.separator();
        plots(ui, axis);
        out
    }
}

/// The model, the kept mean, gravity and the figures.
fn summary(ui: &mut Ui, axis: &AccelAxisView, fit: &AccelFit) {
    let f = &axis.fitted;
    let column = if f.rate_column.is_empty() {
        String::new()
    } else {
        format!(" from column {}", f.rate_column)
    };
    ui.label(format!(
        "Model {} (a curve in T alone: an accelerometer's bias follows its die's temperature){column}.",
        f.calibrated.model.name()
    ));
    if let Some(mean) = f.kept_mean {
        ui.label(format!(
            "Fitted about its mean on the calibration log, {} {UNIT}, which its correction \
             keeps: the figures are of its change with T.",
            num(mean)
        ));
    }
    match &fit.gravity {
        Some(g) => {
            ui.label(RichText::new(gravity_text(g)).strong());
        }
        None => {
            ui.label("Gravity: no accelerometer axis reads half of g or more.");
        }
    }
    for w in f.calibrated.warnings.iter().chain(&fit.warnings) {
        ui.colored_label(ui.visuals().warn_fg_color, w);
    }
}

/// Its figures in the figures panel's tables: in-sample on the calibration log, and beside
/// them, with a validation log open, held out on it (or why it could not be judged there).
fn figures(ui: &mut Ui, state: &AppState, axis: &AccelAxisView, fit: &AccelFit, exact: bool) {
    let window = crate::judge::options::window_label(fit.merit.window_s);
    let scale = Scale {
        window: &window,
        kind: AxisKind::Accel,
    };
    let name = |l: &Option<super::jobs::Loaded>| {
        l.as_ref()
            .map(|l| format!("{} · axis {}", l.name(), axis.fitted.name))
            .unwrap_or_default()
    };
    ui.horizontal_top(|ui| {
        axis_table(
            ui,
            "accel_in",
            &format!("In-sample · {}", name(&state.shown.log)),
            &axis.fitted.calibrated.in_sample,
            exact,
            scale,
        );
        // (space, not a separator: a separator in a row takes the page's whole height, and
        // the plots below would have none)
        ui.add_space(24.0);
        match &axis.held_out {
            Some(Ok(h)) => {
                ui.vertical(|ui| {
                    // (a validation log that is the calibration log's own run is said so)
                    let title = if h.in_sample {
                        format!("{} · {}", h.label, name(&state.shown.validation))
                    } else {
                        format!("Held out · {}", name(&state.shown.validation))
                    };
                    axis_table(ui, "accel_out", &title, &h.evaluation, exact, scale);
                    if let Some(note) = &h.note {
                        ui.colored_label(ui.visuals().warn_fg_color, note);
                    }
                });
            }
            Some(Err(why)) => {
                ui.vertical(|ui| {
                    ui.strong("Held out");
                    ui.colored_label(ui.visuals().warn_fg_color, format!("Not judged: {why}"));
                });
            }
            None => {
                ui.vertical(|ui| {
                    ui.strong("Held out");
                    ui.weak(
                        "Open a validation log (File › Open validation log…)\nto judge the \
                         calibration on a run it was not fitted on.",
                    );
                });
            }
        }
    });
}

/// The gravity sentence, as `calibrate` prints it, in the window's words.
pub fn gravity_text(g: &Gravity) -> String {
    let change = match g.scale_change_per_c {
        Some(c) => format!(
            "; its reading changes by {} ppm/°C of its mean over {} … {} °C (its scale \
             factor's change with T, its bias's included: one orientation cannot part them)",
            num(c * 1e6),
            num(g.range_c.0),
            num(g.range_c.1)
        ),
        None => String::new(),
    };
    format!(
        "Gravity: axis {} carries it (mean {} {UNIT} on the calibration log, kept by its \
         correction){change}",
        g.axis,
        num(g.mean_m_s2)
    )
}

/// The change about the kept mean against time (raw and corrected) and against T (with the
/// model), side by side where the page is wide, else one above the other.
fn plots(ui: &mut Ui, axis: &AccelAxisView) {
    let pal = Palette::of(ui);
    let wide = ui.available_width() > 900.0;
    let h = if wide {
        ui.available_height()
    } else {
        ui.available_height() / 2.0 - ui.spacing().item_spacing.y
    }
    .max(140.0);
    let w = if wide {
        ui.available_width() / 2.0 - ui.spacing().item_spacing.x
    } else {
        ui.available_width()
    };
    let legend = || Legend::default().position(Corner::RightTop);
    let y_label = format!("change about the kept mean, {UNIT}");
    let time_plot = |ui: &mut Ui| {
        Plot::new("accel_time")
            .width(w)
            .height(h)
            .legend(legend())
            .x_axis_label("time, h")
            .y_axis_label(y_label.clone())
            .y_axis_min_width(64.0)
            .show(ui, |pui| {
                pui.line(
                    Line::new("raw", PlotPoints::from(axis.raw_t.clone()))
                        .color(pal.raw)
                        .width(1.0),
                );
                pui.line(
                    Line::new("corrected", PlotPoints::from(axis.cor_t.clone()))
                        .color(pal.corrected)
                        .width(1.2),
                );
            });
    };
    let temp_plot = |ui: &mut Ui| {
        Plot::new("accel_temp")
            .width(w)
            .height(h)
            .legend(legend())
            .x_axis_label("T, °C")
            .y_axis_label(y_label.clone())
            .y_axis_min_width(64.0)
            .show(ui, |pui| {
                pui.add(
                    Points::new("raw", PlotPoints::from(axis.raw_temp.clone()))
                        .color(pal.raw)
                        .radius(1.2),
                );
                pui.line(
                    Line::new("model", PlotPoints::from(axis.model_temp.clone()))
                        .color(pal.model)
                        .width(2.0),
                );
            });
    };
    if wide {
        ui.horizontal(|ui| {
            time_plot(ui);
            temp_plot(ui);
        });
    } else {
        time_plot(ui);
        temp_plot(ui);
    }
}
