//! The result, live: raw and corrected drift over time, on the calibration log (sharing the
//! time axis of the run) or on the held-out validation log; with a calibration opened to
//! compare, its corrected drift as a third line.

use super::action::Action;
use super::plot_items::{Palette, ShadeItem, ShadeSpan, TimeScale, num, settled_and_warmup};
use super::state::AppState;
use super::widgets::{save_plot_entry, time_link};
use eframe::egui::{self, Stroke, Ui, Vec2b};
use egui_plot::{HLine, Legend, Plot};

/// The result plot's id on the calibration log (fixed, so that its bounds can be read back
/// from egui_plot's memory by tests).
pub const RESULT_CAL_ID: &str = "result_cal";
/// The result plot's id on the validation log.
pub const RESULT_VAL_ID: &str = "result_val";

/// The room kept between the drift plot's legend and its header drawn over the plot, points.
const HEADER_GAP: f32 = 12.0;

/// View state of the result plot: what it measured last frame to place its header.
#[derive(Default)]
pub struct ResultView {
    /// The width of the header drawn over the plot, as last drawn there, points, and whether
    /// a validation log was open then (without one it holds a wider button).
    over_w: Option<(f32, bool)>,
    /// The width of the plot's frame (inside its axes), as last drawn, points.
    frame_w: Option<f32>,
}

impl ResultView {
    /// Whether the header is drawn over the plot (at its frame's top right): on a short
    /// window (`compact`) with a calibration to plot, when the frame holds the legend (top
    /// left) and the header side by side; else the header takes a row above the plot. Known
    /// from last frame's widths (the first frame draws it over the plot to measure it).
    pub fn header_over_plot(&self, ui: &Ui, state: &AppState, compact: bool) -> bool {
        if !compact || state.shown.fit.is_none() {
            return false;
        }
        let has_val = state.shown.validation.is_some();
        match (self.over_w.filter(|w| w.1 == has_val), self.frame_w) {
            (Some((header, _)), Some(frame)) => {
                legend_width(ui, &legend_names(state)) + HEADER_GAP + header + 4.0 <= frame
            }
            _ => true,
        }
    }

    /// The result plot with its header: above it, or drawn over its top right corner (see
    /// [`ResultView::header_over_plot`]) so that the plot keeps the row.
    pub fn ui(&mut self, ui: &mut Ui, state: &AppState, compact: bool) -> Vec<Action> {
        let mut out = Vec::new();
        let has_val = state.shown.validation.is_some();
        let mut show_validation = state.view.show_validation && has_val;
        let overlay = self.header_over_plot(ui, state, compact);
        if !overlay {
            let r = ui.horizontal_wrapped(|ui| {
                let form = if compact { Form::Short } else { Form::Full };
                header(ui, form, has_val, &mut show_validation, &mut out)
            });
            out.push(Action::PlotRect("result.header".into(), r.response.rect));
        }
        let plot = self.plot(ui, state, show_validation, &mut out);
        self.frame_w = plot.map(|f| f.width()).or(self.frame_w);
        if overlay && let Some(frame) = plot {
            // Over the top right corner of the plot's frame, on the plot's background (the
            // legend is at the top left).
            let area = egui::Area::new(egui::Id::unique("result_header_overlay"))
                .order(egui::Order::Middle)
                .pivot(egui::Align2::RIGHT_TOP)
                .fixed_pos(frame.right_top() + egui::vec2(-4.0, 4.0))
                .constrain_to(frame);
            let r = area.show(ui.ctx(), |ui| {
                egui::Frame::popup(ui.style())
                    .inner_margin(4.0)
                    .show(ui, |ui| {
                        ui.horizontal(|ui| {
                            header(ui, Form::Over, has_val, &mut show_validation, &mut out)
                        });
                    });
            });
            self.over_w = Some((r.response.rect.width(), has_val));
            out.push(Action::PlotRect("result.header".into(), r.response.rect));
        }
        if show_validation != state.view.show_validation {
            out.push(Action::ShowValidation(show_validation));
        }
        out
    }

