//! The Calibration page: the controls panel on the left (the figures at its foot in a short
//! window), the coefficients panel on the right, the time plots and the drift plot between.

use super::*;
use crate::gui::action::Action;

/// The least height the controls keep to scroll in, in a short window, points: what the
/// figures and an opened calibration's strip at the panel's foot leave them.
const CONTROLS_LEAST_H: f32 = 150.0;
/// A foot panel's frame, points: its 2-point margins above and below and its separator line,
/// and a point of room.
const FOOT_MARGIN: f32 = 6.0;

impl Workbench {
    /// The Calibration page; `compact`: a short window (see [`COMPACT_BELOW_H`]).
    pub(super) fn calibration_page(
        &mut self,
        ui: &mut Ui,
        actions: &mut Vec<Action>,
        compact: bool,
    ) {
        if self.state.shown.validation.is_none() {
            self.state.view.show_validation = false;
        }
        if self.state.has_axis_strip() && !compact {
            let r = Panel::top("axes").resizable(false).show(ui, |ui| {
                actions.extend(self.views.axes.ui(ui, &self.state, false))
            });
            self.window.panel_rects.insert("axes", r.response.rect);
        }
        // An accelerometer axis shown: its own view in m/s², in place of the gyro axis's.
        if let Some(k) = self.state.accel_shown() {
            let r = egui::CentralPanel::default().show(ui, |ui| {
                actions.extend(self.views.accel.ui(ui, &self.state, k))
            });
            self.window.panel_rects.insert("central", r.response.rect);
            return;
        }
        // A campaign's runs: a row above the page, or in a short window at the head of the
        // controls (the plots keep the row).
        let campaign = self
            .state
            .shown
            .log
            .as_ref()
            .is_some_and(|l| l.log.runs().len() > 1);
        if campaign && !compact {
            let r = Panel::top("runs")
                .resizable(false)
                .show(ui, |ui| actions.extend(self.views.runs.ui(ui, &self.state)));
            self.window.panel_rects.insert("runs", r.response.rect);
        }
        if !compact {
            Panel::top("banner")
                .resizable(false)
                .show(ui, |ui| self.banner(ui));
            let r = Panel::bottom("figures").resizable(false).show(ui, |ui| {
                actions.extend(self.views.figures.ui(ui, &self.state, false))
            });
            self.window.panel_rects.insert("figures", r.response.rect);
            if self.state.opened.is_some() {
                let r = Panel::bottom("opened").resizable(false).show(ui, |ui| {
                    actions.extend(self.views.opened.ui(ui, &self.state, false))
                });
                self.window.panel_rects.insert("opened", r.response.rect);
            }
        }
        // Side panels keep the width they are given (their contents fill it, whatever they
        // are): an egui panel otherwise takes its contents' width, so a narrow first frame
        // (the log still loading) or a wider row (a button appearing) would change it. A
        // narrow window starts them narrower, so that the plots between keep some width.
        let width = ui.ctx().content_rect().width();
        let controls_w = if width >= WHOLE_TABLE_FROM_W {
            (width * 0.29).max(crate::gui::view_controls::CONTROLS_W_FOR_TABLE)
        } else {
            width * 0.29
        };
        let r = Panel::left("controls")
            .default_size(controls_w.clamp(300.0, 470.0))
            .size_range(290.0..=520.0)
            .show(ui, |ui| {
                if compact {
                    // The figures at the panel's foot, the opened calibration's strip above
                    // them, each as tall as it asked for last frame while the controls keep
                    // CONTROLS_LEAST_H to scroll in (else it scrolls in its own place: the
                    // strip was drawn over the controls, leaving them 20 points).
                    let r = self.foot(ui, 0, "figures", |wb, ui| {
                        wb.views.figures.ui(ui, &wb.state, true)
                    });
                    actions.extend(r);
                    if self.state.opened.is_some() {
                        let r = self.foot(ui, 1, "opened", |wb, ui| {
                            wb.views.opened.ui(ui, &wb.state, true)
                        });
                        actions.extend(r);
                    }
                }
                let s = ScrollArea::vertical()
                    .auto_shrink([false, false])
                    .show(ui, |ui| {
                        ui.set_min_width(ui.available_width());
                        if campaign && compact {
                            actions.extend(self.views.runs.ui(ui, &self.state));
                            ui.separator();
                        }
                        let focus = PlateauFocus {
                            visible_s: self.views.time.visible_s,
                            selected: self.views.time.selected,
                        };
                        actions.extend(self.views.controls.ui(ui, &self.state, focus));
                    });
                self.window
                    .panel_rects
                    .insert("controls_scroll", s.inner_rect);
            });
        self.window.panel_rects.insert("controls", r.response.rect);
        // The coefficient plots keep a readable height and scroll in their panel (the wheel
        // over a plot scrolls it; Ctrl+wheel zooms the plot).
        let r = Panel::right("coefficients")
            .default_size((width * 0.25).clamp(300.0, 470.0))
            .size_range(300.0..=800.0)
            .show(ui, |ui| {
                ui.set_min_width(ui.available_width());
                ScrollArea::vertical()
                    .id_salt("coefficients_scroll")
                    .auto_shrink([false, false])
                    .show(ui, |ui| {
                        ui.set_min_width(ui.available_width());
                        actions.extend(self.views.coeffs.ui(ui, &self.state));
                    });
            });
        self.window
            .panel_rects
            .insert("coefficients", r.response.rect);
        let mut central = egui::Frame::central_panel(ui.style());
        if compact {
            central.inner_margin.top = COMPACT_MARGIN_Y;
            central.inner_margin.bottom = COMPACT_MARGIN_Y;
        }
        let r = egui::CentralPanel::default().frame(central).show(ui, |ui| {
            if self.state.shown.log.is_none() {
                self.welcome(ui, actions);
                return;
            }
            // The time plots take two thirds, and at least what keeps each of them
            // TIME_PLOT_H tall (a short window: just that, the drift plot needs the rest);
            // the drift plot what is left, never less than DRIFT_PLOT_H (the time plots give
            // way first: on a window that short they are shorter).
            let h = ui.available_height();
            // (compact: no separator line, the drift plot's frame is one)
            let sep = if compact {
                ui.spacing().item_spacing.y
            } else {
                2.0 * ui.spacing().item_spacing.y + 6.0
            };
            self.views.time.compact = compact;
            // The drift plot's header takes a row unless it is drawn over the plot.
            let header = if self.views.result.header_over_plot(ui, &self.state, compact) {
                0.0
            } else {
                ui.spacing().interact_size.y + ui.spacing().item_spacing.y
            };
            let least = self.views.time.height_for(ui, TIME_PLOT_H);
            let want = if compact {
                least
            } else {
                (h * 0.66).max(least)
            };
            let time_h = want.min(h - sep - header - DRIFT_PLOT_H).max(0.0);
            ui.allocate_ui(egui::vec2(ui.available_width(), time_h), |ui| {
                ui.set_min_height(time_h);
                actions.extend(self.views.time.ui(ui, &self.state));
            });
            self.state.view.time_range_s = self.views.time.visible_s.map(|(a, b)| [a, b]);
            if !compact {
                ui.separator();
            }
            actions.extend(self.views.result.ui(ui, &self.state, compact));
        });
        self.window.panel_rects.insert("central", r.response.rect);
    }

