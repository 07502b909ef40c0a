//! What the selected model found: its description, coefficients with standard errors, the
//! non-linear parameters and the cost curves of their searches, and its export.

use super::ModelsView;
use super::{accessible, model_color, plain, swatch};
use crate::gui::action::Action;
use crate::gui::plot_items::num;
use crate::gui::state::AppState;
use crate::judge::compare::ModelReport;
use crate::models::fitted::DriftModel;
use crate::models::regression::RegressionModel;
use eframe::egui::{self, Grid, RichText, Ui};
use egui_plot::{Line, Plot, PlotPoints, Points, VLine};

impl ModelsView {
    pub(super) fn detail(&mut self, ui: &mut Ui, state: &AppState, out: &mut Vec<Action>) {
        let Some(c) = state.shown.models.clone() else {
            ui.heading("Model");
            ui.weak("What each model found appears here after a comparison.");
            return;
        };
        let fitted: Vec<&ModelReport> = c.reports.iter().filter(|r| r.fitted.is_some()).collect();
        ui.horizontal(|ui| {
            ui.heading("Model");
            let shown = self.selected.clone().unwrap_or_else(|| "—".into());
            let r = egui::ComboBox::from_id_salt("models_selected")
                .selected_text(&shown)
                .show_ui(ui, |ui| {
                    for r in &c.reports {
                        ui.selectable_value(&mut self.selected, Some(r.model.clone()), &r.model);
                    }
                })
                .response;
            accessible(&r, "Model shown", &shown);
            r.on_hover_text("The model whose coefficients and searches are shown");
        });
        let report = self
            .selected
            .as_ref()
            .and_then(|n| c.reports.iter().find(|r| &r.model == n));
        match report {
            None => {
                ui.weak("Click a model in the table.");
            }
            Some(r) => {
                ui.label(plain(&r.description));
                match (&r.fitted, &r.error) {
                    (_, Some(e)) => {
                        ui.colored_label(ui.visuals().error_fg_color, format!("Not fitted: {e}"));
                    }
                    (Some(DriftModel::Regression(rc)), _) => regression_detail(ui, &rc.model),
                    (Some(DriftModel::Vakhrameev(cal)), _) => {
                        ui.label(format!(
                            "K0(T), K1±(dT/dt), K2±(d²T/dt²) fitted with the workbench's recipe on {} \
                             samples; the Calibration page shows and edits them.",
                            cal.source.samples
                        ));
                        vakhrameev_detail(ui, cal);
                    }
                    (None, None) => {}
                }
            }
        }
        ui.separator();
        ui.heading("Export");
        if fitted.is_empty() {
            ui.weak("No model was fitted.");
            return;
        }
        // The model exported is the one selected in the table: nothing else is chosen.
        let chosen = self
            .selected
            .as_ref()
            .filter(|n| fitted.iter().any(|r| &r.model == *n));
        match chosen {
            Some(n) => {
                ui.label(format!(
                    "Writes the selected model, {n}, as a calibration file."
                ));
            }
            None => {
                ui.weak("Select a fitted model in the table to export it.");
            }
        }
        ui.add_space(4.0);
        let label = chosen.map_or("Export model…".to_string(), |n| format!("Export {n}…"));
        if ui
            .add_enabled(chosen.is_some(), egui::Button::new(label))
            .on_hover_text(
                "Write the selected model's calibration file (JSON), which `driftlab apply` and \
                 the gyro's processor read. File › Export calibration keeps writing the \
                 Vakhrameev calibration of the Calibration page.",
            )
            .clicked()
        {
            out.push(Action::ExportModel);
        }
    }
}

/// Each coefficient's curve and its knots, placed and set by hand or fitted, as the recipe
/// says (the engine's words, [`crate::models::vakhrameev::knots::Coefficient::knots_text`]).
fn vakhrameev_detail(ui: &mut Ui, cal: &crate::models::vakhrameev::Calibration) {
    use crate::files::session::Coefficient;
    Grid::new("vakhrameev_detail")
        .num_columns(3)
        .spacing([10.0, 2.0])
        .show(ui, |ui| {
            for c in Coefficient::ALL {
                let spec = c.spec(&cal.recipe);
                ui.label(RichText::new(c.label()).strong());
                ui.label(spec.kind.to_string());
                let text = c.knots_text(spec);
                if spec.hand_knots() {
                    ui.label(RichText::new(text).strong());
                } else {
                    ui.weak(text);
                }
                ui.end_row();
            }
        });
}

