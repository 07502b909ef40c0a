//! The corrected drifts of the chosen models overlaid on the raw drift, one colour a model.

use super::ModelsView;
use crate::gui::jobs::Compared;
use crate::gui::plot_items::{BandItem, Palette, TimeScale};
use eframe::egui::{self, Color32, RichText, Ui, Vec2b};
use egui_plot::Plot;

/// Colours of the models, by their place in the comparison: distinct from each other and
/// from the grey of the raw drift, on light and dark backgrounds.
pub fn model_color(k: usize, dark: bool) -> Color32 {
    // Twelve: the ten models compared by default, the custom one and one more, each its own
    // (the tenth took the first's blue beside it).
    const LIGHT: [Color32; 12] = [
        Color32::from_rgb(31, 119, 180),
        Color32::from_rgb(230, 110, 0),
        Color32::from_rgb(40, 150, 40),
        Color32::from_rgb(214, 39, 40),
        Color32::from_rgb(148, 103, 189),
        Color32::from_rgb(140, 86, 75),
        Color32::from_rgb(210, 90, 180),
        Color32::from_rgb(150, 150, 20),
        Color32::from_rgb(20, 170, 190),
        Color32::from_rgb(0, 80, 100),
        Color32::from_rgb(110, 110, 110),
        Color32::from_rgb(70, 60, 170),
    ];
    const DARK: [Color32; 12] = [
        Color32::from_rgb(90, 170, 255),
        Color32::from_rgb(255, 160, 60),
        Color32::from_rgb(100, 210, 100),
        Color32::from_rgb(255, 100, 100),
        Color32::from_rgb(190, 150, 255),
        Color32::from_rgb(205, 150, 120),
        Color32::from_rgb(255, 140, 220),
        Color32::from_rgb(215, 215, 70),
        Color32::from_rgb(70, 220, 235),
        Color32::from_rgb(0, 200, 150),
        Color32::from_rgb(200, 200, 200),
        Color32::from_rgb(150, 140, 255),
    ];
    if dark {
        DARK[k % DARK.len()]
    } else {
        LIGHT[k % LIGHT.len()]
    }
}

/// One entry of the plot's key as one widget, so that a wrap never parts the line from its
/// name: a short line in the curve's colour, then the name (struck through when hidden).
fn key_entry(ui: &mut Ui, name: &str, color: Color32, shown: bool) -> egui::Response {
    const LINE_W: f32 = 16.0;
    const GAP: f32 = 4.0;
    let text_color = if shown {
        ui.visuals().text_color()
    } else {
        color
    };
    let mut job = RichText::new(name).color(text_color);
    if !shown {
        job = job.strikethrough();
    }
    let galley = egui::WidgetText::from(job).into_galley(
        ui,
        Some(egui::TextWrapMode::Extend),
        f32::INFINITY,
        egui::TextStyle::Body,
    );
    let size = egui::vec2(LINE_W + GAP + galley.size().x, galley.size().y.max(12.0));
    let (rect, response) = ui.allocate_exact_size(size, egui::Sense::click());
    if ui.is_rect_visible(rect) {
        let y = rect.center().y;
        ui.painter().hline(
            rect.left()..=rect.left() + LINE_W,
            y,
            egui::Stroke::new(3.0, color),
        );
        let at = egui::pos2(rect.left() + LINE_W + GAP, y - galley.size().y / 2.0);
        ui.painter().galley(at, galley, text_color);
    }
    // Named apart from the presets' check boxes on the left, for screen readers (and tests).
    response.widget_info(|| {
        egui::WidgetInfo::selected(egui::Role::CheckBox, true, shown, format!("show {name}"))
    });
    response
}

/// The raw drift's name in the plot's key.
const RAW: &str = "raw";

