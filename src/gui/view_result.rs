//! The result, live: raw and corrected drift over time (on the calibration log, sharing the
//! time axis of the run, or on the held-out validation log), and the figures of merit with
//! the reduction ratios, in-sample and held out.

use super::app::Action;
use super::plot_items::{BandItem, Palette, ShadeItem, ShadeSpan, TimeScale, num, ratio};
use super::state::AppState;
use super::view_time::time_link;
use crate::judge::metrics::Evaluation;
use eframe::egui::{Grid, RichText, Stroke, Ui, Vec2b};
use egui_plot::{HLine, Legend, Plot};

/// View state of the result plot.
#[derive(Default)]
pub struct ResultView;

impl ResultView {
    /// The result plot with its header.
    pub fn ui(&mut self, ui: &mut Ui, state: &mut AppState, out: &mut Vec<Action>) {
        let pal = Palette::of(ui);
        let has_val = state.validation.is_some();
        if !has_val {
            state.view.show_validation = false;
        }
        ui.horizontal_wrapped(|ui| {
            ui.strong("Drift before and after correction")
                .on_hover_text(
                    "Ω filtered by the recipe's moving average: raw (grey) and corrected (green)",
                );
            ui.separator();
            ui.radio_value(&mut state.view.show_validation, false, "calibration log")
                .on_hover_text("In-sample: the log the calibration was fitted on");
            ui.add_enabled_ui(has_val, |ui| {
                ui.radio_value(&mut state.view.show_validation, true, "validation log")
                    .on_hover_text(
                        "Held out: a second log of the same gyro, corrected with this calibration",
                    );
            });
            if !has_val
                && ui
                    .button("Open validation log…")
                    .on_hover_text(
                        "Load a second log of the same gyro to judge the calibration held out",
                    )
                    .clicked()
            {
                out.push(Action::OpenValidation);
            }
            if ui
                .small_button("PNG")
                .on_hover_text("Save the result plot as PNG")
                .clicked()
            {
                out.push(Action::SavePlotNamed("result".into()));
            }
        });
        let Some(fit) = state.fit.clone() else {
            ui.weak("No calibration yet.");
            return;
        };
        let show_val = state.view.show_validation && fit.outcome.held_out.is_some();
        let (judged, raw_p, cor_p, regime) = if show_val {
            let (Some(h), Some(l)) = (fit.outcome.held_out.as_ref(), fit.lods.held_out.as_ref())
            else {
                return;
            };
            (h, &l.raw_filtered, &l.cor_filtered, &l.regime)
        } else {
            (
                &fit.outcome.in_sample,
                &fit.lods.raw_filtered,
                &fit.lods.cor_filtered,
                &*fit.lods.regime,
            )
        };
        let log = judged.log.clone();
        if log.is_empty()
            || judged.cor_filtered_dph.len() != log.len()
            || judged.raw_filtered_dph.len() != log.len()
        {
            return;
        }
        let scale = TimeScale::for_duration(log.duration_s());
        let t_full = (log.time_s[0], log.time_s[log.len() - 1]);
        let mut plot = Plot::new(if show_val { "result_val" } else { "result_cal" })
            .height(ui.available_height().max(80.0))
            .legend(Legend::default().position(egui_plot::Corner::LeftTop))
            .x_axis_label(format!("time, {}", scale.unit))
            .y_axis_label("drift, °/h")
            .y_axis_min_width(64.0)
            .y_axis_formatter(super::plot_items::tick_y)
            .x_axis_formatter(super::plot_items::tick_x)
            .x_grid_spacer(egui_plot::uniform_grid_spacer(
                super::plot_items::nice_steps_x,
            ))
            .y_grid_spacer(egui_plot::uniform_grid_spacer(
                super::plot_items::nice_steps,
            ))
            .allow_zoom(Vec2b::new(true, false))
            .allow_drag(Vec2b::new(true, false))
            .allow_scroll(Vec2b::new(true, false));
        if !show_val {
            plot = plot
                .link_axis(time_link(), Vec2b::new(true, false))
                .link_cursor(time_link(), Vec2b::new(true, false));
        }
        let resp = ui.scope(|ui| {
            plot.show(ui, |pui| {
                let b = pui.plot_bounds();
                let (x0, x1) = if b.is_valid_x() && b.width() > 0.0 {
                    (b.min()[0] * scale.div, b.max()[0] * scale.div)
                } else {
                    t_full
                };
                let cols = pui.response().rect.width().max(50.0) as usize;
                let spans = regime
                    .runs(&log.time_s, x0, x1, cols / 2)
                    .into_iter()
                    .map(|r| ShadeSpan {
                        x0: r.t0 / scale.div,
                        x1: r.t1 / scale.div,
                        fill: Palette::shade(if r.class == 1 { pal.plus } else { pal.minus }, 0.07),
                        edge: Stroke::NONE,
                    })
                    .collect();
                pui.add(ShadeItem::new("", spans));
                pui.hline(
                    HLine::new("", 0.0)
                        .color(pal.deadband)
                        .width(1.0)
                        .allow_hover(false),
                );
                let raw = crate::signal::lod::reduce(
                    &log.time_s,
                    &judged.raw_filtered_dph,
                    raw_p,
                    x0,
                    x1,
                    cols,
                );
                pui.add(
                    BandItem::new("raw", raw, scale.div, t_full)
                        .color(pal.raw)
                        .width(1.6),
                );
                let cor = crate::signal::lod::reduce(
                    &log.time_s,
                    &judged.cor_filtered_dph,
                    cor_p,
                    x0,
                    x1,
                    cols,
                );
                pui.add(
                    BandItem::new("corrected", cor, scale.div, t_full)
                        .color(pal.corrected)
                        .width(1.8),
                );
            })
        });
        resp.inner.response.context_menu(|ui| {
            if ui
                .button("Save this plot as PNG…")
                .on_hover_text("Write this plot alone as a PNG picture")
                .clicked()
            {
                out.push(Action::SavePlotNamed("result".into()));
                ui.close();
            }
        });
        out.push(Action::PlotRect("result".into(), resp.response.rect));
    }