/// Coefficients with standard errors, the non-linear parameters found and the cost curves
/// of their searches.
fn regression_detail(ui: &mut Ui, m: &RegressionModel) {
    Grid::new("models_coefficients")
        .striped(true)
        .num_columns(3)
        .spacing([14.0, 2.0])
        .show(ui, |ui| {
            ui.label(RichText::new("term").strong());
            ui.label(RichText::new("coefficient").strong())
                .on_hover_text("°/h per unit of the term");
            ui.label(RichText::new("± std error").strong())
                .on_hover_text(
                    "White-noise assumption: correlated noise makes the real uncertainty larger",
                );
            ui.end_row();
            for (k, name) in m.names.iter().enumerate() {
                ui.monospace(name);
                ui.monospace(m.coefficients.get(k).copied().map(num).unwrap_or_default());
                ui.monospace(m.std_errors.get(k).copied().map(num).unwrap_or_default());
                ui.end_row();
            }
        });
    ui.add_space(4.0);
    Grid::new("models_found")
        .num_columns(2)
        .spacing([14.0, 2.0])
        .show(ui, |ui| {
            ui.label("λ (self-heating)");
            ui.monospace(m.lambda_s.map_or("—".into(), |v| format!("{} s", secs(v))));
            ui.end_row();
            ui.label("τd (delay)");
            ui.monospace(match m.delay.points.as_slice() {
                [] => "—".to_string(),
                [p] => format!("{} s", secs(p[1])),
                pts => pts
                    .iter()
                    .map(|p| format!("{} s at {} °C", secs(p[1]), crate::number::fixed(p[0], 1)))
                    .collect::<Vec<_>>()
                    .join("\n"),
            });
            ui.end_row();
            ui.label("lag of T");
            ui.monospace(m.lag_s.map_or("—".into(), |v| format!("{} s", secs(v))));
            ui.end_row();
            if let Some(t2) = &m.temp2 {
                ui.label("second sensor");
                ui.monospace(t2);
                ui.end_row();
            }
            ui.label("fit").on_hover_text(
                "Samples, RMS residual of the raw rate (the gyro's noise is part of it), R²",
            );
            ui.monospace(format!(
                "{} samples, RMS {} °/h, R² {}",
                m.stats.n,
                num(m.stats.rmse),
                crate::number::fixed(m.stats.r2, 3)
            ));
            ui.end_row();
        });
    if m.searches.is_empty() {
        ui.weak("No parameter was searched.");
        return;
    }
    for s in m.searches.iter().filter(|s| s.at_edge) {
        let beyond = if s.best > 0.0 {
            ": the optimum may lie beyond it"
        } else {
            ""
        };
        let (what, unit) = searched(&s.parameter);
        ui.colored_label(
            ui.visuals().warn_fg_color,
            format!(
                "{what}: the best value, {} {unit}, is an end of the range searched{beyond}",
                secs(s.best)
            ),
        );
    }
    ui.add_space(4.0);
    ui.strong("Cost of the searches").on_hover_text(
        "RMS residual of the fit at each value tried; the dashed line marks the value chosen",
    );
    let dark = ui.visuals().dark_mode;
    // One plot a search, each on its own axis with its own unit: a lag in seconds and its
    // change per °C cannot share an axis.
    for (k, s) in m.searches.iter().enumerate() {
        let color = model_color(k, dark);
        let (what, unit) = searched(&s.parameter);
        ui.horizontal_wrapped(|ui| {
            swatch(ui, color);
            ui.label(format!("{what}: best {} {unit}", secs(s.best)))
                .on_hover_text(format!("searched as {}", s.parameter));
        });
        Plot::new(("models_cost", k))
            .height(130.0)
            .x_axis_label(format!("{what}, {unit}"))
            .y_axis_label("RMS, °/h")
            .y_axis_min_width(56.0)
            .y_axis_formatter(fixed_tick)
            .x_axis_formatter(crate::gui::plot_items::tick_x)
            .x_grid_spacer(egui_plot::uniform_grid_spacer(
                crate::gui::plot_items::nice_steps,
            ))
            .y_grid_spacer(egui_plot::uniform_grid_spacer(
                crate::gui::plot_items::nice_steps,
            ))
            .allow_zoom(false)
            .allow_drag(false)
            .allow_scroll(false)
            .show(ui, |pui| {
                let pts: Vec<[f64; 2]> =
                    s.x.iter()
                        .zip(&s.rmse)
                        .filter(|(x, y)| x.is_finite() && y.is_finite())
                        .map(|(&x, &y)| [x, y])
                        .collect();
                pui.line(
                    Line::new(s.parameter.clone(), PlotPoints::from(pts.clone()))
                        .color(color)
                        .width(1.5),
                );
                pui.add(
                    Points::new(s.parameter.clone(), PlotPoints::from(pts))
                        .color(color)
                        .radius(2.0),
                );
                pui.add(
                    VLine::new(s.parameter.clone(), s.best)
                        .color(color)
                        .width(1.0)
                        .style(egui_plot::LineStyle::dashed_dense()),
                );
            });
    }
}

/// What a search's parameter is, in words, and its unit (`lag_per_c` is the lag's change per
/// °C; the others are times).
fn searched(parameter: &str) -> (String, &'static str) {
    if parameter.starts_with("lag_per_c") {
        ("β, the lag's change per °C".into(), "1/°C")
    } else if let Some(rest) = parameter.strip_prefix("lag_s") {
        let at = rest
            .trim()
            .strip_prefix("at ")
            .map(|r| format!(" (β = {})", r.replace(" per degC", " /°C")))
            .unwrap_or_default();
        (format!("lag τ20{at}"), "s")
    } else if parameter.starts_with("lambda_s") {
        ("λ, self-heating".into(), "s")
    } else if let Some(rest) = parameter.strip_prefix("delay_s") {
        let at = rest
            .trim()
            .strip_prefix("at ")
            .map(|r| format!(" at {}", r.replace(" degC", " °C")))
            .unwrap_or_default();
        (format!("delay τd{at}"), "s")
    } else {
        (parameter.to_string(), "")
    }
}

/// A tick label with as many decimals as the visible range needs, the same for every label,
/// never in scientific notation (the cost of a search often changes in its fourth digit only).
fn fixed_tick(mark: egui_plot::GridMark, range: &std::ops::RangeInclusive<f64>) -> String {
    if !crate::gui::plot_items::label_fits(
        mark.value,
        range,
        crate::gui::plot_items::Y_LABEL_MARGIN,
    ) {
        return String::new();
    }
    let span = (range.end() - range.start()).abs() / 5.0;
    let decimals = if span > 0.0 && span.is_finite() {
        ((-span.log10().floor()).max(0.0) as usize).min(9)
    } else {
        4
    };
    format!("{:.decimals$}", mark.value)
}

/// Seconds as the details show them: 0 as "0", else about four significant digits.
fn secs(v: f64) -> String {
    if v == 0.0 { "0".into() } else { num(v) }
}
