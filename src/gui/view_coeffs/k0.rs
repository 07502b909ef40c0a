//! K0(T): the plateau points (mean output against mean temperature, ±1 std) with the fitted
//! curve, held flat beyond the plateaus, its approximation controls, and its knots placed by
//! hand as on the K1 and K2 plots (`knots.rs`).

use super::knots::{draw_knots, shown};
use super::{CoeffView, K0_SLOT};
use crate::files::session::Coefficient;
use crate::gui::action::{Action, Edit};
use crate::gui::plot_items::{Palette, num};
use crate::gui::state::AppState;
use crate::gui::widgets::{approx_controls, save_plot_entry};
use eframe::egui::{self, Ui};
use egui_plot::{Line, LineStyle, MarkerShape, Plot, PlotPoints, Points};

impl CoeffView {
    /// The K0(T) plot with its approximation controls.
    pub(super) fn k0(&mut self, ui: &mut Ui, state: &AppState, height: f32, out: &mut Vec<Action>) {
        let pal = Palette::of(ui);
        let dark = ui.visuals().dark_mode;
        ui.horizontal_wrapped(|ui| {
            ui.strong("K0(T)")
                .on_hover_text("Static bias: mean output on each plateau against its temperature");
            let now = &state.shown.choices.recipe.k0;
            let mut spec = now.clone();
            let asks = approx_controls(ui, "k0", "K0", &mut spec);
            if spec != *now {
                out.push(Action::Edit(Edit::Approx(Coefficient::K0, spec)));
            }
            if asks.reset {
                out.push(Action::Edit(Edit::Approx(
                    Coefficient::K0,
                    now.without_hand_knots(),
                )));
            }
            if asks.table {
                self.open_knot_table(Coefficient::K0);
            }
            if ui
                .small_button("PNG")
                .on_hover_text("Save the K0 plot as PNG")
                .clicked()
            {
                out.push(Action::SavePlotNamed("k0".into()));
            }
        });
        let fit = state.shown.fit.clone();
        let coefs = [Coefficient::K0];
        let pending = self.drag_knot(ui, state, K0_SLOT, &coefs, out);
        let dragging = self.drag.is_some();
        let rule = self.bounds_rule(K0_SLOT, &coefs);
        let resp = ui.scope(|ui| {
            Plot::new("k0_plot")
                .allow_drag(!dragging)
                .allow_boxed_zoom(!dragging)
                // The wheel scrolls the panel (Ctrl+wheel zooms the plot).
                .allow_scroll(false)
                .height(height)
                .x_axis_label("T, °C")
                .y_axis_label("K0, °/h")
                .y_axis_min_width(56.0)
                .y_axis_formatter(crate::gui::plot_items::tick_y)
                .x_axis_formatter(crate::gui::plot_items::tick_x)
                .x_grid_spacer(egui_plot::uniform_grid_spacer(
                    crate::gui::plot_items::nice_steps,
                ))
                .y_grid_spacer(egui_plot::uniform_grid_spacer(
                    crate::gui::plot_items::nice_steps,
                ))
                .show(ui, |pui| {
                    let auto = rule.apply(pui);
                    if fit.is_none() {
                        return auto;
                    }
                    // A plateau edge being dragged: its plateaus and K0 as they will be.
                    let plateaus = state.plateau_stats();
                    let pts: Vec<[f64; 2]> =
                        plateaus.iter().map(|p| [p.temp_c, p.omega_dph]).collect();
                    // A plateau of one sample has no spread to draw.
                    for (p, std) in plateaus.iter().filter_map(|p| Some((p, p.omega_std_dph?))) {
                        pui.line(
                            Line::new(
                                "±1 std",
                                PlotPoints::new(vec![
                                    [p.temp_c, p.omega_dph - std],
                                    [p.temp_c, p.omega_dph + std],
                                ]),
                            )
                            .color(Palette::shade(pal.plateau, 0.6))
                            .width(1.0)
                            .allow_hover(false),
                        );
                    }
                    let previewed = state.shown.preview.as_ref().map(|p| p.preview.k0.clone());
                    let Some(k0) =
                        previewed.or_else(|| shown(state, Coefficient::K0, pending.as_ref()))
                    else {
                        return auto;
                    };
                    let k0 = &k0;
                    let (lo, hi) = (k0.x_min(), k0.x_max());
                    let pad = ((hi - lo) * 0.15).max(2.0);
                    let curve = |a: f64, b: f64| -> Vec<[f64; 2]> {
                        (0..=100)
                            .map(|j| {
                                let x = a + (b - a) * j as f64 / 100.0;
                                [x, k0.eval(x)]
                            })
                            .collect()
                    };
                    pui.line(
                        Line::new(
                            format!("K0 ({})", k0.kind()),
                            PlotPoints::new(curve(lo, hi)),
                        )
                        .color(pal.curve)
                        .width(2.0),
                    );
                    for (a, b) in [(lo - pad, lo), (hi, hi + pad)] {
                        pui.line(
                            Line::new("held beyond the plateaus", PlotPoints::new(curve(a, b)))
                                .color(pal.curve)
                                .style(LineStyle::dashed_dense())
                                .width(1.0),
                        );
                    }
                    match state.shown.log.as_ref().filter(|l| l.log.runs().len() > 1) {
                        Some(l) => campaign_points(pui, state, &l.log, &plateaus, dark),
                        None => pui.points(
                            Points::new("plateaus", PlotPoints::new(pts))
                                .shape(MarkerShape::Circle)
                                .radius(5.0)
                                .filled(true)
                                .color(pal.plateau),
                        ),
                    }
                    let spec = match &pending {
                        Some((_, spec)) => spec,
                        None => &state.shown.choices.recipe.k0,
                    };
                    draw_knots(pui, "K0", k0, spec, pal.curve);
                    auto
                })
        });
        self.note_auto(K0_SLOT, rule, resp.inner.inner);
        let response = &resp.inner.response;
        self.transforms[K0_SLOT] = Some(resp.inner.transform);
        self.hovered[K0_SLOT] = response.hovered();
        self.knot_clicks(ui, state, K0_SLOT, &coefs, response, out);
        response.context_menu(|ui| {
            self.knot_menu(ui, state, &coefs, out);
            if save_plot_entry(ui) {
                out.push(Action::SavePlotNamed("k0".into()));
            }
        });
        out.push(Action::PlotRect("k0".into(), resp.response.rect));
        match fit {
            Some(_) if state.shown.preview.is_some() => {
                ui.weak("Plateaus and K0 as the edge leaves them; K1, K2 and the drift follow its release")
                    .on_hover_text(
                        "While a plateau edge is dragged only its plateaus and K0 are recomputed \
                         (they read the plateaus' samples alone); every axis is refitted when the \
                         mouse button is released",
                    );
            }
            Some(f) => {
                let s = f.outcome.calibration.k0.stats();
                ui.weak(format!(
                    "{} plateaus · RMSE {} °/h · R² {}",
                    s.n,
                    crate::number::or_na(s.computed_rmse(), num),
                    crate::number::or_na(s.computed_r2(), |v| format!("{v:.4}"))
                ))
                .on_hover_text("Fit statistics of K0 over the plateau points");
            }
            None if state.shown.fit_error.is_some() => {
                ui.weak("No fit: the calibration failed (its message is in the status bar).");
            }
            None => {
                ui.weak("No fit yet.");
            }
        }
    }
}