    /// The figures of merit, always visible.
    pub fn figures(ui: &mut Ui, state: &AppState) {
        let Some(fit) = state.fit.as_ref() else {
            ui.weak("Figures of merit appear once the log is calibrated.");
            return;
        };
        let name = |l: &Option<super::jobs::Loaded>| {
            l.as_ref()
                .and_then(|l| l.path.file_name())
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
        };
        // While a refit is on its way (a knot being dragged on a long log) the figures are those
        // of the choices a moment ago: shown greyed and marked, never passed off as the
        // current ones.
        let exact = state.fit_current();
        ui.horizontal_top(|ui| {
            table(
                ui,
                "fig_in",
                &format!("In-sample · {}", name(&state.log)),
                &fit.outcome.in_sample.evaluation,
                exact,
            );
            ui.separator();
            match &fit.outcome.held_out {
                Some(h) => table(
                    ui,
                    "fig_out",
                    &format!("Held out · {}", name(&state.validation)),
                    &h.evaluation,
                    exact,
                ),
                None => {
                    ui.vertical(|ui| {
                        ui.strong("Held out");
                        ui.weak("Open a validation log (File › Open validation log…)\nto judge the calibration on a run it was not fitted on.");
                    });
                }
            }
            ui.separator();
            ui.vertical(|ui| {
                let t = fit.outcome.timings;
                ui.strong("Refit");
                ui.label(format!("{:.1} ms", t.total_ms)).on_hover_text(format!(
                    "Last refit on the worker thread: prepare {:.1} ms, plateaus {:.1} ms, K1/K2 {:.1} ms, \
                     correct {:.1} ms, figures {:.1} ms, validation {:.1} ms (0: reused)",
                    t.prepare_ms, t.plateaus_ms, t.fit_ms, t.correct_ms, t.evaluate_ms, t.validation_ms
                ));
                for w in fit.outcome.warnings.iter().take(3) {
                    ui.colored_label(ui.visuals().warn_fg_color, format!("! {w}"))
                        .on_hover_text(w.as_str());
                }
            });
        });
    }
}

fn table(ui: &mut Ui, id: &str, title: &str, e: &Evaluation, exact: bool) {
    let c = &e.comparison;
    ui.vertical(|ui| {
        ui.horizontal(|ui| {
            ui.strong(title);
            if !exact {
                ui.label(
                    RichText::new("provisional")
                        .italics()
                        .color(ui.visuals().warn_fg_color),
                )
                .on_hover_text(
                    "These figures are those of the choices a moment ago: the refit for the \
                     current ones is on its way",
                );
            }
        })
        .response
        .on_hover_text(format!(
            "{} samples after {} warm-up samples; {} whole 10-min windows; {:.1}% of samples outside the calibrated ranges",
            c.raw.samples,
            e.warmup_samples,
            c.raw.windows,
            e.outside_fraction * 100.0
        ));
        Grid::new(id).striped(true).spacing([14.0, 2.0]).show(ui, |ui| {
            for h in ["°/h", "raw", "corrected", "ratio"] {
                ui.label(RichText::new(h).strong());
            }
            ui.end_row();
            let rows = [
                (
                    "peak-to-peak",
                    "Peak-to-peak of the filtered drift",
                    c.raw.p2p_dph,
                    c.corrected.p2p_dph,
                    c.p2p_ratio,
                ),
                ("std", "Standard deviation of the filtered drift", c.raw.std_dph, c.corrected.std_dph, c.std_ratio),
                (
                    "10-min RMS",
                    "Mean over consecutive 10-minute windows of the RMS within each window",
                    c.raw.win_rms_mean_dph,
                    c.corrected.win_rms_mean_dph,
                    c.win_rms_ratio,
                ),
                (
                    "max |10-min mean|",
                    "Largest |mean| over the consecutive 10-minute windows",
                    c.raw.win_mean_max_abs_dph,
                    c.corrected.win_mean_max_abs_dph,
                    c.win_mean_ratio,
                ),
            ];
            let weak = ui.visuals().weak_text_color();
            for (name, tip, raw, cor, r) in rows {
                ui.label(name).on_hover_text(tip);
                ui.monospace(num(raw));
                let cor_text = RichText::new(num(cor)).monospace();
                ui.label(if exact { cor_text } else { cor_text.italics().color(weak) });
                let good = r >= 1.0;
                let color = match (exact, good) {
                    (false, _) => weak,
                    (true, true) => ui.visuals().text_color(),
                    (true, false) => ui.visuals().error_fg_color,
                };
                let text = RichText::new(ratio(r)).monospace().strong().color(color);
                ui.label(if exact { text } else { text.italics() })
                    .on_hover_text("raw ÷ corrected: above 1 is better");
                ui.end_row();
            }
        });
    });
}