    /// The plot; its frame (inside the axes) once drawn.
    fn plot(
        &mut self,
        ui: &mut Ui,
        state: &AppState,
        show_validation: bool,
        out: &mut Vec<Action>,
    ) -> Option<egui::Rect> {
        let pal = Palette::of(ui);
        let Some(fit) = state.shown.fit.clone() else {
            ui.weak(if state.shown.fit_error.is_some() {
                "No calibration: it failed (its message is in the status bar)."
            } else {
                "No calibration yet."
            });
            return None;
        };
        let show_val = show_validation && fit.outcome.held_out.is_some();
        let (judged, raw_p, cor_p, regime) = if show_val {
            let (Some(h), Some(l)) = (fit.outcome.held_out.as_ref(), fit.lods.held_out.as_ref())
            else {
                return None;
            };
            (
                h,
                &l.raw_filtered,
                (&l.cor_filtered_dph, &l.cor_filtered),
                &l.regime,
            )
        } else {
            (
                &fit.outcome.in_sample,
                &fit.lods.raw_filtered,
                (&fit.lods.cor_filtered_dph, &fit.lods.cor_filtered),
                &*fit.lods.regime,
            )
        };
        let log = judged.log.clone();
        if log.is_empty()
            || cor_p.0.len() != log.len()
            || judged.raw_filtered_dph.len() != log.len()
        {
            return None;
        }
        let scale = TimeScale::for_duration(log.duration_s());
        let t_full = (log.time_s[0], log.time_s[log.len() - 1]);
        // Raw drift over the log's segments; the corrected drift only where the rates have
        // their history (elsewhere it is no reading).
        let (segments, ready) = match (show_val, fit.lods.held_out.as_ref()) {
            (true, Some(l)) => (&l.segments, &l.ready),
            _ => (&fit.lods.segments, &fit.lods.ready),
        };
        // The warm-up of each segment: until its rates have their history and then one
        // filter window more (the centred filter's window is truncated before that), drawn
        // faded and kept out of the y-range (its swing would set the plot's scale).
        let lead_s = fit.outcome.prepared.filter_samples as f64 * fit.outcome.prepared.dt_s;
        let settled = ready.settled(lead_s);
        let raw_warm = segments.minus(&settled);
        let cor_warm = ready.minus(&settled);
        let id = if show_val {
            RESULT_VAL_ID
        } else {
            RESULT_CAL_ID
        };
        // A calibration opened to compare, when it was judged on the log and axis shown.
        let opened = super::opened::drift_line(state, &log)
            .filter(|o| o.cor_filtered_dph.len() == log.len())
            .map(|o| {
                let settled = o.ready.settled(o.filter_lead_s);
                let warm = o.ready.minus(&settled);
                (o, settled, warm)
            });
        let opened_name = state
            .opened
            .as_ref()
            .map(|o| format!("opened {}", o.name()))
            .unwrap_or_default();
        let axis_w = super::widgets::linked_y_axis_width(ui.ctx(), &state.shown.log.as_ref()?.path);
        let mut plot = Plot::new(id)
            .id(eframe::egui::Id::unique(id))
            .height(ui.available_height().max(80.0))
            .legend(Legend::default().position(egui_plot::Corner::LeftTop))
            .x_axis_label(format!("time, {}", scale.unit))
            .y_axis_label("drift, °/h");
        // The values at the cursor: the nearest sample's filtered drift, raw and corrected
        // (the corrected one named as warm-up before the rates have their history).
        let hover = {
            let time_s: &[f64] = &log.time_s;
            let raw: &[f64] = &judged.raw_filtered_dph;
            let cor: &[f64] = cor_p.0;
            let settled = settled.clone();
            let opened = opened.as_ref().map(|(o, settled, _)| {
                (
                    o.cor_filtered_dph.as_slice(),
                    o.ready.clone(),
                    settled.clone(),
                )
            });
            move |x: f64| -> Option<String> {
                let i = crate::signal::lod::nearest_index(time_s, x * scale.div)?;
                let t = time_s[i];
                let cor_text = if settled.holds(t) {
                    format!("{} °/h", num(cor[i]))
                } else if ready.holds(t) {
                    format!(
                        "{} °/h (warm-up, faded: the filter's window is not full yet)",
                        num(cor[i])
                    )
                } else {
                    "— (warm-up: the rates' history is not full yet)".to_string()
                };
                let opened_text = match &opened {
                    Some((o, _, settled)) if settled.holds(t) => {
                        format!("\nopened = {} °/h", num(o[i]))
                    }
                    Some((o, ready, _)) if ready.holds(t) => {
                        format!("\nopened = {} °/h (warm-up, faded)", num(o[i]))
                    }
                    Some(_) => "\nopened = — (warm-up)".to_string(),
                    None => String::new(),
                };
                Some(format!(
                    "t = {} {} ({} s)\nraw drift = {} °/h\ncorrected = {cor_text}{opened_text}",
                    num(t / scale.div),
                    scale.unit,
                    num(t),
                    num(raw[i]),
                ))
            }
        };
        plot = super::plot_items::with_time_axes(plot)
            .allow_zoom(Vec2b::new(true, false))
            .allow_drag(Vec2b::new(true, false))
            .allow_scroll(Vec2b::new(true, false))
            .y_axis_min_width(axis_w)
            .label_formatter(move |pos: &egui_plot::HoverPosition<'_>| {
                let x = match pos {
                    egui_plot::HoverPosition::NearDataPoint { position, .. }
                    | egui_plot::HoverPosition::Elsewhere { position } => position.x,
                };
                hover(x)
            });
        if !show_val {
            plot = plot
                .link_axis(time_link(), Vec2b::new(true, false))
                .link_cursor(time_link(), Vec2b::new(true, false));
        }
        let resp = ui.scope(|ui| {
            plot.show(ui, |pui| {
                let (x0, x1) = super::plot_items::shown_span(pui, scale.div, t_full);
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
                let cols = (x0, x1, cols);
                let x = (scale.div, t_full);
                for item in settled_and_warmup(
                    "raw",
                    &log.time_s,
                    &judged.raw_filtered_dph,
                    raw_p,
                    (&settled, &raw_warm),
                    cols,
                    x,
                ) {
                    pui.add(item.color(pal.raw).width(1.6));
                }
                for item in settled_and_warmup(
                    "corrected",
                    &log.time_s,
                    cor_p.0,
                    cor_p.1,
                    (&settled, &cor_warm),
                    cols,
                    x,
                ) {
                    pui.add(item.color(pal.corrected).width(1.8));
                }
                if let Some((o, settled, warm)) = &opened {
                    for item in settled_and_warmup(
                        &opened_name,
                        &log.time_s,
                        &o.cor_filtered_dph,
                        &o.cor_filtered,
                        (settled, warm),
                        cols,
                        x,
                    ) {
                        pui.add(item.color(pal.opened).width(1.6));
                    }
                }
            })
        });
        resp.inner.response.context_menu(|ui| {
            if save_plot_entry(ui) {
                out.push(Action::SavePlotNamed("result".into()));
            }
        });
        let frame = *resp.inner.transform.frame();
        if let Some(l) = &state.shown.log {
            super::widgets::note_linked_y_axis_width(ui.ctx(), &l.path, resp.response.rect, frame);
        }
        out.push(Action::PlotRect("result".into(), resp.response.rect));
        out.push(Action::PlotRect("result.frame".into(), frame));
        Some(frame)
    }
}

