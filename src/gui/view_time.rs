//! The run over time: raw and filtered Ω with the model, T, dT/dt and d²T/dt², stacked with
//! one shared time axis (zoom and pan together), + and − regimes shaded, plateaus marked.
//! Plateaus are edited here by mouse: drag an edge to move it, drag across the plot with Shift
//! held (or with "Mark plateau" on) to add one, click one to select it.

use super::action::{Action, Edit};
use super::plot_items::{
    BandItem, Palette, ShadeItem, ShadeSpan, TimeScale, num, settled_and_warmup,
};
use super::state::{AppState, sorted_ranges};
use super::widgets::{save_plot_entry, time_link};
use crate::signal::lod::MinMaxPyramid;
use crate::signal::plateau::PlateauRange;
use eframe::egui::{self, CursorIcon, Key, Rect, Stroke, Ui, Vec2b};
use egui_plot::{HLine, HoverPosition, LineStyle, Plot, PlotTransform};

/// The shortest a time plot is drawn, points (below it, the window is too small to read it).
pub const MIN_PLOT_H: f32 = 60.0;

/// The time plots, top to bottom: each one's id (for [`crate::gui::Workbench::plot_rect`] and
/// saving it as PNG) and its y-axis label.
pub const TIME_PLOTS: [(&str, &str); 4] = [
    ("time_omega", "Ω, °/h"),
    ("time_temp", "T, °C"),
    ("time_tdot", "dT/dt, °C/s"),
    ("time_tddot", "d²T/dt², °C/s²"),
];

/// The gap between two time plots on a short window, points: the plots keep the height (each
/// one's frame parts it from the next).
const COMPACT_GAP: f32 = 2.0;