impl ModelsView {
    /// The plot's key, one toggle a curve in its colour: above the plot it wraps to the page's
    /// width and never covers the curves, as a legend inside a plot short of height does with
    /// ten models; on a short window it is a menu of the same toggles (`compact`), so that
    /// its rows do not take the plot's height. A click hides a curve or shows it again.
    fn key(&mut self, ui: &mut Ui, c: &Compared, pal: &Palette, dark: bool, compact: bool) {
        let names: Vec<(&str, Color32)> = std::iter::once((RAW, pal.raw))
            .chain(
                c.reports
                    .iter()
                    .enumerate()
                    .map(|(k, r)| (r.model.as_str(), model_color(k, dark))),
            )
            .collect();
        let shown_count = names
            .iter()
            .filter(|(n, _)| !self.hidden.contains(*n))
            .count();
        let mut entries = |ui: &mut Ui| {
            for &(name, color) in &names {
                let shown = !self.hidden.contains(name);
                let weak = ui.visuals().weak_text_color();
                let r = key_entry(ui, name, if shown { color } else { weak }, shown).on_hover_text(
                    if shown {
                        "click to hide"
                    } else {
                        "click to show"
                    },
                );
                if !compact {
                    ui.add_space(8.0);
                }
                if r.clicked() {
                    if shown {
                        self.hidden.insert(name.to_string());
                    } else {
                        self.hidden.remove(name);
                    }
                }
            }
        };
        if compact {
            let label = format!("key: {shown_count} of {} shown", names.len());
            ui.menu_button(label, |ui| entries(ui))
                .response
                .on_hover_text("the curves drawn: click a name to hide it or show it again");
        } else {
            ui.horizontal_wrapped(entries);
        }
    }

    /// The height under which the plot's key folds into a menu: its rows (three at 1024 px
    /// with twelve models) would leave the plot too short to read.
    const COMPACT_BELOW: f32 = 320.0;

    pub(super) fn plot(&mut self, ui: &mut Ui, c: &Compared) {
        let pal = Palette::of(ui);
        let dark = ui.visuals().dark_mode;
        let compact = ui.available_height() < Self::COMPACT_BELOW;
        ui.horizontal_wrapped(|ui| {
            ui.strong("Corrected drift of each model").on_hover_text(
                "Ω filtered as for the figures: raw (grey) and corrected by each fitted model; \
                     click a name in the key below to hide it",
            );
            ui.separator();
            for (j, l) in c.logs.iter().enumerate() {
                let label = if l.held_out {
                    "validation log"
                } else {
                    "calibration log"
                };
                ui.radio_value(&mut self.log_index, j, label)
                    .on_hover_text(&l.log.source);
            }
            if compact {
                ui.separator();
                self.key(ui, c, &pal, dark, true);
            }
        });
        if !compact {
            self.key(ui, c, &pal, dark, false);
        }
        let Some(cl) = c.logs.get(self.log_index) else {
            return;
        };
        let log = &cl.log;
        let n = log.len();
        if n == 0 || cl.raw_filtered_dph.len() != n {
            return;
        }
        let scale = TimeScale::for_duration(log.duration_s());
        let t_full = (log.time_s[0], log.time_s[n - 1]);
        let li = self.log_index;
        let hidden = &self.hidden;
        let plot = Plot::new("models_drift")
            .height(ui.available_height().max(120.0))
            .x_axis_label(format!("time, {}", scale.unit))
            .y_axis_label("drift, °/h");
        crate::gui::plot_items::with_time_axes(plot)
            .allow_zoom(Vec2b::new(true, false))
            .allow_drag(Vec2b::new(true, false))
            .allow_scroll(Vec2b::new(true, false))
            .show(ui, |pui| {
                let (x0, x1) = crate::gui::plot_items::shown_span(pui, scale.div, t_full);
                let cols = pui.response().rect.width().max(50.0) as usize;
                let raw = cl.segments.reduce(
                    &log.time_s,
                    &cl.raw_filtered_dph,
                    &cl.raw_lod,
                    x0,
                    x1,
                    cols,
                );
                if !hidden.contains(RAW) {
                    pui.add(
                        BandItem::segmented(RAW, raw, scale.div, t_full)
                            .color(pal.raw)
                            .width(1.6),
                    );
                }
                for (k, r) in c.reports.iter().enumerate() {
                    if hidden.contains(&r.model) {
                        continue;
                    }
                    let Some(Some(s)) = c.series.get(k).and_then(|v| v.get(li)) else {
                        continue;
                    };
                    if s.cor_filtered_dph.len() != n {
                        continue;
                    }
                    let band =
                        s.ready
                            .reduce(&log.time_s, &s.cor_filtered_dph, &s.lod, x0, x1, cols);
                    pui.add(
                        BandItem::segmented(&r.model, band, scale.div, t_full)
                            .color(model_color(k, dark))
                            .width(1.4),
                    );
                }
            });
    }
}