/// The names in the drift plot's legend, as the plot names its lines.
fn legend_names(state: &AppState) -> Vec<String> {
    let mut names = vec!["raw".to_string(), "corrected".to_string()];
    if let Some(o) = &state.opened {
        names.push(format!("opened {}", o.name()));
    }
    names
}

/// The width of egui_plot's legend of `names`, points, as egui_plot 0.38 lays it out (each
/// row an icon as wide as the text is tall, a fifth of that, then the name; a frame of 8
/// points' margin at each side and its stroke, 4 points in from the plot's frame).
fn legend_width(ui: &Ui, names: &[String]) -> f32 {
    let font = egui::TextStyle::Body.resolve(ui.style());
    let row = ui.fonts_mut(|f| {
        names
            .iter()
            .map(|n| {
                let g = f.layout_no_wrap(n.clone(), font.clone(), egui::Color32::WHITE);
                g.size().x + 1.2 * g.size().y
            })
            .fold(0.0, f32::max)
    });
    4.0 + 8.0 + row + 8.0 + 2.0
}

/// How much of the header is written: its title in full; in one word (a short window's row);
/// or no title and one-word log names (over the plot, where the y-axis says it is drift).
#[derive(Clone, Copy, PartialEq)]
enum Form {
    Full,
    Short,
    Over,
}

/// The result plot's title, which log it shows, and its PNG button.
fn header(
    ui: &mut Ui,
    form: Form,
    has_val: bool,
    show_validation: &mut bool,
    out: &mut Vec<Action>,
) {
    let tip = "Ω filtered by the recipe's moving average: raw (grey) and corrected (green); a \
               calibration opened to compare draws its corrected drift too (purple)";
    match form {
        Form::Full => {
            ui.strong("Drift before and after correction")
                .on_hover_text(tip);
            ui.separator();
        }
        Form::Short => {
            ui.strong("Drift").on_hover_text(tip);
            ui.separator();
        }
        Form::Over => {}
    }
    let (cal, val) = if form == Form::Over {
        ("calibration", "validation")
    } else {
        ("calibration log", "validation log")
    };
    ui.radio_value(show_validation, false, cal)
        .on_hover_text("In-sample: the drift on the log the calibration was fitted on");
    // Without a validation log its choice is the button that opens one (a choice that cannot
    // be made beside it wrapped the header onto a second row, taken from the plots).
    if has_val {
        ui.radio_value(show_validation, true, val).on_hover_text(
            "Held out: a second log of the same gyro, corrected with this calibration",
        );
    }
    if !has_val
        && ui
            .button("Open validation log…")
            .on_hover_text("Load a second log of the same gyro to judge the calibration held out")
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
}