/// A pending change of the shared time axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum XCommand {
    /// Show the whole log.
    Fit,
    /// Show this range, s.
    Range(f64, f64),
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum End {
    Start,
    End,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Drag {
    /// Moving one end of plateau `index`.
    Edge { index: usize, end: End },
    /// Marking a new plateau from `t0` (its index once it exists).
    New { t0: f64, index: Option<usize> },
}

/// View state of the time plots.
#[derive(Default)]
pub struct TimeView {
    drag: Option<Drag>,
    transforms: Vec<PlotTransform>,
    /// A change of the time axis to apply on the next frame (all plots at once).
    pub x_command: Option<XCommand>,
    /// The selected plateau (row in the table, highlighted in the plots).
    pub selected: Option<usize>,
    /// When on, a plain drag across a time plot marks a plateau.
    pub mark_mode: bool,
    /// The visible time range, s (as drawn last frame).
    pub visible_s: Option<(f64, f64)>,
    /// Screen rectangle of each plot (for saving one as PNG).
    pub rects: Vec<(&'static str, Rect)>,
    /// Each plot's frame (the rectangle inside its axes), as drawn last frame.
    pub frames: Vec<(&'static str, Rect)>,
    /// A short window: the last plot's time axis has its ticks but no title (the drift plot
    /// below, linked in time, gives it), so that each plot keeps more of its height.
    pub compact: bool,
    /// The toolbar's height as drawn last frame (it wraps on a narrow panel), points.
    toolbar_h: Option<f32>,
    div: f64,
    /// Which plot the pointer was over last frame (egui's hit test: not when a window or a
    /// dialog covers it).
    hovered: Option<usize>,
}

struct Series {
    id: &'static str,
    label: &'static str,
}

const EDGE_GRAB_PX: f32 = 6.0;

impl TimeView {
    /// Screen x of time `t_s` on the time plots as drawn last frame.
    pub fn screen_x(&self, t_s: f64) -> Option<f32> {
        let tf = self.transforms.first()?;
        Some(tf.position_from_point_x(t_s / self.div))
    }

    /// The height the toolbar and the plots take with each plot `each` points tall (the
    /// toolbar as drawn last frame, one row before the first).
    pub fn height_for(&self, ui: &Ui, each: f32) -> f32 {
        let spacing = self.gap(ui);
        let toolbar = self
            .toolbar_h
            .unwrap_or(ui.spacing().interact_size.y + spacing);
        toolbar + 4.0 * each + 3.0 * spacing + self.x_axis_h()
    }

    /// The gap between two time plots, points.
    fn gap(&self, ui: &Ui) -> f32 {
        if self.compact {
            COMPACT_GAP
        } else {
            ui.spacing().item_spacing.y
        }
    }

    /// The height the last plot's time axis adds to it, points.
    fn x_axis_h(&self) -> f32 {
        if self.compact { 16.0 } else { 22.0 }
    }

    /// Draws the plots (the whole height given) and handles plateau editing.
    pub fn ui(&mut self, ui: &mut Ui, state: &AppState) -> Vec<Action> {
        let mut out = Vec::new();
        let Some(loaded) = state.shown.log.clone() else {
            ui.centered_and_justified(|ui| {
                ui.label("Open a chamber log (File › Open log…, Ctrl+O, or drop a file here).");
            });
            return out;
        };
        let log = loaded.log.clone();
        let scale = TimeScale::for_duration(log.duration_s());
        self.div = scale.div;
        let pal = Palette::of(ui);
        let fit = state.shown.fit.clone();

        let top = ui.cursor().top();
        self.toolbar(ui, &mut out, scale);
        self.toolbar_h = Some(ui.cursor().top() - top);
        let deleted = self.handle_keys(ui, state);
        let dragged = self.edit_plateaus(ui, state, log.nominal_dt_s());
        // The plateaus as this frame's edit leaves them (the edit itself is carried out at
        // the end of the frame).
        let edited = dragged.or(deleted);
        let ranges = match edited {
            Some(r) => {
                out.push(Action::Edit(r.clone()));
                match r {
                    Edit::Plateaus(r) | Edit::PlateausDragged(r) => r,
                    _ => state.ranges(),
                }
            }
            None => state.ranges(),
        };
        let t_full = (log.time_s[0], log.time_s[log.len() - 1]);
        let specs = TIME_PLOTS.map(|(id, label)| Series { id, label });
        let n = specs.len();
        let spacing = self.gap(ui);
        ui.spacing_mut().item_spacing.y = spacing;
        let x_axis_h = self.x_axis_h();
        let each = ((ui.available_height() - spacing * (n as f32 - 1.0) - x_axis_h) / n as f32)
            .max(MIN_PLOT_H);
        let axis_w = super::widgets::linked_y_axis_width(ui.ctx(), &loaded.path);
        let hover_text = hover_formatter(&loaded, fit.as_deref(), scale);
        let allow_drag = self.drag.is_none();
        let command = self.x_command.take();
        let mut transforms = Vec::with_capacity(n);
        let mut hovered = None;
        self.rects.clear();
        self.frames.clear();
        let new_range = match self.drag {
            Some(Drag::New { index: Some(k), .. }) => Some(k),
            _ => None,
        };

        // Each segment's warm-up (until its rates have their history, then one Ω filter
        // window more) is drawn faded and kept out of the y-ranges: its transients (a
        // truncated filter window, d²T/dt² of a log that starts mid-ramp) would otherwise set
        // the plots' scales. Without a calibration nothing marks it.
        let warmup = fit.as_ref().map(|f| {
            let p = &f.outcome.prepared;
            let settled = f.lods.ready.settled(p.filter_samples as f64 * p.dt_s);
            let of_log = loaded.segments.minus(&settled);
            let of_rates = f.lods.ready.minus(&settled);
            (settled, of_log, of_rates)
        });
        for (k, spec) in specs.iter().enumerate() {
            let last = k + 1 == n;
            let plot = Plot::new(spec.id)
                .id(egui::Id::unique(spec.id))
                .link_axis(time_link(), Vec2b::new(true, false))
                .link_cursor(time_link(), Vec2b::new(true, false))
                .height(if last { each + x_axis_h } else { each })
                .allow_zoom(Vec2b::new(true, false))
                .allow_drag(Vec2b::new(allow_drag, false))
                .allow_scroll(Vec2b::new(true, false))
                .allow_boxed_zoom(allow_drag);
            let plot = super::plot_items::with_time_axes(plot)
                .y_axis_min_width(axis_w)
                .y_axis_label(super::plot_items::axis_label(ui.ctx(), spec.label, each))
                .show_axes(Vec2b::new(last, true))
                .x_axis_label(if last && !self.compact {
                    format!("time, {}", scale.unit)
                } else {
                    String::new()
                })
                .label_formatter(|pos: &HoverPosition<'_>| {
                    let x = match pos {
                        HoverPosition::NearDataPoint { position, .. }
                        | HoverPosition::Elsewhere { position } => position.x,
                    };
                    hover_text(x * scale.div)
                });
            let selected = self.selected;
            let resp = ui.scope(|ui| {
                plot.show(ui, |pui| {
                    // Fitting the axis sets its range outright (auto-bounds would wait for the
                    // items of a frame drawn with the old range), and this frame's bands are
                    // reduced over the new range.
                    let commanded = match command {
                        Some(XCommand::Fit) => {
                            pui.set_plot_bounds_x(t_full.0 / scale.div..=t_full.1 / scale.div);
                            pui.set_auto_bounds(Vec2b::new(false, true));
                            Some(t_full)
                        }
                        Some(XCommand::Range(a, b)) => {
                            pui.set_plot_bounds_x(a / scale.div..=b / scale.div);
                            Some((a, b))
                        }
                        None => None,
                    };
                    // Mouse wheel zooms time around the pointer (Ctrl+wheel is egui_plot's own).
                    if pui.response().hovered() {
                        let (wheel, ctrl) = pui
                            .ctx()
                            .input(|i| (i.smooth_scroll_delta.y, i.modifiers.command));
                        if wheel != 0.0 && !ctrl {
                            let factor = (wheel / 200.0).exp();
                            pui.zoom_bounds_around_hovered(egui::vec2(factor, 1.0));
                        }
                    }
                    let b = pui.plot_bounds();
                    let (x0, x1) = match commanded {
                        Some(r) => r,
                        None if b.is_valid_x() && b.width() > 0.0 => {
                            (b.min()[0] * scale.div, b.max()[0] * scale.div)
                        }
                        None => t_full,
                    };
                    let cols = (pui.response().rect.width().max(50.0)) as usize;
                    // Shading: regimes, then plateaus.
                    let mut spans = Vec::new();
                    if let Some(f) = &fit {
                        for r in f.lods.regime.runs(&log.time_s, x0, x1, cols / 2) {
                            let c = if r.class == 1 { pal.plus } else { pal.minus };
                            spans.push(ShadeSpan {
                                x0: r.t0 / scale.div,
                                x1: r.t1 / scale.div,
                                fill: Palette::shade(c, 0.10),
                                edge: Stroke::NONE,
                            });
                        }
                    }
                    for (j, r) in ranges.iter().enumerate() {
                        let hi = selected == Some(j) || new_range == Some(j);
                        spans.push(ShadeSpan {
                            x0: r.start_s / scale.div,
                            x1: r.end_s / scale.div,
                            fill: Palette::shade(pal.plateau, if hi { 0.32 } else { 0.16 }),
                            edge: Stroke::new(
                                if hi { 2.0 } else { 1.0 },
                                Palette::shade(pal.plateau, if hi { 1.0 } else { 0.5 }),
                            ),
                        });
                    }
                    pui.add(ShadeItem::new("shading", spans));
                    // Every series is reduced segment by segment: nothing is drawn across a
                    // gap in the log.
                    let seg = |values: &[f64], pyramid: &MinMaxPyramid| {
                        loaded
                            .segments
                            .reduce(&log.time_s, values, pyramid, x0, x1, cols)
                    };
                    match k {
                        0 => {
                            if let Some(r) = &loaded.recorded {
                                // The bursts as recorded, behind the means the fit uses.
                                let bands = r.segments.reduce(
                                    &r.log.time_s,
                                    &r.log.omega_dph,
                                    &r.lods.omega,
                                    x0,
                                    x1,
                                    cols,
                                );
                                pui.add(
                                    BandItem::segmented(
                                        "Ω as recorded (bursts)",
                                        bands,
                                        scale.div,
                                        t_full,
                                    )
                                    .color(Palette::shade(pal.raw, 0.55))
                                    .width(1.0)
                                    .no_y_bounds(),
                                );
                            }
                            let raw = BandItem::segmented(
                                if loaded.recorded.is_some() {
                                    "Ω raw (burst means)"
                                } else {
                                    "Ω raw"
                                },
                                seg(&log.omega_dph, &loaded.lods.omega),
                                scale.div,
                                t_full,
                            )
                            .color(Palette::shade(pal.raw, 0.45))
                            .width(1.0);
                            // Without a calibration the raw rate is all there is: the axis
                            // fits it.
                            pui.add(if fit.is_some() {
                                raw.no_y_bounds()
                            } else {
                                raw
                            });
                            if let (Some(f), Some((settled, of_log, of_rates))) = (&fit, &warmup) {
                                let p = &f.outcome.prepared;
                                for item in settled_and_warmup(
                                    "Ω filtered",
                                    &log.time_s,
                                    &p.omega_filtered_dph,
                                    &f.lods.omega_filtered,
                                    (settled, of_log),
                                    (x0, x1, cols),
                                    (scale.div, t_full),
                                ) {
                                    pui.add(item.color(pal.filtered));
                                }
                                let pred = &f.lods.pred_filtered;
                                if pred.len() == log.len() {
                                    for item in settled_and_warmup(
                                        "model, filtered as Ω",
                                        &log.time_s,
                                        pred,
                                        &f.lods.pred,
                                        (settled, of_rates),
                                        (x0, x1, cols),
                                        (scale.div, t_full),
                                    ) {
                                        pui.add(item.color(pal.model).width(1.2));
                                    }
                                }
                            }
                        }
                        1 => {
                            if let Some(r) = &loaded.recorded {
                                let bands = r.segments.reduce(
                                    &r.log.time_s,
                                    &r.log.temp_c,
                                    &r.lods.temp,
                                    x0,
                                    x1,
                                    cols,
                                );
                                pui.add(
                                    BandItem::segmented(
                                        "T as recorded (bursts)",
                                        bands,
                                        scale.div,
                                        t_full,
                                    )
                                    .color(Palette::shade(pal.temp, 0.5))
                                    .width(1.0)
                                    .no_y_bounds(),
                                );
                            }
                            if let Some((settled, of_log, _)) = &warmup {
                                for item in settled_and_warmup(
                                    "T",
                                    &log.time_s,
                                    &log.temp_c,
                                    &loaded.lods.temp,
                                    (settled, of_log),
                                    (x0, x1, cols),
                                    (scale.div, t_full),
                                ) {
                                    pui.add(item.color(pal.temp));
                                }
                            } else {
                                pui.add(
                                    BandItem::segmented(
                                        "T",
                                        seg(&log.temp_c, &loaded.lods.temp),
                                        scale.div,
                                        t_full,
                                    )
                                    .color(pal.temp),
                                );
                            }
                        }
                        _ => {
                            if let Some(f) = &fit {
                                let d = &f.outcome.prepared.deriv;
                                let (v, p, db) = if k == 2 {
                                    (
                                        &d.tdot,
                                        &f.lods.tdot,
                                        f.outcome.calibration.resolved.deadband_tdot,
                                    )
                                } else {
                                    (
                                        &d.tddot,
                                        &f.lods.tddot,
                                        f.outcome.calibration.resolved.deadband_tddot,
                                    )
                                };
                                if v.len() == log.len()
                                    && let Some((settled, _, of_rates)) = &warmup
                                {
                                    // Only where the rates have their history: a segment's
                                    // first samples hold no reading (zero), not a rate.
                                    for item in settled_and_warmup(
                                        spec.label,
                                        &log.time_s,
                                        v,
                                        p,
                                        (settled, of_rates),
                                        (x0, x1, cols),
                                        (scale.div, t_full),
                                    ) {
                                        pui.add(item.color(pal.filtered));
                                    }
                                }
                                for y in [db, -db] {
                                    pui.hline(
                                        HLine::new("dead-band", y)
                                            .color(pal.deadband)
                                            .style(LineStyle::dashed_loose())
                                            .allow_hover(false),
                                    );
                                }
                            }
                        }
                    }
                })
            });
            let plot_resp = resp.inner;
            plot_resp.response.context_menu(|ui| {
                if save_plot_entry(ui) {
                    out.push(Action::SavePlot(spec.id.to_string(), resp.response.rect));
                }
                if ui
                    .button("Show the whole log")
                    .on_hover_text("Whole log on the time axis (Home)")
                    .clicked()
                {
                    self.x_command = Some(XCommand::Fit);
                    ui.close();
                }
            });
            self.rects.push((spec.id, resp.response.rect));
            self.frames.push((spec.id, *plot_resp.transform.frame()));
            super::widgets::note_linked_y_axis_width(
                ui.ctx(),
                &loaded.path,
                resp.response.rect,
                *plot_resp.transform.frame(),
            );
            if plot_resp.response.hovered() {
                hovered = Some(k);
            }
            transforms.push(plot_resp.transform);
        }
        if let Some(t) = transforms.last() {
            let b = t.bounds();
            self.visible_s = Some((b.min()[0] * scale.div, b.max()[0] * scale.div));
        }
        // The grab cursor near a plateau edge.
        if let Some(p) = ui.input(|i| i.pointer.hover_pos())
            && let Some(tf) = transforms.iter().find(|t| t.frame().contains(p))
        {
            let near = ranges.iter().any(|r| {
                [r.start_s, r.end_s]
                    .iter()
                    .any(|&x| (tf.position_from_point_x(x / scale.div) - p.x).abs() <= EDGE_GRAB_PX)
            });
            if near || matches!(self.drag, Some(Drag::Edge { .. })) {
                ui.ctx().set_cursor_icon(CursorIcon::ResizeHorizontal);
            } else if self.mark_mode || ui.input(|i| i.modifiers.shift) {
                ui.ctx().set_cursor_icon(CursorIcon::Crosshair);
            }
        }
        self.transforms = transforms;
        self.hovered = hovered;
        if command.is_some() || self.drag.is_some() {
            ui.ctx().request_repaint();
        }
        out
    }

    fn toolbar(&mut self, ui: &mut Ui, out: &mut Vec<Action>, scale: TimeScale) {
        // Wrapped: on a narrow window the buttons take a second row rather than widening the
        // central panel under the side panels (which clipped the plots).
        // Short labels and close buttons, so that it keeps one row at 1280 points wide (beside
        // a controls panel wide enough for the whole plateau table).
        ui.horizontal_wrapped(|ui| {
            ui.spacing_mut().item_spacing.x = 4.0;
            ui.spacing_mut().button_padding.x = 3.0;
            if ui
                .button("Whole log")
                .on_hover_text("Show the whole log on the time axis (Home)")
                .clicked()
            {
                self.x_command = Some(XCommand::Fit);
            }
            if ui.button("+").on_hover_text("Zoom in on time (+ or mouse wheel)").clicked() {
                self.zoom(0.5);
            }
            if ui.button("−").on_hover_text("Zoom out on time (− or mouse wheel)").clicked() {
                self.zoom(2.0);
            }
            if ui.button("«").on_hover_text("Move back in time (←, or drag the plot)").clicked() {
                self.pan(-0.25);
            }
            if ui.button("»").on_hover_text("Move forward in time (→, or drag the plot)").clicked() {
                self.pan(0.25);
            }
            ui.separator();
            ui.toggle_value(&mut self.mark_mode, "Mark plateau").on_hover_text(
                "When on, dragging across a time plot marks a new plateau. Without it, hold Shift while \
                 dragging. Drag a plateau's edge to move it; click one to select it; Delete removes the \
                 selected plateau.",
            );
            if ui
                .button("PNG")
                .on_hover_text("Save the stacked time plots as one PNG picture (right-click a plot to save it alone)")
                .clicked()
            {
                let rect = self
                    .rects
                    .iter()
                    .map(|r| r.1)
                    .reduce(|a, b| a.union(b))
                    .unwrap_or(Rect::NOTHING);
                out.push(Action::SavePlot("time_plots".into(), rect));
            }
            let pal = Palette::of(ui);
            ui.add(egui::Label::new(egui::RichText::new("+ accel.").color(pal.plus)).extend())
                .on_hover_text("Shaded orange: thermal acceleration, dT/dt·d²T/dt² > 0 (K1+, K2+)");
            ui.add(egui::Label::new(egui::RichText::new("− decel.").color(pal.minus)).extend())
                .on_hover_text("Shaded blue: thermal deceleration, dT/dt·d²T/dt² < 0 (K1−, K2−)");
            ui.add(egui::Label::new(egui::RichText::new("plateau").color(pal.plateau)).extend())
                .on_hover_text("Shaded green: the plateaus that define K0(T)");
            // The range shown, where the row has room for it (the time axis says it too).
            let row_left = ui.max_rect().right() - ui.min_rect().right();
            if let Some((a, b)) = self.visible_s
                && row_left > 130.0
            {
                let text = format!("{} – {} {}", num(a / scale.div), num(b / scale.div), scale.unit);
                ui.add(egui::Label::new(egui::RichText::new(text).weak()).extend());
            }
        });
    }

    fn zoom(&mut self, factor: f64) {
        if let Some((a, b)) = self.visible_s {
            let c = 0.5 * (a + b);
            let h = 0.5 * (b - a) * factor;
            self.x_command = Some(XCommand::Range(c - h, c + h));
        }
    }

    fn pan(&mut self, fraction: f64) {
        if let Some((a, b)) = self.visible_s {
            let d = (b - a) * fraction;
            self.x_command = Some(XCommand::Range(a + d, b + d));
        }
    }

    /// The time axis keys, and Delete on the selected plateau (the plateaus without it).
    fn handle_keys(&mut self, ui: &Ui, state: &AppState) -> Option<Edit> {
        if ui.ctx().egui_wants_keyboard_input() {
            return None;
        }
        let (home, plus, minus, left, right, del) = ui.input(|i| {
            (
                i.key_pressed(Key::Home),
                i.key_pressed(Key::Plus) || i.key_pressed(Key::Equals),
                i.key_pressed(Key::Minus),
                i.key_pressed(Key::ArrowLeft),
                i.key_pressed(Key::ArrowRight),
                i.key_pressed(Key::Delete),
            )
        });
        if home {
            self.x_command = Some(XCommand::Fit);
        }
        if plus {
            self.zoom(0.5);
        }
        if minus {
            self.zoom(2.0);
        }
        if left {
            self.pan(-0.25);
        }
        if right {
            self.pan(0.25);
        }
        if del && let Some(k) = self.selected.take() {
            let mut r = state.ranges();
            if k < r.len() {
                r.remove(k);
                return Some(Edit::Plateaus(r));
            }
        }
        None
    }

    /// Starts, follows and ends a plateau drag, from the pointer and last frame's plots; the
    /// plateaus as the drag leaves them.
    fn edit_plateaus(&mut self, ui: &Ui, state: &AppState, dt_s: f64) -> Option<Edit> {
        let (pressed, down, pos, shift) = ui.input(|i| {
            (
                i.pointer.primary_pressed(),
                i.pointer.primary_down(),
                i.pointer.interact_pos(),
                i.modifiers.shift,
            )
        });
        let p = pos?;
        let div = state
            .shown
            .log
            .as_ref()
            .map_or(1.0, |l| TimeScale::for_duration(l.log.duration_s()).div);
        let (t_lo, t_hi) = state.shown.log.as_ref().map_or((0.0, 1.0), |l| {
            (l.log.time_s[0], l.log.time_s[l.log.len() - 1])
        });
        let over = self
            .hovered
            .and_then(|k| self.transforms.get(k))
            .filter(|t| t.frame().contains(p))
            .copied();
        if pressed && self.drag.is_none() && !ui.ctx().any_popup_open() {
            let tf = over?;
            let t = tf.value_from_position(p).x * div;
            let ranges = state.ranges();
            let mut best: Option<(f32, usize, End)> = None;
            for (k, r) in ranges.iter().enumerate() {
                for (end, x) in [(End::Start, r.start_s), (End::End, r.end_s)] {
                    let d = (tf.position_from_point_x(x / div) - p.x).abs();
                    if d <= EDGE_GRAB_PX && best.is_none_or(|b| d < b.0) {
                        best = Some((d, k, end));
                    }
                }
            }
            if let Some((_, index, end)) = best {
                self.drag = Some(Drag::Edge { index, end });
                self.selected = Some(index);
                return Some(Edit::Plateaus(ranges));
            } else if shift || self.mark_mode {
                self.drag = Some(Drag::New {
                    t0: t.clamp(t_lo, t_hi),
                    index: None,
                });
            } else {
                self.selected = ranges.iter().position(|r| r.contains(t));
            }
            return None;
        }
        let drag = self.drag?;
        let tf = over.or_else(|| self.transforms.first().copied());
        let mut ranges = state.ranges();
        let mut edit = None;
        if let Some(tf) = tf {
            let t = (tf.value_from_position(p).x * div).clamp(t_lo, t_hi);
            let min_w = dt_s.max(1e-9);
            match drag {
                Drag::Edge { index, end } => {
                    if let Some(r) = ranges.get_mut(index) {
                        match end {
                            End::Start => r.start_s = t.min(r.end_s - min_w),
                            End::End => r.end_s = t.max(r.start_s + min_w),
                        }
                    }
                }
                Drag::New { t0, index } => {
                    let r = PlateauRange {
                        start_s: t0.min(t),
                        end_s: t0.max(t).max(t0.min(t) + min_w),
                    };
                    match index {
                        Some(k) if k < ranges.len() => ranges[k] = r,
                        _ => {
                            ranges.push(r);
                            self.drag = Some(Drag::New {
                                t0,
                                index: Some(ranges.len() - 1),
                            });
                        }
                    }
                }
            }
            // Unsorted while the drag lasts, so the index being edited stays put.
            edit = Some(Edit::PlateausDragged(ranges.clone()));
        }
        if !down {
            let edited = match self.drag {
                Some(Drag::Edge { index, .. })
                | Some(Drag::New {
                    index: Some(index), ..
                }) => ranges.get(index).copied(),
                _ => None,
            };
            let min_w = 3.0 * dt_s.max(1e-9);
            let kept = sorted_ranges(
                ranges
                    .into_iter()
                    .filter(|r| Some(*r) != edited || r.end_s - r.start_s >= min_w)
                    .collect(),
            );
            self.selected = edited.and_then(|e| kept.iter().position(|r| *r == e));
            self.drag = None;
            edit = Some(Edit::Plateaus(kept));
        }
        edit
    }
}

/// The text shown when hovering a time plot: every value at the nearest sample.
fn hover_formatter<'a>(
    loaded: &'a super::jobs::Loaded,
    fit: Option<&'a super::jobs::FitView>,
    scale: TimeScale,
) -> impl Fn(f64) -> Option<String> + 'a {
    move |t: f64| {
        let log = &loaded.log;
        let i = crate::signal::lod::nearest_index(&log.time_s, t)?;
        let mut s = format!(
            "t = {} {} ({} s)\nΩ raw = {} °/h\nT = {} °C",
            num(log.time_s[i] / scale.div),
            scale.unit,
            num(log.time_s[i]),
            num(log.omega_dph[i]),
            num(log.temp_c[i]),
        );
        if let Some(f) = fit {
            let p = &f.outcome.prepared;
            let c = &f.outcome.in_sample.corrected;
            if i < p.omega_filtered_dph.len() && i < c.pred_dph.len() {
                let regime = match c.regime[i] {
                    crate::models::vakhrameev::Regime::Plus => "+ (thermal acceleration)",
                    crate::models::vakhrameev::Regime::Minus => "− (thermal deceleration)",
                    crate::models::vakhrameev::Regime::Static => "static",
                };
                s.push_str(&format!(
                    "\nΩ filtered = {} °/h\nmodel = {} °/h\ncorrected = {} °/h\ndT/dt = {} °C/s\nd²T/dt² = {} °C/s²\nregime {regime}",
                    num(p.omega_filtered_dph[i]),
                    num(c.pred_dph[i]),
                    num(c.cor_dph[i]),
                    num(p.deriv.tdot[i]),
                    num(p.deriv.tddot[i]),
                ));
            }
        }
        Some(s)
    }
}