/// A campaign's plateau points, each run in its own colour (named in the legend), and at each
/// temperature that two plateaus or more share the spread of their biases: a bar from the
/// smallest to the largest (the repeatability the calibration records, at its default
/// tolerance).
fn campaign_points(
    pui: &mut egui_plot::PlotUi<'_>,
    state: &AppState,
    log: &crate::log::Log,
    plateaus: &[crate::signal::plateau::PlateauStats],
    dark: bool,
) {
    let ranges: Vec<_> = plateaus.iter().map(|p| p.range).collect();
    let runs = crate::models::campaign::run_of_each(log, &ranges);
    if let Some(f) = &state.shown.fit {
        let tolerance = crate::models::campaign::DEFAULT_TOLERANCE_C;
        for g in crate::judge::campaign::repeatability(&f.outcome.runs, tolerance) {
            let (lo, hi) = g
                .values
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(*v), b.max(*v))
                });
            if lo.is_finite() && hi.is_finite() {
                pui.line(
                    Line::new(
                        "spread at a shared temperature",
                        PlotPoints::new(vec![[g.temp_c, lo], [g.temp_c, hi]]),
                    )
                    .color(if dark {
                        egui::Color32::from_gray(200)
                    } else {
                        egui::Color32::from_gray(60)
                    })
                    .width(3.0)
                    .allow_hover(false),
                );
            }
        }
    }
    for (k, run) in log.runs().iter().enumerate() {
        let pts: Vec<[f64; 2]> = plateaus
            .iter()
            .zip(&runs)
            .filter(|(_, r)| **r == Some(k))
            .map(|(p, _)| [p.temp_c, p.omega_dph])
            .collect();
        if pts.is_empty() {
            continue;
        }
        pui.points(
            Points::new(format!("run {} {}", k + 1, run.name), PlotPoints::new(pts))
                .shape(MarkerShape::Circle)
                .radius(5.0)
                .filled(true)
                .color(crate::gui::view_runs::run_color(k, dark)),
        );
    }
    // A range placed by hand across two runs is a plateau of neither: drawn hollow.
    let neither: Vec<[f64; 2]> = plateaus
        .iter()
        .zip(&runs)
        .filter(|(_, r)| r.is_none())
        .map(|(p, _)| [p.temp_c, p.omega_dph])
        .collect();
    if !neither.is_empty() {
        pui.points(
            Points::new(
                "across two runs (a plateau of neither)",
                PlotPoints::new(neither),
            )
            .shape(MarkerShape::Circle)
            .radius(5.0)
            .filled(false),
        );
    }
}