    /// A strip at the foot of the controls panel (`k`: 0 the figures, 1 the opened
    /// calibration), named `name` among the panel rects: as tall as its contents were last
    /// frame, at most what leaves the controls [`CONTROLS_LEAST_H`], scrolling within.
    fn foot(
        &mut self,
        ui: &mut Ui,
        k: usize,
        name: &'static str,
        contents: impl FnOnce(&mut Self, &mut Ui) -> Vec<Action>,
    ) -> Vec<Action> {
        let most = (ui.available_height() - CONTROLS_LEAST_H).max(FOOT_MARGIN);
        let h = (self.window.foot_h[k] + FOOT_MARGIN).min(most);
        let r = Panel::bottom(name)
            .resizable(false)
            .exact_size(h)
            .show(ui, |ui| {
                // (the panel's frame and separator, 5 points, inside the exact size; a scroll
                // area is otherwise at least 64 points tall, and a taller frame is pushed down
                // over the panel below)
                let o = ScrollArea::vertical()
                    .id_salt((name, "foot"))
                    .max_height(h - FOOT_MARGIN)
                    .min_scrolled_height(0.0)
                    .auto_shrink([false, false])
                    .show(ui, |ui| contents(self, ui));
                (o.inner, o.content_size.y)
            });
        let (out, used) = r.inner;
        if (used - self.window.foot_h[k]).abs() > 0.5 {
            // Its height follows its contents at the next frame.
            self.window.foot_h[k] = used;
            ui.ctx().request_repaint();
        }
        self.window.panel_rects.insert(name, r.response.rect);
        out
    }

    fn welcome(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        ui.vertical_centered(|ui| {
            ui.add_space(ui.available_height() * 0.3);
            ui.heading("driftlab workbench");
            ui.label("Calibrate the thermal drift of a gyroscope from a thermal-chamber log.");
            ui.add_space(12.0);
            if self.jobs.loading.is_some() {
                ui.spinner();
            } else if ui
                .button(RichText::new("Open log…").size(18.0))
                .on_hover_text("Ctrl+O — or drop a log file onto the window")
                .clicked()
            {
                actions.push(Action::OpenLog);
            }
            if let Some(s) = default_log()
                && ui
                    .button("Open the bundled sample log")
                    .on_hover_text(s.display().to_string())
                    .clicked()
            {
                self.start_load(s, LoadOptions::default(), Target::Calibration);
            }
        });
    }
}
